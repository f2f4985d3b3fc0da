#pragma once
/// Depth sensor types (SENSORS.md) and the pinhole camera model.
/// Body frame: x forward, y left, z up (Gazebo, ROS). Image: u right = -y, v down = -z,
/// depth along +x. Pixel (u, v) covers [u, u+1) x [v, v+1); its ray passes its centre (u+0.5, v+0.5).
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vantage/types.hpp"

namespace vantage {

/// Axial depth noise, one standard deviation: sigma(z, theta) = a + b z + c z^2
/// + incidence / sqrt(z) * theta^2 / (pi/2 - theta)^2 [m] at depth z [m] and incidence angle theta
/// [rad] between the pixel's ray and the surface normal (docs/sensor-models.md: structured light
/// and stereo grow with z^2, time of flight is roughly constant; the incidence term is Nguyen,
/// Izadi and Lovell's for the Kinect, 2012, and 0 where no source gives one).
struct DepthNoise {
  double a = 0, b = 0, c = 0;
  std::string source;  ///< where the coefficients come from
  /// Coefficient of the incidence term [m^1.5]; 0: noise independent of the angle.
  double incidence = 0;
  /// The noise at normal incidence (theta = 0).
  double Sigma(double z) const { return a + (b + c * z) * z; }
  /// The noise at incidence `theta` [rad]: infinite at grazing incidence (theta >= pi/2) when the
  /// type has an incidence term.
  double Sigma(double z, double theta) const;
};

/// The aperture besides the camera that a depth measurement needs (issue 43;
/// docs/sensor-models.md, Second aperture): structured light's projector must light the point,
/// stereo's second imager must see it. A time-of-flight sensor's co-located illuminator needs
/// nothing: kind kNone (which also overrides a catalog entry's aperture in a custom type).
struct SecondAperture {
  enum class Kind { kNone, kProjector, kImager };
  Kind kind = Kind::kNone;
  /// Distance [m] from the camera's optical centre to the aperture's, along the image's right
  /// (+u, body -y): the side shadows fall to only mirrors them.
  double baseline = 0;
  /// Angle [rad] by which the aperture's axis turns from the camera's toward the camera (about
  /// body z); 0: parallel axes.
  double toe_in = 0;
  /// Projector field: a frustum of full angles hfov x vfov [rad], or, when cone > 0, a circular
  /// cone of full angle `cone` [rad]. Unset (0): the camera's own field of view.
  double hfov = 0, vfov = 0, cone = 0;
  /// Imager field: its own intrinsics; width 0: the camera's (a rectified stereo pair).
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// Stereo: the largest disparity the matcher searches [px]; points nearer than
  /// fx * baseline / disparity_range (fx: the depth image's) are refused. Unset: no limit.
  std::optional<double> disparity_range;
  std::string source;  ///< where the numbers come from

