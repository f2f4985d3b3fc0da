#pragma once
/// The arm that carries a camera occludes it as it stands in each view (issue 45): each link's
/// mesh has its own BVH (RayBodies), built once per Observe call, and each view traces a
/// PlacedRayScene: a top-level BVH over the cell and the links as Embree instances at that view's
/// poses, so a ray is one query and no link BVH is rebuilt per view.
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "observe/culling.hpp"
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

  /// The scene `candidate` (on an arm) traces `spans` in: as Place, but with only the links that
  /// a ray of those pixels (one pixel wider all round, up to the far plane) or a segment from its
  /// second aperture to a hit could meet; none when no link can be met, and the cell alone
  /// serves. Conservative: a link is left out only when its bounding box, grown by the
  /// aperture's baseline and 1 cm, lies wholly beyond one plane of the pixels' pyramid. Either
  /// way every ray meets what it would in Place's scene.
  std::optional<PlacedRayScene> PlaceForView(const Candidate& candidate,
                                             const std::vector<RowSpan>& spans) const;

 private:
  struct Links {
    std::unique_ptr<RayBodies> bodies;
    std::vector<Aabb> bounds;  ///< each link mesh's box in its link frame (empty: no mesh)
  };
  const RayScene& rays_;
  std::map<const ArmBody*, Links> links_;
};

}  // namespace vantage::detail
