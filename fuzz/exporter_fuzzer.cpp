// libFuzzer target: the exporters of a run's layout (issue 44) fed hostile sensor and target
// names. The input is lines: up to 12 sensor names, then after an empty line up to 4 target
// names (a name the scene readers refuse, one with a control character, is skipped, as no reader
// lets it through; bytes that are not UTF-8 stay: a .vis file may carry them). The oracle:
// - cameras.urdf.xacro and constellation.sdf parse with expat (a conforming XML parser);
// - static_transforms.yaml parses with yaml-cpp and gives every name back;
// - the links and joints of the xacro, the child frames of the YAML and the launch file, and the
//   models of the SDF are unique, and each body frame decodes (SensorNameOfFrame) to its sensor.
// Anything else (an exception, a sanitizer report) is a bug.
#include <expat.h>
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fuzz_util.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/report.hpp"
#include "vantage/visualize.hpp"

namespace {

using vantage::InternalError;

/// Every element's (name, value of its `name` attribute) of an XML text, in document order;
/// throws when expat finds the text not well-formed.
std::vector<std::pair<std::string, std::string>> ParseXmlNames(const std::string& text,
                                                               const char* what) {
  struct State {
    std::vector<std::pair<std::string, std::string>> elements;
  } state;
  XML_Parser parser = XML_ParserCreate("UTF-8");
  XML_SetUserData(parser, &state);
  XML_SetStartElementHandler(parser, [](void* data, const XML_Char* name, const XML_Char** atts) {
    auto* s = static_cast<State*>(data);
    std::string value;
    for (size_t i = 0; atts[i] != nullptr; i += 2)
      if (std::string(atts[i]) == "name") value = atts[i + 1];
    s->elements.emplace_back(name, value);
  });
  const bool ok = XML_Parse(parser, text.data(), static_cast<int>(text.size()), 1) != XML_STATUS_ERROR;
  const std::string error = ok ? "" : XML_ErrorString(XML_GetErrorCode(parser));
  const auto line = XML_GetCurrentLineNumber(parser);
  XML_ParserFree(parser);
  if (!ok) throw InternalError(std::string(what) + ": not XML at line " + std::to_string(line) +
                               ": " + error);
  return state.elements;
}

/// The first two single-quoted Python literals of a line, decoded (\\, \', \xHH).
std::vector<std::string> PythonLiterals(const std::string& line) {
  std::vector<std::string> out;
  for (size_t i = 0; i < line.size() && out.size() < 3; ++i) {
    if (line[i] != '\'') continue;
    std::string value;
    for (++i; i < line.size() && line[i] != '\''; ++i) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        ++i;
        if (line[i] == 'x' && i + 2 < line.size()) {
          value.push_back(static_cast<char>(std::stoi(line.substr(i + 1, 2), nullptr, 16)));
          i += 2;
        } else {
          value.push_back(line[i]);
        }
      } else {
        value.push_back(line[i]);
      }
    }
    out.push_back(value);
  }
  return out;
}

