// The depth-noise model a candidate's pixels are judged by (issue 9; docs/sensor-models.md).
#include "vantage/observe.hpp"

namespace vantage {

const DepthNoise* NoiseModelOf(const Candidate& candidate) {
  if (candidate.sensor.depth_noise) return &*candidate.sensor.depth_noise;
  const SensorType* catalog = FindCatalogType(candidate.type_id);
  return catalog && catalog->depth_noise ? &*catalog->depth_noise : nullptr;
}


}  // namespace vantage
