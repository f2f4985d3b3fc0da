// Measurement quality (issue 9): the filter's checks and plain observations, in the visibility
// stage so that readers of vantage's files and selection need no Embree.
#include <fmt/format.h>

#include <cmath>

#include "vantage/error.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

void QualityFilter::Validate() const {
  if (max_incidence_deg && !(*max_incidence_deg > 0 && *max_incidence_deg <= 90))
    throw InputError(fmt::format("--max-incidence {} must lie in (0, 90] degrees — e.g. 70",
                                 *max_incidence_deg));
  if (max_depth_noise && !(*max_depth_noise > 0 && std::isfinite(*max_depth_noise)))
    throw InputError(fmt::format("--max-depth-noise {} must be a positive number of millimetres — e.g. 2",
                                 *max_depth_noise * 1000));
}

std::vector<Observation> WithoutQuality(std::span<const Observation> observations) {
  std::vector<Observation> plain;
  plain.reserve(observations.size());
  for (const Observation& o : observations) {
    Observation p;
    const bool same = o.plain_reference_indices.empty() && o.quality_pixels == o.target_pixels;
    p.reference_indices = same ? o.reference_indices : o.plain_reference_indices;
    if (same) p.reference_hits = o.reference_hits;  // the plain cells' counts are not kept
    p.rays_traced = o.rays_traced;
    p.target_pixels = p.quality_pixels = o.target_pixels;
    plain.push_back(std::move(p));
  }
  return plain;
}

std::vector<Observation> IdealObservations(std::span<const Observation> observations) {
  std::vector<Observation> ideal;
  ideal.reserve(observations.size());
  for (const Observation& o : observations) {
    Observation p;
    p.reference_indices = o.ideal_differs ? o.ideal_reference_indices : o.reference_indices;
    if (!o.ideal_differs) p.reference_hits = o.reference_hits;
    p.rays_traced = o.rays_traced;
    ideal.push_back(std::move(p));
  }
  return ideal;
}

}  // namespace vantage
