#include "vantage/sensors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "vantage/error.hpp"

namespace vantage {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

SensorType Entry(const char* id, const char* name, const char* technology, int w, int h,
                 double hfov, std::optional<double> vfov, double near, double far, double fps,
                 double cost) {
  SensorType t = SensorType::FromFov(id, w, h, hfov, vfov, near, far);
  t.name = name;
  t.technology = technology;
  t.fps = fps;
  t.cost = cost;
  return t;
}

// PrimeSense PS1080 structured light (Kinect for Xbox 360, Xtion PRO LIVE): Nguyen, Izadi and
// Lovell, "Modeling Kinect Sensor Noise for Improved 3D Reconstruction and Tracking", 3DIMPVT
// 2012: sigma_z(z, theta) = 0.0012 + 0.0019 (z - 0.4)^2 + 0.0001 / sqrt(z) * theta^2 /
// (pi/2 - theta)^2 m, the quadratic expanded into a + b z + c z^2.
DepthNoise PrimeSenseNoise(const char* which) {
  return {0.0012 + 0.0019 * 0.16, -0.0019 * 0.8, 0.0019,
          fmt::format("{}Nguyen, Izadi, Lovell, 3DIMPVT 2012: 0.0012 + 0.0019 (z - 0.4)^2 + "
                      "0.0001 / sqrt(z) theta^2 / (pi/2 - theta)^2 m",
                      which),
          0.0001};
}

// Intel RealSense D400 active stereo: RMS error = z^2 * subpixel / (fx * baseline), subpixel
// 0.08 px typical (Grunnet-Jepsen et al., Intel whitepaper "Tuning depth cameras for best
// performance"); baselines from Intel's D400 datasheet; fx is the catalog's at full resolution.
DepthNoise D400Noise(const SensorType& t, double baseline_m) {
  return {0, 0, 0.08 / (t.fx * baseline_m),
          fmt::format("Intel D400 RMS formula z^2 * 0.08 / (fx * {} m), Intel tuning whitepaper "
                      "and D400 datasheet", baseline_m)};
}

SensorType WithNoise(SensorType t, DepthNoise noise) {
  t.depth_noise = std::move(noise);
  return t;
}

SensorType WithD400Noise(SensorType t, double baseline_m) {
  t.depth_noise = D400Noise(t, baseline_m);
  return t;
}

// The second apertures of the catalog (issue 43; docs/sensor-models.md, "The catalog's apertures"):
// each number from the source named in the aperture's `source`; what no source gives (a
// projector's field, a disparity search range) stays unset rather than guessed.
SecondAperture Imager(double baseline, std::optional<double> disparity_range, std::string source) {
  SecondAperture a;
  a.kind = SecondAperture::Kind::kImager;
  a.baseline = baseline;
  a.disparity_range = disparity_range;
  a.source = std::move(source);
  return a;
}

SecondAperture Projector(double baseline, std::string source) {
  SecondAperture a;
  a.kind = SecondAperture::Kind::kProjector;
  a.baseline = baseline;
  a.source = std::move(source);
  return a;
}

// Intel's D4 vision processor searches 126 disparities (Grunnet-Jepsen et al., "Tuning depth
// cameras for best performance": MinZ = focal length [px] x baseline / 126); baselines from the
// Intel RealSense D400 Series datasheet (337029).
SecondAperture D400Imager(double baseline) {
  return Imager(baseline, 126.0,
                fmt::format("Intel D400 datasheet: baseline {:g} mm; Intel tuning whitepaper: "
                            "126-disparity search",
                            baseline * 1000));
}

SensorType WithAperture(SensorType t, SecondAperture aperture) {
  t.second_aperture = std::move(aperture);
  return t;
}

// A catalog entry whose vendor publishes no price: its cost stands for "not given" (issue 43).
SensorType Unpriced(SensorType t) {
  t.cost = 0;
  t.cost_given = false;
  return t;
}

// The technology of a type: its own, else that of the catalog entry `catalog_id` names.
std::string_view TechnologyOf(const SensorType& type, std::string_view catalog_id) {
  if (!type.technology.empty() || catalog_id.empty()) return type.technology;
  const SensorType* entry = FindCatalogType(catalog_id);
  return entry ? std::string_view(entry->technology) : std::string_view(type.technology);
}

constexpr double kPi = std::numbers::pi;

// A full field angle in (0, pi) [rad].
bool IsFieldAngle(double angle) { return std::isfinite(angle) && angle > 0 && angle < kPi; }

bool Close(double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b)); }

}  // namespace

