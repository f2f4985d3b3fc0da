// The default viewpoint shared by report.html's 3D view and the rendered PNG (issue 16): a
// three-quarter view that frames the targets and the chosen sensors; the method colours and the
// frustum depth the two pictures share.
#include <algorithm>
#include <cmath>

#include "vantage/visualize.hpp"

namespace vantage {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The targets' bounds; without meshes (a page written from a visibility file), those of R's
// voxels; without either, those of the candidates.
Aabb TargetsOf(const Scene& scene, const Report& report) {
  Aabb bounds = scene.TargetBounds();
  if (!bounds.IsEmpty() || report.data == nullptr) return bounds;
  const double cell = report.data->reference.cell_size;
  for (uint64_t key : report.data->reference.keys) {
    const Vec3 c = VoxelCenter(key, cell);
    bounds.Extend(c - Vec3::Constant(0.5 * cell));
    bounds.Extend(c + Vec3::Constant(0.5 * cell));
  }
  if (!bounds.IsEmpty()) return bounds;
  for (const Candidate& c : report.data->candidates) bounds.Extend(c.world_from_body.position);
  return bounds;
}

// Corner `k` (0..7: bit 0 x, bit 1 y, bit 2 z at the maximum) of `box`.
Vec3 Corner(const Aabb& box, int k) {
  return Vec3(k & 1 ? box.max.x() : box.min.x(), k & 2 ? box.max.y() : box.min.y(),
              k & 4 ? box.max.z() : box.min.z());
}

}  // namespace

Rgb MethodColor(std::string_view method) {
  for (const MethodColorEntry& entry : kMethodColors) {
    if (entry.method == method) return entry.color;
  }
  return kOtherMethodColor;
}

Framing DefaultFraming(const Scene& scene, const Report& report) {
  Framing framing;
  framing.targets = TargetsOf(scene, report);
  if (framing.targets.IsEmpty()) framing.targets = Aabb{Vec3::Constant(-0.5), Vec3::Constant(0.5)};
  const Vec3 centre = 0.5 * (framing.targets.min + framing.targets.max);
  Vec3 mean = Vec3::Zero();
  if (report.data != nullptr && report.is_derived) {
    for (uint32_t index : report.PrimaryChosen()) {
      if (index >= report.data->candidates.size()) continue;
      const Vec3 p = report.data->candidates[index].world_from_body.position;
      const Vec3 d = p - centre;
      if (d.norm() > 1e-9) mean += d.normalized();
      // Every chosen sensor is framed (issue 46: a sensor left out of the frame hid the answer);
      // the page's "targets only" view and `render --eye` show small targets close up.
      framing.sensors.push_back(p);
    }
  }
  // Three-quarter view: 35° above the horizon, from the side the chosen sensors stand on (their
  // mean direction) turned by 30° so that sensors in one vertical plane do not overlap; a fixed
  // oblique azimuth when they surround the targets or stand right above them.
  std::vector<double> azimuths = {-50.0 * kPi / 180.0};
  const Vec3 horizontal(mean.x(), mean.y(), 0.0);
  const size_t count = framing.sensors.size();
  if (count > 0 && horizontal.norm() > 0.25 * static_cast<double>(count)) {
    const double side = std::atan2(horizontal.y(), horizontal.x());
    azimuths = {side - 30.0 * kPi / 180.0, side + 30.0 * kPi / 180.0};
  }
  const double elevation = 35.0 * kPi / 180.0;
  // Of the two turns, the one that frames targets and sensors from closer (for 45° and a square
  // picture: the choice of side does not depend on the picture's size).
  std::vector<Vec3> points = framing.sensors;
  for (int corner = 0; corner < 8; ++corner) points.push_back(Corner(framing.targets, corner));
  double best_distance = 0;
  for (const double azimuth : azimuths) {
    const Vec3 direction(std::cos(azimuth) * std::cos(elevation),
                         std::sin(azimuth) * std::cos(elevation), std::sin(elevation));
    const View view = FitView(points, direction, kPi / 4, 1.0);
    const double distance = (view.eye - view.look_at).norm();
    if (best_distance == 0 || distance < best_distance) {
      framing.direction = direction;
      best_distance = distance;
    }
  }
  return framing;
}