  bool active() const { return kind != Kind::kNone; }
};

/// "projector", "imager" or "none".
const char* KindName(SecondAperture::Kind kind);

/// The widest baseline [m] a second aperture may have: no depth sensor's body is wider.
inline constexpr double kMaxBaseline = 1.0;
/// The largest toe-in [rad] (45 deg): beyond it the apertures would barely share a field.
inline constexpr double kMaxToeIn = 0.7853981633974483;
/// The largest unit cost taken: a million candidates at it still sum to a finite, exactly
/// compared total (1e308 each made two sensors cost inf and exact's bound 0).
inline constexpr double kMaxUnitCost = 1e12;

struct SensorType {
  std::string id;          ///< catalog id or a user/model name
  std::string name;        ///< display name
  std::string technology;  ///< e.g. "structured light"
  int width = 0;           ///< pixels
  int height = 0;          ///< pixels
  double fx = 0, fy = 0;   ///< focal lengths [px]
  double cx = 0, cy = 0;   ///< principal point [px], continuous coordinates (cx = W/2 is centred)
  double near = 0;         ///< nearest valid depth [m]
  double far = 0;          ///< farthest valid depth [m]
  double fps = 0;          ///< frame rate [Hz], informative
  double cost = 1.0;       ///< unit cost for budgeted selection
  /// Whether `cost` is a price someone gave (issue 43): false for a catalog entry whose vendor
  /// publishes none (its cost is 0 and stands for "not given"); --budget and --cheapest refuse
  /// such a type until the scene gives it a cost (UnitCostGiven).
  bool cost_given = true;
  /// Depth noise model; unset when no published model is known for the type.
  std::optional<DepthNoise> depth_noise;
  /// Whether its projector washes out another projecting sensor's pattern (projector
  /// interference, docs/constraints.md); unset: from the technology (ProjectsLight).
  std::optional<bool> interferes;
  /// The projector or second imager (physical model, issue 43); unset: the catalog entry's by
  /// type id, else none. Observe applies it unless the ideal pinhole is asked for.
  std::optional<SecondAperture> second_aperture;
  /// Time of flight's mixed ("flying") pixels (physical model, issue 43): a pixel whose depth
  /// differs from a 4-neighbour's by more than this [m] is dropped, as the sensors' own filters
  /// do. Unset: the catalog entry's by type id, else no filter.
  std::optional<double> flying_pixel_threshold;

  /// Horizontal / vertical field of view [rad] implied by the intrinsics.
  double HorizontalFov() const;
  double VerticalFov() const;
  /// Number of pixels, W·H.
  int64_t PixelCount() const { return int64_t{width} * height; }
  /// Throws InputError (prefixed by `where`) on non-positive/NaN sizes, fov >= pi, near >= far.
  void Validate(const std::string& where = "") const;