double DepthNoise::Sigma(double z, double theta) const {
  const double sigma = Sigma(z);
  if (incidence == 0) return sigma;
  const double grazing = kPi / 2 - theta;
  if (!(grazing > 0)) return std::numeric_limits<double>::infinity();
  const double ratio = theta / grazing;
  return sigma + incidence / std::sqrt(z) * ratio * ratio;
}

const char* KindName(SecondAperture::Kind kind) {
  switch (kind) {
    case SecondAperture::Kind::kProjector: return "projector";
    case SecondAperture::Kind::kImager: return "imager";
    case SecondAperture::Kind::kNone: break;
  }
  return "none";
}

std::string SecondApertureProblem(const SensorType& camera, const SecondAperture& a) {
  if (!a.active()) return "";
  if (!std::isfinite(a.baseline) || a.baseline < 0 || a.baseline > kMaxBaseline)
    return fmt::format("baseline = {} m must be in [0, {:g}] m — give the distance between the "
                       "camera's and the {}'s optical centres", a.baseline, kMaxBaseline,
                       KindName(a.kind));
  if (!std::isfinite(a.toe_in) || a.toe_in < 0 || a.toe_in > kMaxToeIn)
    return fmt::format("toe_in = {:g} deg must be in [0, {:g}] deg", a.toe_in * 180 / kPi,
                       kMaxToeIn * 180 / kPi);
  const auto angle = [](const char* name, double value) -> std::string {
    if (value == 0 || IsFieldAngle(value)) return "";
    return fmt::format("{} = {:g} deg must be a field angle in (0, 180) deg", name,
                       value * 180 / kPi);
  };
  for (const std::string& p : {angle("hfov", a.hfov), angle("vfov", a.vfov), angle("cone", a.cone)})
    if (!p.empty()) return p;
  if (a.vfov != 0 && a.hfov == 0) return "vfov needs hfov — give both or a cone";
  if (a.kind == SecondAperture::Kind::kImager) {
    if (a.hfov != 0 || a.cone != 0)
      return "an imager's field is its intrinsics (resolution, intrinsics), not hfov or cone";
    if (a.width != 0 || a.height != 0) {
      if (a.width <= 0 || a.height <= 0 || int64_t{a.width} * a.height > int64_t{64} << 20)
        return fmt::format("resolution {}x{} must be positive and at most 64 Mpx", a.width,
                           a.height);
      if (!std::isfinite(a.fx) || !std::isfinite(a.fy) || a.fx <= 0 || a.fy <= 0 ||
          !std::isfinite(a.cx) || !std::isfinite(a.cy) ||
          std::max(std::abs(a.cx), std::abs(a.cx - a.width)) / a.fx > kMaxRaySlope ||
          std::max(std::abs(a.cy), std::abs(a.cy - a.height)) / a.fy > kMaxRaySlope)
        return "intrinsics must be positive, finite focal lengths and a finite principal point";
    }
  } else if (a.width != 0 || a.height != 0) {
    return "a projector's field is hfov/vfov or a cone, not a resolution";
  }
  if (a.disparity_range) {
    const double d = *a.disparity_range;
    if (a.kind != SecondAperture::Kind::kImager)
      return "disparity_range belongs to a second imager (stereo)";
    if (!std::isfinite(d) || d <= 0 || d > camera.width)
      return fmt::format("disparity_range = {} px must be in (0, {}] px (the image's width)", d,
                         camera.width);
  }
  return "";
}

const SecondAperture* SecondApertureOf(const SensorType& type, std::string_view catalog_id) {
  const SensorType* entry = type.second_aperture ? nullptr : FindCatalogType(catalog_id);
  const std::optional<SecondAperture>& aperture =
      type.second_aperture || !entry ? type.second_aperture : entry->second_aperture;
  return aperture && aperture->active() ? &*aperture : nullptr;
}

