// The arm against the cell and itself (issue 45), with FCL: each link's collision shapes
// (primitives as FCL shapes, meshes as OBBRSS BVHs) posed per view, against the scene's objects
// (primitives where the reader knows them, else their triangles as a BVH) and the keep-out boxes.
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>

#include "vantage/arm.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

using Geometry = std::shared_ptr<fcl::CollisionGeometryd>;

fcl::Transform3d ToFcl(const Pose& pose) {
  fcl::Transform3d transform = fcl::Transform3d::Identity();
  transform.linear() = pose.rotation.toRotationMatrix();
  transform.translation() = pose.position;
  return transform;
}

Geometry MeshGeometry(const TriangleMesh& mesh) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(mesh.vertices.size()));
  model->addSubModel(mesh.vertices, triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

/// One solid: its geometry and where it sits in its frame (a link's or the world's).
struct Solid {
  Geometry geometry;
  Pose frame_from_solid;
};

/// A robot shape as an FCL solid: the primitive itself, or the shape's mesh (link frame).
Solid LinkSolid(const PlacedRobot::LinkShape& shape) {
  const RobotVisual& s = shape.shape;
  switch (s.shape) {
    case RobotVisual::Shape::kBox:
      return {std::make_shared<fcl::Boxd>(s.size), s.link_from_visual};
    case RobotVisual::Shape::kCylinder:
      return {std::make_shared<fcl::Cylinderd>(s.radius, s.length), s.link_from_visual};
    case RobotVisual::Shape::kSphere:
      return {std::make_shared<fcl::Sphered>(s.radius), s.link_from_visual};
    case RobotVisual::Shape::kMesh:
      break;
  }
  return {MeshGeometry(shape.mesh), Pose{}};
}

/// A scene object's solids: its primitives when every shape is one (a YAML box, cylinder or
/// sphere), else its triangles.
std::vector<Solid> ObjectSolids(const SceneObject& object) {
  std::vector<Solid> solids;
  const bool primitives =
      !object.shapes.empty() &&
      std::all_of(object.shapes.begin(), object.shapes.end(), [](const ShapeSource& s) {
        return s.kind == ShapeSource::Kind::kBox || s.kind == ShapeSource::Kind::kCylinder ||
               s.kind == ShapeSource::Kind::kSphere;
      });
  if (primitives) {
    for (const ShapeSource& s : object.shapes) {
      Geometry geometry;
      if (s.kind == ShapeSource::Kind::kBox) geometry = std::make_shared<fcl::Boxd>(s.size);
      if (s.kind == ShapeSource::Kind::kCylinder)
        geometry = std::make_shared<fcl::Cylinderd>(s.size.x(), s.size.y());
      if (s.kind == ShapeSource::Kind::kSphere)
        geometry = std::make_shared<fcl::Sphered>(s.size.x());
      solids.push_back({geometry, s.world_from_shape});
    }
  } else if (!object.mesh.IsEmpty()) {
    solids.push_back({MeshGeometry(object.mesh), Pose{}});
  }
  return solids;
}

struct WorldSolid {
  std::unique_ptr<fcl::CollisionObjectd> object;
  std::string name;  ///< for messages: "object 'bin'", "keep_out 'cable_tray'"
  bool keep_out = false;
};

bool Collide(const fcl::CollisionObjectd& a, const fcl::CollisionObjectd& b) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  return fcl::collide(&a, &b, request, result) > 0;
}

}  // namespace

struct ArmCollisions::Impl {
  std::vector<std::string> links;  ///< links with geometry, the moving ones first
  size_t moving_links = 0;         ///< only they are checked against the cell
  std::vector<std::vector<Solid>> link_solids;
  std::vector<std::pair<size_t, size_t>> self_pairs;  ///< link index pairs checked
  std::vector<WorldSolid> world;             ///< keep-out boxes first, then the cell
  std::set<std::pair<std::string, std::string>> allowed;  ///< both orders
  bool Allowed(const std::string& a, const std::string& b) const {
    return allowed.count({a, b}) > 0;
  }
};

