// constellation.world: the input world, edited as text so that everything vantage does not
// change keeps its exact bytes (comments, plugins, physics, GUI). The XML reader's byte offsets
// (util/xml.hpp) say what to cut and what to copy; the edits are collected as (begin, end,
// replacement) and applied from the back.
//
// Frames (GAZEBO.md, "Sensor orientation and camera"): a candidate's world_from_body is the
// camera frame = world_from_model · model_from_camera, so the model goes to
// world_from_body · model_from_camera⁻¹. Gazebo then puts the camera exactly there; vantage, which
// re-orients every explicit sensor towards the observation point, finds the same pose again when
// the random roll is off (the position is unchanged, so is the look-at).
#include "util/markup.hpp"
#include "util/words.hpp"
#include "vantage/gazebo_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/scene.hpp"
#include "vantage/types.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

using detail::XmlElement;

/// Shortest text that reads back as the same double; never "-0".
std::string Number(double v) {
  if (v == 0) return "0";
  return fmt::format("{}", v);
}

/// `<pose>` text: x y z roll pitch yaw, R = Rz(yaw)·Ry(pitch)·Rx(roll) (GAZEBO.md).
std::string PoseText(const Pose& pose) {
  const Vec3 rpy = RpyFromRotation(pose.rotation.normalized().toRotationMatrix());
  return fmt::format("{} {} {} {} {} {}", Number(pose.position.x()), Number(pose.position.y()),
                     Number(pose.position.z()), Number(rpy.x()), Number(rpy.y()), Number(rpy.z()));
}

/// SDF 1.7+ reserves "::" in names; "/" is vantage's model/sensor separator.
std::string ModelName(const std::string& raw) {
  const std::string name = detail::AsUtf8(raw);  // XML holds UTF-8 only
  std::string out;
  for (size_t i = 0; i < name.size(); ++i) {
    if (name.compare(i, 2, "::") == 0) {
      out += "__";
      ++i;
    } else {
      out.push_back(name[i] == '/' ? '_' : name[i]);
    }
  }
  return out;
}

/// The declared instance name of a world child or nested entity: the model's name attribute, or
/// an include's <name> ("" when the include takes the model file's own name).
std::string DeclaredName(const XmlElement& e) {
  if (e.name == "model") {
    const std::string* name = e.Attribute("name");
    return name ? detail::TrimXmlSpace(*name) : "";
  }
  const XmlElement* name = e.Child("name");
  return name ? name->Trimmed() : "";
}

/// The model name that an include's URI points at ("model://a/b" -> "a", "/x/y/" -> "y").
std::string UriBaseName(std::string uri) {
  while (!uri.empty() && uri.back() == '/') uri.pop_back();
  const size_t scheme = uri.find("://");
  std::string rest = scheme == std::string::npos ? uri : uri.substr(scheme + 3);
  if (uri.rfind("model://", 0) == 0) return rest.substr(0, rest.find('/'));
  const size_t slash = rest.rfind('/');
  return slash == std::string::npos ? rest : rest.substr(slash + 1);
}

/// Offset of the '<' of an element's closing tag (its `end` for an empty element).
size_t ClosingTagBegin(std::string_view text, const XmlElement& e) {
  if (e.content_begin == e.end) return e.end;
  const size_t at = text.rfind("</", e.end - 1);
  VANTAGE_CHECK(at != std::string_view::npos && at >= e.content_begin);
  return at;
}

/// Start of the line holding `pos` when only white space precedes it there, else `pos`.
size_t LineStartIfBlank(std::string_view text, size_t pos) {
  size_t start = pos;
  while (start > 0 && (text[start - 1] == ' ' || text[start - 1] == '\t')) --start;
  return start == 0 || text[start - 1] == '\n' ? start : pos;
}

/// End of the blank line (white space only) starting at `pos`, past its '\n'; npos when the line
/// is not blank or `pos` is the end.
size_t BlankLineEnd(std::string_view text, size_t pos) {
  size_t end = pos;
  while (end < text.size() && (text[end] == ' ' || text[end] == '\t' || text[end] == '\r')) ++end;
  return end < text.size() && text[end] == '\n' ? end + 1 : std::string_view::npos;
}

