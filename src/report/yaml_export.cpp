#include "vantage/yaml_export.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <filesystem>
#include <span>

#include "vantage/error.hpp"

namespace vantage {
namespace {

YAML::Node Seq(std::span<const double> values) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (double v : values) node.push_back(v);
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

}  // namespace

std::string ConstellationYaml(const std::string& scene_path, const std::vector<Candidate>& chosen) {
  YAML::Node scene;
  try {
    scene = YAML::LoadFile(scene_path);
  } catch (const YAML::Exception& e) {
    throw InputError(AtPlace(scene_path, e.mark.line + 1, e.msg));
  }
  // Relative mesh and URDF paths were relative to the scene's folder; the export lives elsewhere.
  const std::filesystem::path folder = std::filesystem::absolute(scene_path).parent_path();
  if (scene["objects"] && scene["objects"].IsSequence()) {
    for (YAML::Node object : scene["objects"]) {
      if (!object.IsMap() || !object["mesh"] || !object["mesh"].IsMap() || !object["mesh"]["file"]) continue;
      const std::filesystem::path file = object["mesh"]["file"].as<std::string>();
      if (file.is_relative()) object["mesh"]["file"] = (folder / file).lexically_normal().string();
    }
  }
  if (scene["robots"] && scene["robots"].IsSequence()) {
    for (YAML::Node robot : scene["robots"]) {
      if (!robot.IsMap() || !robot["urdf"] || !robot["urdf"].IsScalar()) continue;
      const std::filesystem::path file = robot["urdf"].as<std::string>();
      if (file.is_relative()) robot["urdf"] = (folder / file).lexically_normal().string();
    }
  }
  scene.remove("populations");
  YAML::Node sensors(YAML::NodeType::Sequence);
  for (const Candidate& c : chosen) {
    YAML::Node sensor;
    sensor["name"] = c.name;
    sensor["type"] = c.sensor.id;
    const Vec3& p = c.world_from_body.position;
    sensor["position"] = Seq(std::array{p.x(), p.y(), p.z()});
    sensor["orientation"]["quaternion"] = Seq(WxyzOf(c.world_from_body.rotation));
    sensors.push_back(sensor);
  }
  scene["sensors"] = sensors;
  if (scene["settings"] && scene["settings"].IsMap()) {
    scene["settings"]["n"] = static_cast<int>(chosen.size());
    scene["settings"].remove("expected_candidates");
  }
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("vantage constellation: the chosen sensors of " + scene_path) << YAML::Newline
      << scene;
  return std::string(out.c_str()) + "\n";
}

}  // namespace vantage