std::optional<double> FlyingPixelThresholdOf(const SensorType& type,
                                             std::string_view catalog_id) {
  if (type.flying_pixel_threshold) return type.flying_pixel_threshold;
  const SensorType* entry = FindCatalogType(catalog_id);
  return entry ? entry->flying_pixel_threshold : std::nullopt;
}

bool HasPhysicalModel(const SensorType& type, std::string_view catalog_id) {
  return SecondApertureOf(type, catalog_id) != nullptr ||
         FlyingPixelThresholdOf(type, catalog_id).has_value();
}

bool UnitCostGiven(const SensorType& type, std::string_view catalog_id) {
  if (!type.cost_given) return false;
  const SensorType* entry = FindCatalogType(catalog_id);
  return !(entry && !entry->cost_given && type.cost == entry->cost);
}

std::string PhysicalModelGap(const SensorType& type, std::string_view catalog_id) {
  if (SecondApertureOf(type, catalog_id)) return "";
  // A type whose own aperture is `kind: none` said so on purpose.
  if (type.second_aperture) return "";
  const std::string_view technology = TechnologyOf(type, catalog_id);
  if (technology.find("structured light") != std::string_view::npos)
    return "not modelled: no source found gives its projector's pose";
  if (technology.find("stereo") != std::string_view::npos)
    return "not modelled: no source found gives its second imager's pose";
  return "";
}

double StereoNearestDepth(const SensorType& camera, const SecondAperture& aperture) {
  if (aperture.kind != SecondAperture::Kind::kImager || !aperture.disparity_range) return 0;
  return camera.fx * aperture.baseline / *aperture.disparity_range;
}

Vec3 ApertureCentreInBody(const SecondAperture& aperture) {
  return Vec3(0, -aperture.baseline, 0);
}

Mat3 BodyFromAperture(const SecondAperture& aperture) {
  // The aperture sits at -y (right): turning its axis toward the camera turns it toward +y.
  return Eigen::AngleAxisd(aperture.toe_in, Vec3::UnitZ()).toRotationMatrix();
}

bool InApertureField(const SensorType& camera, const SecondAperture& aperture,
                     const Vec3& p_body) {
  return ApertureField(camera, aperture).Contains(p_body);
}

ApertureField::ApertureField(const SensorType& camera, const SecondAperture& aperture)
    : aperture_from_body_(BodyFromAperture(aperture).transpose()),
      centre_(ApertureCentreInBody(aperture)) {
  turned_ = aperture_from_body_ != Mat3::Identity();
  if (aperture.cone > 0) {
    half_cone_ = aperture.cone / 2;
  } else if (aperture.hfov > 0) {
    tan_half_h_ = std::tan(aperture.hfov / 2);
    tan_half_v_ = std::tan((aperture.vfov > 0 ? aperture.vfov : aperture.hfov) / 2);
  }
  // An image: its intrinsics, or the camera's own (rectified pair, projector of the same field).
  const bool own = aperture.width > 0;
  fx_ = own ? aperture.fx : camera.fx;
  fy_ = own ? aperture.fy : camera.fy;
  cx_ = own ? aperture.cx : camera.cx;
  cy_ = own ? aperture.cy : camera.cy;
  width_ = own ? aperture.width : camera.width;
  height_ = own ? aperture.height : camera.height;
  image_width_ = width_;
  image_height_ = height_;
  // Quickly's products (x, |y|, |z| in (1e-140, 1e140)) stay normal and finite, and its margin
  // covers the roundings of tan and atan, while the field's constants lie in these ranges. A cone
  // wider than 3 rad has atan's flat end at its edge: always Exactly.
  const auto moderate = [](double a) { return a > 1e-100 && a < 1e100; };
  if (half_cone_ > 0 && half_cone_ <= 1.5) {
    tan_half_cone_ = std::tan(half_cone_);
    quick_cone_ = moderate(tan_half_cone_);
  }
  quick_frustum_ = tan_half_h_ > 0 && moderate(tan_half_h_) && moderate(tan_half_v_);
  quick_image_ = moderate(fx_) && moderate(fy_) && std::abs(cx_) < 1e100 &&
                 std::abs(cy_) < 1e100 && width_ > 0 && height_ > 0;
}

bool ApertureField::ContainsTurned(const Vec3& d) const {
  return ContainsInFrame(aperture_from_body_ * d);
}