/// The range to cut for an element: its whole lines when it stands alone on them, and then one
/// blank line before it too when a blank line follows (so "A, blank, B, blank, C" loses B and a
/// blank line, not B alone). `ate_blank_line` says whether that happened.
struct Cut {
  size_t begin = 0;
  size_t end = 0;
  bool ate_blank_line = false;
  bool operator<(const Cut& o) const { return begin != o.begin ? begin < o.begin : end < o.end; }
  bool operator==(const Cut& o) const { return begin == o.begin && end == o.end; }
};

Cut CutRange(std::string_view text, const XmlElement& e) {
  const size_t begin = LineStartIfBlank(text, e.begin);
  size_t end = e.end;
  while (end < text.size() && (text[end] == ' ' || text[end] == '\t' || text[end] == '\r')) ++end;
  if (begin == e.begin || (end != text.size() && text[end] != '\n')) return {e.begin, e.end, false};
  end = std::min(end + 1, text.size());
  if (begin > 0 && BlankLineEnd(text, end) != std::string_view::npos) {
    // text[begin - 1] is the '\n' that ends the previous line.
    const size_t newline = begin >= 2 ? text.rfind('\n', begin - 2) : std::string_view::npos;
    const size_t previous_start = newline == std::string_view::npos ? 0 : newline + 1;
    if (BlankLineEnd(text, previous_start) == begin) return {previous_start, end, true};
  }
  return {begin, end, false};
}

/// One text edit: replace [begin, end) by `text`.
struct Edit {
  size_t begin = 0;
  size_t end = 0;
  std::string text;
};

/// Where a depth sensor of the world is declared.
struct SensorSite {
  const XmlElement* element = nullptr;  ///< the sensor model's own element (world file), or null
  const XmlElement* top = nullptr;      ///< its top-level world child
  std::string scoped;                   ///< its model's scoped name
  std::string blocked_by;               ///< when null: the include whose file holds it
};

/// One gz-sim camera model: the model frame is the camera's body frame (link and sensor at
/// identity), a depth_camera whose pinhole is the candidate's exactly: horizontal_fov from fx
/// (Gazebo's fx = W / (2 tan(hfov / 2))), and <lens><intrinsics> when the principal point is off
/// centre or the pixels are not square, which horizontal_fov alone cannot say.
std::string GzCameraText(const Candidate& candidate, const std::string& name,
                         const std::string& indent, const std::string& unit) {
  const SensorType& t = candidate.sensor;
  const std::string i1 = indent + unit;
  const std::string i2 = i1 + unit;
  const std::string i3 = i2 + unit;
  const std::string i4 = i3 + unit;
  const std::string escaped = detail::MarkupEscape(name);
  std::string out = fmt::format("{}<model name=\"{}\">\n", indent, escaped);
  out += fmt::format("{}<static>true</static>\n", i1);
  out += fmt::format("{}<pose>{}</pose>\n", i1, PoseText(candidate.world_from_body));
  out += fmt::format("{}<link name=\"link\">\n", i1);
  out += fmt::format("{}<sensor name=\"depth\" type=\"depth_camera\">\n", i2);
  out += fmt::format("{}<always_on>true</always_on>\n", i3);
  out += fmt::format("{}<update_rate>{}</update_rate>\n", i3, Number(t.fps > 0 ? t.fps : 30));
  // gz-transport topics take no spaces and few symbols: the ROS frame name's encoding.
  out += fmt::format("{}<topic>{}/depth</topic>\n", i3, ExportedFrameName(candidate.name));
  out += fmt::format("{}<camera>\n", i3);
  out += fmt::format("{}<horizontal_fov>{}</horizontal_fov>\n", i4,
                     Number(2 * std::atan(t.width / (2 * t.fx))));
  out += fmt::format("{}<image><width>{}</width><height>{}</height><format>R_FLOAT32</format>"
                     "</image>\n",
                     i4, t.width, t.height);
  out += fmt::format("{}<clip><near>{}</near><far>{}</far></clip>\n", i4, Number(t.near),
                     Number(t.far));
  if (t.cx != t.width / 2.0 || t.cy != t.height / 2.0 || t.fy != t.fx) {
    out += fmt::format("{}<lens><intrinsics><fx>{}</fx><fy>{}</fy><cx>{}</cx><cy>{}</cy><s>0</s>"
                       "</intrinsics></lens>\n",
                       i4, Number(t.fx), Number(t.fy), Number(t.cx), Number(t.cy));
  }
  out += fmt::format("{}</camera>\n", i3);
  out += fmt::format("{}</sensor>\n", i2);
  out += fmt::format("{}</link>\n", i1);
  out += fmt::format("{}</model>\n", indent);
  return out;
}

