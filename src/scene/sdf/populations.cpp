// Sensor types and <population>s: a depth <sensor> becomes a SensorType (one per distinct sensor
// model), and a <population> a Population struct whose positions are drawn later by
// PopulationPositions (GAZEBO.md, "Sensor populations"). Which regions and distributions Gazebo
// supports is checked here, where the element's line is known.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"

namespace vantage::detail::gazebo {

std::optional<std::string> Loader::AddSensorType(const SensorRecord& record,
                                                 const std::string& id) {
  const Doc& doc = *record.doc;
  const XmlElement& sensor = *record.element;
  const XmlElement* camera = sensor.Child("camera");
  if (!camera) {
    Error(doc, sensor.line,
          fmt::format("depth <sensor name='{}'> has no <camera> — add <camera> with "
                      "<horizontal_fov>, <image> and <clip>",
                      record.sensor_name));
    return std::nullopt;
  }
  // SDF's defaults where an element is absent (Gazebo uses them too).
  const double hfov = NumberOr(doc, camera, "horizontal_fov", 1.047, true);
  const XmlElement* image = camera->Child("image");
  int width = 320;
  int height = 240;
  if (const XmlElement* e = image ? image->Child("width") : nullptr) {
    width = static_cast<int>(Integer(doc, *e, 1, 1'000'000).value_or(width));
  }
  if (const XmlElement* e = image ? image->Child("height") : nullptr) {
    height = static_cast<int>(Integer(doc, *e, 1, 1'000'000).value_or(height));
  }
  const XmlElement* clip = camera->Child("clip");
  double near = NumberOr(doc, clip, "near", 0.1, true);
  double far = NumberOr(doc, clip, "far", 100.0, true);
  double fps = 0;
  if (const XmlElement* e = sensor.Child("update_rate")) {
    if (const auto v = Number(doc, *e, "30")) {
      if (*v < 0) {
        Error(doc, e->line, fmt::format("<update_rate> {} must be >= 0 [Hz]", e->Trimmed()));
      } else {
        fps = *v;
      }
    }
  }
  // A depth image's own range (<depth_camera><clip>, SDF 1.7+) replaces <clip> for it.
  const XmlElement* depth_camera = camera->Child("depth_camera");
  const XmlElement* depth_clip = depth_camera ? depth_camera->Child("clip") : nullptr;
  near = NumberOr(doc, depth_clip, "near", near, true);
  far = NumberOr(doc, depth_clip, "far", far, true);
  SensorType type = SensorType::FromFov(id, width, height, hfov, std::nullopt, near, far);
  type.fps = fps;
  // <lens><intrinsics> overrides the field of view (gz-sensors builds the projection from them);
  // SDF's defaults for the ones left out. cx, cy in vantage's continuous image coordinates,
  // which are Gazebo's (the default cx = W/2 is the centre).
  const XmlElement* lens = camera->Child("lens");
  if (const XmlElement* intrinsics = lens ? lens->Child("intrinsics") : nullptr) {
    type.fx = NumberOr(doc, intrinsics, "fx", 277, true);
    type.fy = NumberOr(doc, intrinsics, "fy", 277, true);
    type.cx = NumberOr(doc, intrinsics, "cx", 160, false);
    type.cy = NumberOr(doc, intrinsics, "cy", 120, false);
    if (const XmlElement* skew = intrinsics->Child("s")) {
      if (const auto s = Number(doc, *skew, "0"); s && *s != 0) {
        Error(doc, skew->line,
              fmt::format("<s> {} — vantage's pinhole has no skew; give <s>0</s>", skew->Trimmed()));
      }
    }
  }
  try {
    type.Validate(fmt::format("{}:{}", doc.xml.path, sensor.line));
  } catch (const InputError& e) {
    AddError(e.what());
    return std::nullopt;
  }
  // One type per distinct sensor model; a different model of the same name gets a suffix.
  const auto same = [&](const SensorType& t) {
    return t.width == type.width && t.height == type.height && t.fx == type.fx && t.fy == type.fy &&
           t.cx == type.cx && t.cy == type.cy && t.near == type.near && t.far == type.far &&
           t.fps == type.fps;
  };
  for (int suffix = 1;; ++suffix) {
    const std::string candidate = suffix == 1 ? id : fmt::format("{}_{}", id, suffix);
    const auto found = std::find_if(problem_.sensor_types.begin(), problem_.sensor_types.end(),
                                    [&](const SensorType& t) { return t.id == candidate; });
    const SensorType* existing = found == problem_.sensor_types.end() ? nullptr : &*found;
    if (!existing) {
      type.id = candidate;
      type.name = candidate;
      if (suffix > 1) {
        Note(AtPlace(doc.xml.path, sensor.line,
                     fmt::format("sensor model '{}' differs from another of the same name: its "
                                 "type is called '{}'",
                                 id, candidate)));
      }
      problem_.sensor_types.push_back(type);
      return candidate;
    }
    if (same(*existing)) return candidate;
  }
}

void Loader::ReadPopulation(const Doc& doc, const XmlElement& e) {
  Population population;
  population.file = doc.xml.path;
  population.line = e.line;
  const std::string* name = e.Attribute("name");
  population.name = name ? Trim(*name) : "";
  if (population.name.empty()) {
    Error(doc, e.line, "<population> has no name attribute — add name=\"...\"");
    return;
  }
  const std::string what = fmt::format("population '{}'", population.name);
  if (!population_names_.insert(population.name).second) {
    Error(doc, e.line, fmt::format("a second {} — give each population a unique name", what));
    return;
  }
  bool ok = true;
  const auto fail = [&](int line, const std::string& message) {
    Error(doc, line, fmt::format("{}: {}", what, message));
    ok = false;
  };

  population.pose = WorldPose(doc, e.Child("pose"));
  // Gazebo's regions are <box> and <cylinder>; another shape is a mistake, not "no region".
  for (const XmlElement& child : e.children) {
    static const std::set<std::string> kOtherShapes = {
        "sphere", "plane", "mesh", "capsule", "ellipsoid", "polyline", "heightmap"};
    if (kOtherShapes.contains(child.name)) {
      fail(child.line,
           fmt::format("<{}> is not a population region — use <box> or <cylinder>", child.name));
    }
  }
  const XmlElement* box = e.Child("box");
  const XmlElement* cylinder = e.Child("cylinder");
  if (box && cylinder) fail(cylinder->line, "has both <box> and <cylinder> — keep one region");
  if (box) {
    population.region = RegionShape::kBox;
    const XmlElement* size = box->Child("size");
    if (!size) {
      fail(box->line, "<box> has no <size> — add <size>sx sy sz</size>");
    } else if (const auto v = Vector(doc, *size, true, "0.5 0.5 0.2")) {
      population.box_size = *v;
    } else {
      ok = false;
    }
  } else if (cylinder) {
    population.region = RegionShape::kCylinder;
    const XmlElement* radius = cylinder->Child("radius");
    const XmlElement* length = cylinder->Child("length");
    if (!radius || !length) {
      fail(cylinder->line, "<cylinder> needs <radius> and <length>");
    } else {
      const auto r = PositiveNumber(doc, *radius, "0.35");
      const auto l = PositiveNumber(doc, *length, "0.1");
      if (r && l) {
        population.radius = *r;
        population.length = *l;
      } else {
        ok = false;
      }
    }
  } else {
    population.region = RegionShape::kNone;
  }

  const XmlElement* distribution = e.Child("distribution");
  const XmlElement* type = distribution ? distribution->Child("type") : nullptr;
  if (!type) {
    fail(distribution ? distribution->line : e.line,
         "has no <distribution><type> — add random, uniform, grid, linear-x, linear-y or "
         "linear-z");
  } else {
    static const std::map<std::string, Distribution> kTypes = {
        {"random", Distribution::kRandom},    {"uniform", Distribution::kUniform},
        {"grid", Distribution::kGrid},        {"linear-x", Distribution::kLinearX},
        {"linear-y", Distribution::kLinearY}, {"linear-z", Distribution::kLinearZ}};
    const auto it = kTypes.find(type->Trimmed());
    if (it == kTypes.end()) {
      fail(type->line, fmt::format("unknown <distribution><type> '{}' — use random, uniform, "
                                   "grid, linear-x, linear-y or linear-z",
                                   type->Trimmed()));
    } else {
      population.distribution = it->second;
    }
  }
  const bool is_grid = population.distribution == Distribution::kGrid;
  const bool is_linear = population.distribution == Distribution::kLinearX ||
                         population.distribution == Distribution::kLinearY ||
                         population.distribution == Distribution::kLinearZ;
  if (ok && is_grid) {
    // Gazebo reads rows/cols/step for grid only; SDF defaults 1, 1, (0.5 0.5 0).
    population.rows = 1;
    population.cols = 1;
    population.step = Vec3(0.5, 0.5, 0);
    if (const XmlElement* rows = distribution->Child("rows")) {
      if (const auto v = Integer(doc, *rows, 1, 1'000'000))
        population.rows = static_cast<int>(*v);
      else
        ok = false;
    }
    if (const XmlElement* cols = distribution->Child("cols")) {
      if (const auto v = Integer(doc, *cols, 1, 1'000'000))
        population.cols = static_cast<int>(*v);
      else
        ok = false;
    }
    if (const XmlElement* step = distribution->Child("step")) {
      if (const auto v = Vector(doc, *step, false, "0.5 0.5 0"))
        population.step = *v;
      else
        ok = false;
    }
    if (cylinder) {
      fail(cylinder->line,
           "distribution 'grid' takes no region — remove the <cylinder> "
           "(rows, cols and step place the grid)");
    }
  } else if (ok) {
    // Supported combinations: Gazebo's Population.cc (and PopulationPositions).
    if (!box && !cylinder) {
      fail(e.line, fmt::format("distribution '{}' needs a region — add <box><size>…</size></box> "
                               "or <cylinder>…</cylinder>",
                               type->Trimmed()));
    } else if (is_linear && cylinder) {
      fail(cylinder->line,
           fmt::format("distribution '{}' works in a <box> region only", type->Trimmed()));
    }
    const XmlElement* count = e.Child("model_count");
    if (!count) {
      fail(e.line, "has no <model_count> — add <model_count>N</model_count>");
    } else if (const auto v = Integer(doc, *count, 1, 1'000'000)) {
      population.count = static_cast<int>(*v);
    } else {
      ok = false;
    }
  }

  // The sensor model: one <include> or <model>. Its body is hidden; its depth sensor gives the
  // population's type and camera offset (link · sensor, without the model's own pose: Gazebo
  // sets the clone's pose, GAZEBO.md).
  std::vector<const XmlElement*> models = e.Children("include");
  for (const XmlElement* m : e.Children("model")) models.push_back(m);
  if (models.size() != 1) {
    fail(e.line, fmt::format("holds {} models — a population holds one <include> or <model>",
                             models.size()));
    return;
  }
  std::vector<SensorRecord> sensors;
  ModelContext context;
  context.sink = Sink{nullptr, &sensors, nullptr};
  context.hidden = true;
  context.site = Site{doc.xml.path, e.line};
  if (models[0]->name == "include") {
    const IncludeResult result = ResolveInclude(doc, *models[0]);
    if (result.kind != IncludeResult::Kind::kModel) {
      if (result.kind != IncludeResult::Kind::kFailed)
        fail(models[0]->line, "its model has no depth sensor");
      return;
    }
    context.scoped = result.name;
    VisitModel(*result.doc, *result.model, context);
  } else {
    const std::string* model_name = models[0]->Attribute("name");
    context.scoped = model_name ? Trim(*model_name) : "";
    if (context.scoped.empty()) {
      fail(models[0]->line, "<model> has no name attribute — add name=\"...\"");
      return;
    }
    VisitModel(doc, *models[0], context);
  }
  if (sensors.size() != 1) {
    fail(models[0]->line,
         fmt::format("model '{}' has {} depth sensors — a population's model holds exactly one "
                     "<sensor type=\"depth\">",
                     context.scoped, sensors.size()));
    return;
  }
  const SensorRecord& sensor = sensors[0];
  const std::optional<std::string> id = AddSensorType(sensor, sensor.type_name);
  if (!id || !ok) return;
  population.sensor_type = *id;
  population.model_from_camera = sensor.world_from_model * sensor.model_from_camera;
  problem_.populations.push_back(std::move(population));
}

}  // namespace vantage::detail::gazebo
