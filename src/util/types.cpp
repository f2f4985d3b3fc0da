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

std::optional<Quat> QuatFromWxyz(std::span<const double> wxyz) {
  VANTAGE_CHECK(wxyz.size() == 4);
  for (const double v : wxyz) {
    if (!std::isfinite(v)) return std::nullopt;
  }
  const Quat rotation(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);  // Eigen's constructor takes w first
  const double norm = rotation.norm();
  if (std::isfinite(norm)) {
    // Below 1e-9 it is rounding noise around zero, not a rotation someone meant (the callers'
    // messages say "zero, or shorter than 1e-09").
    if (norm < 1e-9) return std::nullopt;
    return rotation.normalized();
  }
  // The norm of [1e300, 1e300, 0, 0] overflows to inf, and normalising by it gave a zero
  // quaternion that passed (issue 15): scale by the largest component first (only here, so that
  // every other input keeps its last digits).
  double largest = 0;
  for (const double v : wxyz) largest = std::max(largest, std::abs(v));
  const Quat scaled(wxyz[0] / largest, wxyz[1] / largest, wxyz[2] / largest, wxyz[3] / largest);
  return scaled.normalized();
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