/// Whether a <plugin> of the world loads gz-sim's Sensors system (which renders the cameras).
bool HasSensorsSystem(const XmlElement& world) {
  for (const XmlElement* plugin : world.Children("plugin")) {
    const std::string* filename = plugin->Attribute("filename");
    const std::string* name = plugin->Attribute("name");
    if ((filename && filename->find("sensors-system") != std::string::npos) ||
        (name && name->find("systems::Sensors") != std::string::npos))
      return true;
  }
  return false;
}

class Exporter {
 public:
  Exporter(const std::string& path,
           const std::vector<Population>& populations,
           const std::vector<ExplicitSensor>& sensors,
           std::vector<std::string>* notes,
           bool gz_cameras = false)
      : path_(path),
        gz_cameras_(gz_cameras),
        text_(detail::ReadInputFile(path, "world file")),
        doc_(detail::ParseXml(text_, path)),
        populations_(populations),
        sensors_(sensors),
        notes_(notes) {}

  std::string Run(const std::vector<Candidate>& chosen);

 private:
  void Note(const std::string& note) {
    if (notes_ && std::find(notes_->begin(), notes_->end(), note) == notes_->end())
      notes_->push_back(note);
  }
  SensorSite Locate(const ExplicitSensor& sensor) const;
  std::string IncludeText(const XmlElement& include,
                          const std::string& name,
                          const Pose& pose,
                          const std::string& indent) const;
  std::string ModelText(const XmlElement& model,
                        const std::string& name,
                        const Pose& pose,
                        const std::string& indent) const;
  std::string EntityText(const XmlElement& source,
                         const std::string& name,
                         const Pose& pose,
                         const std::string& indent) const;

  std::string path_;
  bool gz_cameras_;  ///< constellation.sdf: generated gz-sim cameras instead of the sources
  std::string text_;
  detail::XmlDocument doc_;
  const std::vector<Population>& populations_;
  const std::vector<ExplicitSensor>& sensors_;
  std::vector<std::string>* notes_;
  const XmlElement* world_ = nullptr;
  std::string unit_ = "  ";  ///< one level of indentation, as the world writes it
};

SensorSite Exporter::Locate(const ExplicitSensor& sensor) const {
  SensorSite site;
  // "model/sensor" names one of several sensors of a model: the model is the element.
  site.scoped = sensor.name.substr(0, sensor.name.find('/'));
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t sep = site.scoped.find("::", start);
    parts.push_back(site.scoped.substr(start, sep - start));
    if (sep == std::string::npos) break;
    start = sep + 2;
  }
  // The loader records the line of the sensor's top-level world child.
  std::vector<const XmlElement*> on_line;
  for (const XmlElement& child : world_->children) {
    if ((child.name == "include" || child.name == "model") && child.line == sensor.line)
      on_line.push_back(&child);
  }
  for (const XmlElement* e : on_line) {
    if (!site.top || DeclaredName(*e) == parts[0]) site.top = e;
  }
  if (!site.top) return site;
  const XmlElement* current = site.top;
  for (size_t i = 1; i < parts.size(); ++i) {
    if (current->name == "include") {
      site.blocked_by = DeclaredName(*current).empty() ? parts[0] : DeclaredName(*current);
      return site;
    }
    const XmlElement* next = nullptr;
    for (const XmlElement& child : current->children) {
      if (child.name != "model" && child.name != "include") continue;
      std::string name = DeclaredName(child);
      if (name.empty() && child.name == "include" && child.Child("uri"))
        name = UriBaseName(child.Child("uri")->Trimmed());
      if (name == parts[i]) {
        next = &child;
        break;
      }
    }
    if (!next) return site;
    current = next;
  }
  site.element = current;
  return site;
}