View FitView(const std::vector<Vec3>& points, const Vec3& direction, double vertical_fov,
             double aspect) {
  Aabb box;
  for (const Vec3& p : points) box.Extend(p);
  if (box.IsEmpty()) box = Aabb{Vec3::Constant(-0.5), Vec3::Constant(0.5)};
  View view;
  view.look_at = 0.5 * (box.min + box.max);
  const Vec3 d = direction.normalized();
  const Vec3 forward = -d;
  Vec3 right = forward.cross(Vec3::UnitZ());
  if (right.norm() < 1e-6) right = forward.cross(Vec3::UnitY());
  right.normalize();
  const Vec3 up = right.cross(forward).normalized();
  const double tan_y = std::tan(0.5 * vertical_fov), tan_x = tan_y * aspect;
  // A point p = look_at + v lies at depth distance - v·d in front of the eye: it is in the frame
  // (with a 5 % margin) when its lateral offsets stay within that depth times tan(fov/2).
  constexpr double kMargin = 1.05;
  const double radius = std::max(0.5 * (box.max - box.min).norm(), 1e-3);
  const auto fit = [&](const Vec3& centre) {
    double distance = 0.5 * radius;
    for (const Vec3& p : points) {
      const Vec3 v = p - centre;
      const double lateral = std::max(std::abs(v.dot(right)) / tan_x, std::abs(v.dot(up)) / tan_y);
      distance = std::max({distance, kMargin * lateral + v.dot(d), v.dot(d) + 0.2 * radius});
    }
    return distance;
  };
  double distance = fit(view.look_at);
  // Centre the picture on the points' extent in the image (not on their bounds' centre), which
  // lets the eye come closer: twice, each time moving the point looked at sideways to the middle
  // of the extent and fitting again.
  for (int round = 0; round < 2; ++round) {
    double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
    for (const Vec3& p : points) {
      const Vec3 v = p - view.look_at;
      const double depth = distance - v.dot(d);
      lo_x = std::min(lo_x, v.dot(right) / depth);
      hi_x = std::max(hi_x, v.dot(right) / depth);
      lo_y = std::min(lo_y, v.dot(up) / depth);
      hi_y = std::max(hi_y, v.dot(up) / depth);
    }
    const Vec3 centre = view.look_at + distance * (0.5 * (lo_x + hi_x) * right + 0.5 * (lo_y + hi_y) * up);
    const double closer = fit(centre);
    if (closer >= distance) break;
    view.look_at = centre;
    distance = closer;
  }
  view.eye = view.look_at + distance * d;
  return view;
}

View DefaultView(const Scene& scene, const Report& report, double vertical_fov, double aspect,
                 const std::vector<Vec3>& frame_also) {
  const Framing framing = DefaultFraming(scene, report);
  std::vector<Vec3> points = framing.sensors;
  points.insert(points.end(), frame_also.begin(), frame_also.end());
  for (int corner = 0; corner < 8; ++corner) points.push_back(Corner(framing.targets, corner));
  return FitView(points, framing.direction, vertical_fov, aspect);
}

double FrustumDepth(const Candidate& sensor, const Aabb& targets) {
  const double near = sensor.sensor.near, far = sensor.sensor.far;
  if (targets.IsEmpty()) return far;
  const Vec3 axis = sensor.world_from_body.rotation * Vec3::UnitX();
  const Vec3 apex = sensor.world_from_body.position;
  double depth = 0.0;
  for (int corner = 0; corner < 8; ++corner)
    depth = std::max(depth, (Corner(targets, corner) - apex).dot(axis));
  return std::clamp(depth, near, far);
}

}  // namespace vantage
