#pragma once
/// The arm that carries a camera occludes it as it stands in each view (issue 45): each link's
/// mesh has its own BVH (RayBodies), built once per Observe call, and each view traces a
/// PlacedRayScene: a top-level BVH over the cell and the links as Embree instances at that view's
/// poses, so a ray is one query and no link BVH is rebuilt per view.
#include <map>
#include <memory>
#include <span>

#include "vantage/candidates.hpp"
#include "vantage/ray_scene.hpp"

namespace vantage::detail {

class ArmOcclusion {
 public:
  /// The link BVHs of every distinct ArmBody among `candidates` (none when no candidate is on an
  /// arm), on `rays`' device.
  ArmOcclusion(const RayScene& rays, std::span<const Candidate> candidates);
  ArmOcclusion(const ArmOcclusion&) = delete;
  ArmOcclusion& operator=(const ArmOcclusion&) = delete;

  /// The scene as one view of the arm sees it: the cell and the arm's links where `arm` puts
  /// them (a link's hit is an occluder). Thread-safe; each call commits a new top-level BVH.
  PlacedRayScene Place(const ArmPose& arm) const;

 private:
  const RayScene& rays_;
  std::map<const ArmBody*, std::unique_ptr<RayBodies>> links_;
};

}  // namespace vantage::detail
