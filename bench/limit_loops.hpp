#pragma once
// The limit loops' shared pieces (bench/ray_limit.cpp, bench/arm_table.cpp): a candidate's pixel
// rays over its culled spans, 16 to a packet, and the physical model's occlusion segments that
// observe casts from its lit target hits, found and cast the same way in both benches.
#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include "observe/culling.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/vantage.hpp"

namespace vantage::bench {

/// Candidate `c`'s pixel rays over `spans`, 16 at a time, into `intersect(RayBatch*)` (a generic
/// lambda, so the call is inlined as in observe).
template <class Intersect>
void TraceSpans(const Candidate& c, std::span<const detail::RowSpan> spans,
                const Intersect& intersect) {
  const Mat3 rotation = c.world_from_body.rotation.toRotationMatrix();
  RayBatch batch;
  for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(c.world_from_body.position[a]);
  batch.tfar = static_cast<float>(c.sensor.far);
  for (const detail::RowSpan& span : spans) {
    for (int u0 = span.u0; u0 <= span.u1; u0 += RayBatch::kWidth) {
      batch.active = std::min(RayBatch::kWidth, span.u1 - u0 + 1);
      for (int lane = 0; lane < batch.active; ++lane) {
        const Vec3 d = rotation * PixelRayInBody(c.sensor, u0 + lane, span.v);
        for (int a = 0; a < 3; ++a) batch.dir[a][lane] = static_cast<float>(d[a]);
      }
      intersect(&batch);
    }
  }
}

/// One candidate's occlusion segments: from the second aperture's centre to each lit point.
struct Segments {
  float centre[3] = {};
  std::vector<std::array<float, 3>> dir;  // the point minus the aperture's centre
};

/// The segments observe casts for `c` (none without a second aperture), found untimed by
/// tracing its spans through `intersect`: each target hit within range, beyond stereo's nearest
/// depth, in the aperture's field and on the side of its surface both centres see (the
/// conditions of observe.cpp's PixelJudge::Take).
template <class Intersect>
Segments FindSegments(const Candidate& c, std::span<const detail::RowSpan> spans,
                      const Intersect& intersect) {
  Segments found;
  const SecondAperture* aperture = SecondApertureOf(c.sensor, c.type_id);
  if (!aperture) return found;
  const Mat3 rotation = c.world_from_body.rotation.toRotationMatrix();
  const Vec3 origin = c.world_from_body.position;
  const Vec3 centre = origin + c.world_from_body.rotation * ApertureCentreInBody(*aperture);
  const double nearest = StereoNearestDepth(c.sensor, *aperture);
  for (int a = 0; a < 3; ++a) found.centre[a] = static_cast<float>(centre[a]);
  TraceSpans(c, spans, [&](RayBatch* batch) {
    intersect(batch);
    for (int lane = 0; lane < batch->active; ++lane) {
      const float t = batch->t[lane];
      if (!batch->is_target[lane] || t < c.sensor.near || t > c.sensor.far || t < nearest) continue;
      const Vec3 p(batch->point[0][lane], batch->point[1][lane], batch->point[2][lane]);
      const Vec3 n(batch->normal[0][lane], batch->normal[1][lane], batch->normal[2][lane]);
      if (!InApertureField(c.sensor, *aperture, rotation.transpose() * (p - origin))) continue;
      if (n.dot(centre - p) * n.dot(origin - p) <= 0) continue;
      const Vec3 d = p - centre;
      found.dir.push_back({static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2])});
    }
  });
  return found;
}

/// `segments` cast 16 to a packet into `occluded(OcclusionBatch*)`, each stopping 0.01 % short of
/// its point as observe's do.
template <class Occluded>
void CastSegments(const Segments& segments, const Occluded& occluded) {
  OcclusionBatch packet;
  for (int a = 0; a < 3; ++a) packet.origin[a] = segments.centre[a];
  packet.tfar = 1.0f - 1e-4f;
  const auto& dirs = segments.dir;
  for (size_t k0 = 0; k0 < dirs.size(); k0 += OcclusionBatch::kWidth) {
    const size_t lanes = std::min<size_t>(OcclusionBatch::kWidth, dirs.size() - k0);
    for (size_t lane = 0; lane < OcclusionBatch::kWidth; ++lane) {
      packet.query[lane] = lane < lanes;
      if (lane < lanes)
        for (int a = 0; a < 3; ++a) packet.dir[a][lane] = dirs[k0 + lane][a];
    }
    occluded(&packet);
  }
}

}  // namespace vantage::bench
