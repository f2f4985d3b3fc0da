#include "vantage/observe.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "observe/arm_occlusion.hpp"
#include "observe/culling.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage {
namespace {

using detail::ReferenceBlocks;
using detail::RowSpan;
using detail::SpansToTrace;

// The cells of one image's hits, in hit order: consecutive repeats merged into one run, since
// neighbouring pixels mostly hit the same cell (which keeps the sort short), each with its pixels.
struct KeyRuns {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> pixels;  ///< per run; filled only when counting points
  void Add(uint64_t key, bool count) {
    if (!keys.empty() && keys.back() == key) {
      if (count) ++pixels.back();
      return;
    }
    keys.push_back(key);
    if (count) pixels.push_back(1);
  }
};

// R's indices of the cells of `runs` go to `indices` (with their pixels, saturated, to `hits` when
// counted), the other keys to `outside` (may be null). Both lists are sorted: one merge splits them.
void SplitByReference(KeyRuns* runs, const Reference& reference, std::vector<uint32_t>* indices,
                      std::vector<uint16_t>* hits, std::vector<uint64_t>* outside) {
  std::vector<uint64_t>& keys = runs->keys;
  std::vector<uint32_t> pixels;
  if (hits) {
    // Sort the runs by key, summing the pixels of equal keys.
    std::vector<std::pair<uint64_t, uint32_t>> pairs(keys.size());
    for (size_t i = 0; i < keys.size(); ++i) pairs[i] = {keys[i], runs->pixels[i]};
    std::sort(pairs.begin(), pairs.end());
    keys.clear();
    for (const auto& [key, count] : pairs) {
      if (!keys.empty() && keys.back() == key) {
        pixels.back() += count;
      } else {
        keys.push_back(key);
        pixels.push_back(count);
      }
    }
  } else {
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  }
  size_t r = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint64_t key = keys[i];
    while (r < reference.keys.size() && reference.keys[r] < key) ++r;
    if (r < reference.keys.size() && reference.keys[r] == key) {
      indices->push_back(static_cast<uint32_t>(r));
      if (hits) hits->push_back(static_cast<uint16_t>(std::min<uint32_t>(pixels[i], kMaxPointCount)));
    } else if (outside) {
      outside->push_back(key);
    }
  }
}

// The physical model of one candidate (issue 43): where its second aperture is in the world, and
// what a hit must satisfy besides the ideal pinhole's.
struct PhysicalModel {
  const SecondAperture* aperture = nullptr;  // null: ideal pinhole
  Vec3 centre;              // the aperture's optical centre, world
  double nearest = 0;       // stereo's nearest depth [m]
  OcclusionBatch segments;  // per batch: from the aperture to the hits
};

PhysicalModel MakePhysicalModel(const Candidate& candidate, bool physical) {
  PhysicalModel model;
  model.aperture = physical ? SecondApertureOf(candidate.sensor, candidate.type_id) : nullptr;
  if (!model.aperture) return model;
  const Pose& pose = candidate.world_from_body;
  model.centre = pose.position + pose.rotation * ApertureCentreInBody(*model.aperture);
  model.nearest = StereoNearestDepth(candidate.sensor, *model.aperture);
  for (int a = 0; a < 3; ++a) model.segments.origin[a] = static_cast<float>(model.centre[a]);
  // Stop 0.01 % short of the point: the surface it lies on must not occlude it, whatever float
  // rounding does to the segment's end.
  model.segments.tfar = 1.0f - 1e-4f;
  return model;
}