  /// Gazebo's model: fx = fy = W / (2 tan(hfov/2)), cx = W/2, cy = H/2. When vfov is given,
  /// fy = H / (2 tan(vfov/2)) (non-square pixels). Does not validate.
  static SensorType FromFov(std::string id, int width, int height, double hfov,
                            std::optional<double> vfov, double near, double far);
};

/// The ten types of the original system (SENSORS.md), then current cameras and their modes from
/// datasheets (docs/sensor-models.md), in that order.
const std::vector<SensorType>& Catalog();
/// Catalog entry by id, or nullptr.
const SensorType* FindCatalogType(std::string_view id);
/// The id of the catalog entry with the same resolution, intrinsics and range (relative
/// tolerance 1e-6): the entry named type.id when it matches, else the first that does; "" when
/// none matches.
std::string MatchCatalogId(const SensorType& type);

/// Whether sensors of `type` interfere: `type.interferes` when set, else whether its technology
/// (or, when empty, that of the catalog entry `catalog_id`) is structured light or time of
/// flight. Active stereo (a texture projector that stereo matching does not rely on) and passive
/// stereo do not.
bool ProjectsLight(const SensorType& type, std::string_view catalog_id = {});

/// What is wrong with `aperture` as `camera`'s second aperture ("" when nothing): a baseline,
/// toe-in, field angle, intrinsics or disparity range that is negative, NaN or beyond what a
/// sensor body allows. SensorType::Validate reports it.
std::string SecondApertureProblem(const SensorType& camera, const SecondAperture& aperture);
/// The second aperture a sensor's pixels need (issue 43): the type's own, else that of the
/// catalog entry `catalog_id` names; nullptr when it has none (or kind none: a time-of-flight
/// illuminator).
const SecondAperture* SecondApertureOf(const SensorType& type, std::string_view catalog_id);

/// The flying-pixel threshold a sensor's pixels are filtered by [m]: the type's own, else that of
/// the catalog entry `catalog_id` names; nullopt when none.
std::optional<double> FlyingPixelThresholdOf(const SensorType& type, std::string_view catalog_id);
/// Whether the physical model changes what the type sees: it has a second aperture or a
/// flying-pixel filter.
bool HasPhysicalModel(const SensorType& type, std::string_view catalog_id);

/// Whether a sensor's unit cost is a given price: false when its type is (or, with the same
/// cost, matches by id) a catalog entry that publishes none and the scene gave it no cost.
bool UnitCostGiven(const SensorType& type, std::string_view catalog_id);

/// Why the physical model cannot judge a type the way its technology needs ("" when it can):
/// structured light and stereo need a second aperture, and a type of that technology (its own,
/// else the catalog entry's) without one is seen as the ideal pinhole — no source gave the
/// projector's or second imager's pose. Time of flight needs none.
std::string PhysicalModelGap(const SensorType& type, std::string_view catalog_id);

/// The nearest depth stereo matching can return, fx * baseline / disparity_range [m]; 0 when the
/// aperture sets no disparity range (or is not an imager).
double StereoNearestDepth(const SensorType& camera, const SecondAperture& aperture);
/// The aperture's optical centre in the camera's body frame, (0, -baseline, 0).
Vec3 ApertureCentreInBody(const SecondAperture& aperture);
/// Rotation from the aperture's body frame (x along its axis) to the camera's: toe-in about z.
Mat3 BodyFromAperture(const SecondAperture& aperture);
/// Whether a camera-body-frame point lies inside the aperture's field (its frustum, cone or
/// image; the camera's own field where the aperture gives none).
bool InApertureField(const SensorType& camera, const SecondAperture& aperture, const Vec3& p_body);

/// InApertureField's test set up once per sensor: the toe-in rotation and the field's tangents are
/// computed here, not for every point (observe judges millions of hits per candidate).
///
/// Contains decides without a division or atan where the point is clearly inside or outside: it
/// compares y, z (cross-multiplied by the depth x) against the field's bounds with a relative
/// margin of 2^-30 that dwarfs the few roundings either form makes. A point within that margin
/// of the field's edge, or where a product would leave the comfortable range of doubles, goes to
/// Exactly, the division formula itself; so the verdict is always Exactly's.
class ApertureField {
 public:
  ApertureField(const SensorType& camera, const SecondAperture& aperture);
  // Always inlined: called out of line from observe's per-hit loop, the point went through memory
  // (its halves stored, then loaded as one 16-byte word: a store-forwarding stall on every hit).
  [[gnu::always_inline]] bool Contains(const Vec3& p_body) const {
    // Without toe-in the rotation is the identity (cos 0 = 1, sin 0 = 0): on a finite point its
    // product changes at most a zero's sign, which no test below reads (on an infinite one,
    // 0 · inf makes NaN, so the product is kept there).
    const Vec3 d = p_body - centre_;
    constexpr double kMax = std::numeric_limits<double>::max();
    const bool finite = std::abs(d.x()) <= kMax && std::abs(d.y()) <= kMax && std::abs(d.z()) <= kMax;
    // The turned (or non-finite) case out of line: a select between d and the product copied d
    // through the stack on every hit.
    if (turned_ || !finite) return ContainsTurned(d);
    return ContainsInFrame(d);
  }
  /// The division formula, for a point already in the aperture's frame with x > 0.
  bool Exactly(const Vec3& p) const;

