#include "vantage/observe.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

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

// Blocks of kCullBlockCells³ reference cells: their bounds cover every target surface point,
// because R holds every cell the targets' surface passes through.
constexpr int64_t kCullBlockCells = 4;

std::vector<Aabb> ReferenceBlocks(const Reference& reference) {
  std::map<std::array<int64_t, 3>, Aabb> blocks;
  const double f = reference.cell_size;
  for (uint64_t key : reference.keys) {
    const VoxelIndex i = UnpackVoxel(key);
    const std::array<int64_t, 3> block{i[0] >= 0 ? i[0] / kCullBlockCells : (i[0] + 1) / kCullBlockCells - 1,
                                       i[1] >= 0 ? i[1] / kCullBlockCells : (i[1] + 1) / kCullBlockCells - 1,
                                       i[2] >= 0 ? i[2] / kCullBlockCells : (i[2] + 1) / kCullBlockCells - 1};
    Aabb& bounds = blocks[block];
    const Vec3 lo(static_cast<double>(i[0]) * f, static_cast<double>(i[1]) * f, static_cast<double>(i[2]) * f);
    bounds.Extend(lo);
    bounds.Extend(lo + Vec3::Constant(f));
  }
  std::vector<Aabb> out;
  out.reserve(blocks.size());
  for (const auto& [block, bounds] : blocks) out.push_back(bounds);
  return out;
}

/// Pixel spans [u0, u1] of one image row.
struct RowSpan {
  int v, u0, u1;
};

// The pixels to trace for one camera, row by row, each pixel once: the union of the projected
// rectangles of the blocks (exact culling), or the whole image.
std::vector<RowSpan> SpansToTrace(const Candidate& candidate, const std::vector<Aabb>& blocks, bool cull) {
  const SensorType& s = candidate.sensor;
  std::vector<RowSpan> spans;
  if (!cull) {
    for (int v = 0; v < s.height; ++v) spans.push_back({v, 0, s.width - 1});
    return spans;
  }
  const Pose body_from_world = candidate.world_from_body.Inverse();
  std::vector<std::vector<std::pair<int, int>>> rows(static_cast<size_t>(s.height));
  for (const Aabb& bounds : blocks) {
    const PixelRect r = RectOfBounds(s, body_from_world, bounds);
    for (int v = r.v0; v <= r.v1 && !r.IsEmpty(); ++v) rows[static_cast<size_t>(v)].emplace_back(r.u0, r.u1);
  }
  for (int v = 0; v < s.height; ++v) {
    auto& row = rows[static_cast<size_t>(v)];
    std::sort(row.begin(), row.end());
    for (size_t i = 0; i < row.size();) {
      int u0 = row[i].first, u1 = row[i].second;
      for (++i; i < row.size() && row[i].first <= u1 + 1; ++i) u1 = std::max(u1, row[i].second);
      spans.push_back({v, u0, u1});
    }
  }
  return spans;
}

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
