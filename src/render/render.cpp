// A picture without a browser (issue #7): the scene ray traced with Embree through the public
// RayScene of the observe stage, targets coloured by how many
// chosen sensors observe the voxel each pixel lands in, the chosen sensors' frusta drawn over it.
#include <fmt/format.h>
#include <stb_image_write.h>
// The legend's letters: stb's quad font (static functions, some unused here).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "util/atomic_file.hpp"
#include "vantage/error.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/render.hpp"

namespace vantage {
namespace {

constexpr double kPi = 3.14159265358979323846;
// From below: at most this many occluders are passed through along one ray, each from this far
// [m] beyond its hit (well under any cell, well over float's step at scene distances).
constexpr int kMaxOccludersPassed = 16;
constexpr double kPassStep = 1e-4;
// Markers carry their number up to this many chosen sensors (more would hide the picture).
constexpr size_t kMostNumberedSensors = 12;

// Packed voxel key -> number of chosen sensors that observe it (inside R and outside it).
std::unordered_map<uint64_t, int> ObservationCounts(const VisibilityFile& data,
                                                    const std::vector<uint32_t>& chosen) {
  std::unordered_map<uint64_t, int> counts;
  for (uint32_t index : chosen) {
    const Observation& o = data.observations.at(index);
    for (uint32_t r : o.reference_indices) ++counts[data.reference.keys.at(r)];
    for (uint64_t key : o.outside_keys) ++counts[key];
  }
  return counts;
}

// Drop lines and the markers' outlines: dark, unlike any surface colour.
constexpr Rgb kDropLineColor = {40, 48, 60};

Rgb TargetColor(int sensors_seeing) {
  if (sensors_seeing <= 0) return kUnobservedColor;
  return kObservedColors[static_cast<size_t>(std::min(sensors_seeing, 3) - 1)];
}

// Pinhole camera of the picture: right/up/forward basis, +z up in the world.
struct ViewCamera {
  Vec3 eye, forward, right, up;
  double tan_half_x = 1, tan_half_y = 1;
  int width = 0, height = 0;

  Vec3 RayThrough(double x, double y) const {
    const double sx = (2.0 * x / width - 1.0) * tan_half_x;
    const double sy = (1.0 - 2.0 * y / height) * tan_half_y;
    return (forward + sx * right + sy * up).normalized();
  }
  // Continuous pixel coordinates of a world point, nullopt behind the eye.
  bool Project(const Vec3& p, double* x, double* y) const {
    const Vec3 v = p - eye;
    const double z = v.dot(forward);
    if (z <= 1e-9) return false;
    *x = (v.dot(right) / (z * tan_half_x) + 1.0) * 0.5 * width;
    *y = (1.0 - v.dot(up) / (z * tan_half_y)) * 0.5 * height;
    return true;
  }
};

ViewCamera MakeCamera(const View& view, const RenderOptions& options) {
  ViewCamera camera;
  camera.eye = view.eye;
  camera.forward = (view.look_at - view.eye).normalized();
  Vec3 right = camera.forward.cross(Vec3::UnitZ());
  if (right.norm() < 1e-6) right = camera.forward.cross(Vec3::UnitY());  // looking straight up/down
  camera.right = right.normalized();
  camera.up = camera.right.cross(camera.forward).normalized();
  camera.width = options.width;
  camera.height = options.height;
  camera.tan_half_y = std::tan(0.5 * options.vertical_fov);
  camera.tan_half_x = camera.tan_half_y * options.width / options.height;
  return camera;
}

// Line overlay: per-pixel opacity (the strongest wins), composited once at the end so that
// overlapping samples do not accumulate.
class Overlay {
 public:
  /// `over_target`: per pixel, 1 where it shows a target; the lines there are drawn at
  /// `target_alpha` so that they do not bury the target's colours (issue 46).
  Overlay(const ViewCamera& camera, const std::vector<float>& depth,
          const std::vector<uint8_t>& over_target, float target_alpha = 1.0f)
      : camera_(camera),
        depth_(depth),
        over_target_(over_target),
        target_alpha_(target_alpha),
        alpha_(depth.size(), 0.0f) {}

