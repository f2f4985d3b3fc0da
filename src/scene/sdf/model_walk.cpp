// The walk over world -> include/model -> link -> visual/sensor as Gazebo classic saw it: the
// include's <pose> replaces the model's own, world_from_visual = model · link · visual, nested
// models are named "outer::inner", and a model holding a depth sensor (with what it nests) adds no
// geometry. The walk only records visuals, sensors and model names; the scene is built from them
// afterwards (roles.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"

namespace vantage::detail::gazebo {

bool Loader::IsCameraSensorType(const std::string& type) const {
  // Gazebo classic calls it "depth"; newer SDF spells "depth_camera" and "rgbd_camera" ("rgbd" is
  // sdformat's alias). The Classic plugin used depth sensors only, so a plain "camera" (an RGB
  // camera on a robot, say) counts only in a world without it.
  return type == "depth" || type == "depth_camera" || type == "rgbd_camera" || type == "rgbd" ||
         (type == "camera" && !has_classic_plugin_);
}

void Loader::VisitModel(const Doc& doc, const XmlElement& model, const ModelContext& context) {
  open_models_.emplace_back(&model, fmt::format("'{}' ({})", context.scoped, doc.xml.path));
  struct Close {
    std::vector<std::pair<const XmlElement*, std::string>>& open;
    ~Close() { open.pop_back(); }
  } close{open_models_};
  if (context.sink.models) context.sink.models->emplace_back(context.scoped, context.hidden);
  const std::string* own_name = model.Attribute("name");
  const std::string type_name = own_name ? Trim(*own_name) : context.scoped;

  // The model's named frames, for relative_to. Includes are resolved here, once.
  std::map<std::string, FrameEntry> entries;
  std::map<const XmlElement*, IncludeResult> includes;
  const auto add_entry = [&](const std::string& name, const XmlElement& element, FrameEntry entry) {
    if (name.empty()) {
      Error(doc, element.line,
            fmt::format("<{}> in model '{}' has no name — add name=\"...\"", element.name,
                        context.scoped));
      return;
    }
    if (!entries.emplace(name, entry).second) {
      Error(doc, element.line,
            fmt::format("model '{}' has two children named '{}' — names must be unique",
                        context.scoped, name));
    }
  };
  bool has_depth_sensor = false;
  for (const XmlElement& child : model.children) {
    const std::string* name_attribute = child.Attribute("name");
    const std::string name = name_attribute ? Trim(*name_attribute) : "";
    if (child.name == "link" || child.name == "model") {
      add_entry(name, child,
                FrameEntry{&doc, child.Child("pose"), true, "", child.line,
                           child.name == "model" && child.Attribute("placement_frame")});
      if (child.name == "link") {
        for (const XmlElement* sensor : child.Children("sensor")) {
          const std::string* type = sensor->Attribute("type");
          if (type && IsCameraSensorType(*type)) has_depth_sensor = true;
        }
      }
    } else if (child.name == "frame") {
      const std::string* attached_to = child.Attribute("attached_to");
      add_entry(name, child,
                FrameEntry{&doc, child.Child("pose"), true, attached_to ? Trim(*attached_to) : "",
                           child.line});
    } else if (child.name == "include") {
      IncludeResult result = ResolveInclude(doc, child);
      RefuseCycle(doc, child, &result);
      if (result.kind == IncludeResult::Kind::kModel && child.Child("pose") == nullptr) {
        // No include pose: the model's own <pose>, relative to the parent model.
        add_entry(result.name, child,
                  FrameEntry{result.doc, result.model->Child("pose"), false, "", child.line});
      } else if (result.kind != IncludeResult::Kind::kSkipped &&
                 result.kind != IncludeResult::Kind::kFailed) {
        add_entry(result.name, child,
                  FrameEntry{&doc, child.Child("pose"), true, "", child.line,
                             child.Child("placement_frame") != nullptr});
      }
      includes[&child] = std::move(result);
    }
  }
  // GAZEBO.md: sensor models' bodies never occlude; the model holding a depth sensor (and what
  // it nests) contributes no geometry.
  const bool hidden = context.hidden || has_depth_sensor;

  std::map<std::string, Pose> resolved;
  std::set<std::string> visiting;
  const auto in_model = [&](const std::string& name, int line) {
    return FrameInModel(name, entries, resolved, visiting, context.scoped, doc, line);
  };
  // SDF 1.8 placement_frame: the pose given is that of frame F of the model, so the model frame
  // goes to world_from_F · model_from_F⁻¹ (libsdformat's rule; tested against it).
  Pose world_from_model = context.world_from_model;
  const std::string& placement = context.placement_frame;
  if (!placement.empty() && placement != "__model__" && !entries.contains(placement)) {
    Error(*context.placement_doc, context.placement_line,
          fmt::format("placement_frame '{}' names no link, model or frame of model '{}' — name "
                      "one of its own frames",
                      placement, context.scoped));
  } else if (!placement.empty()) {
    world_from_model =
        world_from_model *
        FrameInModel(placement, entries, resolved, visiting, context.scoped,
                     *context.placement_doc, context.placement_line)
            .Inverse();
  }
  // Pose of a link's child (visual, sensor) in the link: relative_to defaults to the link.
  const auto link_from_child = [&](const std::string& link, const XmlElement* pose) {
    const std::string relative_to = RelativeTo(doc, pose);
    Pose value = PoseValue(doc, pose);
    if (relative_to.empty() || relative_to == link) return value;
    return in_model(link, pose->line).Inverse() * in_model(relative_to, pose->line) * value;
  };

  for (const XmlElement& child : model.children) {
    const std::string* name_attribute = child.Attribute("name");
    const std::string name = name_attribute ? Trim(*name_attribute) : "";
    if (child.name == "link" && !name.empty()) {
      const Pose model_from_link = in_model(name, child.line);
      if (!hidden && context.sink.visuals) {
        for (const XmlElement* visual : child.Children("visual")) {
          const std::string* visual_name = visual->Attribute("name");
          VisualRecord record;
          record.model = context.scoped;
          record.link = name;
          record.name = visual_name ? *visual_name : "";
          record.world_from_visual = world_from_model * model_from_link *
                                     link_from_child(name, visual->Child("pose"));
          record.doc = &doc;
          record.element = visual;
          record.site = context.site;
          context.sink.visuals->push_back(std::move(record));
        }
      }
      if (context.sink.sensors) {
        for (const XmlElement* sensor : child.Children("sensor")) {
          const std::string* type = sensor->Attribute("type");
          if (!type || !IsCameraSensorType(*type)) continue;
          const std::string* sensor_name = sensor->Attribute("name");
          SensorRecord record;
          record.model = context.scoped;
          record.type_name = type_name;
          record.sensor_name = sensor_name ? *sensor_name : "";
          record.world_from_model = world_from_model;
          record.model_from_camera = model_from_link * link_from_child(name, sensor->Child("pose"));
          record.doc = &doc;
          record.element = sensor;
          record.site = context.site;
          context.sink.sensors->push_back(std::move(record));
        }
      }
    } else if (child.name == "model" && !name.empty()) {
      ModelContext nested = context;
      nested.scoped = context.scoped + "::" + name;
      nested.world_from_model = world_from_model * in_model(name, child.line);
      SetPlacementFrame(doc, nullptr, doc, child, &nested);
      nested.hidden = hidden;
      VisitModel(doc, child, nested);
    } else if (child.name == "include") {
      const IncludeResult& result = includes[&child];
      if (result.kind == IncludeResult::Kind::kSkipped ||
          result.kind == IncludeResult::Kind::kFailed || result.name.empty()) {
        continue;
      }
      ModelContext nested = context;
      nested.scoped = context.scoped + "::" + result.name;
      nested.world_from_model = world_from_model * in_model(result.name, child.line);
      nested.placement_frame.clear();
      if (result.kind == IncludeResult::Kind::kModel)
        SetPlacementFrame(doc, &child, *result.doc, *result.model, &nested);
      nested.hidden = hidden;
      if (result.kind == IncludeResult::Kind::kGroundPlane) {
        if (nested.sink.models) nested.sink.models->emplace_back(nested.scoped, hidden);
        if (!hidden && nested.sink.visuals) {
          nested.sink.visuals->push_back(VisualRecord{nested.scoped, "", "ground_plane",
                                                      nested.world_from_model, &doc, nullptr,
                                                      context.site});
        }
      } else {
        VisitModel(*result.doc, *result.model, nested);
      }
    }
  }
}

void Loader::RefuseCycle(const Doc& doc, const XmlElement& include, IncludeResult* result) {
  if (result->kind != IncludeResult::Kind::kModel) return;
  const auto open = std::find_if(open_models_.begin(), open_models_.end(),
                                 [&](const auto& entry) { return entry.first == result->model; });
  if (open == open_models_.end()) return;
  // Walking it again would recurse without end (a stack overflow before this check).
  std::vector<std::string> cycle;
  for (auto it = open; it != open_models_.end(); ++it) cycle.push_back(it->second);
  cycle.push_back(open->second);
  Error(doc, include.line,
        fmt::format("<include> of '{}' closes an include cycle: {} — remove one of these "
                    "includes",
                    result->name,
                    cycle.size() == 2 ? cycle.front() + " includes itself"
                                      : Join(cycle, " includes ")));
  result->kind = IncludeResult::Kind::kFailed;
}

void Loader::VisitWorldEntity(const Doc& doc, const XmlElement& e) {
  ModelContext context;
  context.sink = Sink{&visuals_, &sensors_, &models_};
  context.site = Site{doc.xml.path, e.line};
  const XmlElement* model = &e;
  const Doc* model_doc = &doc;
  if (e.name == "include") {
    const IncludeResult result = ResolveInclude(doc, e);
    if (result.kind == IncludeResult::Kind::kSkipped || result.kind == IncludeResult::Kind::kFailed)
      return;
    context.scoped = result.name;
    if (result.kind == IncludeResult::Kind::kModel) {
      model = result.model;
      model_doc = result.doc;
      // GAZEBO.md: the include's <pose> replaces the model file's own.
      const XmlElement* include_pose = e.Child("pose");
      context.world_from_model = include_pose ? WorldPose(doc, include_pose)
                                              : WorldPose(*result.doc, result.model->Child("pose"));
      SetPlacementFrame(doc, &e, *result.doc, *result.model, &context);
    } else {
      context.world_from_model = WorldPose(doc, e.Child("pose"));
    }
  } else {
    const std::string* name = e.Attribute("name");
    context.scoped = name ? Trim(*name) : "";
    if (context.scoped.empty()) {
      Error(doc, e.line, "<model> has no name attribute — add name=\"...\"");
      return;
    }
    context.world_from_model = WorldPose(doc, e.Child("pose"));
    SetPlacementFrame(doc, nullptr, doc, e, &context);
  }
  if (!top_names_.insert(context.scoped).second) {
    Error(doc, e.line,
          fmt::format("a second model named '{}' — give each model a unique name (<include> "
                      "takes <name>)",
                      context.scoped));
    return;
  }
  if (model == &e && e.name == "include") {  // ground plane stand-in
    models_.emplace_back(context.scoped, false);
    visuals_.push_back(VisualRecord{context.scoped, "", "ground_plane", context.world_from_model,
                                    &doc, nullptr, context.site});
    return;
  }
  VisitModel(*model_doc, *model, context);
}

}  // namespace vantage::detail::gazebo
