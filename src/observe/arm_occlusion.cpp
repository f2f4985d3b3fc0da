#include "observe/arm_occlusion.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "vantage/error.hpp"
#include "vantage/sensors.hpp"

namespace vantage::detail {

ArmOcclusion::ArmOcclusion(const RayScene& rays, std::span<const Candidate> candidates)
    : rays_(rays) {
  for (const Candidate& candidate : candidates) {
    if (!candidate.arm) continue;
    const ArmBody* body = candidate.arm->body.get();
    VANTAGE_CHECK(body != nullptr);
    if (links_.count(body)) continue;
    Links& links = links_[body];
    links.bodies = std::make_unique<RayBodies>(rays, body->link_meshes);
    for (const TriangleMesh& mesh : body->link_meshes) {
      Aabb box;
      for (const Vec3& v : mesh.vertices) box.Extend(v);
      links.bounds.push_back(box);
    }
  }
}

PlacedRayScene ArmOcclusion::Place(const ArmPose& arm) const {
  const auto found = links_.find(arm.body.get());
  VANTAGE_CHECK(found != links_.end());
  VANTAGE_CHECK(arm.world_from_link.size() == found->second.bodies->size());
  return PlacedRayScene(rays_, *found->second.bodies, arm.world_from_link);
}

std::optional<PlacedRayScene> ArmOcclusion::PlaceForView(const Candidate& candidate,
                                                         const std::vector<RowSpan>& spans) const {
  VANTAGE_CHECK(candidate.arm != nullptr);
  const ArmPose& arm = *candidate.arm;
  const auto found = links_.find(arm.body.get());
  VANTAGE_CHECK(found != links_.end());
  const Links& links = found->second;
  VANTAGE_CHECK(arm.world_from_link.size() == links.bodies->size());
  if (spans.empty()) return std::nullopt;  // no ray at all
  // The pixels' pyramid in the body frame (x forward): a ray through pixel (u, v) is
  // (1, -(u + 0.5 - cx) / fx, -(v + 0.5 - cy) / fy) (PixelRayInBody), so its y / x and z / x are
  // monotonic in u and v; one pixel wider all round (the flying-pixel filter's neighbours).
  const SensorType& s = candidate.sensor;
  int u_min = spans.front().u0, u_max = spans.front().u1;
  int v_min = spans.front().v, v_max = spans.front().v;
  for (const RowSpan& span : spans) {
    u_min = std::min(u_min, span.u0);
    u_max = std::max(u_max, span.u1);
    v_min = std::min(v_min, span.v);
    v_max = std::max(v_max, span.v);
  }
  const double y_low = -(u_max + 1 + 0.5 - s.cx) / s.fx, y_high = -(u_min - 1 + 0.5 - s.cx) / s.fx;
  const double z_low = -(v_max + 1 + 0.5 - s.cy) / s.fy, z_high = -(v_min - 1 + 0.5 - s.cy) / s.fy;
  // A segment from the second aperture's centre c to a hit p stays within |c - o| of the
  // pyramid (its point c + k (p - c) is (1 - k) (c - o) from o + k (p - o), inside); 1 cm more
  // for float rounding.
  double grow = 0.01;
  if (const SecondAperture* aperture = SecondApertureOf(s, candidate.type_id))
    grow += ApertureCentreInBody(*aperture).norm();
  const double far = s.far * (1 + 1e-6) + grow;
  const Mat3 body_from_world = candidate.world_from_body.rotation.toRotationMatrix().transpose();
  const Vec3& origin = candidate.world_from_body.position;
  // Beyond the plane n . q = 0 (n pointing out, unit) by more than `grow`, for all corners.
  const auto beyond = [&](const std::array<Vec3, 8>& corners, const Vec3& normal) {
    const Vec3 unit = normal.normalized();
    for (const Vec3& q : corners)
      if (unit.dot(q) <= grow) return false;
    return true;
  };
  std::vector<uint8_t> placed(links.bounds.size(), 0);
  bool any = false;
  for (size_t l = 0; l < links.bounds.size(); ++l) {
    const Aabb& box = links.bounds[l];
    if (box.IsEmpty()) continue;  // no mesh, never hit
    const Pose& world_from_link = arm.world_from_link[l];
    std::array<Vec3, 8> corners;
    for (int k = 0; k < 8; ++k) {
      const Vec3 local((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                       (k & 4) ? box.max.z() : box.min.z());
      corners[static_cast<size_t>(k)] = body_from_world * (world_from_link * local - origin);
    }
    const bool out = beyond(corners, Vec3(-1, 0, 0)) ||          // behind the camera
                     beyond(corners, Vec3(y_low, -1, 0)) ||       // y < y_low x
                     beyond(corners, Vec3(-y_high, 1, 0)) ||      // y > y_high x
                     beyond(corners, Vec3(z_low, 0, -1)) ||       // z < z_low x
                     beyond(corners, Vec3(-z_high, 0, 1)) ||      // z > z_high x
                     std::all_of(corners.begin(), corners.end(),  // beyond the far plane
                                 [&](const Vec3& q) { return q.x() > far; });
    if (out) continue;
    placed[l] = 1;
    any = true;
  }
  if (!any) return std::nullopt;
  return PlacedRayScene(rays_, *links.bodies, arm.world_from_link, placed);
}

}  // namespace vantage::detail
