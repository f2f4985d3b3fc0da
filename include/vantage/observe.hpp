#pragma once
/// Observe: each candidate's depth image ray cast against the whole scene; the voxels of the
/// target points it sees form its observation set O_i (SYSTEM.md, coverage metric).
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/reference.hpp"
#include "vantage/scene.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

/// The noise model of a candidate: its type's own, else the catalog entry its type_id names.
const DepthNoise* NoiseModelOf(const Candidate& candidate);

struct ObserveOptions {
  /// The sensor model (issue 43; docs/sensor-models.md): true, physical (a pixel's hit counts
  /// only where the type's second aperture sees it and stereo can match it); false, the paper's
  /// ideal pinhole (--ideal). Unset: physical, except for a Gazebo world of the original system,
  /// read as that system (ideal) unless --physical; the pipeline decides by the scene's file.
  std::optional<bool> physical;

  /// Trace only pixels whose ray can reach a target's bounds (exact: same result as tracing all).
  bool cull = true;
  QualityFilter quality;
  /// Keep each cell's pixel count (Observation::reference_hits) for --min-points.
  bool count_points = true;
  /// Called from worker threads with (candidates done, total); may be empty.
  std::function<void(size_t, size_t)> progress;
  /// InputError naming the option for an invalid quality filter.
  void Validate() const { quality.Validate(); }
};

/// How candidates are traced where the caller may spread the work: empty, by Observe in this
/// process. The distributed layer (vantage/distribute.hpp) traces a share in each process and
/// gathers the rest (MPI), or keeps its share only (--shard). Returns one observation per
/// candidate, as Observe does.
using TraceFunction = std::function<std::vector<Observation>(
    const RayScene& rays, const Reference& reference, std::span<const Candidate> candidates,
    const ObserveOptions& options)>;

/// One Observation per candidate, in candidate order, traced in `rays` (the RayScene of the scene
/// whose targets `reference` was built from: culling traces only the pixels whose rays can reach
/// its cells). Deterministic whatever the thread count. InputError for an invalid sensor or
/// option.
std::vector<Observation> Observe(const RayScene& rays, const Reference& reference,
                                 std::span<const Candidate> candidates,
                                 const ObserveOptions& options = {});

/// The same, building the scene's RayScene for this call only (tests, one-off calls).
std::vector<Observation> Observe(const Scene& scene, const Reference& reference,
                                 std::span<const Candidate> candidates,
                                 const ObserveOptions& options = {});

/// The rays Observe will trace for each candidate, in candidate order: the pixels left after
/// culling (the whole image without it), counted without casting a ray. The cost of observing a
/// candidate, by which the distributed layer splits the work.
std::vector<uint64_t> CountRaysToTrace(const Reference& reference,
                                       std::span<const Candidate> candidates,
                                       const ObserveOptions& options = {});

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
