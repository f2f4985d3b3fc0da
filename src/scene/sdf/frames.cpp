// Frames of a model scope for `<pose relative_to="X">`: the pose of a link, nested model, include
// or <frame> in its model, resolved once each by following relative_to (or attached_to) to the
// model frame. Names are those of the same model only, so each resolves unambiguously; a name
// that is not there, or a cycle, is an error at the pose's line (GAZEBO.md, "Poses and geometry").
#include <fmt/format.h>

#include <map>
#include <set>
#include <string>

#include "scene/sdf/loader.hpp"

namespace vantage::detail::gazebo {

Pose Loader::FrameInModel(const std::string& name,
                          std::map<std::string, FrameEntry>& entries,
                          std::map<std::string, Pose>& resolved,
                          std::set<std::string>& visiting,
                          const std::string& model,
                          const Doc& doc,
                          int line) {
  if (name.empty() || name == "__model__" || name == model) return Pose{};
  if (const auto it = resolved.find(name); it != resolved.end()) return it->second;
  const auto entry_it = entries.find(name);
  if (entry_it == entries.end()) {
    Error(doc, line,
          fmt::format("relative_to '{}' names no link, model or frame of model '{}' — name one of "
                      "its own frames (scoped names a::b are not supported)",
                      name, model));
    return Pose{};
  }
  const FrameEntry& entry = entry_it->second;
  if (!visiting.insert(name).second) {
    Error(*entry.doc, entry.line,
          fmt::format("frame '{}' of model '{}' is placed relative to itself (a relative_to "
                      "cycle) — break the cycle",
                      name, model));
    return Pose{};
  }
  std::string parent = entry.default_parent;
  if (entry.honours_relative_to) {
    const std::string relative_to = RelativeTo(*entry.doc, entry.pose);
    if (!relative_to.empty()) parent = relative_to;
  }
  if (const auto placed = entries.find(parent);
      placed != entries.end() && placed->second.is_placed_by_frame) {
    Error(*entry.doc, entry.pose ? entry.pose->line : entry.line,
          fmt::format("frame '{}' of model '{}' is placed relative to '{}', a model placed by "
                      "its placement_frame — place it relative to another frame",
                      name, model, parent));
  }
  const Pose parent_pose = FrameInModel(parent, entries, resolved, visiting, model, *entry.doc,
                                        entry.pose ? entry.pose->line : entry.line);
  Pose pose = parent_pose * PoseValue(*entry.doc, entry.pose);
  visiting.erase(name);
  resolved[name] = pose;
  return pose;
}

}  // namespace vantage::detail::gazebo
