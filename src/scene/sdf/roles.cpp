// Which visuals are targets, and the scene objects they form. A visual's colour comes from its Ogre
// material script, then its inline <material> (Gazebo applies those after the script); the
// plugin segmented by colour, so a visual is a target when its colour rounds to
// sensorDataSegmentationColorRGB, unless --target names the target models. sceneModelPath is only
// cross-checked (GAZEBO.md, "Targets").
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"

namespace vantage::detail::gazebo {
namespace {

namespace fs = std::filesystem;

/// True when `name` selects `model`: the same scoped name or an ancestor of it ("a" selects
/// "a::b").
bool NameSelects(const std::string& name, const std::string& model) {
  return model == name || (model.size() > name.size() + 2 && model.rfind(name + "::", 0) == 0);
}

}  // namespace

MaterialColours Loader::ColoursOf(const VisualRecord& visual) {
  MaterialColours colours;
  const XmlElement* material = visual.element ? visual.element->Child("material") : nullptr;
  if (!material) return colours;
  const Doc& doc = *visual.doc;
  if (const XmlElement* script = material->Child("script")) {
    const XmlElement* name_element = script->Child("name");
    const std::string name = name_element ? name_element->Trimmed() : "";
    std::vector<std::string> uris;
    bool is_script_missing = false;  // then the script, not the name, is the cause
    for (const XmlElement* uri : script->Children("uri")) {
      const std::string text = uri->Trimmed();
      if (text.empty() || text == "__default__") continue;
      uris.push_back(text);
      std::vector<std::string> searched;
      const std::optional<std::string> location = ResolveResourceUri(text, doc, &searched);
      if (!location) {
        for (std::string& folder : searched) folder = folder.empty() ? "." : folder;
        MissingMaterial(AtPlace(
            doc.xml.path, uri->line,
            fmt::format("material script '{}' (<script><uri>) of visual '{}' of model '{}' not "
                        "found (looked in {}) — add the folder that holds it with "
                        "--resource-path or GAZEBO_RESOURCE_PATH",
                        text, visual.name, visual.model,
                        searched.empty() ? "no folder" : Join(searched, ", "))));
        is_script_missing = true;
        continue;
      }
      std::vector<std::string> files;
      if (IsDirectory(*location)) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(*location, ec)) {
          if (entry.path().extension() == ".material") files.push_back(entry.path().string());
        }
        std::sort(files.begin(), files.end());
      } else {
        files.push_back(*location);
      }
      for (const std::string& file : files) {
        if (!material_files_.insert(file).second) continue;
        const size_t known = materials_.problems.size();
        if (!materials_.LoadFile(file)) {
          Note(fmt::format("{}: cannot read the material script", file));
        }
        for (size_t i = known; i < materials_.problems.size(); ++i) Note(materials_.problems[i]);
      }
    }
    if (!name.empty()) {
      if (const MaterialColours* found = materials_.Find(name)) {
        colours = *found;
      } else if (!is_script_missing) {
        MissingMaterial(AtPlace(
            doc.xml.path, name_element->line,
            fmt::format("material '{}' (<script><name>) of visual '{}' of model '{}' is not "
                        "defined in {}: the visual has no colour (never a target)",
                        name, visual.name, visual.model,
                        uris.empty() ? "any loaded material script" : Join(uris, ", "))));
      }
    }
  }
  // Gazebo applies inline colours after the script.
  MaterialColours inline_colours;
  const auto read = [&](const char* key, std::optional<Rgb>* slot) {
    const XmlElement* e = material->Child(key);
    if (!e) return;
    const size_t count = SplitWords(e->text).size();
    const auto values = Numbers(doc, *e, count == 3 ? 3 : 4, "0 1 0 1");
    if (values) *slot = Rgb{(*values)[0], (*values)[1], (*values)[2]};
  };
  read("ambient", &inline_colours.ambient);
  read("diffuse", &inline_colours.diffuse);
  read("emissive", &inline_colours.emissive);
  colours.Override(inline_colours);
  return colours;
}

