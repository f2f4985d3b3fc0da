// report.json's installation constraints (docs/outputs.md).
#include "report/constraints_json.hpp"

#include <algorithm>

namespace vantage::detail {
namespace {

using nlohmann::ordered_json;

ordered_json ConflictJson(const Conflict& c, const VisibilityFile& data) {
  ordered_json j = {{"a", data.candidates.at(c.a).name},
                    {"b", data.candidates.at(c.b).name},
                    {"kind", ConflictKindName(c.kind)}};
  j[c.kind == ConflictKind::kInterference ? "shared" : "distance"] = c.value;
  return j;
}

}  // namespace

ordered_json KeepOutBoxJson(const KeepOutBox& box) {
  // The box is [min, max] in its own frame: its centre, mapped into the world, and its edges
  // along its own axes, turned by the frame's rotation.
  const Vec3 center = box.world_from_box * Vec3(0.5 * (box.min + box.max));
  const Vec3 size = box.max - box.min;
  return {{"name", box.name},
          {"center", ordered_json::array({center.x(), center.y(), center.z()})},
          {"size", ordered_json::array({size.x(), size.y(), size.z()})},
          {"quaternion", WxyzOf(box.world_from_box.rotation)}};
}

ordered_json ConstraintsJson(const ConstraintsInfo& info) {
  ordered_json j;
  j["applied"] = info.is_applied;
  if (info.interference_overlap) {
    size_t pairs = 0;
    for (const Conflict& c : info.constraints.conflicts)
      pairs += c.kind == ConflictKind::kInterference ? 1 : 0;
    j["interference"] = {{"max_overlap", *info.interference_overlap},
                         {"projecting_candidates", info.projecting},
                         {"conflicting_pairs", pairs}};
  }
  if (info.min_separation) {
    size_t pairs = 0;
    for (const Conflict& c : info.constraints.conflicts)
      pairs += c.kind == ConflictKind::kSeparation ? 1 : 0;
    j["separation"] = {{"min_separation", *info.min_separation}, {"conflicting_pairs", pairs}};
  }
  if (!info.keep_out_boxes.empty()) {
    ordered_json regions = ordered_json::array();
    for (const KeepOutBox& box : info.keep_out_boxes) regions.push_back(KeepOutBoxJson(box));
    j["keep_out"] = {{"boxes", info.keep_out_boxes.size()},
                     {"excluded_candidates", info.keep_out_excluded},
                     {"candidates_inside", info.keep_out_violations.size()},
                     {"regions", std::move(regions)}};
  }
  if (const auto& rule = info.constraints.calibration) {
    ordered_json c;
    if (rule->min_cells) c["min_cells"] = *rule->min_cells;
    if (rule->min_fraction) c["min_fraction"] = *rule->min_fraction;
    j["calibration"] = std::move(c);
  }
  return j;
}

ordered_json ResultConstraintsJson(const Selection& selection, const ConstraintsInfo& info,
                                   const VisibilityFile& data) {
  const ConstraintCheck check =
      CheckConstraints(data.observations, selection.chosen, info.constraints);
  ordered_json j;
  const bool has_calibration = info.constraints.calibration.has_value();
  ordered_json inside = ordered_json::array();
  for (const uint32_t i : selection.chosen) {
    if (std::binary_search(info.keep_out_violations.begin(), info.keep_out_violations.end(), i))
      inside.push_back(data.candidates.at(i).name);
  }
  j["satisfied"] =
      check.conflicts.empty() && (!has_calibration || check.connected()) && inside.empty();
  ordered_json broken = ordered_json::array();
  for (const Conflict& c : check.conflicts) broken.push_back(ConflictJson(c, data));
  j["conflicts"] = std::move(broken);
  if (!info.keep_out_boxes.empty()) j["keep_out_violations"] = std::move(inside);
  if (info.is_applied) {
    ordered_json avoided = ordered_json::array();
    for (const Conflict& c : ConflictsAvoided(selection.chosen, info.constraints))
      avoided.push_back(ConflictJson(c, data));
    j["conflicts_avoided"] = std::move(avoided);
  }
  ordered_json edges = ordered_json::array();
  for (const OverlapEdge& e : check.edges) {
    edges.push_back({{"a", data.candidates.at(e.a).name},
                     {"b", data.candidates.at(e.b).name},
                     {"cells", e.cells}});
  }
  j["overlap_graph"] = std::move(edges);
  if (has_calibration) {
    j["connected"] = check.connected();
    ordered_json components = ordered_json::array();
    for (const std::vector<uint32_t>& component : check.components) {
      ordered_json names = ordered_json::array();
      for (const uint32_t i : component) names.push_back(data.candidates.at(i).name);
      components.push_back(std::move(names));
    }
    j["components"] = std::move(components);
  }
  return j;
}

}  // namespace vantage::detail
