// Results people can look at (issue #7): the ray-traced PNG against analytic answers (a sphere
// seen from one side), the ROS static transforms, and report.html — self-contained, and opened in
// headless Chromium (no script error, no network request, a 3D view that is not blank, a chart).
#include "vantage/render.hpp"
#include "vantage/visualize.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string_view>

#include "test_util.hpp"
#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/reference.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kCell = 0.005;
constexpr double kRadius = 0.1;

// A camera at `eye` looking at `target`, square image, fine pixels (well below a cell at 1 m).
Candidate Camera(
    const std::string& name, const Vec3& eye, const Vec3& target, int pixels, double hfov) {
  Candidate c;
  c.name = name;
  c.sensor = SensorType::FromFov("test", pixels, pixels, hfov, std::nullopt, 0.05, 3.0);
  c.type_id = "test";
  c.world_from_body = Pose{eye, LookAt(eye, target)};
  return c;
}

Scene SphereScene(double radius) {
  Scene scene;
  scene.objects.push_back({"ball", Role::kTarget, MakeSphere(radius, kCell / 10), {}});
  return scene;
}

// A scene, its observed data and a report of one greedy selection of n sensors; not movable
// (the report points at the data).
struct SceneRun {
  Scene scene;
  VisibilityFile data;
  Report report;
};

std::unique_ptr<SceneRun> MakeRun(Scene scene, std::vector<Candidate> cameras, int n) {
  auto run = std::make_unique<SceneRun>();
  run->scene = std::move(scene);
  run->data.scene = "sphere (built in code)";
  run->data.reference = BuildReference(run->scene, ReferenceOptions{kCell});
  run->data.candidates = std::move(cameras);
  run->data.observations = Observe(run->scene, run->data.reference, run->data.candidates);
  SelectOptions options;
  options.n = n;
  options.method = Method::kGreedy;
  run->report.scene = run->data.scene;
  run->report.data = &run->data;
  run->report.results = Select(run->data.observations, run->data.reference.size(), options);
  DeriveReport(&run->report);
  return run;
}

// Pixel class by hue (shading scales colours): -1 neither target colour, 0 unobserved,
// k = observed by k (3 = three or more) chosen sensors.
int Classify(const Rgb& p) {
  const Eigen::Vector3d v(p[0], p[1], p[2]);
  if (v.norm() < 30) return -1;
  int best = -1;
  double best_cos = 0.995;
  const std::array<Rgb, 4> palette = {kUnobservedColor, kObservedColors[0], kObservedColors[1],
                                      kObservedColors[2]};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d c(palette[k][0], palette[k][1], palette[k][2]);
    const double cos = v.dot(c) / (v.norm() * c.norm());
    if (cos > best_cos) {
      best_cos = cos;
      best = k;
    }
  }
  return best;
}

struct Counts {
  int unobserved = 0;
  int observed = 0;
  std::array<int, 4> by_class = {0, 0, 0, 0};
  int frustum = 0;
  double ObservedShare() const {
    return observed + unobserved ? static_cast<double>(observed) / (observed + unobserved) : 0.0;
  }
};

Counts CountPixels(const Image& image) {
  Counts counts;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const Rgb p = image.At(x, y);
      if (p == kFrustumColor) ++counts.frustum;
      const int k = Classify(p);
      if (k < 0) continue;
      ++counts.by_class[k];
      (k == 0 ? counts.unobserved : counts.observed) += 1;
    }
  }
  return counts;
}

Image ReadPng(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(path.c_str(), &width, &height, &channels, 3);
  Image image;
  if (pixels == nullptr) return image;
  image.width = width;
  image.height = height;
  image.rgb.assign(pixels, pixels + 3 * static_cast<size_t>(width) * static_cast<size_t>(height));
  stbi_image_free(pixels);
  return image;
}

RenderOptions View(const Vec3& eye, int size, double fov) {
  RenderOptions options;
  options.width = options.height = size;
  options.vertical_fov = fov;
  options.eye = eye;
  options.look_at = Vec3::Zero();
  options.draw_frusta = false;
  options.draw_markers = false;
  return options;
}

// --------------------------------------------------------------------------------------------
// The picture

// One camera on +x at distance d sees the cap x > r²/d: (1 - r/d)/2 of the sphere. The picture
// must colour exactly what report.json counts: everything from the camera's own viewpoint, nothing
// from behind, and from the side the share of the disc with x > r²/d.
TEST(Render, VisibleCapIsColouredObservedAsTheReportCounts) {
  const double d = 1.0;
  const double hfov = 15.0 * kPi / 180.0;
  auto run =
      MakeRun(SphereScene(kRadius), {Camera("cam", Vec3(d, 0, 0), Vec3::Zero(), 600, hfov)}, 1);
  ASSERT_EQ(run->report.results.size(), 1u);
  const double coverage = run->report.results[0].coverage;
  EXPECT_NEAR(coverage, 0.5 * (1 - kRadius / d), 0.03);

  // From the camera itself: every target pixel observed.
  const Counts own =
      CountPixels(RenderView(run->scene, run->report, View(Vec3(d, 0, 0), 200, hfov)));
  EXPECT_GT(own.observed, 5000);
  EXPECT_GE(own.ObservedShare(), 0.98) << own.observed << " observed, " << own.unobserved << " not";

  // From behind: nothing observed.
  const Counts behind =
      CountPixels(RenderView(run->scene, run->report, View(Vec3(-d, 0, 0), 200, hfov)));
  EXPECT_GT(behind.unobserved, 5000);
  EXPECT_LE(behind.ObservedShare(), 0.02);

  // From the side (through the PNG file): the disc's share with x > a = r²/d,
  // (acos(a/r) - (a/r)·sqrt(1 - (a/r)²)) / pi.
  test::TempDir dir;
  const std::string png = dir.File("side.png");
  WritePng(png, RenderView(run->scene, run->report, View(Vec3(0, -3, 0), 300, 8.0 * kPi / 180.0)));
  const Image side = ReadPng(png);
  if (const char* keep = std::getenv("VANTAGE_KEEP_RENDER"); keep != nullptr && *keep) {
    RenderOptions with_frusta = View(Vec3(0.35, -0.9, 0.45), 640, 30.0 * kPi / 180.0);
    with_frusta.draw_frusta = true;
    WritePng(keep, RenderView(run->scene, run->report, with_frusta));
  }
  ASSERT_EQ(side.width, 300);
  ASSERT_EQ(side.height, 300);
  const double s = kRadius / d;
  const double expected = (std::acos(s) - s * std::sqrt(1 - s * s)) / kPi;
  const Counts counts = CountPixels(side);
  EXPECT_GT(counts.observed + counts.unobserved, 10000);
  EXPECT_NEAR(counts.ObservedShare(), expected, 0.03);
}

TEST(Render, CountsColoursAndFrustaOfTwoSensors) {
  const double hfov = 15.0 * kPi / 180.0;
  auto run = MakeRun(SphereScene(kRadius),
                     {Camera("east", Vec3(1, 0, 0), Vec3::Zero(), 500, hfov),
                      Camera("north", Vec3(0, 1, 0), Vec3::Zero(), 500, hfov)},
                     2);
  ASSERT_EQ(run->report.results[0].chosen.size(), 2u);
  RenderOptions options;
  options.width = 400;
  options.height = 300;
  const Counts counts = CountPixels(RenderView(run->scene, run->report, options));  // default view
  EXPECT_GT(counts.by_class[1], 500);             // seen by one sensor
  EXPECT_GT(counts.by_class[2], 100);             // the band both see
  EXPECT_EQ(counts.by_class[3], 0);               // no third sensor
  EXPECT_GT(counts.observed, counts.unobserved);  // the default view looks from the sensors' side
  EXPECT_GT(counts.frustum, 50);
  // Without frusta the markers stay (issue 46); without markers either, nothing is drawn.
  options.draw_frusta = false;
  const int markers_only = CountPixels(RenderView(run->scene, run->report, options)).frustum;
  EXPECT_GT(markers_only, 10);
  EXPECT_LT(markers_only, counts.frustum);
  options.draw_markers = false;
  EXPECT_EQ(CountPixels(RenderView(run->scene, run->report, options)).frustum, 0);
}