Observation ObserveOne(const RayScene& rays, const Reference& reference, const Candidate& candidate,
                       const std::vector<Aabb>& blocks, const ObserveOptions& options,
                       const detail::ArmOcclusion& arms) {
  const SensorType& s = candidate.sensor;
  const Mat3 world_from_body = candidate.world_from_body.rotation.toRotationMatrix();
  const Vec3 origin = candidate.world_from_body.position;
  const double cell = reference.cell_size;
  const QualityFilter& quality = options.quality;
  const double min_cos_incidence =
      quality.max_incidence_deg ? std::cos(*quality.max_incidence_deg * std::numbers::pi / 180.0) : -1.0;
  const DepthNoise* noise = quality.max_depth_noise ? NoiseModelOf(candidate) : nullptr;
  PhysicalModel physical = MakePhysicalModel(candidate, options.physical.value_or(true));
  const bool is_physical = physical.aperture != nullptr;
  Observation observation;
  // keys: every measured pixel's cell; quality_keys: those passing the filter; ideal_keys: as
  // the ideal pinhole counts (the filter's pixels when one is on), with the physical model only.
  KeyRuns keys, quality_keys, ideal_keys;
  const bool count = options.count_points;

  RayBatch batch;
  for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(origin[a]);
  // The direction's body-x component is 1, so the hit parameter t is the depth itself.
  batch.tfar = std::nextafter(static_cast<float>(s.far), std::numeric_limits<float>::infinity());
  bool passes_quality[RayBatch::kWidth];
  uint64_t keys_of[RayBatch::kWidth];

  for (const RowSpan& span : SpansToTrace(candidate, blocks, options.cull)) {
    for (int u_start = span.u0; u_start <= span.u1; u_start += RayBatch::kWidth) {
      batch.active = std::min(RayBatch::kWidth, span.u1 - u_start + 1);
      for (int lane = 0; lane < batch.active; ++lane) {
        const Vec3 d = world_from_body * PixelRayInBody(s, u_start + lane, span.v);
        for (int a = 0; a < 3; ++a) batch.dir[a][lane] = static_cast<float>(d[a]);
      }
      rays.Intersect(&batch);
      if (candidate.arm) arms.Clip(*candidate.arm, &batch);  // the arm carrying it (issue 45)
      observation.rays_traced += static_cast<uint64_t>(batch.active);
      for (int lane = 0; lane < RayBatch::kWidth; ++lane) physical.segments.query[lane] = false;
      for (int lane = 0; lane < batch.active; ++lane) {
        if (!batch.is_target[lane]) continue;
        const double t = batch.t[lane];
        if (t < s.near || t > s.far) continue;
        const Vec3 d(batch.dir[0][lane], batch.dir[1][lane], batch.dir[2][lane]);
        const Vec3 p(batch.point[0][lane], batch.point[1][lane], batch.point[2][lane]);
        const VoxelIndex index = VoxelKeyOf(p, cell);
        VANTAGE_CHECK(VoxelIndexFits(index));
        const uint64_t key = PackVoxel(index);
        bool passes = true;
        if (quality.max_incidence_deg) {
          const Vec3 n(batch.normal[0][lane], batch.normal[1][lane], batch.normal[2][lane]);
          const double norms = d.norm() * n.norm();
          passes = norms > 0 && std::abs(d.dot(n)) >= min_cos_incidence * norms;
        }
        if (passes && noise) passes = noise->Sigma(t) <= *quality.max_depth_noise;
        if (!is_physical) {
          ++observation.target_pixels;
          keys.Add(key, count && !quality.active());
          if (!quality.active() || !passes) continue;
          ++observation.quality_pixels;
          quality_keys.Add(key, count);
          continue;
        }
        if (passes) ideal_keys.Add(key, false);
        // Physical: stereo cannot match nearer than its disparity search reaches; the aperture
        // must have the point in its field and lie on the side of the surface the camera sees.
        if (t < physical.nearest) continue;
        const Vec3 p_body = world_from_body.transpose() * (p - origin);
        if (!InApertureField(s, *physical.aperture, p_body)) continue;
        const Vec3 n(batch.normal[0][lane], batch.normal[1][lane], batch.normal[2][lane]);
        if (n.dot(physical.centre - p) * n.dot(origin - p) <= 0) continue;
        const Vec3 segment = p - physical.centre;
        for (int a = 0; a < 3; ++a) physical.segments.dir[a][lane] = static_cast<float>(segment[a]);
        physical.segments.query[lane] = true;
        passes_quality[lane] = passes;
        keys_of[lane] = key;
      }
      if (!is_physical) continue;
      // One occlusion packet for the hits that reached it, in lane order as before.
      rays.Occluded(&physical.segments);
      for (int lane = 0; lane < batch.active; ++lane) {
        if (!physical.segments.query[lane] || physical.segments.occluded[lane]) continue;
        ++observation.target_pixels;
        keys.Add(keys_of[lane], count && !quality.active());
        if (!quality.active() || !passes_quality[lane]) continue;
        ++observation.quality_pixels;
        quality_keys.Add(keys_of[lane], count);
      }
    }
  }
  if (!quality.active()) {
    observation.quality_pixels = observation.target_pixels;
    SplitByReference(&keys, reference, &observation.reference_indices,
                     count ? &observation.reference_hits : nullptr, &observation.outside_keys);
  } else {
    SplitByReference(&quality_keys, reference, &observation.reference_indices,
                     count ? &observation.reference_hits : nullptr, &observation.outside_keys);
    SplitByReference(&keys, reference, &observation.plain_reference_indices, nullptr, nullptr);
  }
  if (is_physical) {
    SplitByReference(&ideal_keys, reference, &observation.ideal_reference_indices, nullptr, nullptr);
    observation.ideal_differs = observation.ideal_reference_indices != observation.reference_indices;
    if (!observation.ideal_differs) observation.ideal_reference_indices.clear();
  }
  return observation;
}

}  // namespace

std::vector<Observation> Observe(const RayScene& rays, const Reference& reference,
                                 std::span<const Candidate> candidates, const ObserveOptions& options) {
  for (const Candidate& c : candidates) CheckCandidate(c, c.name);
  options.Validate();
  const std::vector<Aabb> blocks = ReferenceBlocks(reference);
  const detail::ArmOcclusion arms(candidates);
  std::vector<Observation> observations(candidates.size());
  std::atomic<size_t> done{0};
  // Candidates are independent; each fills its own slot, so the result does not depend on the
  // thread count or the order of completion.
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    if (InterruptRequested()) return;  // the rest is skipped; thrown once the loop is left
    observations[i] = ObserveOne(rays, reference, candidates[i], blocks, options, arms);
    const size_t finished = ++done;
    if (options.progress) options.progress(finished, candidates.size());
  });
  ThrowIfInterrupted();
  return observations;
}

std::vector<uint64_t> CountRaysToTrace(const Reference& reference,
                                       std::span<const Candidate> candidates,
                                       const ObserveOptions& options) {
  const std::vector<Aabb> blocks = ReferenceBlocks(reference);
  std::vector<uint64_t> rays(candidates.size(), 0);
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    for (const RowSpan& span : SpansToTrace(candidates[i], blocks, options.cull))
      rays[i] += static_cast<uint64_t>(span.u1 - span.u0 + 1);
  });
  return rays;
}

std::vector<Observation> Observe(const Scene& scene, const Reference& reference,
                                 std::span<const Candidate> candidates, const ObserveOptions& options) {
  return Observe(RayScene(scene), reference, candidates, options);
}

}  // namespace vantage