std::string Exporter::IncludeText(const XmlElement& include,
                                  const std::string& name,
                                  const Pose& pose,
                                  const std::string& indent) const {
  const XmlElement* uri = include.Child("uri");
  VANTAGE_CHECK(uri != nullptr);  // the loader resolved this include
  const std::string inner = indent + unit_;
  std::string out = indent + "<include>\n";
  out += fmt::format("{}<name>{}</name>\n", inner, detail::MarkupEscape(name));
  out += fmt::format("{}<uri>{}</uri>\n", inner, detail::MarkupEscape(uri->Trimmed()));
  out += fmt::format("{}<static>1</static>\n", inner);
  out += fmt::format("{}<pose>{}</pose>\n", inner, PoseText(pose));
  // Anything else the include carries (a plugin, say) comes along as written.
  static const std::set<std::string, std::less<>> kReplaced = {"name", "uri", "static", "pose",
                                                               "placement_frame"};
  for (const XmlElement& child : include.children) {
    if (kReplaced.contains(child.name)) continue;
    out += inner + text_.substr(child.begin, child.end - child.begin) + "\n";
  }
  out += indent + "</include>\n";
  return out;
}

std::string Exporter::ModelText(const XmlElement& model,
                                const std::string& name,
                                const Pose& pose,
                                const std::string& indent) const {
  // The start tag, renamed; the content as written, without its own <pose> and <static>.
  std::string out = indent + "<model name=\"" + detail::MarkupEscape(name) + "\"";
  for (const auto& [key, value] : model.attributes) {
    if (key == "name" || key == "placement_frame") continue;
    out += fmt::format(" {}=\"{}\"", key, detail::MarkupEscape(value));
  }
  out += ">\n";
  const std::string inner = indent + unit_;
  out += fmt::format("{}<static>1</static>\n", inner);
  out += fmt::format("{}<pose>{}</pose>", inner, PoseText(pose));
  size_t pos = model.content_begin;
  const size_t content_end = ClosingTagBegin(text_, model);
  for (const XmlElement& child : model.children) {
    if (child.name != "pose" && child.name != "static") continue;
    const Cut cut = CutRange(text_, child);
    out += text_.substr(pos, cut.begin - pos);
    pos = cut.end;
  }
  out += text_.substr(pos, content_end - pos);
  if (!out.empty() && out.back() != '\n') {
    // The closing tag gets its own line at the model's indentation.
    while (!out.empty() && (out.back() == ' ' || out.back() == '\t')) out.pop_back();
    if (out.back() != '\n') out += "\n";
  }
  out += indent + "</model>\n";
  return out;
}

std::string Exporter::EntityText(const XmlElement& source,
                                 const std::string& name,
                                 const Pose& pose,
                                 const std::string& indent) const {
  return source.name == "include" ? IncludeText(source, name, pose, indent)
                                  : ModelText(source, name, pose, indent);
}