// Where a world point lands in a picture of `view`, as a pinhole with up +z (the picture's own
// camera, derived here from the view's definition); nullopt behind the eye.
std::optional<std::pair<double, double>> PixelOf(const struct View& view, const Vec3& p, int width,
                                                 int height, double fov) {
  const Vec3 forward = (view.look_at - view.eye).normalized();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized(), up = right.cross(forward);
  const Vec3 v = p - view.eye;
  const double depth = v.dot(forward);
  if (depth <= 0) return std::nullopt;
  const double t = std::tan(fov / 2);
  return std::make_pair((v.dot(right) / (depth * t * width / height) + 1) * 0.5 * width,
                        (1 - v.dot(up) / (depth * t)) * 0.5 * height);
}

// Every chosen camera is in the default picture however far it stands (issue 46: cameras beyond
// 12 target radii were left out): its gold marker is drawn where it projects.
TEST(Render, DefaultViewShowsEveryChosenCameraHoweverFar) {
  const std::vector<Vec3> eyes = {Vec3(0.4, 0.1, 0.3), Vec3(-3.5, 0.5, 0.4), Vec3(0.2, 2.9, 1.5)};
  std::vector<Candidate> cameras;
  for (size_t k = 0; k < eyes.size(); ++k)
    cameras.push_back(Camera("cam" + std::to_string(k), eyes[k], Vec3::Zero(), 200, 0.3));
  auto run = MakeRun(SphereScene(kRadius), cameras, 3);
  ASSERT_EQ(run->report.PrimaryChosen().size(), 3u);
  RenderOptions options;
  options.width = 400;
  options.height = 300;
  options.draw_frusta = false;
  const Image image = RenderView(run->scene, run->report, options);
  const struct View view = DefaultView(run->scene, run->report, options.vertical_fov, 4.0 / 3.0);
  for (const Vec3& eye : eyes) {
    const auto pixel = PixelOf(view, eye, options.width, options.height, options.vertical_fov);
    ASSERT_TRUE(pixel.has_value());
    const int x = static_cast<int>(pixel->first), y = static_cast<int>(pixel->second);
    ASSERT_TRUE(x >= 0 && y >= 0 && x < options.width && y < options.height)
        << "(" << eye.transpose() << ") projects to " << x << ", " << y;
    EXPECT_EQ(image.At(x, y), kFrustumColor) << "no marker at " << x << ", " << y;
  }
  // The sphere is in the picture too.
  EXPECT_GT(CountPixels(image).observed, 20);
}

// A camera 0.6 m above a floor (an occluder) gets a dashed dark line straight down to it: dark
// pixels along the projected segment from the marker to the floor point, none beyond the floor
// point on the segment's extension.
TEST(Render, DropLineRunsFromTheCameraDownToTheFloor) {
  Scene scene = SphereScene(kRadius);
  TriangleMesh floor = MakeBox(Vec3(3.0, 3.0, 0.02));
  floor.Transform(Pose{Vec3(0, 0, -0.11 - 0.01), Quat::Identity()});
  scene.objects.push_back({"floor", Role::kOccluder, std::move(floor), {}});
  const Vec3 apex(0.5, 0.2, 0.49);
  auto run = MakeRun(std::move(scene), {Camera("cam", apex, Vec3::Zero(), 200, 0.4)}, 1);
  RenderOptions options;
  options.width = options.height = 400;
  options.draw_frusta = false;
  options.eye = Vec3(2.0, -1.5, 0.8);
  options.look_at = Vec3(0.2, 0.1, 0.0);
  const Image image = RenderView(run->scene, run->report, options);
  const struct View view{*options.eye, *options.look_at};
  const auto top = PixelOf(view, apex, 400, 400, options.vertical_fov);
  const auto foot = PixelOf(view, Vec3(apex.x(), apex.y(), -0.11), 400, 400, options.vertical_fov);
  const auto below = PixelOf(view, Vec3(apex.x(), apex.y(), -0.45), 400, 400, options.vertical_fov);
  ASSERT_TRUE(top && foot && below);
  const auto dark = [&](double fx, double fy) {
    const int cx = static_cast<int>(fx), cy = static_cast<int>(fy);
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = cx + dx, y = cy + dy;
        if (x < 0 || y < 0 || x >= 400 || y >= 400) continue;
        const Rgb p = image.At(x, y);
        if (p[0] < 90 && p[1] < 95 && p[2] < 105) return true;
      }
    return false;
  };
  int on_line = 0, samples = 0;
  for (double t = 0.15; t <= 0.85; t += 0.02, ++samples)
    on_line += dark(top->first + t * (foot->first - top->first), top->second + t * (foot->second - top->second));
  EXPECT_GT(on_line, samples / 3) << on_line << " of " << samples;  // dashed: about half
  int beyond = 0;
  for (double t = 0.2; t <= 0.9; t += 0.05)
    beyond += dark(foot->first + t * (below->first - foot->first), foot->second + t * (below->second - foot->second));
  EXPECT_EQ(beyond, 0);
}

// From below with the occluders left out: a sphere resting in a cup-like floor box, seen by one
// camera above, shows its unseen underside in red; the default view (from above) shows mostly
// observed surface, the floor hiding the underside.
TEST(Render, FromBelowShowsTheUnseenUndersideThroughTheOccluders) {
  Scene scene = SphereScene(kRadius);
  TriangleMesh floor = MakeBox(Vec3(1.0, 1.0, 0.02));
  floor.Transform(Pose{Vec3(0, 0, -0.11), Quat::Identity()});
  scene.objects.push_back({"floor", Role::kOccluder, std::move(floor), {}});
  auto run = MakeRun(std::move(scene), {Camera("top", Vec3(0.05, 0.02, 0.8), Vec3::Zero(), 400, 0.5)}, 1);
  RenderOptions options;
  options.width = options.height = 300;
  options.draw_frusta = false;
  options.draw_markers = false;
  const Counts above = CountPixels(RenderView(run->scene, run->report, options));
  options.from_below = true;
  const Image below_image = RenderView(run->scene, run->report, options);
  const Counts below = CountPixels(below_image);
  EXPECT_GT(above.observed, above.unobserved);
  EXPECT_GT(below.unobserved, 1000);
  EXPECT_GT(below.unobserved, below.observed);
  // No occluder grey: the floor is left out.
  int grey = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 300; ++x) {
      const Rgb p = below_image.At(x, y);
      if (std::abs(p[0] - p[1]) < 4 && std::abs(p[1] - p[2]) < 4 && p[0] > 60 && p[0] < 200) ++grey;
    }
  EXPECT_LT(grey, 50);
}

// The default framing (issue 16): every framed point inside the picture, the frame tight (the
// farthest point at the 5 % margin), the eye 35° above the horizon.
TEST(DefaultView, FitViewFramesEveryPointTightly) {
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(0.2, 0.1, 0.05), Vec3(-0.6, 0.4, 0.7),
                                    Vec3(0.5, -0.5, 0.6), Vec3(0.1, 0.9, 0.65)};
  const double fov = 45.0 * kPi / 180.0, aspect = 4.0 / 3.0;
  const Vec3 direction = Vec3(std::cos(0.3) * std::cos(35 * kPi / 180), std::sin(0.3) * std::cos(35 * kPi / 180),
                              std::sin(35 * kPi / 180));
  const struct View view = FitView(points, direction, fov, aspect);
  const Vec3 forward = (view.look_at - view.eye).normalized();
  EXPECT_NEAR(-forward.z(), std::sin(35 * kPi / 180), 1e-9);
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized(), up = right.cross(forward);
  double largest = 0;
  for (const Vec3& p : points) {
    const Vec3 v = p - view.eye;
    const double depth = v.dot(forward);
    ASSERT_GT(depth, 0);
    const double x = v.dot(right) / (depth * std::tan(fov / 2) * aspect);
    const double y = v.dot(up) / (depth * std::tan(fov / 2));
    EXPECT_LE(std::abs(x), 1.0 / 1.05 + 1e-9);
    EXPECT_LE(std::abs(y), 1.0 / 1.05 + 1e-9);
    largest = std::max({largest, std::abs(x), std::abs(y)});
  }
  EXPECT_NEAR(largest, 1.0 / 1.05, 1e-6);
}