void Check(bool condition, const std::string& what) {
  if (!condition) throw InternalError("exporter oracle: " + what);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vantage;
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> sensors, targets;
  std::set<std::string> seen;
  bool in_targets = false;
  for (size_t start = 0; start <= input.size();) {
    size_t end = input.find('\n', start);
    if (end == std::string::npos) end = input.size();
    const std::string line = input.substr(start, end - start);
    start = end + 1;
    if (line.empty()) {
      in_targets = true;
      continue;
    }
    if (!detail::NameProblem(line).empty() || !seen.insert(line).second) continue;
    std::vector<std::string>& list = in_targets ? targets : sensors;
    if (list.size() < (in_targets ? 4u : 12u)) list.push_back(line);
  }
  if (sensors.empty()) return 0;

  VisibilityFile file;
  file.reference.cell_size = 0.01;
  file.reference.keys = {1, 2, 3};
  for (size_t i = 0; i < sensors.size(); ++i) {
    Candidate c;
    c.name = sensors[i];
    c.type_id = "tiny";
    c.sensor.id = "tiny";
    c.sensor.width = 64;
    c.sensor.height = 48;
    c.sensor.fx = c.sensor.fy = 50;
    c.sensor.cx = 32;
    c.sensor.cy = 24;
    c.sensor.near = 0.1;
    c.sensor.far = 3;
    c.world_from_body = Pose{Vec3(0.1 * static_cast<double>(i), 0, 1), Quat::Identity()};
    file.candidates.push_back(c);
    file.observations.emplace_back();
  }
  Report report;
  report.data = &file;
  report.is_derived = true;
  Selection selection;
  selection.method = "greedy";
  selection.n = static_cast<int>(sensors.size());
  for (uint32_t i = 0; i < sensors.size(); ++i) selection.chosen.push_back(i);
  report.results = {selection};
  report.primary = 0;

  // cameras.urdf.xacro: XML; links and joints unique; body links decode to the sensors.
  const auto xacro = ParseXmlNames(CamerasXacro(report), "cameras.urdf.xacro");
  std::set<std::string> links, joints;
  std::vector<std::string> body_frames;
  for (const auto& [element, name] : xacro) {
    if (element == "link" && name != "$(arg parent_frame)") {
      Check(links.insert(name).second, "xacro: link '" + name + "' twice");
      if (name.size() < 14 || name.compare(name.size() - 14, 14, "_optical_frame") != 0)
        body_frames.push_back(name);
    }
    if (element == "joint") Check(joints.insert(name).second, "xacro: joint '" + name + "' twice");
  }
  Check(body_frames.size() == sensors.size(), "xacro: one body link per sensor");
  for (size_t i = 0; i < sensors.size(); ++i)
    Check(SensorNameOfFrame(body_frames[i]) == sensors[i], "xacro: frame does not decode");

  // static_transforms.launch.py: node names and child frames unique, the xacro's frames.
  const std::string launch = StaticTransformsLaunch(report);
  std::set<std::string> nodes, launch_frames;
  for (size_t start = 0; start < launch.size();) {
    size_t end = launch.find('\n', start);
    if (end == std::string::npos) end = launch.size();
    const std::string line = launch.substr(start, end - start);
    start = end + 1;
    if (line.rfind("        _static_transform(", 0) != 0) continue;
    const std::vector<std::string> literals = PythonLiterals(line);
    Check(literals.size() >= 2, "launch: a call without its names");
    Check(nodes.insert(literals[0]).second, "launch: node '" + literals[0] + "' twice");
    Check(launch_frames.insert(literals[1]).second, "launch: frame '" + literals[1] + "' twice");
  }
  Check(launch_frames == links, "launch: frames are not the xacro's");

  // static_transforms.yaml: YAML; child frames unique and the xacro's; names given back.
  const YAML::Node yaml = YAML::Load(StaticTransformsYaml(report));
  std::set<std::string> yaml_frames;
  size_t body = 0;
  for (const YAML::Node& entry : yaml["transforms"]) {
    const std::string child = entry["child_frame"].as<std::string>();
    Check(yaml_frames.insert(child).second, "yaml: frame '" + child + "' twice");
    if (entry["type"]) {
      Check(entry["name"].as<std::string>() == detail::AsUtf8(sensors.at(body)),
            "yaml: the name is not the sensor's");
      ++body;
    }
  }
  Check(yaml_frames == links, "yaml: frames are not the xacro's");

  // constellation.sdf: XML; the world's models unique.
  Scene scene;
  for (const std::string& name : targets) {
    SceneObject object;
    object.name = name;
    object.role = Role::kTarget;
    ShapeSource box;
    box.size = Vec3(0.1, 0.1, 0.1);
    object.shapes.push_back(box);
    scene.objects.push_back(object);
  }
  ScoringOptions scoring;
  scoring.cell_size = 0.01;
  const auto sdf =
      ParseXmlNames(SceneConstellationSdf(scene, file.candidates, scoring), "constellation.sdf");
  std::set<std::string> models;
  for (const auto& [element, name] : sdf)
    if (element == "model") Check(models.insert(name).second, "sdf: model '" + name + "' twice");
  Check(models.size() == sensors.size() + targets.size(), "sdf: a model is missing");
  return 0;
}
