#pragma once
/// Geometry value types shared by every stage: poses, voxel keys, bounds.
/// Units: metres and radians; frames are named in variables (world_from_body).
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>

namespace vantage {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;

/// A rigid transform target_from_source: p_target = rotation * p_source + position.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat rotation = Quat::Identity();

  Vec3 operator*(const Vec3& p) const { return rotation * p + position; }
  Pose operator*(const Pose& other) const {
    return Pose{rotation * other.position + position, (rotation * other.rotation).normalized()};
  }
  Pose Inverse() const {
    const Quat inv = rotation.conjugate();
    return Pose{-(inv * position), inv};
  }
  /// Gazebo's `<pose>x y z roll pitch yaw</pose>`: R = Rz(yaw)·Ry(pitch)·Rx(roll).
  static Pose FromXyzRpy(double x, double y, double z, double roll, double pitch, double yaw);
};

/// R = Rz(yaw)·Ry(pitch)·Rx(roll) (fixed-axis XYZ, as SDF and ROS).
Mat3 RotationFromRpy(double roll, double pitch, double yaw);
/// Inverse of RotationFromRpy: (roll, pitch, yaw) with pitch in [-pi/2, pi/2].
Vec3 RpyFromRotation(const Mat3& rotation);

/// Quaternions in files (report.json, candidates.csv, scene and constellation YAML, the page) are
/// [w, x, y, z]; Eigen's coeffs() are x, y, z, w. These two convert, and nothing else does.
/// The rotation as unit [w, x, y, z].
std::array<double, 4> WxyzOf(const Quat& rotation);
/// The unit rotation of [w, x, y, z] (size 4, any length); nullopt when the length is below 1e-9.
std::optional<Quat> QuatFromWxyz(std::span<const double> wxyz);
/// A direction read from a file (a joint's axis, a plane's normal) at length 1; nullopt when a
/// component is not finite or the length is below `min_length` (rounding noise, not a direction
/// someone meant). Any finite direction has its unit vector, even where the length overflows a
/// double: (0, 1e190, 1) is (0, 1, 1e-190), not the zero vector Eigen's normalized() gives.
std::optional<Vec3> UnitDirection(const Vec3& direction, double min_length);

/// Integer cell of a point: floor(p / F) per axis, grid aligned to the world origin (PCL
/// VoxelGrid).
using VoxelIndex = std::array<int64_t, 3>;

/// floor(x) as an integer, without a libm call (it runs for every ray that hits a target). Values
/// beyond ±2^62 and NaN saturate, so VoxelIndexFits rejects them instead of undefined behaviour.
inline int64_t FloorToInt(double x) {
  if (!(std::abs(x) < 0x1p62)) return x > 0 ? INT64_MAX : INT64_MIN;
  const auto truncated = static_cast<int64_t>(x);
  return static_cast<double>(truncated) > x ? truncated - 1 : truncated;
}

inline VoxelIndex VoxelKeyOf(const Vec3& p, double cell_size) {
  return {FloorToInt(p.x() / cell_size), FloorToInt(p.y() / cell_size),
          FloorToInt(p.z() / cell_size)};
}

/// Cells are packed into 64 bits (21 bits per axis, offset 2^20), ordered by x, then y, then z.
/// Range: |index| < 2^20 per axis (about ±5 km at 5 mm cells).
constexpr int64_t kVoxelAxisOffset = int64_t{1} << 20;
/// True when the index fits the packed range.
bool VoxelIndexFits(const VoxelIndex& index);
/// Packs an index; the caller checks VoxelIndexFits first (throws InternalError otherwise).
uint64_t PackVoxel(const VoxelIndex& index);
VoxelIndex UnpackVoxel(uint64_t key);
/// Centre of a packed cell, in world coordinates.
Vec3 VoxelCenter(uint64_t key, double cell_size);

/// Axis-aligned bounds; empty when min > max.
struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
  bool IsEmpty() const { return (min.array() > max.array()).any(); }
  void Extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void Extend(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
};

/// What vantage can ray cast (issue 15), checked where each value enters: geometry when a scene
/// is loaded, candidates before any ray, render's viewpoint. Embree takes float origins,
/// directions and vertices and asserts (Debian's build aborts) on rays beyond about 1.8e18, and
/// builds a wrong BVH for vertices near that. 1e9 m is far beyond any real cell, still resolved
/// to 64 m by a float, and every ray end (origin + far · direction, at most 1e9 + 1e9 · 1.5e6 m)
/// stays far inside float and Embree's range.
constexpr double kMaxWorldCoordinate = 1e9;  ///< |x|, |y|, |z| of geometry, sensors, the eye [m]
constexpr double kMaxSensorRange = 1e9;      ///< a sensor's far [m]
/// The finest voxel F [m]: 1 µm, below what any depth camera resolves and a few float steps (the
/// precision of Embree's rays, 6e-8 m at 1 m from the origin) wide. Finer cells only overflowed
/// the tessellation (chord F / 10) or the grid's memory with a message blaming the geometry.
constexpr double kMinCellSize = 1e-6;
/// |y| and |z| of a pixel ray scaled to depth x = 1 (fields of view up to 2 atan(1e6) ≈ 180°).
constexpr double kMaxRaySlope = 1e6;

/// "" when every coordinate of `p` is finite and within ±kMaxWorldCoordinate; else the words for
/// a message, e.g. "(1e+19, 0, 0) m, beyond the ±1e+09 m that vantage can ray cast".
std::string WorldPointProblem(const Vec3& p);

}  // namespace vantage
