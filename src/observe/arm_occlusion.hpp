#pragma once
/// The arm that carries a camera occludes it as it stands in each view (issue 45): each link's
/// mesh has its own BVH, built once per Observe call, and a view's rays are tested against every
/// link in the link's frame (the ray moved by the inverse of the view's world_from_link), so the
/// BVHs are never rebuilt per view. Embree's instancing, done by hand per packet.
#include <map>
#include <memory>
#include <span>

#include "vantage/candidates.hpp"
#include "vantage/ray_scene.hpp"

namespace vantage::detail {

class ArmOcclusion {
 public:
  /// The BVHs of every distinct ArmBody among `candidates` (none when no candidate is on an arm).
  explicit ArmOcclusion(std::span<const Candidate> candidates);
  ~ArmOcclusion();
  ArmOcclusion(const ArmOcclusion&) = delete;
  ArmOcclusion& operator=(const ArmOcclusion&) = delete;

  /// Lanes of `batch` (already traced in the scene) whose ray meets a link of `arm` before its
  /// hit become that link's hit: t the link's, not a target. Thread-safe.
  void Clip(const ArmPose& arm, RayBatch* batch) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vantage::detail
