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
  Overlay(const ViewCamera& camera, const std::vector<float>& depth)
      : camera_(camera), depth_(depth), alpha_(depth.size(), 0.0f) {}

  void Segment(const Vec3& a, const Vec3& b) {
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
      const Vec3 point = p + (q - p) * (static_cast<double>(i) / samples);
      double x = 0, y = 0;
      if (!camera_.Project(point, &x, &y)) continue;
      const double distance = (point - camera_.eye).norm();
      // Two pixels wide so that the lines stay visible at large sizes.
      Mark(x - 0.5, y - 0.5, distance);
      Mark(x + 0.5, y + 0.5, distance);
    }
  }

  void Disc(const Vec3& center, double radius_px) {
    double cx = 0, cy = 0;
    if (!camera_.Project(center, &cx, &cy)) return;
    const double distance = (center - camera_.eye).norm();
    for (double dy = -radius_px; dy <= radius_px; dy += 1.0) {
      for (double dx = -radius_px; dx <= radius_px; dx += 1.0) {
        if (dx * dx + dy * dy <= radius_px * radius_px) Mark(cx + dx, cy + dy, distance);
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
  void Mark(double x, double y, double distance) {
    // Tested as doubles: a point just in front of the eye projects to pixel ±1e10 and beyond,
    // which no int holds.
    if (!(x >= 0 && y >= 0 && x < camera_.width && y < camera_.height)) return;
    const int xi = static_cast<int>(x), yi = static_cast<int>(y);
    const size_t i =
        static_cast<size_t>(yi) * static_cast<size_t>(camera_.width) + static_cast<size_t>(xi);
    // Hidden behind the surface this pixel shows: drawn faintly.
    const bool is_visible = distance <= static_cast<double>(depth_[i]) * 1.002 + 1e-6;
    alpha_[i] = std::max(alpha_[i], is_visible ? 1.0f : 0.3f);
  }

  const ViewCamera& camera_;
  const std::vector<float>& depth_;
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
void DrawLegend(const Report& report, Image* image) {
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
  rows.emplace_back(kOccluderColor, "occluder");
  rows.emplace_back(kFrustumColor, "chosen sensors, frusta to the targets");
  const int scale = std::max(1, static_cast<int>(std::lround(image->height / 480.0)));
  const int line = 14 * scale, pad = 6 * scale, swatch = 9 * scale;
  int text_width = 0;
  for (const auto& row : rows) {
    std::string copy = row.second;
    text_width = std::max(text_width, stb_easy_font_width(copy.data()) * scale);
  }
  const int x0 = pad, y0 = pad;
  const int width = pad + swatch + pad + text_width + pad;
  const int height = pad + static_cast<int>(rows.size()) * line + pad / 2;
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

  View view = DefaultView(scene, report, options.vertical_fov,
                          static_cast<double>(options.width) / options.height);
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
            const RayHit hit = rays.IntersectHit(origin.data(), dir_f.data(),
                                                         std::numeric_limits<float>::infinity());
            Rgb color{};
            double shade = 1.0;
            if (hit.object < 0) {
              // Background: a soft vertical gradient.
              const double s = static_cast<double>(y) / options.height;
              color = {static_cast<uint8_t>(236 - 36 * s), static_cast<uint8_t>(239 - 33 * s),
                       static_cast<uint8_t>(243 - 25 * s)};
            } else {
              depth[i] = hit.t;
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
    Overlay overlay(camera, depth);
    const Aabb targets = DefaultFraming(scene, report).targets;
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
      overlay.Disc(apex, std::max(3.0, options.height / 160.0));
    }
    overlay.Composite(kFrustumColor, &image);
  }
  if (options.draw_legend) DrawLegend(report, &image);
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