// A target floor at the bottom of a deep bin (issue 43): a line of sight below
// atan(0.4 / 0.28) = 55° cannot pass over a 0.4 m wall and reach a floor at most 0.28 m across
// (its diagonal), so the 35° look sees none of it and the default look turns steeper than that.
// (A 1 cm target 3 m above frames the view from far, as chosen sensors above a bin do; it is
// 0.1 % of the target surface.) Without the walls the 35° look sees the floor's top, half the
// target surface, as every other look does, and stays.
TEST(DefaultView, LooksIntoADeepBinInsteadOfAtItsWalls) {
  const auto scene_with = [](bool walls) {
    Scene scene;
    const auto add = [&](const char* name, Role role, const Vec3& size, const Vec3& centre) {
      TriangleMesh box = MakeBox(size);
      box.Transform(Pose{centre, Quat::Identity()});
      scene.objects.push_back({name, role, std::move(box), {}});
    };
    add("floor", Role::kTarget, Vec3(0.2, 0.2, 0.01), Vec3(0, 0, 0.005));
    add("marker", Role::kTarget, Vec3(0.01, 0.01, 0.01), Vec3(0, 0, 3.0));
    if (walls) {
      add("north", Role::kOccluder, Vec3(0.22, 0.01, 0.4), Vec3(0, 0.105, 0.2));
      add("south", Role::kOccluder, Vec3(0.22, 0.01, 0.4), Vec3(0, -0.105, 0.2));
      add("east", Role::kOccluder, Vec3(0.01, 0.2, 0.4), Vec3(0.105, 0, 0.2));
      add("west", Role::kOccluder, Vec3(0.01, 0.2, 0.4), Vec3(-0.105, 0, 0.2));
    }
    return scene;
  };
  const Report none;  // no result: the fixed oblique azimuth
  EXPECT_NEAR(DefaultFraming(scene_with(false), none).direction.z(), std::sin(35 * kPi / 180),
              1e-12);
  const Vec3 into = DefaultFraming(scene_with(true), none).direction;
  EXPECT_NEAR(into.norm(), 1.0, 1e-12);
  EXPECT_GT(std::atan2(into.z(), std::hypot(into.x(), into.y())), std::atan(0.4 / 0.28));
}

// Frusta end at the targets' far side: a sensor on +x at d looking at a cube of half-size r
// around the origin reaches depth d + r, and never beyond `far`.
TEST(DefaultView, FrustumDepthIsTheTargetsFarSideWithinFar) {
  Candidate c = Camera("cam", Vec3(1.0, 0, 0), Vec3::Zero(), 64, 0.5);
  const Aabb cube{Vec3::Constant(-0.1), Vec3::Constant(0.1)};
  EXPECT_NEAR(FrustumDepth(c, cube), 1.1, 1e-9);
  c.sensor.far = 0.8;
  EXPECT_NEAR(FrustumDepth(c, cube), 0.8, 1e-12);
  EXPECT_NEAR(FrustumDepth(c, Aabb{}), 0.8, 1e-12);
}

// The default view of the page and the picture frames the chosen sensors too, not only the
// targets (issue 16: the example's cameras were out of the frame).
TEST(DefaultView, FramesTheChosenSensors) {
  auto run = MakeRun(SphereScene(kRadius),
                     {Camera("high", Vec3(0.3, 0.2, 0.9), Vec3::Zero(), 200, 0.5),
                      Camera("side", Vec3(-0.8, 0.1, 0.1), Vec3::Zero(), 200, 0.5)},
                     2);
  const double fov = 45.0 * kPi / 180.0;
  const struct View view = DefaultView(run->scene, run->report, fov, 1.0);
  const Vec3 forward = (view.look_at - view.eye).normalized();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized(), up = right.cross(forward);
  for (const Vec3& p : {Vec3(0.3, 0.2, 0.9), Vec3(-0.8, 0.1, 0.1), Vec3(0.1, 0.1, 0.1),
                        Vec3(-0.1, -0.1, -0.1)}) {
    const Vec3 v = p - view.eye;
    const double depth = v.dot(forward);
    ASSERT_GT(depth, 0);
    EXPECT_LE(std::abs(v.dot(right)) / (depth * std::tan(fov / 2)), 1.0);
    EXPECT_LE(std::abs(v.dot(up)) / (depth * std::tan(fov / 2)), 1.0);
  }
}

// A box face that lies on a cell boundary shows whole cells (issue 16: moiré stripes). The
// target cube spans x from 0 to 10 cells, so its +x face lies exactly on the boundary x = 10
// cells; hit points placed at eye + t·d rounded to the layer on either side pixel by pixel.
// Every pixel now lands in the face's own cells, those R counts (half-open cells: the layer of
// the face's points, x = 10 — VoxelKeyOf, the metric's own rule), as observe places its hits
// (session 17: RayHit::point). Marked observed, that layer shows on every pixel of the face; the
// layer behind it (inside the cube, no cell of the face) on none.
TEST(Render, BoxFaceOnACellBoundaryShowsWholeCells) {
  Scene scene;
  TriangleMesh box = MakeBox(Vec3::Constant(10 * kCell));
  box.Transform(Pose{Vec3::Constant(5 * kCell), Quat::Identity()});
  scene.objects.push_back({"cube", Role::kTarget, std::move(box), {}});
  const Vec3 centre = Vec3::Constant(5 * kCell);
  const int64_t face_layer = VoxelKeyOf(Vec3(10 * kCell, 5 * kCell, 5 * kCell), kCell)[0];
  const auto layer = [](int64_t x) {
    Observation observed;
    for (int64_t y = 0; y < 10; ++y)
      for (int64_t z = 0; z < 10; ++z) observed.outside_keys.push_back(PackVoxel({x, y, z}));
    std::sort(observed.outside_keys.begin(), observed.outside_keys.end());
    return observed;
  };
  const std::array<Vec3, 2> eyes = {Vec3(centre + Vec3(0.4, 0.0, 0.0)),
                                    Vec3(centre + Vec3(0.4, 0.013, -0.021))};
  for (const int64_t x : {face_layer, face_layer - 1}) {
    auto run = MakeRun(Scene(scene), {Camera("front", centre + Vec3(0.4, 0, 0), centre, 64, 0.3)}, 1);
    run->data.observations[0] = layer(x);
    for (const Vec3& eye : eyes) {
      RenderOptions options = View(eye, 240, 0.12);
      options.look_at = centre;
      const Counts counts = CountPixels(RenderView(run->scene, run->report, options));
      if (x == face_layer) {
        EXPECT_GT(counts.observed, 10000);
        EXPECT_EQ(counts.unobserved, 0) << counts.observed << " observed";
      } else {
        EXPECT_EQ(counts.observed, 0) << counts.unobserved << " unobserved";
        EXPECT_GT(counts.unobserved, 10000);
      }
    }
  }
}

