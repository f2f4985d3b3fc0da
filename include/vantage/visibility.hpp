#pragma once
/// The visibility matrix: one observation set O_i per candidate (SYSTEM.md, pipeline stage 4), the
/// one input of every selection method. Std only, so that selection sees neither the scene, the
/// candidates' geometry nor Embree.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace vantage {

/// Measurement quality a pixel must reach for its hit to count (issue 9; docs/sensor-models.md).
/// Unset fields do not filter. Part of the matrix because it says what the sets mean.
struct QualityFilter {
  /// Largest angle between the ray and the surface's normal [deg], in (0, 90].
  std::optional<double> max_incidence_deg;
  /// Largest depth noise sigma(z) of the sensor's DepthNoise at the hit's depth [m]. Pixels of
  /// types without a noise model pass (the report names those types).
  std::optional<double> max_depth_noise;
  bool active() const { return max_incidence_deg.has_value() || max_depth_noise.has_value(); }
  /// InputError naming the option (--max-incidence, --max-depth-noise) for out-of-range values.
  void Validate() const;
};

/// Where Observation::reference_hits saturates.
inline constexpr uint16_t kMaxPointCount = UINT16_MAX;

/// O_i of one candidate.
struct Observation {
  /// R's cells seen (indices into Reference::keys, sorted, unique) by pixels that pass the
  /// quality filter; with no filter, by any pixel. Selection maximises coverage of these.
  std::vector<uint32_t> reference_indices;
  /// Point density (docs/constraints.md): per entry of reference_indices, the pixels (those that
  /// counted it: passing the filter, if any) whose hit lies in that cell, saturating at
  /// kMaxPointCount. Empty when not recorded (files of format version 3 and older).
  std::vector<uint16_t> reference_hits;
  std::vector<uint64_t> outside_keys;  ///< packed keys seen but not in R, sorted, unique (same pixels)
  /// With a quality filter: R's cells seen by any pixel, passing or not (the plain coverage);
  /// empty without one.
  std::vector<uint32_t> plain_reference_indices;
  /// Made with the physical sensor model (issue 43) where it changed what this candidate sees:
  /// R's cells the ideal pinhole would have counted (the same quality filter), for the ideal
  /// coverage the report shows beside. Empty, and ideal_differs false, where they are the same.
  std::vector<uint32_t> ideal_reference_indices;
  bool ideal_differs = false;
  uint64_t rays_traced = 0;     ///< pixels actually ray cast (after culling)
  uint64_t target_pixels = 0;   ///< pixels whose first hit is a target within [near, far]
  uint64_t quality_pixels = 0;  ///< of those, the ones that pass the quality filter
  /// Whether reference_hits holds one count per cell of reference_indices.
  bool has_point_counts() const { return reference_hits.size() == reference_indices.size(); }
};

/// The same observations counting every pixel (reference_indices = plain_reference_indices)
/// when they were made with a quality filter; a plain copy otherwise. For the plain coverage
/// that the report shows beside the quality-filtered one.
std::vector<Observation> WithoutQuality(std::span<const Observation> observations);

/// The same observations as the ideal pinhole made them (reference_indices =
/// ideal_reference_indices where the physical model changed them; pixel counts kept only where
/// it did not). For the ideal coverage that the report shows beside the physical one.
std::vector<Observation> IdealObservations(std::span<const Observation> observations);

}  // namespace vantage