bool ApertureField::Exactly(const Vec3& p) const {
  if (!(p.x() > 0)) return false;
  const double right = -p.y() / p.x(), down = -p.z() / p.x();  // image-plane slopes
  if (half_cone_ > 0) return std::atan(std::hypot(right, down)) <= half_cone_;
  if (tan_half_h_ > 0) return std::abs(right) <= tan_half_h_ && std::abs(down) <= tan_half_v_;
  const double u = cx_ + fx_ * right, v = cy_ + fy_ * down;
  return u >= 0 && v >= 0 && u < width_ && v < height_;
}

double SensorType::HorizontalFov() const { return 2.0 * std::atan(width / (2.0 * fx)); }
double SensorType::VerticalFov() const { return 2.0 * std::atan(height / (2.0 * fy)); }

SensorType SensorType::FromFov(std::string id, int width, int height, double hfov,
                               std::optional<double> vfov, double near, double far) {
  SensorType t;
  t.id = std::move(id);
  t.name = t.id;
  t.width = width;
  t.height = height;
  t.fx = width / (2.0 * std::tan(hfov / 2.0));
  t.fy = vfov ? height / (2.0 * std::tan(*vfov / 2.0)) : t.fx;
  t.cx = width / 2.0;
  t.cy = height / 2.0;
  t.near = near;
  t.far = far;
  return t;
}

void SensorType::Validate(const std::string& where) const {
  const auto fail = [&](const std::string& what) {
    throw InputError(where.empty() ? fmt::format("sensor type '{}': {}", id, what)
                                   : fmt::format("{}: sensor type '{}': {}", where, id, what));
  };
  if (width <= 0 || height <= 0)
    fail(fmt::format("resolution {}x{} must be positive — set width and height >= 1", width, height));
  if (int64_t{width} * height > int64_t{64} << 20)
    fail(fmt::format("resolution {}x{} is above 64 Mpx — use a real sensor resolution", width, height));
  if (!std::isfinite(fx) || !std::isfinite(fy) || fx <= 0 || fy <= 0)
    fail("focal lengths must be positive and finite — field of view must lie in (0, pi)");
  if (!std::isfinite(cx) || !std::isfinite(cy)) fail("principal point must be finite");
  if (!std::isfinite(near) || near <= 0) fail(fmt::format("near = {} must be > 0", near));
  if (!std::isfinite(far) || far <= near)
    fail(fmt::format("near = {} must be below far = {} — swap or fix the range", near, far));
  if (far > kMaxSensorRange)
    fail(fmt::format("far = {:g} m is beyond the {:g} m that vantage can ray cast — give the "
                     "sensor's real range",
                     far, kMaxSensorRange));
  // The corner pixels have the steepest rays (the slope is linear in u and v).
  for (const int u : {0, width - 1}) {
    for (const int v : {0, height - 1}) {
      const Vec3 ray = PixelRayInBody(*this, u, v);
      if (!ray.allFinite() || (ray.array().abs() > kMaxRaySlope).any()) {
        fail(fmt::format("the ray of pixel ({}, {}) has slopes ({:g}, {:g}), beyond the ±{:g} "
                         "that vantage can ray cast (fx = {:g}, fy = {:g}, cx = {:g}, cy = {:g} "
                         "px) — give the focal lengths and principal point of a real camera",
                         u, v, ray.y(), ray.z(), kMaxRaySlope, fx, fy, cx, cy));
      }
    }
  }
  if (!(cost >= 0 && cost <= kMaxUnitCost))
    fail(fmt::format("cost = {} must be from 0 to {:g}", cost, kMaxUnitCost));
  // An arm's tour waits frames / fps at each view: 1e-300 Hz made tours of 10^300 s.
  if (!(fps == 0 || (fps >= 1e-6 && fps <= 1e6)))
    fail(fmt::format("fps = {} must be a frame rate from 1e-06 to 1e+06 Hz (0: not given)", fps));
  if (second_aperture) {
    const std::string problem = SecondApertureProblem(*this, *second_aperture);
    if (!problem.empty()) fail("second_aperture: " + problem);
  }
  if (flying_pixel_threshold) {
    const double threshold = *flying_pixel_threshold;
    if (!std::isfinite(threshold) || threshold <= 0 || threshold > kMaxSensorRange)
      fail(fmt::format("flying_pixel_threshold = {} m must be a depth step in (0, {:g}] m", threshold,
                       kMaxSensorRange));
  }
  if (depth_noise) {
    const DepthNoise& n = *depth_noise;
    if (!std::isfinite(n.a) || !std::isfinite(n.b) || !std::isfinite(n.c))
      fail("depth_noise coefficients must be finite");
    if (!std::isfinite(n.incidence) || n.incidence < 0)
      fail(fmt::format("depth_noise incidence coefficient = {} must be finite and >= 0 — noise "
                       "grows toward grazing incidence",
                       n.incidence));
    // sigma is a quadratic: checking both ends of the range and the vertex covers it.
    const double vertex = n.c != 0 ? -n.b / (2 * n.c) : near;
    for (double z : {near, far, std::clamp(vertex, near, far)}) {
      if (n.Sigma(z) < 0)
        fail(fmt::format("depth_noise gives sigma({:g} m) = {:g} m < 0 — give a, b, c with "
                         "a + b z + c z^2 >= 0 over [near, far]", z, n.Sigma(z)));
    }
  }
}