TEST(Render, BadOptionsAndUnwritablePathsAreInputErrors) {
  auto run =
      MakeRun(SphereScene(kRadius), {Camera("cam", Vec3(1, 0, 0), Vec3::Zero(), 64, 0.3)}, 1);
  RenderOptions options;
  options.width = 0;
  EXPECT_THROW(RenderView(run->scene, run->report, options), InputError);
  options = View(Vec3(0.5, 0.5, 0.5), 32, 0.5);
  options.look_at = Vec3(0.5, 0.5, 0.5);
  EXPECT_THROW(RenderView(run->scene, run->report, options), InputError);
  options.vertical_fov = kPi;
  EXPECT_THROW(RenderView(run->scene, run->report, options), InputError);
  const Image image = RenderView(run->scene, run->report, View(Vec3(1, 1, 1), 32, 0.5));
  try {
    WritePng("/nonexistent-folder/x/view.png", image);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/x/view.png:"), std::string::npos)
        << e.what();
  }
}

// --------------------------------------------------------------------------------------------
// Static transforms

// docs/outputs.md, Frame names: every name of up to 4 bytes over an alphabet that holds the
// encoding's own escape '.', SDF's "::", a space, a non-ASCII byte and the optical suffix's
// letters gives a distinct frame, of the frame alphabet only, that decodes back to the name, is
// never another camera's optical frame or joint, and never the parent frame (issue 44).
TEST(StaticTransforms, FrameNamesAreUniqueAndReversibleOverEveryShortName) {
  const std::string alphabet = std::string("._: a-1") + '\xc3';
  std::vector<std::string> names = {"cam_optical", "cam_optical_frame", "cam", "world",
                                    "x_optical_optical", "_optical", "cam--left", "$(arg x)"};
  std::vector<std::string> level = {""};
  for (int length = 1; length <= 4; ++length) {
    std::vector<std::string> next;
    for (const std::string& prefix : level)
      for (const char c : alphabet) next.push_back(prefix + c);
    names.insert(names.end(), next.begin(), next.end());
    level = std::move(next);
  }
  std::map<std::string, std::string> frames;  // frame -> name
  for (const std::string& name : names) {
    const std::string frame = ExportedFrameName(name);
    ASSERT_TRUE(frames.emplace(frame, name).second)
        << "'" << name << "' and '" << frames[frame] << "' share the frame " << frame;
    EXPECT_EQ(SensorNameOfFrame(frame), name);
    for (const char c : frame)
      EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')
          << frame;
    EXPECT_NE(frame, "world");
  }
  for (const auto& [frame, name] : frames) {
    EXPECT_FALSE(frames.contains(frame + "_optical_frame")) << name;
    EXPECT_FALSE(frames.contains(frame + "_optical")) << name;  // its joint would clash
  }
  EXPECT_EQ(ExportedFrameName("d415_overhead_35"), "d415_overhead_35");
  EXPECT_EQ(ExportedFrameName("rig::wrist"), "rig..wrist");
  EXPECT_EQ(ExportedFrameName("cam 1"), "cam.201");
  EXPECT_EQ(ExportedFrameName("base_link", "base_link"), ".62ase_link");
  EXPECT_THROW(SensorNameOfFrame("a.zz"), InputError);
  EXPECT_THROW(SensorNameOfFrame("a b"), InputError);
}

TEST(StaticTransforms, ChosenSensorsWithRosQuaternionsAndOpticalFrames) {
  const Vec3 eye(0.8, 0.3, 0.5);
  auto run = MakeRun(SphereScene(kRadius),
                     {Camera("cam_a", eye, Vec3::Zero(), 64, 0.5),
                      Camera("cam_b", Vec3(-0.9, 0, 0.1), Vec3::Zero(), 64, 0.5)},
                     2);
  const YAML::Node yaml = YAML::Load(StaticTransformsYaml(run->report, "base_link"));
  EXPECT_EQ(yaml["schema"].as<std::string>(), "vantage.static_transforms/1");
  const YAML::Node transforms = yaml["transforms"];
  ASSERT_EQ(transforms.size(), 4u);
  for (size_t k = 0; k < 2; ++k) {
    const Candidate& c = run->data.candidates[run->report.results[0].chosen[k]];
    const YAML::Node body = transforms[2 * k];
    const YAML::Node optical = transforms[2 * k + 1];
    EXPECT_EQ(body["name"].as<std::string>(), c.name);
    EXPECT_EQ(body["parent_frame"].as<std::string>(), "base_link");
    EXPECT_EQ(body["child_frame"].as<std::string>(), c.name);
    const auto xyz = body["xyz"].as<std::vector<double>>();
    EXPECT_TRUE(Vec3(xyz[0], xyz[1], xyz[2]).isApprox(c.world_from_body.position, 1e-8));
    const auto q = body["quaternion_xyzw"].as<std::vector<double>>();
    const Quat world_from_body(q[3], q[0], q[1], q[2]);  // Eigen's constructor takes w first
    EXPECT_NEAR(std::abs(world_from_body.dot(c.world_from_body.rotation)), 1.0, 1e-8);
    EXPECT_EQ(optical["name"].as<std::string>(), c.name + "_optical_frame");
    EXPECT_EQ(optical["parent_frame"].as<std::string>(), c.name);
    const auto o = optical["quaternion_xyzw"].as<std::vector<double>>();
    const Quat body_from_optical(o[3], o[0], o[1], o[2]);
    // The optical frame's z looks where the camera looks; its x is the image's right, y down.
    const Mat3 world_from_optical = (world_from_body * body_from_optical).toRotationMatrix();
    const Vec3 forward = (Vec3::Zero() - c.world_from_body.position).normalized();
    EXPECT_TRUE(world_from_optical.col(2).isApprox(forward, 1e-6));
    EXPECT_TRUE(
        world_from_optical.col(0).isApprox(-(c.world_from_body.rotation * Vec3::UnitY()), 1e-6));
    EXPECT_TRUE(
        world_from_optical.col(1).isApprox(-(c.world_from_body.rotation * Vec3::UnitZ()), 1e-6));
  }
  run->report.results.clear();
  DeriveReport(&run->report);
  const YAML::Node empty = YAML::Load(StaticTransformsYaml(run->report));
  EXPECT_EQ(empty["transforms"].size(), 0u);
}

// --------------------------------------------------------------------------------------------
// report.html

std::string DataJsonOf(const std::string& html) {
  const std::string open = R"(<script id="vantage-data" type="application/json">)";
  const size_t begin = html.find(open);
  if (begin == std::string::npos) return "";
  const size_t end = html.find("</script>", begin);
  return html.substr(begin + open.size(), end - begin - open.size());
}