std::string Exporter::Run(const std::vector<Candidate>& chosen) {
  const XmlElement& root = doc_.root;
  world_ = root.Child("world");
  if (!world_) throw InputError(AtPlace(path_, root.line, "no <world> element"));

  // Indentation: that of the world's first child, one level = what it adds to the world's.
  std::string indent = "  ";
  if (!world_->children.empty()) {
    const size_t begin = world_->children.front().begin;
    const size_t start = LineStartIfBlank(text_, begin);
    if (start != begin) indent = text_.substr(start, begin - start);
    const size_t world_start = LineStartIfBlank(text_, world_->begin);
    const std::string world_indent = text_.substr(world_start, world_->begin - world_start);
    if (indent.size() > world_indent.size() && indent.rfind(world_indent, 0) == 0)
      unit_ = indent.substr(world_indent.size());
  }

  std::map<std::string, const XmlElement*> population_elements;
  std::vector<const XmlElement*> cut_top;  // top-level elements removed entirely
  for (const XmlElement& child : world_->children) {
    if (child.name != "population") continue;
    const std::string* name = child.Attribute("name");
    if (name) population_elements[detail::TrimXmlSpace(*name)] = &child;
    cut_top.push_back(&child);
  }

  // Explicit sensors: cut their elements. One nested in an included file cannot be cut: it stays,
  // unless its top-level element goes anyway (a sensor model nesting another).
  std::vector<const XmlElement*> cut_nested;
  std::map<std::string, SensorSite> sites;
  std::map<const XmlElement*, int> sensors_per_element;
  for (const ExplicitSensor& sensor : sensors_) {
    SensorSite site = Locate(sensor);
    if (site.element) {
      ++sensors_per_element[site.element];
      (site.element == site.top ? cut_top : cut_nested).push_back(site.element);
    }
    sites[sensor.name] = site;
  }
  const auto is_cut_top = [&](const XmlElement* e) {
    return e && std::find(cut_top.begin(), cut_top.end(), e) != cut_top.end();
  };
  int sensors_kept = 0;
  for (const ExplicitSensor& sensor : sensors_) {
    const SensorSite& site = sites[sensor.name];
    if (site.element) continue;
    const std::string where = site.blocked_by.empty()
                                  ? std::string("was not found in the world's text")
                                  : fmt::format(
                                        "is part of the included model '{}' (model files "
                                        "are not rewritten)",
                                        site.blocked_by);
    if (is_cut_top(site.top)) {
      Note(AtPlace(
          path_, sensor.line,
          fmt::format("constellation.world: sensor '{}' {} and goes with it", sensor.name, where)));
    } else {
      ++sensors_kept;
      Note(AtPlace(path_, sensor.line,
                   fmt::format("constellation.world: sensor '{}' {} and stays as it is",
                               sensor.name, where)));
    }
  }

  // The names the world keeps: a new model may not take one (SDF wants siblings' names unique).
  std::set<std::string> taken;
  for (const XmlElement& child : world_->children) {
    if (is_cut_top(&child)) continue;
    std::string name = DeclaredName(child);
    if (const std::string* attribute = child.Attribute("name"); name.empty() && attribute)
      name = detail::TrimXmlSpace(*attribute);
    if (name.empty() && child.name == "include" && child.Child("uri"))
      name = UriBaseName(child.Child("uri")->Trimmed());
    if (!name.empty()) taken.insert(name);
  }

  // The chosen sensors' new elements.
  std::string added;
  int sensors_added = 0;
  for (const Candidate& candidate : chosen) {
    const XmlElement* source = nullptr;
    Pose model_from_camera;
    int sensor_count = 1;
    if (!candidate.population.empty()) {
      const auto population =
          std::find_if(populations_.begin(), populations_.end(),
                       [&](const Population& p) { return p.name == candidate.population; });
      const auto element = population_elements.find(candidate.population);
      if (population == populations_.end() || element == population_elements.end()) {
        throw InputError(AtPlace(path_, 0,
                                 fmt::format("candidate '{}': population '{}' is not in the world",
                                             candidate.name, candidate.population)));
      }
      model_from_camera = population->model_from_camera;
      source = element->second->Child("include");
      if (!source) source = element->second->Child("model");
    } else {
      const auto sensor =
          std::find_if(sensors_.begin(), sensors_.end(),
                       [&](const ExplicitSensor& s) { return s.name == candidate.name; });
      if (sensor == sensors_.end()) {
        throw InputError(
            AtPlace(path_, 0,
                    fmt::format("candidate '{}' is no population clone and no sensor of the world",
                                candidate.name)));
      }
      const SensorSite& site = sites[sensor->name];
      if (!site.element) continue;  // it stays in place, or cannot be placed alone (noted)
      model_from_camera = sensor->model_from_camera;
      source = site.element;
      sensor_count = sensors_per_element[site.element];
      if (sensor_count > 1) {
        Note(AtPlace(path_, sensor->line,
                     fmt::format("constellation.world: sensor '{}' shares its model with {} other "
                                 "depth sensor(s), which come along",
                                 sensor->name, sensor_count - 1)));
      }
    }
    VANTAGE_CHECK(source != nullptr);
    const std::string name = ConstellationModelName(candidate.name, &taken);
    if (gz_cameras_) {
      added += GzCameraText(candidate, name, indent, unit_);
      ++sensors_added;
      continue;
    }
    const Pose world_from_model = candidate.world_from_body * model_from_camera.Inverse();
    added += EntityText(*source, name, world_from_model, indent);
    sensors_added += sensor_count;
  }

  // Edits: cuts (a range inside another is dropped), the additions, numberOfSamplingSensors.
  std::vector<Cut> cuts;
  cuts.reserve(cut_top.size() + cut_nested.size());
  std::sort(cut_top.begin(), cut_top.end(),
            [](const XmlElement* a, const XmlElement* b) { return a->begin < b->begin; });
  cut_top.erase(std::unique(cut_top.begin(), cut_top.end()), cut_top.end());
  for (const XmlElement* e : cut_top) cuts.push_back(CutRange(text_, *e));
  for (const XmlElement* e : cut_nested) {
    const bool inside = std::any_of(cut_top.begin(), cut_top.end(), [&](const XmlElement* t) {
      return t->begin <= e->begin && e->end <= t->end;
    });
    if (!inside) cuts.push_back(CutRange(text_, *e));
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<Edit> edits;
  edits.reserve(cuts.size() + 2);
  for (const Cut& cut : cuts) edits.push_back(Edit{cut.begin, cut.end, ""});

  std::string header = fmt::format("{}<!-- vantage: the {} chosen sensor{} -->\n", indent,
                                   chosen.size(), chosen.size() == 1 ? "" : "s");
  if (gz_cameras_ && !HasSensorsSystem(*world_)) {
    header += fmt::format("{}<plugin filename=\"gz-sim-sensors-system\" "
                          "name=\"gz::sim::systems::Sensors\">\n{}{}<render_engine>ogre2"
                          "</render_engine>\n{}</plugin>\n",
                          indent, indent, unit_, indent);
  }
  if (!cut_top.empty()) {
    // Where the first removed element was, after the blank line that its cut may have taken.
    const Cut first = CutRange(text_, *cut_top.front());
    edits.push_back(
        Edit{first.begin, first.begin, (first.ate_blank_line ? "\n" : "") + header + added});
  } else {
    const size_t closing = ClosingTagBegin(text_, *world_);
    const size_t at = LineStartIfBlank(text_, closing);
    edits.push_back(Edit{at, at, (at == closing ? "\n" : "") + header + added});
  }

  // numberOfSamplingSensors: a plugin's check of the sensor count, now that of the new world.
  std::vector<const XmlElement*> stack = {world_};
  while (!stack.empty()) {
    const XmlElement* e = stack.back();
    stack.pop_back();
    const bool is_removed = std::any_of(cuts.begin(), cuts.end(), [&](const auto& cut) {
      return cut.begin <= e->begin && e->end <= cut.end;
    });
    if (is_removed) continue;
    for (const XmlElement& child : e->children) {
      if (e->name == "plugin" && child.name == "numberOfSamplingSensors") {
        edits.push_back(Edit{child.content_begin, ClosingTagBegin(text_, child),
                             std::to_string(sensors_added + sensors_kept)});
      } else {
        stack.push_back(&child);
      }
    }
  }

  // Apply from the back; an insertion sorts after a cut that ends where it begins.
  std::stable_sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) {
    return a.begin != b.begin ? a.begin > b.begin : a.end > b.end;
  });
  std::string out = text_;
  for (const Edit& edit : edits) out.replace(edit.begin, edit.end - edit.begin, edit.text);
  return out;
}

}  // namespace

