#include "observe/arm_occlusion.hpp"

#include "vantage/error.hpp"

namespace vantage::detail {

ArmOcclusion::ArmOcclusion(const RayScene& rays, std::span<const Candidate> candidates)
    : rays_(rays) {
  for (const Candidate& candidate : candidates) {
    if (!candidate.arm) continue;
    const ArmBody* body = candidate.arm->body.get();
    VANTAGE_CHECK(body != nullptr);
    if (!links_.count(body)) links_[body] = std::make_unique<RayBodies>(rays, body->link_meshes);
  }
}

PlacedRayScene ArmOcclusion::Place(const ArmPose& arm) const {
  const auto found = links_.find(arm.body.get());
  VANTAGE_CHECK(found != links_.end());
  VANTAGE_CHECK(arm.world_from_link.size() == found->second->size());
  return PlacedRayScene(rays_, *found->second, arm.world_from_link);
}

}  // namespace vantage::detail
