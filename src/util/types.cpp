#include "vantage/types.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "vantage/error.hpp"

namespace vantage {

Mat3 RotationFromRpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
          Eigen::AngleAxisd(roll, Vec3::UnitX()))
      .toRotationMatrix();
}

Vec3 RpyFromRotation(const Mat3& r) {
  // R = Rz(y) Ry(p) Rx(r): r20 = -sin(p), r21 = cos(p) sin(r), r22 = cos(p) cos(r),
  // r10 = cos(p) sin(y), r00 = cos(p) cos(y).
  const double sp = std::clamp(-r(2, 0), -1.0, 1.0);
  const double pitch = std::asin(sp);
  if (std::abs(sp) < 1.0 - 1e-12) {
    return Vec3(std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0)));
  }
  // Gimbal lock: only roll ∓ yaw is defined; put it all in yaw.
  const double yaw = std::atan2(-r(0, 1), r(1, 1));
  return Vec3(0.0, pitch, yaw);
}

std::array<double, 4> WxyzOf(const Quat& rotation) {
  const Quat q = rotation.normalized();
  return {q.w(), q.x(), q.y(), q.z()};
}

namespace {

/// `v` at length 1, or nullopt (see UnitDirection). Where the length is finite this is Eigen's
/// normalized(), so that every ordinary input keeps its last digits.
template <typename Vector>
std::optional<Vector> UnitOf(const Vector& v, double min_length) {
  if (!v.allFinite()) return std::nullopt;
  const double length = v.norm();
  if (std::isfinite(length)) {
    if (length < min_length) return std::nullopt;
    return v.normalized();
  }
  // The length of [1e300, 1e300, 0, 0] overflows to inf, and normalising by it gave a zero
  // quaternion that passed (issue 15), as (0, 1e190, 1) gave a joint a zero axis: scale by the
  // largest component first, only here.
  const Vector scaled = v / v.cwiseAbs().maxCoeff();
  return scaled.normalized();
}

}  // namespace

std::optional<Quat> QuatFromWxyz(std::span<const double> wxyz) {
  VANTAGE_CHECK(wxyz.size() == 4);
  // Eigen's coeffs() order (x, y, z, w), so that the length is summed as Quat::norm() sums it.
  const Eigen::Vector4d xyzw(wxyz[1], wxyz[2], wxyz[3], wxyz[0]);
  // Below 1e-9 it is rounding noise around zero, not a rotation someone meant (the callers'
  // messages say "zero, or shorter than 1e-09").
  const std::optional<Eigen::Vector4d> unit = UnitOf(xyzw, 1e-9);
  if (!unit) return std::nullopt;
  return Quat(*unit);  // Eigen's Quaternion(Vector4) takes x, y, z, w
}

std::optional<Vec3> UnitDirection(const Vec3& direction, double min_length) {
  return UnitOf(direction, min_length);
}

Pose Pose::FromXyzRpy(double x, double y, double z, double roll, double pitch, double yaw) {
  return Pose{Vec3(x, y, z), Quat(RotationFromRpy(roll, pitch, yaw)).normalized()};
}

bool VoxelIndexFits(const VoxelIndex& index) {
  for (int64_t v : index) {
    if (v < -kVoxelAxisOffset || v >= kVoxelAxisOffset) return false;
  }
  return true;
}

uint64_t PackVoxel(const VoxelIndex& index) {
  VANTAGE_CHECK(VoxelIndexFits(index));
  const auto axis = [](int64_t v) { return static_cast<uint64_t>(v + kVoxelAxisOffset); };
  return (axis(index[0]) << 42) | (axis(index[1]) << 21) | axis(index[2]);
}

VoxelIndex UnpackVoxel(uint64_t key) {
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  return {static_cast<int64_t>((key >> 42) & kMask) - kVoxelAxisOffset,
          static_cast<int64_t>((key >> 21) & kMask) - kVoxelAxisOffset,
          static_cast<int64_t>(key & kMask) - kVoxelAxisOffset};
}

Vec3 VoxelCenter(uint64_t key, double cell_size) {
  const VoxelIndex i = UnpackVoxel(key);
  return Vec3((static_cast<double>(i[0]) + 0.5) * cell_size,
              (static_cast<double>(i[1]) + 0.5) * cell_size,
              (static_cast<double>(i[2]) + 0.5) * cell_size);
}

std::string WorldPointProblem(const Vec3& p) {
  if (p.allFinite() && (p.array().abs() <= kMaxWorldCoordinate).all()) return "";
  return fmt::format("({:g}, {:g}, {:g}) m, beyond the ±{:g} m that vantage can ray cast", p.x(),
                     p.y(), p.z(), kMaxWorldCoordinate);
}

}  // namespace vantage
