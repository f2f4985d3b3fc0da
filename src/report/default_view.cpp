// The default viewpoint shared by report.html's 3D view and the rendered PNG.
#include <algorithm>
#include <cmath>

#include "vantage/visualize.hpp"

namespace vantage {

View DefaultView(const Scene& scene, const Report& report, double vertical_fov) {
  Aabb bounds = scene.TargetBounds();
  if (bounds.IsEmpty()) {
    for (const SceneObject& object : scene.objects) {
      if (!object.mesh.IsEmpty()) bounds.Extend(object.mesh.Bounds());
    }
  }
  std::vector<Vec3> sensors;
  if (report.data) {
    for (uint32_t index : report.PrimaryChosen()) {
      if (index < report.data->candidates.size())
        sensors.push_back(report.data->candidates[index].world_from_body.position);
    }
    if (bounds.IsEmpty()) {
      for (const Candidate& c : report.data->candidates) bounds.Extend(c.world_from_body.position);
    }
  }
  if (bounds.IsEmpty()) bounds = Aabb{Vec3::Constant(-0.5), Vec3::Constant(0.5)};
  View view;
  view.look_at = 0.5 * (bounds.min + bounds.max);

  // Frame the targets with room around them, and the chosen sensors that stand close to them;
  // far sensors are left out of the frame (their frusta still cross it), or the targets would
  // shrink to a few pixels.
  const double target_radius = std::max(0.5 * (bounds.max - bounds.min).norm(), 1e-3);
  double radius = 1.8 * target_radius;
  for (const Vec3& p : sensors) {
    const double d = (p - view.look_at).norm();
    if (d <= 3.0 * target_radius) radius = std::max(radius, 1.1 * d);
  }

  // Look from the side the chosen sensors look from, a little off their mean direction and from
  // above, so that the picture shows depth; a fixed oblique direction when there is none.
  const Vec3 oblique = Vec3(1.0, -1.2, 0.9).normalized();
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : sensors) {
    const Vec3 d = p - view.look_at;
    if (d.norm() > 1e-9) mean += d.normalized();
  }
  Vec3 direction = oblique;
  if (!sensors.empty() && mean.norm() > 0.2 * static_cast<double>(sensors.size()))
    direction = (mean.normalized() + 0.5 * oblique).normalized();
  direction.z() = std::max(direction.z(), 0.35);
  if (Vec3(direction.x(), direction.y(), 0).norm() < 0.2) direction += Vec3(0.3, -0.36, 0);
  direction.normalize();
  const double distance = 1.1 * radius / std::sin(0.5 * vertical_fov);
  view.eye = view.look_at + distance * direction;
  return view;
}

}  // namespace vantage