// True when an attribute src= or href= (any case, spaces and a quote allowed) names a network or
// protocol-relative URL: "//host" or "http(s)://host".
bool LoadsFromElsewhere(std::string html) {
  std::transform(html.begin(), html.end(), html.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const auto skip_spaces = [&](size_t i) {
    while (i < html.size() && std::isspace(static_cast<unsigned char>(html[i]))) ++i;
    return i;
  };
  for (const std::string_view attribute : {"src", "href"}) {
    for (size_t at = html.find(attribute); at != std::string::npos;
         at = html.find(attribute, at + 1)) {
      size_t i = skip_spaces(at + attribute.size());
      if (i >= html.size() || html[i] != '=') continue;
      i = skip_spaces(i + 1);
      if (i < html.size() && (html[i] == '"' || html[i] == '\'')) ++i;
      i = skip_spaces(i);
      for (const std::string_view scheme : {"https:", "http:"})
        if (html.compare(i, scheme.size(), scheme) == 0) i += scheme.size();
      if (html.compare(i, 2, "//") == 0) return true;
    }
  }
  return false;
}

size_t CountOf(const std::string& text, const std::string& what) {
  size_t count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

bool HasThreeJs() {
  return std::filesystem::exists(HtmlReportOptions{}.three_js_dir + "/three.min.js") &&
         std::filesystem::exists(HtmlReportOptions{}.three_js_dir +
                                 "/examples/js/controls/OrbitControls.js");
}

TEST(HtmlReport, SelfContainedEscapedAndWithoutNetworkUrls) {
  auto run = MakeRun(
      SphereScene(kRadius),
      {Camera("cam</script><img src=x onerror=alert(1)>", Vec3(1, 0, 0), Vec3::Zero(), 64, 0.5),
       Camera("plain", Vec3(0, 1, 0), Vec3::Zero(), 64, 0.5)},
      2);
  const std::string html = HtmlReport(run->report, run->scene);
  // No element loads anything from elsewhere: no src/href to a network (or protocol-relative) URL.
  EXPECT_FALSE(LoadsFromElsewhere(html));
  EXPECT_EQ(html.find("<link"), std::string::npos);
  // Every <script> is closed once: the hostile name did not end one early.
  EXPECT_EQ(CountOf(html, "<script"), CountOf(html, "</script>"));
  EXPECT_NE(html.find("id=\"vantage-status\""), std::string::npos);
  const nlohmann::json data = nlohmann::json::parse(DataJsonOf(html));
  EXPECT_EQ(data["candidates"][0]["name"], "cam</script><img src=x onerror=alert(1)>");
  EXPECT_EQ(data["chosen"].size(), 2u);
  EXPECT_EQ(data["voxels"]["count"], run->data.reference.size());
  double gains = 0;
  for (const auto& s : data["chosen"]) gains += s["marginal_gain"].get<double>();
  EXPECT_NEAR(gains, run->report.results[0].coverage, 1e-12);
  if (HasThreeJs()) {
    EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);
    EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  }

  // Without three.js: a page all the same, saying why there is no 3D view.
  HtmlReportOptions options;
  options.three_js_dir = "/nonexistent/three";
  const std::string bare = HtmlReport(run->report, run->scene, options);
  EXPECT_EQ(bare.find("REVISION"), std::string::npos);
  EXPECT_NE(DataJsonOf(bare).find("three.js r111 was not found"), std::string::npos);

  // Huge meshes are simplified for the page, and the page says so.
  options = HtmlReportOptions{};
  options.max_mesh_triangles = 400;
  ASSERT_GT(run->scene.TriangleCount(), 400u);
  const nlohmann::json small =
      nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene, options)));
  const std::string indices = small["meshes"][0]["indices"];
  EXPECT_LE(indices.size() * 3 / 4 / 12, 400u);
  EXPECT_GT(indices.size() * 3 / 4 / 12, 50u);
  EXPECT_NE(small["notes"].dump().find("simplified from"), std::string::npos);
}

std::vector<uint8_t> Base64Decoded(const std::string& text) {
  const std::string alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<uint8_t> bytes;
  uint32_t bits = 0;
  int count = 0;
  for (const char ch : text) {
    if (ch == '=') break;
    bits = (bits << 6) | static_cast<uint32_t>(alphabet.find(ch));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<uint8_t>(bits >> count));
    }
  }
  return bytes;
}

template <typename T>
std::vector<T> Base64Values(const std::string& text) {
  const std::vector<uint8_t> bytes = Base64Decoded(text);
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

// Vertex clustering written as its definition reads, one scan with ordered maps: each vertex
// joins the cluster of its cell (numbered as cells are first met), a cluster sits at the mean of
// its vertices, a triangle is dropped when two corners share a cluster or its corners repeat an
// earlier triangle's.
TriangleMesh ClusteredAsDefined(const TriangleMesh& mesh, double cell) {
  std::map<std::array<int64_t, 3>, uint32_t> cluster_of_cell;
  std::vector<uint32_t> cluster;
  std::vector<Vec3> sums;
  std::vector<int> counts;
  for (const Vec3& v : mesh.vertices) {
    const std::array<int64_t, 3> key = {static_cast<int64_t>(std::floor(v.x() / cell)),
                                        static_cast<int64_t>(std::floor(v.y() / cell)),
                                        static_cast<int64_t>(std::floor(v.z() / cell))};
    const auto [it, is_new] = cluster_of_cell.emplace(key, static_cast<uint32_t>(sums.size()));
    if (is_new) {
      sums.push_back(Vec3::Zero());
      counts.push_back(0);
    }
    cluster.push_back(it->second);
    sums[it->second] += v;
    ++counts[it->second];
  }
  TriangleMesh out;
  for (size_t i = 0; i < sums.size(); ++i) out.vertices.push_back(sums[i] / counts[i]);
  std::set<std::array<uint32_t, 3>> seen;
  for (const auto& t : mesh.triangles) {
    const std::array<uint32_t, 3> c = {cluster[t[0]], cluster[t[1]], cluster[t[2]]};
    std::array<uint32_t, 3> corners = c;
    std::sort(corners.begin(), corners.end());
    if (corners[0] == corners[1] || corners[1] == corners[2]) continue;
    if (seen.insert(corners).second) out.triangles.push_back(c);
  }
  return out;
}

// The page's meshes are the scene's clustered at the smallest cell of the documented sequence
// (1/4096 of the scene's diagonal, times 1.4 a round) whose triangles fit the budget: every mesh,
// vertex for vertex (as float) and index for index.
std::vector<uint8_t> FromBase64(const std::string& text) {
  static const std::string alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<uint8_t> out;
  uint32_t buffer = 0;
  int bits = 0;
  for (const char c : text) {
    if (c == '=') break;
    buffer = (buffer << 6) | static_cast<uint32_t>(alphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

// The page's what-if data (issue 46) decoded as docs/outputs.md describes it gives back every
// candidate's observed cells exactly, whichever form each took; the parts are the cells each
// target alone would give R (two spheres apart), adding up to |R|.
TEST(HtmlReport, WhatIfSetsAndPartsDecodeToTheObservations) {
  Scene scene = SphereScene(kRadius);
  TriangleMesh second = MakeSphere(0.05, kCell / 10);
  second.Transform(Pose{Vec3(0.4, 0, 0), Quat::Identity()});
  scene.objects.push_back({"small", Role::kTarget, second, {}});
  Scene small_only;
  small_only.objects.push_back({"small", Role::kTarget, second, {}});
  const size_t small_cells = BuildReference(small_only, ReferenceOptions{kCell}).size();
  const size_t ball_cells = BuildReference(SphereScene(kRadius), ReferenceOptions{kCell}).size();
  auto run = MakeRun(std::move(scene),
                     {Camera("east", Vec3(1.2, 0, 0), Vec3::Zero(), 300, 0.6),
                      Camera("north", Vec3(0.1, 1.0, 0.2), Vec3::Zero(), 16, 0.5),
                      Camera("none", Vec3(5, 0, 3), Vec3(6, 0, 3), 16, 0.2)},
                     2);
  const nlohmann::json data = nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene)));
  ASSERT_TRUE(data["whatif"].is_object());
  const size_t cells = run->data.reference.size();
  EXPECT_EQ(data["whatif"]["cells"], cells);
  const std::vector<uint8_t> raw = FromBase64(data["whatif"]["sets"]);
  size_t at = 0;
  const auto varint = [&] {
    uint64_t value = 0;
    for (int shift = 0;; shift += 7) {
      const uint8_t b = raw.at(at++);
      value |= uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) return value;
    }
  };
  std::set<int> modes;
  for (size_t c = 0; c < run->data.candidates.size(); ++c) {
    const uint64_t head = varint();
    std::vector<uint32_t> decoded;
    modes.insert(static_cast<int>(head & 1));
    if (head & 1) {
      for (size_t r = 0; r < cells; ++r)
        if (raw.at(at + r / 8) & (1 << (r % 8))) decoded.push_back(static_cast<uint32_t>(r));
      at += (cells + 7) / 8;
    } else {
      int64_t r = -1;
      for (uint64_t k = 0; k < head >> 1; ++k) {
        r += static_cast<int64_t>(varint()) + 1;
        decoded.push_back(static_cast<uint32_t>(r));
      }
    }
    EXPECT_EQ(decoded.size(), head >> 1);
    EXPECT_EQ(decoded, run->data.observations[c].reference_indices) << run->data.candidates[c].name;
  }
  EXPECT_EQ(at, raw.size());
  EXPECT_EQ(modes.size(), 2u) << "expected a bitset (east sees much) and a list (north sees little)";
  ASSERT_EQ(data["whatif"]["parts"].size(), 2u);
  EXPECT_EQ(data["whatif"]["parts"][0]["name"], "ball");
  EXPECT_EQ(data["whatif"]["parts"][0]["cells"], ball_cells);
  EXPECT_EQ(data["whatif"]["parts"][1]["name"], "small");
  EXPECT_EQ(data["whatif"]["parts"][1]["cells"], small_cells);
  EXPECT_EQ(ball_cells + small_cells, cells);
  // Every chosen sensor is framed (the page fits its view to these points).
  EXPECT_EQ(data["view"]["sensors"].size(), run->report.PrimaryChosen().size());

  // Above the budget: no what-if, and a note that says why.
  HtmlReportOptions small_budget;
  small_budget.max_whatif_bytes = 100;
  const nlohmann::json without =
      nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene, small_budget)));
  EXPECT_TRUE(without["whatif"].is_null());
  EXPECT_NE(without["notes"].dump().find("what-if layout is not offered"), std::string::npos);
}

