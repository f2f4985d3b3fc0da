#pragma once
/// Embree behind a small interface: the scene's BVH built once per geometry, shared read-only by
/// every thread and every stage that casts rays (observe, the robustness read-outs, refinement,
/// the rendered view). The only file that includes Embree is src/observe/ray_scene.cpp (STYLE.md).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vantage/scene.hpp"

namespace vantage {

/// One ray of a packet: origin o and direction d (not normalised) in world coordinates.
struct RayBatch {
  static constexpr int kWidth = 16;
  float origin[3];                      ///< shared by the packet (one camera centre)
  /// Per-lane direction, SoA. Zeroed: Debian's Embree asserts that the rays of a packet are
  /// finite, and lanes past `active` reach that check uninitialised (aborts at random otherwise).
  float dir[3][kWidth] = {};
  int active = 0;                       ///< lanes in use, from 0
  float tfar = 0;                       ///< farthest distance searched (in units of |d|)
  // Results: ray parameter of the first hit (inf when none) and whether it hit a target.
  float t[kWidth];
  bool is_target[kWidth];
  float normal[3][kWidth];  ///< geometric normal of the hit (not normalised; valid on hits)
  /// The hit on a target, valid where is_target: the point at Embree's barycentric coordinates
  /// on the scene's own (double) triangle, v0 + u (v1 - v0) + v (v2 - v0). On a face that lies on
  /// a grid plane it has the plane's coordinate exactly, so its cell is the face's cell of R;
  /// origin + t d (float t and d) fell on either side of the plane ray by ray.
  double point[3][kWidth];
};

/// Segments from one point (a projector, a second imager) to up to 16 points, each tested for an
/// occluder between them (issue 43: the physical sensor model).
struct OcclusionBatch {
  static constexpr int kWidth = 16;
  float origin[3];
  /// Per lane, the segment's end minus its start: the ray runs over parameters [0, tfar].
  float dir[3][kWidth] = {};
  bool query[kWidth] = {};  ///< lanes to test; the others are left alone
  /// Where the segments stop, short of their ends so the surface a point lies on does not
  /// occlude it.
  float tfar = 1;
  bool occluded[kWidth];  ///< result, valid where query
};

/// The first hit of one ray, with what it hit (for shading a rendered view).
struct RayHit {
  float t = 0;             ///< ray parameter of the hit; inf on a miss
  int32_t object = -1;     ///< index into Scene::objects; -1 on a miss
  uint32_t triangle = 0;   ///< triangle index in that object's mesh
  float normal[3] = {};    ///< geometric normal, world frame, not normalised (Embree's Ng)
  bool is_target = false;
  /// The hit on a target, valid where is_target: as RayBatch::point, so that a rendered pixel
  /// lands in the cell the observations count.
  double point[3] = {};
};

/// Owns an Embree device and a committed scene of every object (targets and occluders). Build it
/// once per scene geometry and pass it to every call that casts rays into that geometry.
class RayScene {
 public:
  /// Copies the scene's triangles (as float) into Embree and builds the BVH. InternalError when
  /// Embree cannot create a device.
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  /// Traces the active lanes of `batch` (coherent packet) and fills t / is_target. Thread-safe.
  void Intersect(RayBatch* batch) const;
  /// Tests the queried lanes of `batch` for an occluder (any hit) along their segments, as one
  /// packet. Thread-safe.
  void Occluded(OcclusionBatch* batch) const;
  /// Single ray with the object, triangle and normal it hits. Thread-safe.
  RayHit IntersectHit(const float origin[3], const float dir[3], float tfar) const;

  /// A 64-bit hash of the geometry as it is traced: each object's role, its vertices as the ray
  /// caster holds them (float), the targets' in double too, and its triangles, in order. Equal
  /// in every process given the same scene content, whatever the files' paths; computed on each
  /// call (the distributed layer's check that its processes trace the same scene).
  uint64_t GeometryFingerprint() const;

 private:
  friend class RayBodies;
  friend class PlacedRayScene;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Rigid bodies with BVHs of their own (a robot's links, issue 45), built once on a RayScene's
/// Embree device; PlacedRayScene puts them at any view's poses without rebuilding them.
class RayBodies {
 public:
  /// One BVH per mesh, in the mesh's own frame (an empty mesh has none and is never hit).
  RayBodies(const RayScene& scene, std::span<const TriangleMesh> meshes);
  ~RayBodies();
  RayBodies(const RayBodies&) = delete;
  RayBodies& operator=(const RayBodies&) = delete;
  size_t size() const;

 private:
  friend class PlacedRayScene;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A RayScene with RayBodies at one view's poses, as Embree instances: a top-level BVH over the
/// scene (one instance, identity) and each body (an instance at its world_from_body), so a ray
/// is one query that meets whichever is first. Building it commits a BVH over 1 + bodies boxes
/// only; the scene's and the bodies' BVHs are shared. A body's hit is an occluder (is_target
/// false), its normal turned into the world frame. The RayScene and the RayBodies must outlive it.
class PlacedRayScene {
 public:
  /// InternalError on a non-finite pose (nothing non-finite reaches Embree). `placed` (one per
  /// body; empty: all) leaves out the bodies it marks 0, e.g. those no ray of a view can reach.
  PlacedRayScene(const RayScene& scene, const RayBodies& bodies,
                 std::span<const Pose> world_from_body, std::span<const uint8_t> placed = {});
  ~PlacedRayScene();
  PlacedRayScene(PlacedRayScene&&) noexcept;
  PlacedRayScene& operator=(PlacedRayScene&&) noexcept;
  PlacedRayScene(const PlacedRayScene&) = delete;
  PlacedRayScene& operator=(const PlacedRayScene&) = delete;

  /// As RayScene::Intersect, the bodies included. Thread-safe.
  void Intersect(RayBatch* batch) const;
  /// As RayScene::Occluded, the bodies included. Thread-safe.
  void Occluded(OcclusionBatch* batch) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vantage