const std::vector<SensorType>& Catalog() {
  // SENSORS.md: the ten types of the original system (Gazebo values, square pixels: their ids and
  // intrinsics stay, so the paper's worlds still match them), then current cameras and modes from
  // vendors' datasheets (separate fields of view). docs/sensor-models.md gives each number's
  // source.
  static const std::vector<SensorType> catalog = {
      // Khoshelham and Oude Elberink, "Accuracy and Resolution of Kinect Depth Data for Indoor
      // Mapping Applications", Sensors 12(2), 2012: IR projector 7.5 cm from the IR camera.
      WithAperture(
          WithNoise(Entry("kinect_xbox_360", "Microsoft Kinect for Xbox 360", "structured light",
                          640, 480, 0.994838, std::nullopt, 0.4, 4.0, 30, 150),
                    PrimeSenseNoise("")),
          Projector(0.075, "Khoshelham and Oude Elberink, Sensors 2012: projector-camera base 7.5 cm")),
      WithNoise(Entry("asus_xtion_pro_live", "ASUS Xtion PRO LIVE", "structured light", 640, 480,
                      1.01229, std::nullopt, 0.5, 3.5, 30, 200),
                PrimeSenseNoise("same PrimeSense PS1080 engine as the Kinect for Xbox 360; ")),
      Entry("ensenso_n35", "IDS Ensenso N35", "structured light (projected-texture stereo)", 1280,
            1024, 1.01229, std::nullopt, 0.46, 4.0, 10, 5000),
      // Fankhauser et al., "Kinect v2 for Mobile Robot Navigation: Evaluation and Modeling",
      // ICAR 2015: axial sigma = 1.5 - 0.5 z + 0.3 z^2 mm at normal incidence.
      WithNoise(Entry("kinect_xbox_one", "Microsoft Kinect for Xbox One", "time of flight", 512,
                      424, 1.22173, std::nullopt, 0.5, 4.5, 30, 200),
                {0.0015, -0.0005, 0.0003,
                 "Fankhauser et al., ICAR 2015: 1.5 - 0.5 z + 0.3 z^2 mm at normal incidence"}),
      Entry("orbbec_astra", "Orbbec Astra", "structured light", 640, 480, 1.0472, std::nullopt,
            0.6, 8.0, 30, 150),
      // Carnegie Robotics: the S7's stereo baseline is 7 cm; the MultiSense searches 64, 128 or
      // 256 disparities (support article "What does maximum disparities mean?"): the widest.
      WithAperture(Entry("multisense_s7", "Carnegie Robotics MultiSense S7", "stereo", 2048, 1088,
                         1.39626, std::nullopt, 0.4, 5.0, 15, 6000),
                   Imager(0.07, 256.0,
                          "Carnegie Robotics MultiSense S7 datasheet: baseline 70 mm; up to 256 "
                          "disparities")),
      Entry("intel_realsense_sr300", "Intel RealSense SR300", "structured light (coded)", 640,
            480, 1.24791, std::nullopt, 0.2, 1.5, 60, 150),
      // Not a depth datasheet: the original system's Gazebo model, whose 4416x1242 and 110 deg
      // are the ZED's side-by-side RGB pair (two 2208x1242 images), kept so that the paper's
      // worlds still match it; the name says so. Stereolabs ZED datasheet: baseline 120 mm; its
      // disparity search is not published.
      WithAperture(Entry("zed", "Stereolabs ZED, Gazebo model", "stereo", 4416, 1242, 1.91986,
                         std::nullopt, 0.7, 20.0, 15, 450),
                   Imager(0.12, std::nullopt, "Stereolabs ZED datasheet: baseline 120 mm")),
      WithAperture(WithD400Noise(Entry("intel_realsense_d415", "Intel RealSense D415",
                                       "active stereo", 1280, 720, 1.106539, std::nullopt, 0.16,
                                       10.0, 90, 300),
                                 0.055),
                   D400Imager(0.055)),
      Entry("photoneo_phoxi_s", "Photoneo PhoXi 3D Scanner S", "structured light", 2064, 1536,
            0.672088562, std::nullopt, 0.354, 0.588, 5, 9000),
      WithAperture(WithD400Noise(Entry("intel_realsense_d435", "Intel RealSense D435",
                                       "active stereo", 1280, 720, 87 * kDeg, 58 * kDeg, 0.28,
                                       10.0, 90, 300),
                                 0.050),
                   D400Imager(0.050)),
      WithAperture(WithD400Noise(Entry("intel_realsense_d455", "Intel RealSense D455",
                                       "active stereo", 1280, 720, 87 * kDeg, 58 * kDeg, 0.52,
                                       6.0, 90, 400),
                                 0.095),
                   D400Imager(0.095)),
      // Azure Kinect DK hardware specification: random error std. dev. <= 17 mm (an upper
      // bound, constant over the range).
      WithNoise(Entry("azure_kinect_nfov", "Azure Kinect DK, NFOV unbinned", "time of flight", 640,
                      576, 75 * kDeg, 65 * kDeg, 0.5, 3.86, 30, 400),
                {0.017, 0, 0, "Azure Kinect DK hardware specification: random error <= 17 mm"}),
      WithNoise(Entry("azure_kinect_wfov", "Azure Kinect DK, WFOV 2x2 binned", "time of flight",
                      512, 512, 120 * kDeg, 120 * kDeg, 0.25, 2.88, 30, 400),
                {0.017, 0, 0, "Azure Kinect DK hardware specification: random error <= 17 mm"}),
      // Modes (issue 43). D400 datasheet: D415 depth field 65 x 40 deg, Min-Z at 1280x720 about
      // 0.45 m (also the tuning whitepaper's MinZ for disparity shift 0), depth at 1280x720 up to
      // 30 fps, at 848x480 up to 90 fps; the family's range 0.16 (D415) / 0.11 (D430 module of
      // the D435) to 10 m where no Min-Z is given for the mode. Stereo's own nearest depth
      // f·B/126 applies on top under the physical model.
      WithAperture(WithD400Noise(Entry("intel_realsense_d415_1280x720",
                                       "Intel RealSense D415, 1280x720", "active stereo", 1280,
                                       720, 65 * kDeg, 40 * kDeg, 0.45, 10.0, 30, 300),
                                 0.055),
                   D400Imager(0.055)),
      WithAperture(WithD400Noise(Entry("intel_realsense_d415_848x480",
                                       "Intel RealSense D415, 848x480", "active stereo", 848, 480,
                                       65 * kDeg, 40 * kDeg, 0.16, 10.0, 90, 300),
                                 0.055),
                   D400Imager(0.055)),
      WithAperture(WithD400Noise(Entry("intel_realsense_d435_848x480",
                                       "Intel RealSense D435, 848x480", "active stereo", 848, 480,
                                       87 * kDeg, 58 * kDeg, 0.11, 10.0, 90, 300),
                                 0.050),
                   D400Imager(0.050)),
      // Azure Kinect DK hardware specification, depth modes: NFOV 2x2 binned 320x288, 75x65 deg,
      // 0.5-5.46 m, 30 fps; WFOV unbinned 1024x1024, 120x120 deg, 0.25-2.21 m, 15 fps.
      WithNoise(Entry("azure_kinect_nfov_binned", "Azure Kinect DK, NFOV 2x2 binned",
                      "time of flight", 320, 288, 75 * kDeg, 65 * kDeg, 0.5, 5.46, 30, 400),
                {0.017, 0, 0, "Azure Kinect DK hardware specification: random error <= 17 mm"}),
      WithNoise(Entry("azure_kinect_wfov_unbinned", "Azure Kinect DK, WFOV unbinned",
                      "time of flight", 1024, 1024, 120 * kDeg, 120 * kDeg, 0.25, 2.21, 15, 400),
                {0.017, 0, 0, "Azure Kinect DK hardware specification: random error <= 17 mm"}),
      // Orbbec Femto Bolt (issue 43): Orbbec, "Femto Bolt Hardware Specifications", depth camera
      // supported operating modes (Microsoft's 1 MP ToF depth camera): NFOV unbinned 640x576,
      // NFOV 2x2 binned 320x288, both 75x65 deg; WFOV 2x2 binned 512x512, WFOV unbinned
      // 1024x1024, both 120x120 deg; ranges and frame rates below. No price and no noise figure
      // are published there; time of flight needs no second aperture.
      Unpriced(Entry("femto_bolt_nfov_unbinned", "Orbbec Femto Bolt, NFOV unbinned",
                     "time of flight", 640, 576, 75 * kDeg, 65 * kDeg, 0.5, 3.86, 30, 0)),
      Unpriced(Entry("femto_bolt_nfov_binned", "Orbbec Femto Bolt, NFOV 2x2 binned",
                     "time of flight", 320, 288, 75 * kDeg, 65 * kDeg, 0.5, 5.46, 30, 0)),
      Unpriced(Entry("femto_bolt_wfov_binned", "Orbbec Femto Bolt, WFOV 2x2 binned",
                     "time of flight", 512, 512, 120 * kDeg, 120 * kDeg, 0.25, 2.88, 30, 0)),
      Unpriced(Entry("femto_bolt_wfov_unbinned", "Orbbec Femto Bolt, WFOV unbinned",
                     "time of flight", 1024, 1024, 120 * kDeg, 120 * kDeg, 0.25, 2.21, 25, 0)),
  };
  return catalog;
}