// The page's parts come from R's part_of (issue 47) exactly as from clipping every target triangle
// again: two overlapping spheres, so that the cells both touch go to the first in scene order,
// and the second's count is below what it alone would give R.
TEST(HtmlReport, WhatIfPartsFromReferenceEqualClippingAgain) {
  Scene scene = SphereScene(kRadius);
  TriangleMesh second = MakeSphere(kRadius, kCell / 10);
  second.Transform(Pose{Vec3(kRadius, 0, 0), Quat::Identity()});
  scene.objects.push_back({"second", Role::kTarget, second, {}});
  Scene second_only;
  second_only.objects.push_back({"second", Role::kTarget, second, {}});
  const size_t second_alone = BuildReference(second_only, ReferenceOptions{kCell}).size();
  auto run = MakeRun(std::move(scene), {Camera("east", Vec3(1.2, 0, 0), Vec3::Zero(), 64, 0.6)}, 1);
  const nlohmann::json from_r =
      nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene)))["whatif"];
  run->data.reference.part_of.clear();  // R without its parts: the page clips the targets again
  const nlohmann::json clipped =
      nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene)))["whatif"];
  ASSERT_EQ(from_r["parts"].size(), 2u);
  EXPECT_EQ(from_r["parts"], clipped["parts"]);
  EXPECT_EQ(from_r["cell_part"], clipped["cell_part"]);
  EXPECT_EQ(from_r["parts"][1]["name"], "second");
  EXPECT_LT(from_r["parts"][1]["cells"].get<size_t>(), second_alone);
  EXPECT_EQ(from_r["parts"][0]["cells"].get<size_t>() + from_r["parts"][1]["cells"].get<size_t>(),
            run->data.reference.size());
}

TEST(HtmlReport, SimplifiedMeshesAreVertexClusteringAtTheSmallestCellThatFits) {
  Scene scene = SphereScene(kRadius);
  TriangleMesh box = MakeBox(Vec3(0.3, 0.05, 0.2));
  for (Vec3& v : box.vertices) v += Vec3(0, 0.3, -0.05);
  box.triangles.push_back(box.triangles.front());  // a repeated triangle: drawn once
  scene.objects.push_back({"wall", Role::kOccluder, box, {}});
  auto run = MakeRun(std::move(scene), {Camera("cam", Vec3(1, 0, 0), Vec3::Zero(), 64, 0.5)}, 1);

  Aabb bounds;
  for (const SceneObject& object : run->scene.objects) bounds.Extend(object.mesh.Bounds());
  const double diagonal = (bounds.max - bounds.min).norm();
  for (const size_t budget : {size_t{1992}, size_t{1500}, size_t{400}, size_t{60}, size_t{1}}) {
    SCOPED_TRACE(budget);
    ASSERT_GT(run->scene.TriangleCount(), budget);
    std::vector<TriangleMesh> expected;
    double cell = 0;
    for (int round = 0; round < 40; ++round) {  // the last round whether it fits or not
      cell = round == 0 ? diagonal / 4096.0 : cell * 1.4;
      expected.clear();
      size_t triangles = 0;
      for (const SceneObject& object : run->scene.objects) {
        expected.push_back(ClusteredAsDefined(object.mesh, cell));
        triangles += expected.back().triangles.size();
      }
      if (triangles <= budget) break;
    }
    HtmlReportOptions options;
    options.max_mesh_triangles = budget;
    const nlohmann::json page =
        nlohmann::json::parse(DataJsonOf(HtmlReport(run->report, run->scene, options)));
    ASSERT_EQ(page["meshes"].size(), expected.size());
    for (size_t m = 0; m < expected.size(); ++m) {
      const auto positions = Base64Values<float>(page["meshes"][m]["positions"]);
      const auto indices = Base64Values<uint32_t>(page["meshes"][m]["indices"]);
      ASSERT_EQ(positions.size(), 3 * expected[m].vertices.size());
      ASSERT_EQ(indices.size(), 3 * expected[m].triangles.size());
      for (size_t i = 0; i < expected[m].vertices.size(); ++i) {
        for (int a = 0; a < 3; ++a)
          ASSERT_EQ(positions[3 * i + a], static_cast<float>(expected[m].vertices[i][a]));
      }
      for (size_t t = 0; t < expected[m].triangles.size(); ++t) {
        for (int a = 0; a < 3; ++a) ASSERT_EQ(indices[3 * t + a], expected[m].triangles[t][a]);
      }
    }
    size_t kept = 0;
    for (const TriangleMesh& mesh : expected) kept += mesh.triangles.size();
    char words[96];
    std::snprintf(words, sizeof words, "to %zu triangles (vertex clustering, %.3g m cells)", kept,
                  cell);
    EXPECT_NE(page["notes"].dump().find(words), std::string::npos) << page["notes"].dump();
  }
}

// The page's bulk arrays are written into its JSON after the rest is serialised (issue 47), each
// where a token stands: names that look like those tokens stay names, and every array is the
// scene's own (positions as floats, triangles as indices), whatever the names hold.
TEST(HtmlReport, BulkArraysAreTheSceneWhateverTheNamesHold) {
  const std::vector<std::string> names = {
      std::string("\x01vantage-blob-0\x02"), std::string("\x01vantage-blob-99999\x02"),
      std::string("a\x01vantage-blob-1\x02<b"), "plain"};
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    auto run = MakeRun(SphereScene(kRadius), {Camera(name, Vec3(1, 0, 0), Vec3::Zero(), 64, 0.5)},
                       1);
    const std::string html = HtmlReport(run->report, run->scene);
    const nlohmann::json page = nlohmann::json::parse(DataJsonOf(html));
    EXPECT_EQ(page["candidates"][0]["name"], name);
    ASSERT_EQ(page["meshes"].size(), run->scene.objects.size());
    for (size_t m = 0; m < run->scene.objects.size(); ++m) {
      const TriangleMesh& mesh = run->scene.objects[m].mesh;
      const auto positions = Base64Values<float>(page["meshes"][m]["positions"]);
      const auto indices = Base64Values<uint32_t>(page["meshes"][m]["indices"]);
      ASSERT_EQ(positions.size(), 3 * mesh.vertices.size());
      ASSERT_EQ(indices.size(), 3 * mesh.triangles.size());
      for (size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a)
          ASSERT_EQ(positions[3 * i + a], static_cast<float>(mesh.vertices[i][a]));
      for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int a = 0; a < 3; ++a) ASSERT_EQ(indices[3 * t + a], mesh.triangles[t][a]);
    }
    // Each reference cell once in the voxel index, each seen by the one chosen camera or not.
    const auto seen = Base64Decoded(page["voxels"]["seen"]);
    ASSERT_EQ(seen.size(), run->data.reference.size());
    std::vector<uint8_t> expected(run->data.reference.size(), 0);
    for (const uint32_t r : run->data.observations[0].reference_indices) expected[r] = 1;
    EXPECT_EQ(seen, expected);
    EXPECT_EQ(Base64Values<uint16_t>(page["voxels"]["index"]).size(),
              3 * run->data.reference.size());
    EXPECT_EQ(CountOf(html, "<script"), CountOf(html, "</script>"));
  }
}