std::string ConstellationWorld(const std::string& world_path,
                               const std::vector<Candidate>& chosen,
                               const std::vector<Population>& populations,
                               const std::vector<ExplicitSensor>& sensors,
                               std::vector<std::string>* notes) {
  return Exporter(world_path, populations, sensors, notes).Run(chosen);
}

std::string ConstellationSdf(const std::string& world_path,
                             const std::vector<Candidate>& chosen,
                             const std::vector<Population>& populations,
                             const std::vector<ExplicitSensor>& sensors,
                             std::vector<std::string>* notes) {
  return Exporter(world_path, populations, sensors, notes, /*gz_cameras=*/true).Run(chosen);
}

std::string ConstellationModelName(const std::string& name, std::set<std::string>* taken) {
  std::string base = ModelName(name);
  // sdformat reserves "world" and every "__...__" name (and "::" never reaches here).
  const bool reserved = base.empty() || base == "world" ||
                        (base.size() >= 4 && base.rfind("__", 0) == 0 &&
                         base.compare(base.size() - 2, 2, "__") == 0);
  if (reserved) base = "vantage_" + base;
  std::string unique = base;
  for (int k = 2; !taken->insert(unique).second; ++k) unique = fmt::format("{}_{}", base, k);
  return unique;
}

namespace {

/// `text` as one word for a POSIX shell: as it is when it holds only safe characters, else in
/// single quotes (a quote inside as '\'').
std::string ShellWord(const std::string& text) {
  const bool safe = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_-./:=,+@%", c) != nullptr;
  });
  if (safe) return text;
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// `vantage evaluate FILE --cell-size F --target T ...` with every option of `scoring` that is
/// set, in the CLI's units (max_depth_noise in mm).
std::string RescoreCommand(const std::string& file, const std::vector<std::string>& targets,
                           const ScoringOptions& scoring) {
  std::string command = fmt::format("vantage evaluate {} --cell-size {}", ShellWord(file),
                                    Number(scoring.cell_size));
  for (const std::string& target : targets) command += " --target " + ShellWord(target);
  if (scoring.quality.max_incidence_deg)
    command += " --max-incidence " + Number(*scoring.quality.max_incidence_deg);
  if (scoring.quality.max_depth_noise)
    command += " --max-depth-noise " + Number(*scoring.quality.max_depth_noise * 1000.0);
  if (scoring.min_points) command += fmt::format(" --min-points {}", *scoring.min_points);
  if (scoring.min_density) command += " --min-density " + Number(*scoring.min_density);
  return command;
}

