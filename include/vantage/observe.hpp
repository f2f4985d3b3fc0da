#pragma once
/// Observe: each candidate's depth image ray cast against the whole scene; the voxels of the
/// target points it sees form its observation set O_i (SYSTEM.md, coverage metric).
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/reference.hpp"
#include "vantage/scene.hpp"

namespace vantage {

/// Measurement quality a pixel must reach for its hit to count (issue 9; docs/sensor-models.md).
/// Unset fields do not filter.
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

/// The noise model of a candidate: its type's own, else the catalog entry its type_id names.
const DepthNoise* NoiseModelOf(const Candidate& candidate);

/// O_i of one candidate.
struct Observation {
  /// R's cells seen (indices into Reference::keys, sorted, unique) by pixels that pass the
  /// quality filter; with no filter, by any pixel. Selection maximises coverage of these.
  std::vector<uint32_t> reference_indices;
  std::vector<uint64_t> outside_keys;  ///< packed keys seen but not in R, sorted, unique (same pixels)
  /// With a quality filter: R's cells seen by any pixel, passing or not (the plain coverage);
  /// empty without one.
  std::vector<uint32_t> plain_reference_indices;
  uint64_t rays_traced = 0;     ///< pixels actually ray cast (after culling)
  uint64_t target_pixels = 0;   ///< pixels whose first hit is a target within [near, far]
  uint64_t quality_pixels = 0;  ///< of those, the ones that pass the quality filter
};

/// The same observations counting every pixel (reference_indices = plain_reference_indices)
/// when they were made with a quality filter; a plain copy otherwise. For the plain coverage
/// that the report shows beside the quality-filtered one.
std::vector<Observation> WithoutQuality(std::span<const Observation> observations);

struct ObserveOptions {
  /// Trace only pixels whose ray can reach a target's bounds (exact: same result as tracing all).
  bool cull = true;
  QualityFilter quality;
  /// Called from worker threads with (candidates done, total); may be empty.
  std::function<void(size_t, size_t)> progress;
};

/// One Observation per candidate, in candidate order. Deterministic whatever the thread count.
/// `reference` must be BuildReference of the same scene: culling traces only the pixels whose
/// rays can reach its cells.
std::vector<Observation> Observe(const Scene& scene, const Reference& reference,
                                 std::span<const Candidate> candidates,
                                 const ObserveOptions& options = {});

/// Everything `vantage select` needs to rerun selection without re-rendering.
struct VisibilityFile {
  std::string scene;  ///< path of the scene it came from
  uint64_t seed = 1;
  int n = 1;
  int ransac_iterations = 1000;
  double ransac_stop_coverage = 1.0;
  /// The scene's selection settings (format version 2; version 1 files read as the defaults).
  std::string method;            ///< settings.method; empty = the command's default
  std::optional<double> goal;    ///< settings.goal (set cover)
  int k = 1;                     ///< settings.k (k-coverage when >= 2)
  std::optional<double> budget;  ///< settings.budget
  Reference reference;
  std::vector<Candidate> candidates;
  std::vector<Observation> observations;  ///< one per candidate
  QualityFilter quality;  ///< the filter the observations were made with (format version 3)
};

/// Writes the versioned binary file (magic, version, payload, FNV-1a 64 checksum) atomically.
void SaveVisibilityFile(const std::string& path, const VisibilityFile& file);
/// Reads it back; InputError naming the file when it is not one, corrupt, or another version.
VisibilityFile LoadVisibilityFile(const std::string& path);

}  // namespace vantage

namespace vantage {

/// Peak memory that Observe and selection will need, estimated before any ray is cast (upper
/// bounds where cheap to know, else typical sizes). Bytes.
struct MemoryEstimate {
  uint64_t scene = 0;         ///< Embree BVH and vertex copies
  uint64_t hit_buffers = 0;   ///< per-thread voxel keys of one image
  uint64_t observations = 0;  ///< the visibility matrix (sorted index lists)
  uint64_t selection = 0;     ///< selection's bitset matrix
  uint64_t Total() const { return scene + hit_buffers + observations + selection; }
};
MemoryEstimate EstimateMemory(const Scene& scene, size_t reference_size,
                              std::span<const Candidate> candidates, size_t threads);

}  // namespace vantage