const SensorType* FindCatalogType(std::string_view id) {
  for (const SensorType& t : Catalog()) {
    if (t.id == id) return &t;
  }
  return nullptr;
}

std::string MatchCatalogId(const SensorType& type) {
  const auto same = [&](const SensorType& t) {
    return t.width == type.width && t.height == type.height && Close(t.fx, type.fx) &&
           Close(t.fy, type.fy) && Close(t.cx, type.cx) && Close(t.cy, type.cy) &&
           Close(t.near, type.near) && Close(t.far, type.far);
  };
  // Two products may share a depth camera (the Femto Bolt carries the Azure Kinect's modes): a
  // type named after an entry keeps that entry; any other takes the first that matches.
  if (const SensorType* own = FindCatalogType(type.id); own && same(*own)) return own->id;
  for (const SensorType& t : Catalog()) {
    if (same(t)) return t.id;
  }
  return "";
}

Vec3 PixelRayInBody(const SensorType& type, int u, int v) {
  // Optical frame (x right, y down, z forward) -> body (x forward, y left, z up).
  return Vec3(1.0, -PixelRight(type, u), -PixelDown(type, v));
}

std::optional<Eigen::Vector2d> ProjectBodyPoint(const SensorType& type, const Vec3& p_body) {
  if (!(p_body.x() > 0)) return std::nullopt;
  return Eigen::Vector2d(type.cx + type.fx * (-p_body.y() / p_body.x()),
                         type.cy + type.fy * (-p_body.z() / p_body.x()));
}

bool ProjectsLight(const SensorType& type, std::string_view catalog_id) {
  if (type.interferes) return *type.interferes;
  std::string_view technology = type.technology;
  if (technology.empty() && !catalog_id.empty()) {
    if (const SensorType* entry = FindCatalogType(catalog_id)) technology = entry->technology;
  }
  return technology.starts_with("structured light") || technology.starts_with("time of flight");
}

}  // namespace vantage