/// One SDF `<geometry>` of a shape (SDF's box, cylinder, sphere and plane are centred at their
/// origin, the cylinder along z, the plane facing +z: as MakeBox and the others build them).
std::string GeometryText(const ShapeSource& shape) {
  const Vec3& s = shape.size;
  switch (shape.kind) {
    case ShapeSource::Kind::kBox:
      return fmt::format("<box><size>{} {} {}</size></box>", Number(s.x()), Number(s.y()),
                         Number(s.z()));
    case ShapeSource::Kind::kCylinder:
      return fmt::format("<cylinder><radius>{}</radius><length>{}</length></cylinder>",
                         Number(s.x()), Number(s.y()));
    case ShapeSource::Kind::kSphere:
      return fmt::format("<sphere><radius>{}</radius></sphere>", Number(s.x()));
    case ShapeSource::Kind::kPlane:
      return fmt::format("<plane><normal>0 0 1</normal><size>{} {}</size></plane>",
                         Number(s.x()), Number(s.y()));
    case ShapeSource::Kind::kMesh:
      return fmt::format("<mesh><uri>{}</uri><scale>{} {} {}</scale></mesh>",
                         detail::MarkupEscape(shape.mesh_path), Number(shape.scale.x()),
                         Number(shape.scale.y()), Number(shape.scale.z()));
  }
  return {};
}

}  // namespace

