// The default viewpoint shared by report.html's 3D view and the rendered PNG (issue 16): a
// three-quarter view that frames the targets and the chosen sensors; the method colours and the
// frustum depth the two pictures share.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

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

// How much target surface a viewpoint sees (issue 43: a deep bin's parts hid behind its walls
// from the fixed three-quarter view). Points spread over the targets' surface by area, each
// counted when the segment from it to the eye meets no triangle of the scene; a brute-force
// probe (the report layer casts no Embree rays) that a work limit keeps cheap on large meshes.
class SurfaceProbe {
 public:
  explicit SurfaceProbe(const Scene& scene) {
    double total_area = 0;
    uint64_t triangle_count = 0;
    for (size_t o = 0; o < scene.objects.size(); ++o) {
      const TriangleMesh& mesh = scene.objects[o].mesh;
      if (mesh.IsEmpty()) continue;
      objects_.push_back({&mesh, mesh.Bounds(), Chunks(mesh)});
      triangle_count += mesh.triangles.size();
      if (scene.objects[o].is_target()) total_area += mesh.Area();
    }
    if (!(total_area > 0) || triangle_count == 0) return;
    // The samples times the triangles each segment may be tested against, per viewpoint.
    const uint64_t samples = std::min<uint64_t>(kMaxSamples, kWorkPerView / triangle_count);
    if (samples < kMinSamples) return;  // too large to probe: the fixed look stays
    // Systematic sampling over the targets' cumulative area; within a triangle, the R2
    // low-discrepancy sequence mapped uniformly onto it.
    const double step = total_area / static_cast<double>(samples);
    double next = 0.5 * step, cumulative = 0;
    uint64_t k = 0;
    for (const SceneObject& object : scene.objects) {
      if (!object.is_target()) continue;
      const TriangleMesh& mesh = object.mesh;
      for (const auto& tri : mesh.triangles) {
        const Vec3& a = mesh.vertices[tri[0]];
        const Vec3& b = mesh.vertices[tri[1]];
        const Vec3& c = mesh.vertices[tri[2]];
        cumulative += 0.5 * (b - a).cross(c - a).norm();
        for (; next < cumulative && k < samples; next += step, ++k) {
          const double r1 = std::fmod(0.5 + 0.7548776662466927 * static_cast<double>(k), 1.0);
          const double r2 = std::fmod(0.5 + 0.5698402909980532 * static_cast<double>(k), 1.0);
          const double s = std::sqrt(r1);
          samples_.push_back((1 - s) * a + s * (1 - r2) * b + s * r2 * c);
        }
      }
    }
  }

  bool usable() const { return !samples_.empty(); }

  /// The fraction of the samples that `eye` sees.
  double SeenFraction(const Vec3& eye) const {
    size_t seen = 0;
    for (const Vec3& p : samples_) seen += Blocked(p, eye) ? 0 : 1;
    return static_cast<double>(seen) / static_cast<double>(samples_.size());
  }

 private:
  static constexpr uint64_t kMaxSamples = 256, kMinSamples = 32;
  static constexpr uint64_t kWorkPerView = uint64_t{2} << 20;

  // Consecutive triangles (a mesh file's order is spatially coherent) under one box, widened a
  // little so that rounding in the box test never skips a triangle the segment meets.
  struct Chunk {
    Aabb bounds;
    uint32_t begin, end;
  };
  struct Object {
    const TriangleMesh* mesh;
    Aabb bounds;
    std::vector<Chunk> chunks;
  };
  static constexpr uint32_t kChunkTriangles = 32;

  static std::vector<Chunk> Chunks(const TriangleMesh& mesh) {
    std::vector<Chunk> chunks;
    const auto count = static_cast<uint32_t>(mesh.triangles.size());
    for (uint32_t begin = 0; begin < count; begin += kChunkTriangles) {
      Chunk chunk{Aabb{}, begin, std::min(count, begin + kChunkTriangles)};
      for (uint32_t t = chunk.begin; t < chunk.end; ++t)
        for (const uint32_t v : mesh.triangles[t]) chunk.bounds.Extend(mesh.vertices[v]);
      const Vec3 slack = Vec3::Constant(1e-9 * (chunk.bounds.max - chunk.bounds.min).norm() + 1e-12);
      chunk.bounds.min -= slack;
      chunk.bounds.max += slack;
      chunks.push_back(chunk);
    }
    return chunks;
  }

