#include "vantage/observe.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "observe/ray_scene.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

using detail::RayBatch;
using detail::RayScene;

/// Inclusive pixel rectangle.
struct PixelRect {
  int u0, v0, u1, v1;
  bool IsEmpty() const { return u0 > u1 || v0 > v1; }
};

PixelRect FullImage(const SensorType& s) { return {0, 0, s.width - 1, s.height - 1}; }

// Pixels whose centre ray can reach a point of `bounds` within [near, far]. Exact culling: a ray
// through pixel centre c hits p only if p projects to c, and the projection of a box lying in
// front of the camera is inside the bounding rectangle of its projected corners. One pixel of
// padding absorbs the float rounding of the traced rays.
PixelRect RectOfBounds(const SensorType& s, const Pose& body_from_world, const Aabb& bounds) {
  double depth_min = std::numeric_limits<double>::infinity();
  double depth_max = -depth_min;
  double u_min = depth_min, u_max = -depth_min, v_min = depth_min, v_max = -depth_min;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 world((corner & 1) ? bounds.max.x() : bounds.min.x(),
                     (corner & 2) ? bounds.max.y() : bounds.min.y(),
                     (corner & 4) ? bounds.max.z() : bounds.min.z());
    const Vec3 body = body_from_world * world;
    depth_min = std::min(depth_min, body.x());
    depth_max = std::max(depth_max, body.x());
    if (const auto uv = ProjectBodyPoint(s, body)) {
      u_min = std::min(u_min, uv->x());
      u_max = std::max(u_max, uv->x());
      v_min = std::min(v_min, uv->y());
      v_max = std::max(v_max, uv->y());
    }
  }
  // Depth is linear, so the box's depths lie between its corners' depths.
  const double slack = 1e-6 * (1.0 + s.far);
  if (depth_max < s.near - slack || depth_min > s.far + slack) return {0, 0, -1, -1};
  if (depth_min <= 1e-9) return FullImage(s);  // the box straddles the camera plane
  const auto lo = [](double x) { return static_cast<int>(std::max(-1.0, std::ceil(x - 0.5) - 1)); };
  const auto hi = [](double x) { return static_cast<int>(std::min(1e9, std::floor(x - 0.5) + 1)); };
  PixelRect r{lo(u_min), lo(v_min), hi(u_max), hi(v_max)};
  r.u0 = std::max(r.u0, 0);
  r.v0 = std::max(r.v0, 0);
  r.u1 = std::min(r.u1, s.width - 1);
  r.v1 = std::min(r.v1, s.height - 1);
  return r;
}

// Rectangles to trace for one camera: one per target object, overlapping ones merged so that no
// pixel is traced twice.
std::vector<PixelRect> RectsToTrace(const Candidate& candidate, const std::vector<Aabb>& targets,
                                    bool cull) {
  const SensorType& s = candidate.sensor;
  if (!cull) return {FullImage(s)};
  const Pose body_from_world = candidate.world_from_body.Inverse();
  std::vector<PixelRect> rects;
  for (const Aabb& bounds : targets) {
    const PixelRect r = RectOfBounds(s, body_from_world, bounds);
    if (!r.IsEmpty()) rects.push_back(r);
  }
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t i = 0; i < rects.size() && !merged; ++i) {
      for (size_t j = i + 1; j < rects.size() && !merged; ++j) {
        const PixelRect& a = rects[i];
        const PixelRect& b = rects[j];
        if (a.u0 <= b.u1 && b.u0 <= a.u1 && a.v0 <= b.v1 && b.v0 <= a.v1) {
          rects[i] = {std::min(a.u0, b.u0), std::min(a.v0, b.v0), std::max(a.u1, b.u1),
                      std::max(a.v1, b.v1)};
          rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
      }
    }
  }
  return rects;
}

Observation ObserveOne(const RayScene& rays, const Reference& reference, const Candidate& candidate,
                       const std::vector<Aabb>& targets, bool cull) {
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

  for (const PixelRect& rect : RectsToTrace(candidate, targets, cull)) {
    for (int v = rect.v0; v <= rect.v1; ++v) {
      for (int u_start = rect.u0; u_start <= rect.u1; u_start += RayBatch::kWidth) {
        batch.active = std::min(RayBatch::kWidth, rect.u1 - u_start + 1);
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
          keys.push_back(PackVoxel(index));
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
  std::vector<Aabb> targets;
  for (const SceneObject& object : scene.objects) {
    if (object.is_target() && !object.mesh.IsEmpty()) targets.push_back(object.mesh.Bounds());
  }
  const RayScene rays(scene);
  std::vector<Observation> observations(candidates.size());
  std::atomic<size_t> done{0};
  // Candidates are independent; each fills its own slot, so the result does not depend on the
  // thread count or the order of completion.
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
    observations[i] = ObserveOne(rays, reference, candidates[i], targets, options.cull);
    const size_t finished = ++done;
    if (options.progress) options.progress(finished, candidates.size());
  });
  return observations;
}

}  // namespace vantage