std::string SceneConstellationSdf(const Scene& scene, const std::vector<Candidate>& chosen,
                                  const ScoringOptions& scoring,
                                  std::vector<std::string>* notes) {
  // The models' names first: the command names the targets by them.
  std::set<std::string> models;
  std::vector<std::string> object_names;
  std::vector<std::string> targets;
  for (const SceneObject& object : scene.objects) {
    object_names.push_back(object.shapes.empty() ? ""
                                                 : ConstellationModelName(object.name, &models));
    if (object.is_target() && !object.shapes.empty()) targets.push_back(object_names.back());
  }
  std::vector<std::string> camera_names;
  for (const Candidate& candidate : chosen)
    camera_names.push_back(ConstellationModelName(candidate.name, &models));
  // (An XML comment may not hold "--": the command is an element's text, which may.)
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<!-- vantage constellation: the scene's objects and the chosen cameras, for gz-sim.\n"
      "     Score it again, in this folder, with the command in <vantage:rescore> below: the\n"
      "     run's cell size, targets and options that shaped its coverage (docs/outputs.md). -->\n"
      "<sdf version=\"1.9\" xmlns:vantage=\"https://vantage.invalid/sdf\">\n"
      "  <world name=\"constellation\">\n";
  if (scoring.cell_size > 0) {
    out += fmt::format("    <vantage:rescore>{}</vantage:rescore>\n",
                       detail::MarkupEscape(RescoreCommand("constellation.sdf", targets, scoring)));
  }
  // A world that names any system loads no default ones: these are gz-sim's usual four.
  for (const auto& [file, name] :
       {std::pair{"physics", "Physics"}, {"user-commands", "UserCommands"},
        {"scene-broadcaster", "SceneBroadcaster"}, {"sensors", "Sensors"}}) {
    out += fmt::format("    <plugin filename=\"gz-sim-{}-system\" name=\"gz::sim::systems::{}\">",
                       file, name);
    out += std::string_view(name) == "Sensors"
               ? "\n      <render_engine>ogre2</render_engine>\n    </plugin>\n"
               : "</plugin>\n";
  }
  std::vector<std::string> left_out;
  for (size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& object = scene.objects[o];
    if (object.shapes.empty()) {
      left_out.push_back(object.name);
      continue;
    }
    const std::string& name = object_names[o];
    out += fmt::format("    <model name=\"{}\">\n      <static>true</static>\n"
                       "      <link name=\"link\">\n",
                       detail::MarkupEscape(name));
    for (size_t k = 0; k < object.shapes.size(); ++k) {
      const ShapeSource& shape = object.shapes[k];
      for (const char* element : {"visual", "collision"}) {
        out += fmt::format("        <{0} name=\"{0}_{1}\"><pose>{2}</pose><geometry>{3}"
                           "</geometry></{0}>\n",
                           element, k, PoseText(shape.world_from_shape), GeometryText(shape));
      }
    }
    out += "      </link>\n    </model>\n";
  }
  for (size_t k = 0; k < chosen.size(); ++k)
    out += GzCameraText(chosen[k], camera_names[k], "    ", "  ");
  out += "  </world>\n</sdf>\n";
  if (notes && !left_out.empty())
    notes->push_back(fmt::format("constellation.sdf: {} object{} left out ({}): robot links and "
                                 "objects a state reshaped are known only as triangles",
                                 left_out.size(), left_out.size() == 1 ? " is" : "s are",
                                 detail::JoinQuoted(left_out)));
  return out;
}

bool IsGazeboWorldPath(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".world" || extension == ".sdf";
}

}  // namespace vantage