  // Whether a triangle lies on the open segment from `p` to `eye` (leaving p's own surface).
  bool Blocked(const Vec3& p, const Vec3& eye) const {
    const Vec3 d = eye - p;
    const double length = d.norm();
    if (!(length > 0)) return false;
    const double t_min = 1e-6 / length + 1e-9;  // a micrometre off the surface the point lies on
    for (const Object& object : objects_) {
      if (!SegmentMeetsBox(p, d, object.bounds)) continue;
      const TriangleMesh& mesh = *object.mesh;
      for (const Chunk& chunk : object.chunks) {
        if (!SegmentMeetsBox(p, d, chunk.bounds)) continue;
        for (uint32_t index = chunk.begin; index < chunk.end; ++index) {
          const auto& tri = mesh.triangles[index];
          const Vec3& a = mesh.vertices[tri[0]];
          const Vec3 e1 = mesh.vertices[tri[1]] - a, e2 = mesh.vertices[tri[2]] - a;
          // Möller–Trumbore.
          const Vec3 q = d.cross(e2);
          const double det = e1.dot(q);
          if (std::abs(det) < 1e-18) continue;
          const Vec3 s = p - a;
          const double u = s.dot(q) / det;
          if (u < 0 || u > 1) continue;
          const Vec3 r = s.cross(e1);
          const double v = d.dot(r) / det;
          if (v < 0 || u + v > 1) continue;
          const double t = e2.dot(r) / det;
          if (t > t_min && t < 1) return true;
        }
      }
    }
    return false;
  }

  static bool SegmentMeetsBox(const Vec3& p, const Vec3& d, const Aabb& box) {
    double lo = 0, hi = 1;
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(d[axis]) < 1e-300) {
        if (p[axis] < box.min[axis] || p[axis] > box.max[axis]) return false;
        continue;
      }
      double t0 = (box.min[axis] - p[axis]) / d[axis], t1 = (box.max[axis] - p[axis]) / d[axis];
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
      if (lo > hi) return false;
    }
    return true;
  }

  std::vector<Object> objects_;
  std::vector<Vec3> samples_;
};

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
  const auto along = [](double azimuth, double elevation) {
    return Vec3(std::cos(azimuth) * std::cos(elevation), std::sin(azimuth) * std::cos(elevation),
                std::sin(elevation));
  };
  // Of the two turns, the one that frames targets and sensors from closer (for 45° and a square
  // picture: the choice of side does not depend on the picture's size).
  std::vector<Vec3> points = framing.sensors;
  for (int corner = 0; corner < 8; ++corner) points.push_back(Corner(framing.targets, corner));
  double best_distance = 0;
  for (const double azimuth : azimuths) {
    const Vec3 direction = along(azimuth, 35.0 * kPi / 180.0);
    const View view = FitView(points, direction, kPi / 4, 1.0);
    const double distance = (view.eye - view.look_at).norm();
    if (best_distance == 0 || distance < best_distance) {
      framing.direction = direction;
      best_distance = distance;
    }
  }
  // Targets deep in a bin hide behind its walls from 35°: when that look sees less than half of
  // the target surface the best of the steeper looks (and the other sides) sees, the first look
  // seeing nearly as much as the best replaces it, lowest elevation first (issue 43).
  const SurfaceProbe probe(scene);
  if (!probe.usable()) return framing;
  const auto seen = [&](const Vec3& direction) {
    return probe.SeenFraction(FitView(points, direction, kPi / 4, 1.0).eye);
  };
  const double current = seen(framing.direction);
  // No look sees more than all of it: a first look seeing half stays without probing the others.
  if (current >= 0.5) return framing;
  std::vector<std::pair<Vec3, double>> looks;
  for (const double degrees : {35.0, 50.0, 65.0, 80.0}) {
    for (const double base : azimuths) {
      for (const double turn : {0.0, 0.5 * kPi, kPi, 1.5 * kPi})
        looks.emplace_back(along(base + turn, degrees * kPi / 180.0), 0.0);
    }
  }
  // Each look is probed on its own (the probe only reads the scene), in a fixed order of results.
  tbb::parallel_for(size_t{0}, looks.size(),
                    [&](size_t i) { looks[i].second = seen(looks[i].first); });
  double best = current;
  for (const auto& look : looks) best = std::max(best, look.second);
  if (current >= 0.5 * best) return framing;
  for (const auto& [direction, fraction] : looks) {
    if (fraction >= 0.95 * best) {
      framing.direction = direction;
      break;
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
  return FramedView(DefaultFraming(scene, report), vertical_fov, aspect, frame_also);
}

View FramedView(const Framing& framing, double vertical_fov, double aspect,
                const std::vector<Vec3>& frame_also) {
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