void Loader::BuildScene(std::vector<GazeboVisual>* visuals_out) {
  // Roles. --target overrides everything; else the plugin's colour segmentation decides and
  // sceneModelPath's names are cross-checked (a note for each disagreement).
  std::vector<bool> is_target(visuals_.size(), false);
  const std::string colour_text = fmt::format("{} {} {}", segmentation_colour_[0],
                                              segmentation_colour_[1], segmentation_colour_[2]);
  if (!options_.targets.empty()) {
    for (const std::string& name : options_.targets) {
      const bool exists = std::any_of(models_.begin(), models_.end(),
                                      [&](const auto& m) { return NameSelects(name, m.first); });
      const bool visible = std::any_of(visuals_.begin(), visuals_.end(),
                                       [&](const auto& v) { return NameSelects(name, v.model); });
      std::vector<std::string> names;
      for (const auto& m : models_) names.push_back(m.first);
      if (!exists) {
        Error(path_, 0,
              fmt::format("{} '{}' names no model of the world — models: {}",
                          options_.targets_origin, name,
                          Join(names, ", ")));
      } else if (!visible) {
        Error(path_, 0,
              fmt::format("{} '{}' has no visible geometry (a sensor model, or a model "
                          "without <visual>) — name a model with visuals",
                          options_.targets_origin, name));
      }
    }
    for (size_t i = 0; i < visuals_.size(); ++i) {
      for (const std::string& name : options_.targets)
        if (NameSelects(name, visuals_[i].model)) is_target[i] = true;
    }
  } else {
    for (size_t i = 0; i < visuals_.size(); ++i) {
      const std::optional<Rgb> colour = ColoursOf(visuals_[i]).SegmentationColour();
      is_target[i] = colour && ToRgb255(*colour) == segmentation_colour_;
    }
  }

  // Geometry, grouped into one object per (model, role), in declaration order.
  struct Group {
    std::string model;
    Role role;
    TriangleMesh mesh;
    std::string file;  // the first visual's place
    int line = 0;
  };
  std::vector<Group> groups;
  std::map<std::pair<std::string, Role>, size_t> group_index;
  for (size_t i = 0; i < visuals_.size(); ++i) {
    const VisualRecord& visual = visuals_[i];
    std::optional<TriangleMesh> mesh = GeometryOf(visual, is_target[i]);
    if (visuals_out) {
      visuals_out->push_back(GazeboVisual{
          visual.model, visual.link, visual.name, visual.world_from_visual, is_target[i],
          visual.doc->xml.path, visual.element ? visual.element->line : visual.site.line});
    }
    if (!mesh || mesh->IsEmpty()) continue;
    mesh->Transform(visual.world_from_visual);
    const Role role = is_target[i] ? Role::kTarget : Role::kOccluder;
    const auto key = std::make_pair(visual.model, role);
    auto it = group_index.find(key);
    if (it == group_index.end()) {
      it = group_index.emplace(key, groups.size()).first;
      groups.push_back(Group{visual.model, role, TriangleMesh{}, visual.doc->xml.path,
                             visual.element ? visual.element->line : visual.site.line});
    }
    groups[it->second].mesh.Append(*mesh);
  }
  for (Group& group : groups) {
    // A model with both roles: the target part keeps the model's name.
    const bool is_split = group_index.contains(std::make_pair(group.model, Role::kTarget)) &&
                          group_index.contains(std::make_pair(group.model, Role::kOccluder));
    SceneObject object;
    object.name =
        is_split && group.role == Role::kOccluder ? group.model + "/occluder" : group.model;
    object.role = group.role;
    object.mesh = std::move(group.mesh);
    object.file = std::move(group.file);
    object.line = group.line;
    problem_.scene.objects.push_back(std::move(object));
  }

  if (!options_.targets.empty()) return;
  std::set<std::string> target_models;
  for (size_t i = 0; i < visuals_.size(); ++i)
    if (is_target[i]) target_models.insert(visuals_[i].model);
  if (target_models.empty() && !diag_.HasErrors()) {
    std::string listed;
    if (scene_model_names_ && !scene_model_names_->empty())
      listed = fmt::format(" (sceneModelPath lists {})", Join(*scene_model_names_, ", "));
    Error(segmentation_site_.file.empty() ? path_ : segmentation_site_.file,
          segmentation_site_.line,
          fmt::format("{} {} matches no visual's material colour (emissive where set, else "
                      "diffuse){} — colour the targets so, or pass --target NAME",
                      is_segmentation_given_ ? "<sensorDataSegmentationColorRGB>"
                                             : "the plugin's default segmentation colour",
                      colour_text, listed));
    // The likely cause: a visual whose material script or material was not found, or a script
    // whose colour was skipped (those were notes, never shown once the load failed).
    for (const std::string& missing : missing_materials_) AddError(missing);
    for (const std::string& problem : materials_.problems) AddError(problem);
    return;
  }
  if (!scene_model_names_) return;
  const std::string place = AtPlace(scene_model_site_.file, scene_model_site_.line, "");
  for (const std::string& name : *scene_model_names_) {
    const bool exists = std::any_of(models_.begin(), models_.end(),
                                    [&](const auto& m) { return NameSelects(name, m.first); });
    const bool coloured = std::any_of(target_models.begin(), target_models.end(),
                                      [&](const std::string& m) { return NameSelects(name, m); });
    if (!exists) {
      Note(fmt::format("{}sceneModelPath lists '{}', which is no model of the world", place, name));
    } else if (!coloured) {
      Note(
          fmt::format("{}sceneModelPath lists '{}', which has no visual of colour {}: it is "
                      "not a target (the plugin segments by colour)",
                      place, name, colour_text));
    }
  }
  for (const std::string& model : target_models) {
    const bool listed = std::any_of(scene_model_names_->begin(), scene_model_names_->end(),
                                    [&](const std::string& n) { return NameSelects(n, model); });
    if (!listed) {
      Note(
          fmt::format("{}model '{}' has colour {} but sceneModelPath does not list it: it is a "
                      "target (the plugin segments by colour)",
                      place, model, colour_text));
    }
  }
}

}  // namespace vantage::detail::gazebo
