#pragma once
/// constellation.yaml: a vantage YAML scene with only the chosen sensors (issue #7, exports).
#include <string>
#include <vector>

#include "vantage/candidates.hpp"

namespace vantage {

/// The YAML scene at `scene_path` with its populations and sensors replaced by `chosen`, each an
/// explicit sensor at its camera pose (orientation as a quaternion, so no look-at or roll is
/// applied again). Mesh paths become absolute so the file loads from any folder. Throws
/// InputError when the scene cannot be read.
std::string ConstellationYaml(const std::string& scene_path, const std::vector<Candidate>& chosen);

}  // namespace vantage