  /// A line from a to b; `dash` > 0: dashes and gaps of that many pixels.
  void Segment(const Vec3& a, const Vec3& b, double dash = 0) {
    // Clip to the half-space in front of the eye, then sample at about two samples per pixel.
    Vec3 p = a, q = b;
    const double za = (p - camera_.eye).dot(camera_.forward),
                 zb = (q - camera_.eye).dot(camera_.forward);
    constexpr double kMinDepth = 1e-6;
    if (za <= kMinDepth && zb <= kMinDepth) return;
    if (za <= kMinDepth) p = p + (q - p) * ((kMinDepth - za) / (zb - za));
    if (zb <= kMinDepth) q = q + (p - q) * ((kMinDepth - zb) / (za - zb));
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (!camera_.Project(p, &x0, &y0) || !camera_.Project(q, &x1, &y1)) return;
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int samples = length < 20000.0 ? static_cast<int>(std::max(2.0, 2.0 * length)) : 40000;
    for (int i = 0; i <= samples; ++i) {
      // Samples are about half a pixel apart: a dash of `dash` pixels is 2 * dash samples.
      if (dash > 0 && static_cast<int>(i / (2.0 * dash)) % 2 == 1) continue;
      const Vec3 point = p + (q - p) * (static_cast<double>(i) / samples);
      double x = 0, y = 0;
      if (!camera_.Project(point, &x, &y)) continue;
      const double distance = (point - camera_.eye).norm();
      // Two pixels wide so that the lines stay visible at large sizes.
      Mark(x - 0.5, y - 0.5, distance);
      Mark(x + 0.5, y + 0.5, distance);
    }
  }

  /// A disc of `radius_px` around the point; markers are not dimmed over targets (they are small).
  void Disc(const Vec3& center, double radius_px) {
    double cx = 0, cy = 0;
    if (!camera_.Project(center, &cx, &cy)) return;
    const double distance = (center - camera_.eye).norm();
    for (double dy = -radius_px; dy <= radius_px; dy += 1.0) {
      for (double dx = -radius_px; dx <= radius_px; dx += 1.0) {
        if (dx * dx + dy * dy <= radius_px * radius_px)
          Mark(cx + dx, cy + dy, distance, /*dim_over_target=*/false);
      }
    }
  }

  void Composite(const Rgb& color, Image* image) const {
    for (size_t i = 0; i < alpha_.size(); ++i) {
      if (alpha_[i] <= 0.0f) continue;
      for (int c = 0; c < 3; ++c) {
        const float mixed = (1.0f - alpha_[i]) * static_cast<float>(image->rgb[3 * i + c]) +
                            alpha_[i] * static_cast<float>(color[c]);
        image->rgb[3 * i + c] = static_cast<uint8_t>(std::lround(std::clamp(mixed, 0.0f, 255.0f)));
      }
    }
  }

 private:
  void Mark(double x, double y, double distance, bool dim_over_target = true) {
    // Tested as doubles: a point just in front of the eye projects to pixel ±1e10 and beyond,
    // which no int holds.
    if (!(x >= 0 && y >= 0 && x < camera_.width && y < camera_.height)) return;
    const int xi = static_cast<int>(x), yi = static_cast<int>(y);
    const size_t i =
        static_cast<size_t>(yi) * static_cast<size_t>(camera_.width) + static_cast<size_t>(xi);
    // Hidden behind the surface this pixel shows: drawn faintly.
    const bool is_visible = distance <= static_cast<double>(depth_[i]) * 1.002 + 1e-6;
    float alpha = is_visible ? 1.0f : 0.3f;
    if (dim_over_target && over_target_[i]) alpha = std::min(alpha, target_alpha_);
    alpha_[i] = std::max(alpha_[i], alpha);
  }