 private:
  // Contains for d = p_body - centre_ where the rotation must be applied.
  bool ContainsTurned(const Vec3& d) const;
  // Contains of a point p already in the aperture's frame: Quickly, else Exactly.
  [[gnu::always_inline]] bool ContainsInFrame(const Vec3& p) const {
    if (!(p.x() > 0)) return false;
    const int verdict = Quickly(p);
    return verdict < 0 ? Exactly(p) : verdict != 0;
  }
  // 1 inside, 0 outside, -1 too close to the edge (or out of range) to tell without Exactly.
  [[gnu::always_inline]] int Quickly(const Vec3& p) const {
    constexpr double kMargin = 0x1p-30, kLow = 1e-140, kHigh = 1e140;
    const double x = p.x(), ay = std::abs(p.y()), az = std::abs(p.z());
    if (!(x > kLow && x < kHigh && ay < kHigh && az < kHigh)) return -1;
    // Whether a >= 0 (1), a < 0 (0), or unsure (-1), given a's scale.
    const auto sign = [](double a, double scale) {
      const double m = scale * kMargin;
      return a > m ? 1 : a < -m ? 0 : -1;
    };
    const auto both = [](int a, int b) { return a == 0 || b == 0 ? 0 : a < 0 || b < 0 ? -1 : 1; };
    if (half_cone_ > 0) {
      if (!quick_cone_) return -1;
      // Squares in (1e-180, 1e180): normal, or too small to matter beside the margin.
      const double limit = x * tan_half_cone_;
      if (!(limit > 1e-90 && limit < 1e90 && ay < 1e90 && az < 1e90)) return -1;
      return sign(limit * limit - (p.y() * p.y() + p.z() * p.z()),
                  limit * limit + p.y() * p.y() + p.z() * p.z());
    }
    if (tan_half_h_ > 0) {
      if (!quick_frustum_) return -1;
      const double h = x * tan_half_h_, v = x * tan_half_v_;
      return both(sign(h - ay, h + ay), sign(v - az, v + az));
    }
    if (!quick_image_) return -1;
    // u = cx - fx y / x, v = cy - fy z / x; times x: u x = cx x - fx y.
    const double ux = cx_ * x - fx_ * p.y(), vx = cy_ * x - fy_ * p.z();
    const double su = std::abs(cx_ * x) + std::abs(fx_ * p.y()) + image_width_ * x;
    const double sv = std::abs(cy_ * x) + std::abs(fy_ * p.z()) + image_height_ * x;
    // both(both(sign(ux, su), sign(w x - ux, su)), both(sign(vx, sv), sign(h x - vx, sv))),
    // each comparison made and the four combined without a branch (the scales are >= 0, so no
    // term is both above its margin and below its negative): 0 where one lies below, 1 where
    // all lie above, else -1.
    const double mu = su * kMargin, mv = sv * kMargin;
    const double right = image_width_ * x - ux, bottom = image_height_ * x - vx;
    const bool below = (ux < -mu) | (right < -mu) | (vx < -mv) | (bottom < -mv);
    const bool above = (ux > mu) & (right > mu) & (vx > mv) & (bottom > mv);
    return below ? 0 : above ? 1 : -1;
  }

  Mat3 aperture_from_body_;
  bool turned_ = true;  // aperture_from_body_ is not the identity
  Vec3 centre_;
  double half_cone_ = 0;                  // > 0: a cone of this half angle
  double tan_half_h_ = 0, tan_half_v_ = 0;  // > 0: a frustum
  double fx_, fy_, cx_, cy_;              // else an image: the aperture's or the camera's
  int width_, height_;
  double image_width_, image_height_;  // the same, converted once (exact) for Quickly
  // Quickly's own: tan(half_cone_), and whether its products stay in range for this field.
  double tan_half_cone_ = 0;
  bool quick_cone_ = false, quick_frustum_ = false, quick_image_ = false;
};

/// The image-plane slopes of the ray through the centre of pixel (u, v): rightward (u + 0.5 - cx)
/// / fx and downward (v + 0.5 - cy) / fy. PixelRayInBody is (1, -right, -down); a caller that
/// walks an image computes each column's and row's quotient once (observe).
inline double PixelRight(const SensorType& type, int u) { return (u + 0.5 - type.cx) / type.fx; }
inline double PixelDown(const SensorType& type, int v) { return (v + 0.5 - type.cy) / type.fy; }
/// Body-frame direction of the ray through the centre of pixel (u, v), scaled so that its x
/// (depth) component is 1: a hit at ray parameter t has depth t.
Vec3 PixelRayInBody(const SensorType& type, int u, int v);
/// Continuous image coordinates of a body-frame point with depth x > 0; nullopt when x <= 0.
std::optional<Eigen::Vector2d> ProjectBodyPoint(const SensorType& type, const Vec3& p_body);

}  // namespace vantage
