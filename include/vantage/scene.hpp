#pragma once
/// The scene: triangles of every object in world coordinates, each object a target or an
/// occluder (SYSTEM.md, pipeline stage 1), and the meshes/primitives it is built from.
#include <cstdint>
#include <string>
#include <vector>

#include "vantage/types.hpp"

namespace vantage {

/// Indexed triangle mesh; vertices in metres.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;

  bool IsEmpty() const { return triangles.empty(); }
  Aabb Bounds() const;
  /// Sum of triangle areas [m²].
  double Area() const;
  /// Bytes its vertices and triangles hold: what a copy of it costs (the memory estimates).
  uint64_t Bytes() const;
  /// Appends another mesh (indices shifted).
  void Append(const TriangleMesh& other);
  /// Applies p -> pose * p to every vertex.
  void Transform(const Pose& pose);
  /// Multiplies every vertex component-wise by `scale` (before any pose).
  void Scale(const Vec3& scale);
};

enum class Role { kTarget, kOccluder };

/// A shape as a simulator declares it (SDF `<geometry>`), placed in the world: what an object's
/// triangles were made from, for exports that write shapes (constellation.sdf).
struct ShapeSource {
  enum class Kind { kBox, kCylinder, kSphere, kPlane, kMesh };
  Kind kind = Kind::kBox;
  /// box: edge lengths; plane: x, y edge lengths (z unused); cylinder: radius, length (along z);
  /// sphere: radius. Centred at the shape's origin, as MakeBox and the others build them.
  Vec3 size = Vec3::Zero();
  std::string mesh_path;     ///< kMesh: the file, absolute
  Vec3 scale = Vec3::Ones();  ///< kMesh: applied to the file's coordinates before the pose
  Pose world_from_shape;
};

/// One object of the scene, already in world coordinates.
struct SceneObject {
  std::string name;
  Role role = Role::kOccluder;
  TriangleMesh mesh;  ///< world frame
  /// The shapes `mesh` was made of, when the reader knows them (YAML objects); empty otherwise.
  std::vector<ShapeSource> shapes;
  /// Where it is declared, for messages: the YAML entry, the URDF robot, the SDF <visual> (for
  /// a model of several visuals, the first). Empty and 0 when not known.
  std::string file = {};
  int line = 0;
  bool is_target() const { return role == Role::kTarget; }
};

struct Scene {
  std::vector<SceneObject> objects;

  size_t TargetCount() const;
  size_t TriangleCount() const;
  /// Bounds of every target's triangles (empty when there is none).
  Aabb TargetBounds() const;
};

/// Throws InputError "FILE:LINE: object 'NAME' reaches ..." when a vertex of any object (target
/// or occluder) lies beyond ±kMaxWorldCoordinate, where the ray caster is no longer exact (issue
/// 15), or when every triangle of a target collapses once its vertices are floats (the ray
/// caster's precision: a target of 1e-12 m could never be hit). The place is the object's own
/// (SceneObject::file, line), else `source`; with a `state_line`, the objects are those of a
/// scene state declared at source:state_line, named with the state in the message.
void CheckSceneExtent(const Scene& scene, const std::string& source, int state_line = 0,
                      const std::string& state = {});

/// One warning per occluder whose every triangle collapses once its vertices are floats (a 1e-9 m
/// bolt, or a 5 cm one 10^6 m from the origin): the ray caster cannot represent it, so it hides
/// nothing and the coverage is what the cameras would see without it. Placed as
/// CheckSceneExtent places its errors. With `before` (the scene a state changes), occluders
/// already collapsed there are not named again.
std::vector<std::string> CollapsedOccluderWarnings(const Scene& scene, const std::string& source,
                                                   int state_line = 0,
                                                   const std::string& state = {},
                                                   const Scene* before = nullptr);

/// Axis-aligned box of the given edge lengths, centred at the origin (12 triangles, outward).
TriangleMesh MakeBox(const Vec3& size);
/// Sphere of `radius` at the origin, tessellated so that the chord error is below
/// `max_chord_error` (UV sphere).
TriangleMesh MakeSphere(double radius, double max_chord_error);
/// Capsule along z, centred at the origin: a cylinder of `length` between two hemispheres of
/// `radius` (SDF's <capsule>), chord error below the bound.
TriangleMesh MakeCapsule(double radius, double length, double max_chord_error);
/// Ellipsoid of semi-axes `radii` along x, y, z at the origin (SDF's <ellipsoid>), chord error
/// below the bound.
TriangleMesh MakeEllipsoid(const Vec3& radii, double max_chord_error);
/// Closed cylinder along z, centred at the origin (caps included), chord error below the bound.
TriangleMesh MakeCylinder(double radius, double length, double max_chord_error);
/// Rectangle in the z = 0 plane, centred at the origin, normal +z (two triangles).
TriangleMesh MakePlane(double size_x, double size_y);

/// Reads any mesh format Assimp reads (STL, DAE, OBJ, PLY...), all its nodes flattened with
/// their transforms, every triangle kept (degenerate ones too). Throws InputError naming the
/// file when it is unreadable, holds no triangle or has a non-finite vertex.
TriangleMesh ReadMeshFile(const std::string& path);
/// `raw` (ReadMeshFile(path)) with every vertex multiplied component-wise by `scale`, its
/// degenerate triangles dropped. Throws InputError "PATH: a vertex of the mesh ... lies at (x, y,
/// z) m, beyond the ±1e+09 m that vantage can ray cast ..." when a scaled vertex of any triangle
/// lies beyond ±kMaxWorldCoordinate (checked before a triangle is dropped: a vertex far out
/// makes its triangles slivers), or naming the file when every triangle is degenerate.
TriangleMesh ScaledMesh(TriangleMesh raw, const Vec3& scale, const std::string& path);
/// ScaledMesh(ReadMeshFile(path), scale, path).
TriangleMesh LoadMeshFile(const std::string& path, const Vec3& scale = Vec3::Ones());

}  // namespace vantage