ArmCollisions::ArmCollisions(const PlacedRobot& robot, const Scene& scene,
                             const std::vector<KeepOutBox>& keep_out,
                             const std::vector<std::string>& moving_joints,
                             const std::vector<std::pair<std::string, std::string>>& allowed_pairs)
    : impl_(new Impl(), [](Impl* impl) { delete impl; }) {
  const RobotModel& model = robot.model;
  for (const auto& [a, b] : allowed_pairs) {
    impl_->allowed.insert({a, b});
    impl_->allowed.insert({b, a});
  }
  // The links a moving joint carries: each child of a moving joint and everything below it.
  std::set<std::string> moving(moving_joints.begin(), moving_joints.end());
  std::set<std::string> carried;
  for (const RobotJoint& joint : model.joints) {  // tree order: parents first
    const bool moves = moving.count(joint.name) > 0 ||
                       (!joint.mimic.empty() && moving.count(joint.mimic) > 0);
    if (moves || carried.count(joint.parent_link)) carried.insert(joint.child_link);
  }
  std::set<std::pair<std::string, std::string>> adjacent;
  for (const RobotJoint& joint : model.joints) {
    adjacent.insert({joint.parent_link, joint.child_link});
    adjacent.insert({joint.child_link, joint.parent_link});
  }
  std::vector<std::string> all_links;  // with geometry, moving or not (self pairs)
  std::vector<std::vector<Solid>> all_solids;
  for (const auto& [link, shapes] : robot.collision_shapes) {
    std::vector<Solid> solids;
    for (const PlacedRobot::LinkShape& shape : shapes) solids.push_back(LinkSolid(shape));
    all_links.push_back(link);
    all_solids.push_back(std::move(solids));
  }
  // Moving links come first; the fixed ones follow (self pairs with a moving link only).
  std::vector<size_t> order;
  for (size_t i = 0; i < all_links.size(); ++i)
    if (carried.count(all_links[i])) order.push_back(i);
  const size_t moving_count = order.size();
  for (size_t i = 0; i < all_links.size(); ++i)
    if (!carried.count(all_links[i])) order.push_back(i);
  for (size_t i : order) {
    impl_->links.push_back(all_links[i]);
    impl_->link_solids.push_back(all_solids[i]);
  }
  for (size_t a = 0; a < moving_count; ++a) {
    for (size_t b = a + 1; b < impl_->links.size(); ++b) {
      const std::string& la = impl_->links[a];
      const std::string& lb = impl_->links[b];
      if (adjacent.count({la, lb}) || impl_->Allowed(la, lb)) continue;
      impl_->self_pairs.emplace_back(a, b);
    }
  }
  for (const KeepOutBox& box : keep_out) {
    const Vec3 size = box.max - box.min;
    const Pose world_from_solid = box.world_from_box * Pose{0.5 * (box.min + box.max), Quat::Identity()};
    auto object = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(size),
                                                          ToFcl(world_from_solid));
    object->computeAABB();
    impl_->world.push_back({std::move(object), box.name, true});
  }
  const std::string own_prefix = robot.name + "::";
  for (const SceneObject& object : scene.objects) {
    if (object.name.rfind(own_prefix, 0) == 0) continue;  // the robot's own links
    for (Solid& solid : ObjectSolids(object)) {
      auto fcl_object = std::make_unique<fcl::CollisionObjectd>(solid.geometry,
                                                                ToFcl(solid.frame_from_solid));
      fcl_object->computeAABB();
      impl_->world.push_back({std::move(fcl_object), object.name, false});
    }
  }
  impl_->moving_links = moving_count;
}

ArmCollisions::~ArmCollisions() = default;
ArmCollisions::ArmCollisions(ArmCollisions&&) noexcept = default;
ArmCollisions& ArmCollisions::operator=(ArmCollisions&&) noexcept = default;

ArmCollision ArmCollisions::Check(const std::map<std::string, Pose>& world_from_link,
                                  std::string* what) const {
  // The links' solids at this view (fresh objects: the call is thread-safe).
  std::vector<std::vector<std::unique_ptr<fcl::CollisionObjectd>>> posed(impl_->links.size());
  for (size_t l = 0; l < impl_->links.size(); ++l) {
    const Pose& world_from_link_l = world_from_link.at(impl_->links[l]);
    for (const Solid& solid : impl_->link_solids[l]) {
      posed[l].push_back(std::make_unique<fcl::CollisionObjectd>(
          solid.geometry, ToFcl(world_from_link_l * solid.frame_from_solid)));
      posed[l].back()->computeAABB();
    }
  }
  const auto hits = [&](size_t link, const fcl::CollisionObjectd& other) {
    for (const auto& object : posed[link])
      if (Collide(*object, other)) return true;
    return false;
  };
  for (const bool keep_out : {true, false}) {
    for (size_t l = 0; l < impl_->moving_links; ++l) {
      for (const WorldSolid& solid : impl_->world) {
        if (solid.keep_out != keep_out) continue;
        if (!keep_out && impl_->Allowed(impl_->links[l], solid.name)) continue;
        if (!hits(l, *solid.object)) continue;
        if (what)
          *what = fmt::format("link '{}' and {} '{}'", impl_->links[l],
                              keep_out ? "keep_out box" : "object", solid.name);
        return keep_out ? ArmCollision::kKeepOut : ArmCollision::kScene;
      }
    }
  }
  for (const auto& [a, b] : impl_->self_pairs) {
    for (const auto& object : posed[b]) {
      if (!hits(a, *object)) continue;
      if (what) *what = fmt::format("links '{}' and '{}'", impl_->links[a], impl_->links[b]);
      return ArmCollision::kSelf;
    }
  }
  return ArmCollision::kNone;
}

}  // namespace vantage
