// The parameters of the original Gazebo plugin (numberOfIntendedSensors, voxelGridFilterLeafSize,
// sensorDataSegmentationColorRGB, ...), read from any <plugin> of the world so that a world made
// for the plugin runs unchanged (GAZEBO.md, "The plugin's parameters").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"
#include "util/cell_size.hpp"
#include "vantage/error.hpp"
#include "vantage/scene_settings.hpp"

namespace vantage::detail::gazebo {
namespace {

// The selection setting whose plugin parameter is `name`, else null.
const SceneSelectionSetting* SettingOfParameter(std::string_view name) {
  for (const SceneSelectionSetting& setting : kSceneSelectionSettings)
    if (setting.plugin_parameter == name) return &setting;
  return nullptr;
}

}  // namespace

void Loader::ReadPlugin() {
  // The selection settings' parameters come from their rows (scene_settings.hpp).
  static const std::set<std::string> kKnown = [] {
    std::set<std::string> known = {"voxelGridFilterLeafSize",        "sensorOrientationRandomRoll",
                                   "sensorDataSegmentationColorRGB", "sceneModelPath",
                                   "observationPoint",               "numberOfSamplingSensors"};
    for (const SceneSelectionSetting& setting : kSceneSelectionSettings)
      if (!setting.plugin_parameter.empty()) known.emplace(setting.plugin_parameter);
    return known;
  }();
  const Doc& doc = *world_doc_;
  // Any <plugin> of the world file, at any depth, with these children.
  std::vector<const XmlElement*> stack = {world_};
  std::vector<const XmlElement*> plugins;
  while (!stack.empty()) {
    const XmlElement* e = stack.back();
    stack.pop_back();
    for (const XmlElement& child : e->children) {
      if (child.name == "plugin") {
        plugins.push_back(&child);
      } else {
        stack.push_back(&child);
      }
    }
  }
  std::sort(plugins.begin(), plugins.end(),
            [](const XmlElement* a, const XmlElement* b) { return a->line < b->line; });
  std::map<std::string, const XmlElement*> params;
  constexpr int64_t kMaxCount = 1'000'000'000;
  // In document order, so that errors come in the file's order.
  for (const XmlElement* plugin : plugins) {
    const std::string* filename = plugin->Attribute("filename");
    if (filename && filename->find("sensor_placement_optimization") != std::string::npos)
      has_classic_plugin_ = true;
    for (const XmlElement& child : plugin->children) {
      if (!kKnown.contains(child.name)) continue;
      has_classic_plugin_ = true;
      const auto [it, inserted] = params.emplace(child.name, &child);
      if (!inserted) {
        Error(doc, child.line,
              fmt::format("<{}> is given twice (first at line {}) — keep one", child.name,
                          it->second->line));
        continue;
      }
      const XmlElement* e = &child;
      const std::string& name = child.name;
      if (const SceneSelectionSetting* setting = SettingOfParameter(name)) {
        ReadSelectionSetting(doc, *e, *setting, kMaxCount);
      } else if (name == "numberOfSamplingSensors") {
        if (const auto v = Integer(doc, *e, 1, kMaxCount))
          problem_.expected_candidates = static_cast<int>(*v);
      } else if (name == "voxelGridFilterLeafSize") {
        if (const auto v = PositiveNumber(doc, *e, "0.005")) {
          // The same range as a YAML scene's cell_size, named at its line (issue 15: 1e300 was
          // refused later with no place).
          if (const std::string problem = detail::CellSizeProblem(*v); !problem.empty())
            Error(doc, e->line, fmt::format("<voxelGridFilterLeafSize>: {}", problem));
          else
            problem_.cell_size = *v;
        }
      } else if (name == "sensorOrientationRandomRoll") {
        if (const auto v = Boolean(doc, *e)) problem_.random_roll = *v;
      } else if (name == "observationPoint") {
        if (const auto v = Vector(doc, *e, false, "0 0 0")) {
          // The same range as --observation-point: every look-at direction starts here.
          if (const std::string beyond = WorldPointProblem(*v); !beyond.empty())
            Error(doc, e->line,
                  fmt::format("<observationPoint> {} — give a point near the targets", beyond));
          problem_.observation_point = *v;
        }
      } else if (name == "sensorDataSegmentationColorRGB") {
        ReadSegmentationColour(doc, *e);
      } else if (name == "sceneModelPath") {
        // "PATH|A+B": the names after '|' are the target models.
        const std::string text = e->Trimmed();
        const size_t bar = text.find('|');
        scene_model_names_ = bar == std::string::npos ? std::vector<std::string>{}
                                                      : SplitList(text.substr(bar + 1), '+');
        scene_model_site_ = Site{doc.xml.path, e->line};
      }
    }
  }
  if (!params.contains("sensorDataSegmentationColorRGB") && !plugins.empty())
    segmentation_site_ = Site{doc.xml.path, plugins.front()->line};
}

void Loader::ReadSelectionSetting(const Doc& doc, const XmlElement& e,
                                  const SceneSelectionSetting& setting, int64_t max_count) {
  // Its line, for errors found after deployment (n above the candidates). The plugin is read
  // from the world file, the problem's source.
  SelectionSettings& selection = problem_.selection;
  selection.lines[std::string(setting.field)] = e.line;
  std::visit(
      [&](auto member) {
        using Held = std::decay_t<decltype(selection.*member)>;
        if constexpr (std::is_same_v<Held, int>) {
          if (const auto v = Integer(doc, e, static_cast<int64_t>(setting.low), max_count))
            selection.*member = static_cast<int>(*v);
        } else if constexpr (std::is_same_v<Held, std::optional<Method>>) {
          throw InternalError("the plugin has no method parameter: " + e.name);
        } else {  // a number, in percent where the row says so
          const double scale = setting.plugin_percent ? 100.0 : 1.0;
          const auto v = Number(doc, e, setting.plugin_example);
          if (!v) return;
          if (setting.OutOfRange(*v, scale)) {
            Error(doc, e.line,
                  setting.plugin_percent
                      ? fmt::format("<{}> {} must be a percentage from {:g} to {:g}", e.name,
                                    e.Trimmed(), setting.low * scale, setting.high * scale)
                      : fmt::format("<{}> {} {}", e.name, e.Trimmed(), setting.out_of_range));
          } else {
            selection.*member = *v / scale;
          }
        }
      },
      setting.member);
}

void Loader::ReadSegmentationColour(const Doc& doc, const XmlElement& e) {
  segmentation_site_ = Site{doc.xml.path, e.line};
  is_segmentation_given_ = true;
  const auto v = Numbers(doc, e, 3, "0 255 0");
  if (!v) return;
  bool ok = true;
  for (size_t i = 0; i < 3; ++i) {
    const double c = (*v)[i];
    ok = ok && c >= 0 && c <= 255 && c == std::round(c);
    if (ok) segmentation_colour_[i] = static_cast<int>(c);
  }
  if (!ok) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be three whole numbers from 0 to 255 — write e.g. "
                      "<{}>0 255 0</{}>",
                      e.name, e.Trimmed(), e.name, e.name));
    segmentation_colour_ = kDefaultSegmentationColour;
  }
}

}  // namespace vantage::detail::gazebo