// The page is src/report/assets/report.html with its @NAME@ placeholders filled in, and holds
// report.css and report.js byte for byte: what the build embeds is the files in the repository.
TEST(HtmlReport, PageIsTheAssetFilesFilledIn) {
  auto run =
      MakeRun(SphereScene(kRadius), {Camera("cam", Vec3(1, 0, 0), Vec3::Zero(), 16, 0.5)}, 1);
  HtmlReportOptions options;
  options.three_js_dir = "/nonexistent/three";
  const std::string html = HtmlReport(run->report, run->scene, options);
  const std::string assets = std::string(VANTAGE_SOURCE_DIR) + "/src/report/assets/";
  const std::string css = test::ReadText(assets + "report.css");
  const std::string js = test::ReadText(assets + "report.js");
  ASSERT_GT(css.size(), 1000u);
  ASSERT_GT(js.size(), 10000u);
  EXPECT_NE(html.find(css), std::string::npos);
  EXPECT_NE(html.find(js), std::string::npos);
  EXPECT_NE(html.find("<title>vantage report</title>"), std::string::npos);
  // The template's text between placeholders, in order; the page ends as the template does.
  const std::string page = test::ReadText(assets + "report.html");
  std::vector<std::string> pieces = {""};
  bool in_name = false;
  for (const char ch : page) {
    if (ch == '@') {
      in_name = !in_name;
      if (!in_name) pieces.emplace_back();
    } else if (!in_name) {
      pieces.back() += ch;
    }
  }
  ASSERT_FALSE(in_name);
  ASSERT_GE(pieces.size(), 6u);
  EXPECT_EQ(html.rfind(pieces.front(), 0), 0u);
  size_t at = 0;
  for (const std::string& piece : pieces) {
    at = html.find(piece, at);
    ASSERT_NE(at, std::string::npos) << piece;
    at += piece.size();
  }
  EXPECT_EQ(html.size() - pieces.back().size(), html.rfind(pieces.back()));
}

// Chromium from PATH (or $VANTAGE_CHROMIUM); "" when there is none.
std::string FindChromium() {
  if (const char* env = std::getenv("VANTAGE_CHROMIUM"); env != nullptr && *env) return env;
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const std::string command = std::string("command -v ") + name + " 2>/dev/null";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) continue;
    std::array<char, 512> buffer = {};
    const bool found = std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr;
    ::pclose(pipe);
    if (found) {
      std::string path(buffer.data());
      while (!path.empty() && (path.back() == '\n' || path.back() == '\r')) path.pop_back();
      if (!path.empty()) return path;
    }
  }
  return "";
}

// Headless Chromium, isolated and offline: its own profile, background traffic off, every host
// unresolvable (debian-deps.md: swiftshader gives WebGL). The 240 s stop is for a hung browser
// only: software WebGL opens the 7 MB page in ~9 s on 2 idle cores, and 90 s was once spent at
// load 16 (a fresh clone's CI beside three builds) by a page that was fine.
int RunChromium(const std::string& chromium,
                const std::string& profile,
                const std::string& args,
                const std::string& out,
                const std::string& err,
                double* seconds) {
  const std::string command =
      "timeout 240 '" + chromium +
      "' --headless --no-sandbox --enable-unsafe-swiftshader --user-data-dir='" + profile +
      "' --no-first-run --disable-background-networking --disable-component-update --disable-sync "
      "--disable-default-apps --disable-extensions --no-pings '--host-resolver-rules=MAP * "
      "~NOTFOUND' "
      "--virtual-time-budget=3000 " +
      args + " >'" + out + "' 2>'" + err + "' </dev/null";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return status;
}

// URLs of the network requests that the page itself made (Chromium's own background requests
// have no file:// isolation key).
std::vector<std::string> PageNetworkRequests(const std::string& net_log_path) {
  std::vector<std::string> urls;
  const nlohmann::json log = nlohmann::json::parse(test::ReadText(net_log_path), nullptr, false);
  if (log.is_discarded() || !log.contains("constants") || !log.contains("events")) {
    urls.emplace_back("(net log unreadable)");
    return urls;
  }
  const auto& types = log["constants"]["logEventTypes"];
  if (!types.contains("URL_REQUEST_START_JOB")) return urls;
  const int start_job = types["URL_REQUEST_START_JOB"].get<int>();
  for (const auto& event : log["events"]) {
    if (!event.contains("type") || event["type"] != start_job || !event.contains("params"))
      continue;
    const auto& params = event["params"];
    const std::string url = params.value("url", "");
    const std::string key = params.value("network_isolation_key", "");
    if (key.find("file://") != std::string::npos && url.rfind("file:", 0) != 0 &&
        url.rfind("data:", 0) != 0)
      urls.push_back(url);
  }
  return urls;
}

