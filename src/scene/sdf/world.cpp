// Gazebo SDF worlds, read the way the original Gazebo plugin saw them (GAZEBO.md).
//
// Parsing: vantage's own XML reader (util/xml.hpp explains why not sdformat's element tree),
// then a walk over world → include/model → link → visual/sensor that reproduces Gazebo classic:
// includes resolved against the model path, the include's <pose> replacing the model's own,
// world_from_visual = model · link · visual, nested models named "outer::inner", sensor bodies
// hidden, Ogre material colours for the plugin's colour segmentation, <population> elements as
// Population structs (their positions are drawn later by PopulationPositions).
//
// Frames: `<pose relative_to="X">` is honoured when X names the parent (or "__model__"/"world")
// or a link, nested model, include or <frame> of the same model, and at world level a world
// <frame>, <model> or named <include> (values.cpp, WorldFrame); anything else (scoped names
// "a::b", a frame placed relative to a model that a placement_frame places) is an error. SDF
// 1.8's placement_frame (an include's element, a model's attribute) places the model so that
// that frame lands at the pose given (model_walk.cpp). The SDF 1.5/1.6 `frame` attribute is
// ignored, as Gazebo classic ignored it. `<state>` and merge-includes are not applied (a note
// says so).
//
// Targets: a visual is a target when its colour rounds (round(255·v)) to the plugin's
// sensorDataSegmentationColorRGB. Its colour is the emissive one where the Ogre script or the
// inline <material> sets it (even 0 0 0), else the diffuse one; inline colours replace the
// script's channel by channel (Gazebo applies them after the script); ambient never counts; a
// visual with neither, or with a material that cannot be found (a note), is never a target.
// Objects: one SceneObject per model instance (scoped name) and role; a model with visuals of
// both roles gives "NAME" (target part) and "NAME/occluder". sceneModelPath's names are only
// cross-checked (each disagreement is a note: the plugin segmented by colour); no target at all
// is an error at <sensorDataSegmentationColorRGB>. --target NAME (LoadOptions::targets) makes
// exactly those models, with everything they nest, targets; an unknown name is an error.
// Sensor models: a model with a camera <sensor> (depth, depth_camera, rgbd, rgbd_camera; camera
// too in a world without the Classic plugin) in one of its links (and what it nests) adds no
// geometry; outside populations it becomes an ExplicitSensor named after the instance, with
// <lens><intrinsics> and <depth_camera><clip> read (populations.cpp). With the Classic plugin it is
// re-aimed at the observation point, as the plugin did; without it, it keeps its own orientation
// (a gz-sim world's cameras are a real layout: docs/from-your-stack.md). Fuel URIs come from the
// local Fuel cache (resolution.cpp).
//
// Files (scene/sdf/): loader.hpp declares the reader; values.cpp, resolution.cpp, frames.cpp,
// model_walk.cpp, plugin.cpp, populations.cpp, roles.cpp, geometry.cpp and materials.cpp hold its
// parts; this file runs them in order.
#include "scene/sdf/world.hpp"

#include <fmt/format.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/sdf/loader.hpp"

namespace vantage {
namespace detail::gazebo {

Problem Loader::Load(std::vector<GazeboVisual>* visuals_out) {
  problem_.source = path_;
  world_doc_ = LoadSdf(path_, "");
  ThrowIfErrors();  // nothing else can be read without the world file
  VANTAGE_CHECK(world_doc_ != nullptr);
  const std::vector<const XmlElement*> worlds = world_doc_->xml.root.Children("world");
  if (worlds.size() != 1) {
    Error(*world_doc_, world_doc_->xml.root.line,
          worlds.empty() ? "no <world> element — vantage reads world files (a model file goes in "
                           "a world with <include>)"
                         : "more than one <world> — keep one per file");
    ThrowIfErrors();
  }
  world_ = worlds[0];
  ReadPlugin();
  // --cell-size replaces voxelGridFilterLeafSize before BuildScene tessellates the primitives.
  if (options_.cell_size) problem_.cell_size = *options_.cell_size;
  for (const XmlElement& child : world_->children) {
    if (child.name == "include" || child.name == "model") {
      VisitWorldEntity(*world_doc_, child);
    } else if (child.name == "population") {
      ReadPopulation(*world_doc_, child);
    } else if (child.name == "vantage:keep_out") {
      ReadKeepOut(*world_doc_, child);
    } else if (child.name == "vantage:min_separation") {
      ReadMinSeparation(*world_doc_, child);
    } else if (child.name == "keep_out" || child.name == "min_separation") {
      Error(*world_doc_, child.line,
            fmt::format("<{0}> needs the vantage: prefix — write <vantage:{0}> (a custom "
                        "element, which libsdformat keeps; docs/constraints.md)",
                        child.name));
    } else if (child.name == "state") {
      Note(AtPlace(path_, child.line, "<state> is not applied: poses come from the models"));
    } else if (child.name == "actor") {
      Note(AtPlace(path_, child.line, "<actor> skipped: vantage reads static scenes"));
    }
  }

  // Explicit sensors: plain models holding a camera. The Classic plugin re-orients them; in a
  // world without it they are a real layout and keep their own orientation.
  std::map<std::string, int> sensors_per_model;
  for (const SensorRecord& r : sensors_) ++sensors_per_model[r.model];
  for (const SensorRecord& r : sensors_) {
    const bool is_many = sensors_per_model[r.model] > 1;
    const std::string type_id = is_many ? r.type_name + "/" + r.sensor_name : r.type_name;
    const std::optional<std::string> id = AddSensorType(r, type_id);
    if (!id) continue;
    ExplicitSensor sensor;
    sensor.name = is_many ? r.model + "/" + r.sensor_name : r.model;
    sensor.sensor_type = *id;
    sensor.pose = r.world_from_model;
    sensor.look_at = has_classic_plugin_;
    sensor.model_from_camera = r.model_from_camera;
    sensor.file = r.site.file;
    sensor.line = r.site.line;
    problem_.sensors.push_back(std::move(sensor));
  }

  BuildScene(visuals_out);
  ThrowIfErrors();
  // Without the original plugin nothing names an observation point: candidates look at the
  // part, as a YAML scene's do, not at the world's origin (a cell 2 m away lost half its
  // coverage, silently). With the plugin, its default 0 0 0 (GAZEBO.md).
  if (!has_classic_plugin_ && problem_.scene.TargetCount() > 0) {
    const Aabb bounds = problem_.scene.TargetBounds();
    problem_.observation_point = 0.5 * (bounds.min + bounds.max);
    const Vec3& p = problem_.observation_point;
    Note(fmt::format(
        "{}: no <observationPoint> (the world has no sensor placement plugin): candidates look "
        "at the centre of the targets' bounds, [{:.4g}, {:.4g}, {:.4g}] m",
        path_, p.x(), p.y(), p.z()));
  }
  return std::move(problem_);
}

}  // namespace detail::gazebo

Problem detail::LoadGazeboWorld(const std::string& path,
                                const LoadOptions& options,
                                std::vector<GazeboVisual>* visuals) {
  options.Validate();
  return gazebo::Loader(path, options).Load(visuals);
}

Problem LoadGazeboWorld(const std::string& path, const LoadOptions& options) {
  return detail::LoadGazeboWorld(path, options, nullptr);
}

}  // namespace vantage
