#pragma once
/// Depth sensor types (SENSORS.md) and the pinhole camera model.
/// Body frame: x forward, y left, z up (Gazebo, ROS). Image: u right = -y, v down = -z,
/// depth along +x. Pixel (u, v) covers [u, u+1) x [v, v+1); its ray passes its centre (u+0.5, v+0.5).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vantage/types.hpp"

namespace vantage {

/// Axial depth noise, one standard deviation: sigma(z) = a + b z + c z^2 [m] at depth z [m]
/// (docs/sensor-models.md: structured light and stereo grow with z^2, time of flight is roughly
/// constant).
struct DepthNoise {
  double a = 0, b = 0, c = 0;
  std::string source;  ///< where the coefficients come from
  double Sigma(double z) const { return a + (b + c * z) * z; }
};

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
  /// Depth noise model; unset when no published model is known for the type.
  std::optional<DepthNoise> depth_noise;
  /// Whether its projector washes out another projecting sensor's pattern (projector
  /// interference, docs/constraints.md); unset: from the technology (ProjectsLight).
  std::optional<bool> interferes;

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

/// The 14 types of SENSORS.md, in its order.
const std::vector<SensorType>& Catalog();
/// Catalog entry by id, or nullptr.
const SensorType* FindCatalogType(std::string_view id);
/// The id of the catalog entry with the same resolution, intrinsics and range (relative
/// tolerance 1e-6), or "" when none matches.
std::string MatchCatalogId(const SensorType& type);

/// Whether sensors of `type` interfere: `type.interferes` when set, else whether its technology
/// (or, when empty, that of the catalog entry `catalog_id`) is structured light or time of
/// flight. Active stereo (a texture projector that stereo matching does not rely on) and passive
/// stereo do not.
bool ProjectsLight(const SensorType& type, std::string_view catalog_id = {});

/// Body-frame direction of the ray through the centre of pixel (u, v), scaled so that its x
/// (depth) component is 1: a hit at ray parameter t has depth t.
Vec3 PixelRayInBody(const SensorType& type, int u, int v);
/// Continuous image coordinates of a body-frame point with depth x > 0; nullopt when x <= 0.
std::optional<Eigen::Vector2d> ProjectBodyPoint(const SensorType& type, const Vec3& p_body);

}  // namespace vantage
