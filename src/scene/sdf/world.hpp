#pragma once
/// Internals of the Gazebo world loader (LoadGazeboWorld in vantage/problem.hpp; scene/sdf/),
/// exposed for tests: every rendered visual with its world pose and role.
#include <string>
#include <vector>

#include "vantage/problem.hpp"
#include "vantage/types.hpp"

namespace vantage::detail {

/// One visual that the loader rendered into the scene.
struct GazeboVisual {
  std::string model;       ///< scoped instance name: "outer::inner" for nested models
  std::string link;        ///< link name ("" for the synthetic ground plane)
  std::string name;        ///< the <visual>'s name
  Pose world_from_visual;  ///< model · link · visual
  bool is_target = false;
  std::string file;  ///< file declaring the <visual>
  int line = 0;
};

/// LoadGazeboWorld, also listing the visuals it rendered (in declaration order) when `visuals`
/// is not null.
Problem LoadGazeboWorld(const std::string& path,
                        const LoadOptions& options,
                        std::vector<GazeboVisual>* visuals);

}  // namespace vantage::detail