  const ViewCamera& camera_;
  const std::vector<float>& depth_;
  const std::vector<uint8_t>& over_target_;
  float target_alpha_ = 1.0f;
  std::vector<float> alpha_;
};

// Corner of a sensor's image at `depth`, in the world: body x forward, u right = -y,
// v down = -z (sensors.hpp).
Vec3 FrustumCorner(const Candidate& c, double u, double v, double depth) {
  const SensorType& s = c.sensor;
  const Vec3 body(1.0, -(u - s.cx) / s.fx, -(v - s.cy) / s.fy);
  return c.world_from_body * (depth * body);
}

// Sensors observing the surface cell a pixel lands in: the cell of its exact hit point, as the
// observations count it (RayHit::point), so that a face on a cell boundary shows its own cells.
int CellCount(const std::unordered_map<uint64_t, int>& counts, const Vec3& point, double cell_size) {
  const VoxelIndex key = VoxelKeyOf(point, cell_size);
  if (!VoxelIndexFits(key)) return 0;
  const auto it = counts.find(PackVoxel(key));
  return it == counts.end() ? 0 : it->second;
}

// Fills the rectangle [x0, x1) x [y0, y1) with `color` at opacity `alpha`.
void FillRect(Image* image, int x0, int y0, int x1, int y1, const Rgb& color, double alpha) {
  for (int y = std::max(0, y0); y < std::min(image->height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(image->width, x1); ++x) {
      const size_t i = 3 * (static_cast<size_t>(y) * static_cast<size_t>(image->width) +
                            static_cast<size_t>(x));
      for (int c = 0; c < 3; ++c)
        image->rgb[i + c] = static_cast<uint8_t>(
            std::lround((1.0 - alpha) * image->rgb[i + c] + alpha * color[c]));
    }
  }
}

// `text` at (x, y) (its top left), stb_easy_font's quads scaled by `scale`.
void DrawText(Image* image, int x, int y, const std::string& text, int scale, const Rgb& color) {
  std::vector<char> buffer(text.size() * 300 + 64);
  std::string copy = text;
  const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(),
                                        static_cast<int>(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
    for (int v = 0; v < 4; ++v) {
      float xy[2];
      std::memcpy(xy, buffer.data() + 16 * (4 * q + v), sizeof(xy));
      for (int a = 0; a < 2; ++a) {
        lo[a] = std::min(lo[a], xy[a]);
        hi[a] = std::max(hi[a], xy[a]);
      }
    }
    FillRect(image, x + static_cast<int>(std::lround(lo[0] * scale)),
             y + static_cast<int>(std::lround(lo[1] * scale)),
             x + static_cast<int>(std::lround(hi[0] * scale)),
             y + static_cast<int>(std::lround(hi[1] * scale)), color, 1.0);
  }
}

// The legend, top left: the result shown in its method's colour, then the picture's colours.
void DrawLegend(const Report& report, const RenderOptions& options,
                const std::vector<std::pair<double, double>>& markers,
                const std::vector<uint8_t>& over_target, Image* image) {
  std::vector<std::pair<Rgb, std::string>> rows;
  if (report.primary >= 0) {
    const Selection& s = report.results.at(static_cast<size_t>(report.primary));
    rows.emplace_back(MethodColor(s.method),
                      fmt::format("{}, N = {}: coverage {:.2f} %", s.method, s.n, 100 * s.coverage));
  } else {
    rows.emplace_back(kOtherMethodColor, "no result: no chosen sensors");
  }
  rows.emplace_back(kUnobservedColor, "target not observed");
  for (size_t k = 0; k < kObservedColors.size(); ++k)
    rows.emplace_back(kObservedColors[k],
                      fmt::format("observed by {}{} chosen sensor{}", k + 1,
                                  k + 1 == kObservedColors.size() ? "+" : "", k ? "s" : ""));
  if (options.from_below) {
    rows.emplace_back(kOccluderColor, "seen from below, occluders left out");
  } else {
    rows.emplace_back(kOccluderColor, "occluder");
  }
  if (options.draw_markers || options.draw_frusta)
    rows.emplace_back(kFrustumColor, options.draw_frusta
                                         ? "chosen sensors (# as chosen), frusta to the targets"
                                         : "chosen sensors (# as chosen)");
  if (options.draw_markers) rows.emplace_back(kDropLineColor, "height: dashed line to the surface beneath");
  const int scale = std::max(1, static_cast<int>(std::lround(image->height / 480.0)));
  const int line = 14 * scale, pad = 6 * scale, swatch = 9 * scale;
  int text_width = 0;
  for (const auto& row : rows) {
    std::string copy = row.second;
    text_width = std::max(text_width, stb_easy_font_width(copy.data()) * scale);
  }
  const int width = pad + swatch + pad + text_width + pad;
  const int height = pad + static_cast<int>(rows.size()) * line + pad / 2;
  // The corner that hides no sensor marker and the least target surface (top left among equals):
  // the legend must not cover the answer.
  int x0 = pad, y0 = pad;
  long best = -1;
  for (int corner = 0; corner < 4; ++corner) {
    const int x = corner & 1 ? image->width - pad - width : pad;
    const int y = corner & 2 ? image->height - pad - height : pad;
    long cost = 0;
    for (const auto& [mx, my] : markers) {
      if (mx >= x - pad && mx < x + width + pad && my >= y - pad && my < y + height + pad)
        cost += 1000000;
    }
    for (int yy = std::max(0, y); yy < std::min(image->height, y + height); ++yy)
      for (int xx = std::max(0, x); xx < std::min(image->width, x + width); ++xx)
        cost += over_target[static_cast<size_t>(yy) * static_cast<size_t>(image->width) +
                            static_cast<size_t>(xx)];
    if (best < 0 || cost < best) {
      best = cost;
      x0 = x;
      y0 = y;
    }
  }
  FillRect(image, x0, y0, x0 + width, y0 + height, Rgb{255, 255, 255}, 0.85);
  for (size_t r = 0; r < rows.size(); ++r) {
    const int y = y0 + pad + static_cast<int>(r) * line;
    if (r == 0) {
      // The method's row as the chart draws a method (a line), not as a surface colour: local's
      // red must not read as "not observed".
      FillRect(image, x0 + pad, y + swatch / 2 - scale, x0 + pad + swatch, y + swatch / 2 + scale,
               rows[r].first, 1.0);
    } else {
      FillRect(image, x0 + pad, y, x0 + pad + swatch, y + swatch, rows[r].first, 1.0);
    }
    DrawText(image, x0 + pad + swatch + pad, y + scale, rows[r].second, scale, Rgb{29, 35, 43});
  }
}

// The lowest point of the scene's meshes (where a drop line ends when nothing lies below).
double LowestPoint(const Scene& scene) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const SceneObject& object : scene.objects) {
    if (!object.mesh.IsEmpty()) lowest = std::min(lowest, object.mesh.Bounds().min.z());
  }
  return lowest;
}