// A page as large as the issue asks to keep fast: 450 candidates, ~100,000 voxels.
TEST(HtmlReport, OpensInHeadlessChromiumOfflineWithA3dViewAndAChart) {
  const std::string chromium = FindChromium();
  if (chromium.empty())
    GTEST_SKIP() << "Chromium not found (install Debian's chromium: scripts/install-deps.sh)";
  ASSERT_TRUE(HasThreeJs()) << "three.js r111 missing under " << HtmlReportOptions{}.three_js_dir
                            << " — install Debian's libjs-three (scripts/install-deps.sh)";

  auto run = std::make_unique<SceneRun>();
  run->scene.objects.push_back({"ball", Role::kTarget, MakeSphere(0.36, kCell / 10), {}});
  TriangleMesh floor = MakeBox(Vec3(2.0, 2.0, 0.05));
  floor.Transform(Pose{Vec3(0, 0, -0.45), Quat::Identity()});
  run->scene.objects.push_back({"floor", Role::kOccluder, std::move(floor), {}});
  VisibilityFile& data = run->data;
  data.scene = "synthetic";
  data.reference = BuildReference(run->scene, ReferenceOptions{kCell});
  ASSERT_GT(data.reference.size(), 80000u);
  // Candidates on a ring of latitudes above; each "observes" the cap facing it (synthetic sets,
  // enough for the page).
  std::vector<Vec3> centres;
  for (uint64_t key : data.reference.keys) centres.push_back(VoxelCenter(key, kCell));
  for (int i = 0; i < 450; ++i) {
    const double azimuth = 2 * kPi * i / 450.0 * 7.0, elevation = 0.15 + 1.2 * (i % 45) / 45.0;
    const Vec3 eye = 1.3 * Vec3(std::cos(azimuth) * std::cos(elevation),
                                std::sin(azimuth) * std::cos(elevation), std::sin(elevation));
    data.candidates.push_back(Camera("cand_" + std::to_string(i), eye, Vec3::Zero(), 320, 0.8));
    Observation o;
    const Vec3 towards = eye.normalized();
    for (uint32_t r = 0; r < centres.size(); ++r) {
      if (centres[r].normalized().dot(towards) > 0.3 + 0.4 * (i % 7) / 7.0)
        o.reference_indices.push_back(r);
    }
    data.observations.push_back(std::move(o));
  }
  run->report.data = &data;
  run->report.scene = data.scene;
  SelectOptions options;
  options.method = Method::kGreedy;
  for (int n = 1; n <= 4; ++n) {
    options.n = n;
    std::vector<Selection> s = Select(data.observations, data.reference.size(), options);
    run->report.results.insert(run->report.results.end(), s.begin(), s.end());
  }
  Selection bounded = run->report.results.back();  // a result with a proven bound, for the chart
  bounded.method = "exact";
  bounded.upper_bound = std::min(1.0, bounded.coverage + 0.02);
  run->report.results.push_back(bounded);
  DeriveReport(&run->report);

  test::TempDir dir;
  const std::string page = dir.File("report.html");
  const auto build_start = std::chrono::steady_clock::now();
  const std::string html = HtmlReport(run->report, run->scene);
  std::printf(
      "report.html: %.1f MB in %.2f s\n", static_cast<double>(html.size()) / 1e6,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count());
  test::WriteText(page, html);

  // 1. The DOM after the scripts ran, the console and the network log.
  double seconds = 0;
  RunChromium(chromium, dir.File("profile"),
              "--enable-logging=stderr --v=0 '--log-net-log=" + dir.File("net.json") +
                  "' --dump-dom 'file://" + page + "'",
              dir.File("dom.html"), dir.File("dom.err"), &seconds);
  const std::string dom = test::ReadText(dir.File("dom.html"));
  const std::string console = test::ReadText(dir.File("dom.err"));
  const size_t element = dom.find("id=\"vantage-status\"");
  ASSERT_NE(element, std::string::npos) << "no status element in the DOM; stderr:\n"
                                        << console.substr(0, 4000);
  const size_t text = dom.find('>', element);
  ASSERT_NE(text, std::string::npos);
  EXPECT_EQ(dom.substr(text + 1, dom.find('<', text) - text - 1), "ok") << console.substr(0, 4000);
  EXPECT_EQ(console.find("Uncaught"), std::string::npos) << console.substr(0, 4000);
  EXPECT_NE(dom.find("<canvas"), std::string::npos);  // the 3D view was built
  EXPECT_NE(dom.find("id=\"chart\""), std::string::npos);
  EXPECT_EQ(CountOf(dom, "class=\"series\""), 2u);  // greedy and exact
  EXPECT_GE(CountOf(dom, "<tr"), 450u + 1 + 4 + 1);
  EXPECT_EQ(PageNetworkRequests(dir.File("net.json")), std::vector<std::string>{});
  EXPECT_LT(seconds, 60.0);
  std::printf("chromium --dump-dom: %.1f s\n", seconds);

  // 2. A screenshot: the 3D view (below the 42 px header, 480 px high) is not blank.
  RunChromium(
      chromium, dir.File("profile"),
      "--window-size=800,600 '--screenshot=" + dir.File("shot.png") + "' 'file://" + page + "'",
      dir.File("shot.out"), dir.File("shot.err"), &seconds);
  std::printf("chromium --screenshot: %.1f s\n", seconds);
  const Image shot = ReadPng(dir.File("shot.png"));
  ASSERT_EQ(shot.width, 800) << test::ReadText(dir.File("shot.err")).substr(0, 4000);
  ASSERT_EQ(shot.height, 600);
  double sum = 0, sum2 = 0;
  int n = 0, target_pixels = 0;
  for (int y = 60; y < 500; ++y) {
    for (int x = 200; x < 800; ++x) {  // right of the layer panel
      const Rgb p = shot.At(x, y);
      const double luminance = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      sum += luminance;
      sum2 += luminance * luminance;
      ++n;
      if (Classify(p) >= 0) ++target_pixels;
    }
  }
  const double variance = sum2 / n - (sum / n) * (sum / n);
  EXPECT_GT(variance, 100.0) << "the 3D view looks blank";
  EXPECT_GT(target_pixels, 2000) << "no voxel colours in the 3D view";
  if (const char* keep = std::getenv("VANTAGE_KEEP_SCREENSHOT"); keep != nullptr && *keep)
    std::filesystem::copy_file(dir.File("shot.png"), keep,
                               std::filesystem::copy_options::overwrite_existing);
}

// --------------------------------------------------------------------------------------------
// The CLI: every output folder gets report.html and static_transforms.yaml; `vantage render`.

TEST(RenderCli, OptimizeWritesThePageAndRenderWritesAPng) {
  test::TempDir dir;
  const std::string scene =
      std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
  const test::CommandResult optimize = test::RunVantage(
      "optimize '" + scene + "' -n 2 --method greedy --out '" + dir.File("out") + "'");
  ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
  EXPECT_TRUE(std::filesystem::exists(dir.File("out/report.html")));
  const YAML::Node transforms = YAML::LoadFile(dir.File("out/static_transforms.yaml"));
  EXPECT_EQ(transforms["transforms"].size(), 4u);

  const test::CommandResult render =
      test::RunVantage("render '" + dir.File("out") + "' --png '" + dir.File("view.png") +
                       "' --width 320 --height 240");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const Image image = ReadPng(dir.File("view.png"));
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  EXPECT_GT(CountPixels(image).observed, 100);

  const test::CommandResult missing = test::RunVantage("render '" + dir.File("nowhere") + "'");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find(dir.File("nowhere") + ":"), std::string::npos) << missing.err;
  const test::CommandResult same_point =
      test::RunVantage("render '" + dir.File("out") + "' --png '" + dir.File("x.png") +
                       "' --eye 0 0 1 --look-at 0 0 1");
  EXPECT_EQ(same_point.exit_code, 2) << same_point.err;
}

}  // namespace
}  // namespace vantage

namespace vantage {
namespace {

// The page's issue-9 sections run in a browser too: the robustness table of a run with a quality
// filter, one column per state of a scene with states, and a scene's keep-out boxes.
TEST(HtmlReport, RobustnessQualityAndStatesSectionsRender) {
  const std::string chromium = FindChromium();
  if (chromium.empty())
    GTEST_SKIP() << "Chromium not found (install Debian's chromium: scripts/install-deps.sh)";
  test::TempDir dir;
  const std::string scene = dir.File("states.yaml");
  test::WriteText(scene, test::ReadText(test::DataPath("cli/cube_cell.yaml")) +
                             "\nstates:\n  - name: plain\n  - name: lifted\n    move: {cube: {xyz: [0, 0, 0.02]}}\n");
  // Keep-out boxes (a rotated one): their layer, legend and view, opened on that view.
  const struct {
    std::string args, expect, hash;
  } runs[] = {{"optimize " + test::DataPath("cli/cube_cell.yaml") + " -n 2 --max-incidence 60",
               ">fails<", ""},
              {"optimize " + scene + " -n 2 --over-states min", ">state lifted<", ""},
              {"optimize " + test::DataPath("cli/keep_out_cell.yaml") + " --method greedy",
               "keep-out boxes (no sensor inside): robot, cable_tray", "#view=keepout"}};
  int k = 0;
  for (const auto& run : runs) {
    const std::string out = dir.File("out" + std::to_string(k++));
    const auto optimize = test::RunVantage(run.args + " --out " + out);
    ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
    double seconds = 0;
    RunChromium(chromium, dir.File("profile"),
                "--dump-dom 'file://" + out + "/report.html" + run.hash + "'", dir.File("dom.html"),
                dir.File("dom.err"), &seconds);
    const std::string dom = test::ReadText(dir.File("dom.html"));
    EXPECT_NE(dom.find(">ok<"), std::string::npos) << run.args << "\n" << test::ReadText(dir.File("dom.err")).substr(0, 2000);
    EXPECT_NE(dom.find(run.expect), std::string::npos) << run.args;
  }
}

}  // namespace
}  // namespace vantage
