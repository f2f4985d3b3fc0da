#include "vantage/observe.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include "observe/culling.hpp"
#include "observe/ray_scene.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

using detail::ReferenceBlocks;
using detail::RayBatch;
using detail::RowSpan;
using detail::SpansToTrace;
using detail::RayScene;

Observation ObserveOne(const RayScene& rays, const Reference& reference, const Candidate& candidate,
                       const std::vector<Aabb>& blocks, bool cull) {
  const SensorType& s = candidate.sensor;
  const Mat3 world_from_body = candidate.world_from_body.rotation.toRotationMatrix();
  const Vec3 origin = candidate.world_from_body.position;
  const double cell = reference.cell_size;
  Observation observation;
  std::vector<uint64_t> keys;

  RayBatch batch;
  for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(origin[a]);
  // The direction's body-x component is 1, so the hit parameter t is the depth itself.
  batch.tfar = std::nextafter(static_cast<float>(s.far), std::numeric_limits<float>::infinity());

  for (const RowSpan& span : SpansToTrace(candidate, blocks, cull)) {
    const int v = span.v;
    {
      for (int u_start = span.u0; u_start <= span.u1; u_start += RayBatch::kWidth) {
        batch.active = std::min(RayBatch::kWidth, span.u1 - u_start + 1);
        for (int lane = 0; lane < batch.active; ++lane) {
          const Vec3 d = world_from_body * PixelRayInBody(s, u_start + lane, v);
          for (int a = 0; a < 3; ++a) batch.dir[a][lane] = static_cast<float>(d[a]);
        }
        rays.Intersect(&batch);
        observation.rays_traced += static_cast<uint64_t>(batch.active);
        for (int lane = 0; lane < batch.active; ++lane) {
          if (!batch.is_target[lane]) continue;
          const double t = batch.t[lane];
          if (t < s.near || t > s.far) continue;
          const Vec3 d(batch.dir[0][lane], batch.dir[1][lane], batch.dir[2][lane]);
          const Vec3 p = origin + t * d;
          const VoxelIndex index = VoxelKeyOf(p, cell);
          VANTAGE_CHECK(VoxelIndexFits(index));
          const uint64_t key = PackVoxel(index);
          // Neighbouring pixels mostly hit the same cell: skipping repeats keeps the sort short.
          if (keys.empty() || keys.back() != key) keys.push_back(key);
        }
      }
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  // Both lists are sorted: one merge splits the keys into R's indices and the rest.
  size_t r = 0;
  for (uint64_t key : keys) {
    while (r < reference.keys.size() && reference.keys[r] < key) ++r;
    if (r < reference.keys.size() && reference.keys[r] == key) {
      observation.reference_indices.push_back(static_cast<uint32_t>(r));
    } else {
      observation.outside_keys.push_back(key);
    }
  }
  return observation;
}

}  // namespace

std::vector<Observation> Observe(const Scene& scene, const Reference& reference,
                                 std::span<const Candidate> candidates, const ObserveOptions& options) {
  for (const Candidate& c : candidates) c.sensor.Validate(c.name);
  const std::vector<Aabb> blocks = ReferenceBlocks(reference);
  const RayScene rays(scene);
  std::vector<Observation> observations(candidates.size());
  std::atomic<size_t> done{0};
  // Candidates are independent; each fills its own slot, so the result does not depend on the
  // thread count or the order of completion.
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    observations[i] = ObserveOne(rays, reference, candidates[i], blocks, options.cull);
    const size_t finished = ++done;
    if (options.progress) options.progress(finished, candidates.size());
  });
  return observations;
}

}  // namespace vantage