// The chosen sensors' markers, each a gold disc with a dark rim and (up to 12 sensors) its number
// in the order chosen, and a dashed line straight down from it to the first surface below (the
// height cue, issue 46).
void DrawMarkers(const RayScene& rays, const Scene& scene, const VisibilityFile& data,
                 const std::vector<uint32_t>& chosen, const ViewCamera& camera,
                 const std::vector<float>& depth, const std::vector<uint8_t>& over_target,
                 Image* image) {
  const double lowest = LowestPoint(scene);
  Overlay drops(camera, depth, over_target, 0.6f), rims(camera, depth, over_target),
      discs(camera, depth, over_target);
  const double radius = std::max(3.0, camera.height / 160.0);
  const std::array<float, 3> down = {0.0f, 0.0f, -1.0f};
  for (uint32_t index : chosen) {
    const Vec3 apex = data.candidates.at(index).world_from_body.position;
    const std::array<float, 3> origin = {static_cast<float>(apex.x()), static_cast<float>(apex.y()),
                                         static_cast<float>(apex.z())};
    const RayHit below =
        rays.IntersectHit(origin.data(), down.data(), std::numeric_limits<float>::infinity());
    const double foot_z = below.object >= 0 ? apex.z() - static_cast<double>(below.t)
                                            : std::min(lowest, apex.z());
    if (std::isfinite(foot_z) && apex.z() - foot_z > 1e-6) {
      const Vec3 foot(apex.x(), apex.y(), foot_z);
      drops.Segment(apex, foot, std::max(3.0, camera.height / 120.0));
      drops.Disc(foot, 0.5 * radius);
    }
    rims.Disc(apex, radius + std::max(1.0, radius / 3));
    discs.Disc(apex, radius);
  }
  drops.Composite(kDropLineColor, image);
  rims.Composite(kDropLineColor, image);
  discs.Composite(kFrustumColor, image);
  if (chosen.size() > kMostNumberedSensors) return;
  const int scale = std::max(1, static_cast<int>(std::lround(camera.height / 480.0)));
  for (size_t k = 0; k < chosen.size(); ++k) {
    double x = 0, y = 0;
    if (!camera.Project(data.candidates.at(chosen[k]).world_from_body.position, &x, &y)) continue;
    if (!(x >= 0 && y >= 0 && x < camera.width && y < camera.height)) continue;
    const std::string label = std::to_string(k + 1);
    std::string copy = label;
    const int text_width = stb_easy_font_width(copy.data()) * scale;
    const int left = static_cast<int>(x + radius) + 3 * scale, top = static_cast<int>(y - radius) - 9 * scale;
    FillRect(image, left - 2 * scale, top - scale, left + text_width + scale, top + 8 * scale,
             Rgb{255, 255, 255}, 0.85);
    DrawText(image, left, top, label, scale, kDropLineColor);
  }
}

}  // namespace

void RenderOptions::Validate() const {
  if (width < 16 || width > 8192)
    throw InputError(fmt::format("render: width {} must be within 16..8192", width));
  if (height < 16 || height > 8192)
    throw InputError(fmt::format("render: height {} must be within 16..8192", height));
  if (!(vertical_fov > 0 && vertical_fov < kPi))
    throw InputError(
        fmt::format("render: vertical_fov {} rad must be within (0, pi)", vertical_fov));
  // Both become ray origins and directions (issue 15: --eye 1e308 aborted in Embree).
  const auto check_point = [](const std::optional<Vec3>& point, const char* name) {
    if (point && !WorldPointProblem(*point).empty())
      throw InputError(fmt::format("render: {} at {}", name, WorldPointProblem(*point)));
  };
  check_point(eye, "eye (--eye)");
  check_point(look_at, "look_at (--look-at)");
}

Image RenderView(const RayScene& rays, const Scene& scene, const Report& report,
                 const RenderOptions& options) {
  options.Validate();
  VANTAGE_CHECK(report.data != nullptr);
  const VisibilityFile& data = *report.data;
  const std::vector<uint32_t>& chosen = report.PrimaryChosen();
  const std::unordered_map<uint64_t, int> counts = ObservationCounts(data, chosen);

  const Framing framing = DefaultFraming(scene, report);  // once: its surface probe costs
  View view = FramedView(framing, options.vertical_fov,
                         static_cast<double>(options.width) / options.height, options.frame_also);
  if (options.from_below) {
    // The same azimuth, as far under the horizon as the default is above it.
    // Framing the targets only: the underside is what this view is for.
    Framing below = framing;
    below.direction.z() = -below.direction.z();
    std::vector<Vec3> points;
    for (int corner = 0; corner < 8; ++corner)
      points.push_back(Vec3(corner & 1 ? below.targets.max.x() : below.targets.min.x(),
                            corner & 2 ? below.targets.max.y() : below.targets.min.y(),
                            corner & 4 ? below.targets.max.z() : below.targets.min.z()));
    view = FitView(points, below.direction, options.vertical_fov,
                   static_cast<double>(options.width) / options.height);
  }
  if (options.look_at) view.look_at = *options.look_at;
  if (options.eye) view.eye = *options.eye;
  if ((view.eye - view.look_at).norm() < 1e-9)
    throw InputError(fmt::format(
        "render: the eye ({}, {}, {}) is the point looked at — give two different points",
        view.eye.x(), view.eye.y(), view.eye.z()));
  const ViewCamera camera = MakeCamera(view, options);

  Image image;
  image.width = options.width;
  image.height = options.height;
  const size_t pixel_count =
      static_cast<size_t>(options.width) * static_cast<size_t>(options.height);
  image.rgb.assign(3 * pixel_count, 0);
  std::vector<float> depth(pixel_count, std::numeric_limits<float>::infinity());
  std::vector<uint8_t> over_target(pixel_count, 0);

  const Vec3 key_light = (-camera.forward + 0.8 * camera.up - 0.5 * camera.right).normalized();
  const double cell_size = data.reference.cell_size;
  const std::array<float, 3> origin = {static_cast<float>(view.eye.x()),
                                       static_cast<float>(view.eye.y()),
                                       static_cast<float>(view.eye.z())};
  // Rows fill preallocated slots by index: the picture does not depend on the thread count.
  tbb::parallel_for(
      tbb::blocked_range<int>(0, options.height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          for (int x = 0; x < options.width; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(options.width) +
                             static_cast<size_t>(x);
            const Vec3 dir = camera.RayThrough(x + 0.5, y + 0.5);
            const std::array<float, 3> dir_f = {static_cast<float>(dir.x()),
                                                static_cast<float>(dir.y()),
                                                static_cast<float>(dir.z())};
            RayHit hit = rays.IntersectHit(origin.data(), dir_f.data(),
                                           std::numeric_limits<float>::infinity());
            // From below, occluders are passed through: the ray goes on from just beyond each.
            for (int skipped = 0; options.from_below && hit.object >= 0 && !hit.is_target &&
                                  skipped < kMaxOccludersPassed;
                 ++skipped) {
              const double t = static_cast<double>(hit.t) + kPassStep;
              const std::array<float, 3> beyond = {
                  static_cast<float>(view.eye.x() + t * dir.x()),
                  static_cast<float>(view.eye.y() + t * dir.y()),
                  static_cast<float>(view.eye.z() + t * dir.z())};
              hit = rays.IntersectHit(beyond.data(), dir_f.data(),
                                      std::numeric_limits<float>::infinity());
              if (hit.object >= 0) hit.t = static_cast<float>(t + hit.t);
              if (skipped + 1 == kMaxOccludersPassed && !hit.is_target) hit.object = -1;
            }
            Rgb color{};
            double shade = 1.0;
            if (hit.object < 0) {
              // Background: a soft vertical gradient.
              const double s = static_cast<double>(y) / options.height;
              color = {static_cast<uint8_t>(236 - 36 * s), static_cast<uint8_t>(239 - 33 * s),
                       static_cast<uint8_t>(243 - 25 * s)};
            } else {
              depth[i] = hit.t;
              over_target[i] = hit.is_target ? 1 : 0;
              Vec3 normal(hit.normal[0], hit.normal[1], hit.normal[2]);
              if (normal.norm() > 0) normal.normalize();
              if (normal.dot(dir) > 0) normal = -normal;  // two-sided: the side facing the eye
              // A headlight (every visible face lit) plus a key light from the upper left of the
              // view, so that faces of different orientation differ.
              const double facing = normal.norm() > 0 ? -normal.dot(dir) : 1.0;
              const double key = std::max(0.0, normal.dot(key_light));
              shade = 0.3 + 0.45 * facing + 0.3 * key;
              if (hit.is_target) {
                const Vec3 point(hit.point[0], hit.point[1], hit.point[2]);
                color = TargetColor(CellCount(counts, point, cell_size));
              } else {
                // Neighbouring occluders (a table on a floor) differ a little in lightness.
                const double tint =
                    0.86 + 0.07 * static_cast<double>(static_cast<uint32_t>(hit.object) % 5) / 2.0;
                for (int c = 0; c < 3; ++c)
                  color[c] =
                      static_cast<uint8_t>(std::lround(std::min(255.0, tint * kOccluderColor[c])));
              }
            }
            for (int c = 0; c < 3; ++c)
              image.rgb[3 * i + c] =
                  static_cast<uint8_t>(std::lround(std::clamp(shade * color[c], 0.0, 255.0)));
          }
        }
      });

  if (options.draw_frusta) {
    // Faint over the targets: with several sensors their lines all converge there.
    Overlay overlay(camera, depth, over_target, 0.35f);
    const Aabb& targets = framing.targets;
    for (uint32_t index : chosen) {
      const Candidate& c = data.candidates.at(index);
      const Vec3 apex = c.world_from_body.position;
      const double w = c.sensor.width, h = c.sensor.height, d = FrustumDepth(c, targets);
      const std::array<Vec3, 4> corners = {FrustumCorner(c, 0, 0, d), FrustumCorner(c, w, 0, d),
                                           FrustumCorner(c, w, h, d), FrustumCorner(c, 0, h, d)};
      for (int k = 0; k < 4; ++k) {
        overlay.Segment(apex, corners[k]);
        overlay.Segment(corners[k], corners[(k + 1) % 4]);
      }
    }
    overlay.Composite(kFrustumColor, &image);
  }
  if (options.draw_markers) DrawMarkers(rays, scene, data, chosen, camera, depth, over_target, &image);
  if (options.draw_legend) {
    std::vector<std::pair<double, double>> markers;
    for (uint32_t index : chosen) {
      double x = 0, y = 0;
      if (camera.Project(data.candidates.at(index).world_from_body.position, &x, &y))
        markers.emplace_back(x, y);
    }
    DrawLegend(report, options, markers, over_target, &image);
  }
  return image;
}

Image RenderView(const Scene& scene, const Report& report, const RenderOptions& options) {
  options.Validate();
  return RenderView(RayScene(scene), scene, report, options);
}

void WritePng(const std::string& path, const Image& image) {
  VANTAGE_CHECK(image.width > 0 && image.height > 0 &&
                image.rgb.size() ==
                    3 * static_cast<size_t>(image.width) * static_cast<size_t>(image.height));
  // Encoded in memory, then written through a temporary and a rename (issue 15: writing straight
  // onto the path destroyed the earlier picture first and lost a full disk's error).
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<size_t>(size));
  };
  if (stbi_write_png_to_func(append, &png, image.width, image.height, 3, image.rgb.data(),
                             3 * image.width) == 0)
    throw InputError(AtPlace(path, 0, "cannot encode the PNG file"));
  detail::WriteFileAtomically(path, png);
}

}  // namespace vantage
