// Scene module: primitives against analytic areas and bounds, mesh files through Assimp, the
// YAML scene format (docs/scene-format.md) and its error messages.
#include "vantage/scene.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <functional>
#include <cstdlib>
#include <cstdio>
#include <csignal>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "scene/plain_obj.hpp"
#include "scene/ply_body.hpp"
#include "util/isolated.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"
#include "vantage/scene_settings.hpp"

namespace vantage {
namespace {

using test::TempDir;
using test::WriteText;

constexpr double kPi = std::numbers::pi;

Vec3 Normal(const TriangleMesh& mesh, const std::array<uint32_t, 3>& t) {
  const Vec3& a = mesh.vertices[t[0]];
  return (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
}

Vec3 Centroid(const TriangleMesh& mesh, const std::array<uint32_t, 3>& t) {
  return (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
}

/// For a convex mesh around the origin every face's normal points away from the origin.
void ExpectOutwardNormals(const TriangleMesh& mesh) {
  for (const auto& t : mesh.triangles) {
    EXPECT_GT(Normal(mesh, t).dot(Centroid(mesh, t)), 0.0);
  }
}

/// Closed surface: every undirected edge is shared by exactly two triangles, in opposite
/// directions (consistent orientation).
void ExpectClosed(const TriangleMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
}

/// Distance from the origin to a triangle's plane: no point of the facet is nearer.
double PlaneDistance(const TriangleMesh& mesh, const std::array<uint32_t, 3>& t) {
  const Vec3 n = Normal(mesh, t).normalized();
  return std::abs(n.dot(mesh.vertices[t[0]]));
}

bool HasVertexNear(const TriangleMesh& mesh, const Vec3& p, double tolerance = 1e-9) {
  for (const Vec3& v : mesh.vertices) {
    if ((v - p).norm() < tolerance) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// Primitives

TEST(Scene, BoxHasAnalyticAreaBoundsAndOutwardFaces) {
  const TriangleMesh box = MakeBox(Vec3(0.2, 0.4, 0.6));
  EXPECT_EQ(box.triangles.size(), 12u);
  EXPECT_NEAR(box.Area(), 2 * (0.2 * 0.4 + 0.4 * 0.6 + 0.6 * 0.2), 1e-12);
  const Aabb b = box.Bounds();
  EXPECT_TRUE(b.min.isApprox(Vec3(-0.1, -0.2, -0.3)));
  EXPECT_TRUE(b.max.isApprox(Vec3(0.1, 0.2, 0.3)));
  ExpectOutwardNormals(box);
  ExpectClosed(box);
}

TEST(Scene, SphereAreaWithinTheChordErrorBound) {
  const double r = 0.1, e = 0.0005;
  const TriangleMesh sphere = MakeSphere(r, e);
  // An inscribed convex polyhedron whose faces all lie at least r − e from the centre holds the
  // ball of radius r − e: its area lies between the two spheres' areas.
  EXPECT_LT(sphere.Area(), 4 * kPi * r * r);
  EXPECT_GT(sphere.Area(), 4 * kPi * (r - e) * (r - e));
  for (const auto& t : sphere.triangles) EXPECT_GT(PlaneDistance(sphere, t), r - e);
  for (const Vec3& v : sphere.vertices) EXPECT_NEAR(v.norm(), r, 1e-12);
  const Aabb b = sphere.Bounds();
  EXPECT_NEAR(b.max.z(), r, 1e-12);
  EXPECT_NEAR(b.min.z(), -r, 1e-12);
  EXPECT_LE(b.max.x(), r + 1e-12);
  EXPECT_GT(b.max.x(), r - e);
  ExpectOutwardNormals(sphere);
  ExpectClosed(sphere);
}

TEST(Scene, SphereCoarseBoundStillHolds) {
  // A bound larger than the radius: the coarsest sphere still keeps every face off the centre.
  const TriangleMesh sphere = MakeSphere(1.0, 1.5);
  EXPECT_GE(sphere.triangles.size(), 6u);
  for (const auto& t : sphere.triangles) EXPECT_GT(PlaneDistance(sphere, t), 1.0 - 1.5);
  ExpectClosed(sphere);
}

TEST(Scene, CylinderAreaWithinTheChordErrorBound) {
  const double r = 0.05, l = 0.2, e = 0.0005;
  const TriangleMesh cylinder = MakeCylinder(r, l, e);
  const auto area = [&](double radius) { return 2 * kPi * radius * l + 2 * kPi * radius * radius; };
  EXPECT_LT(cylinder.Area(), area(r));
  EXPECT_GT(cylinder.Area(), area(r - e));
  const Aabb b = cylinder.Bounds();
  EXPECT_NEAR(b.min.z(), -l / 2, 1e-12);
  EXPECT_NEAR(b.max.z(), l / 2, 1e-12);
  EXPECT_NEAR(b.max.x(), r, 1e-12);  // a vertex at azimuth 0
  ExpectOutwardNormals(cylinder);
  ExpectClosed(cylinder);
}

TEST(Scene, CylinderUsesTheFewestSegmentsThatMeetTheBound) {
  // r (1 − cos(π/n)) < e with r = 1, e = 0.01: π/n < acos(0.99) = 0.141539 → n > 22.196 → 23.
  const TriangleMesh cylinder = MakeCylinder(1.0, 1.0, 0.01);
  int rim = 0;
  for (const Vec3& v : cylinder.vertices) {
    if (std::abs(v.z() - 0.5) < 1e-12 && std::abs(v.head<2>().norm() - 1.0) < 1e-12) ++rim;
  }
  EXPECT_EQ(rim, 23);
}

// SDF's <capsule> (session 10's sweep: it was skipped, so the occluder was missing): every vertex
// at the radius from the axis segment, the area between the capsules of radius r − e and r, and
// each facet's centre no deeper than the chord error bound.
TEST(Scene, CapsuleOnItsSurfaceWithinTheChordErrorBound) {
  const double r = 0.05, l = 0.2, e = 0.0005;
  const TriangleMesh capsule = MakeCapsule(r, l, e);
  const auto depth = [&](const Vec3& p) {  // distance from the axis segment, minus r
    return r - (p - Vec3(0, 0, std::clamp(p.z(), -l / 2, l / 2))).norm();
  };
  for (const Vec3& v : capsule.vertices) EXPECT_NEAR(depth(v), 0.0, 1e-12) << v.transpose();
  for (const auto& t : capsule.triangles) {
    const Vec3 centre = (capsule.vertices[t[0]] + capsule.vertices[t[1]] +
                         capsule.vertices[t[2]]) / 3;
    EXPECT_LT(depth(centre), e);
    EXPECT_GE(depth(centre), 0.0);
  }
  const auto area = [&](double radius) { return 2 * kPi * radius * l + 4 * kPi * radius * radius; };
  EXPECT_LT(capsule.Area(), area(r));
  EXPECT_GT(capsule.Area(), area(r - e));
  const Aabb b = capsule.Bounds();
  EXPECT_NEAR(b.max.z(), l / 2 + r, 1e-12);
  EXPECT_NEAR(b.min.z(), -l / 2 - r, 1e-12);
  ExpectOutwardNormals(capsule);
  ExpectClosed(capsule);
  EXPECT_THROW(MakeCapsule(r, 0.0, e), InputError);
  // The tessellation's limit names the capsule (was "sphere", the shape it is made from).
  try {
    MakeCapsule(1000.0, 1.0, 1e-9);
    ADD_FAILURE() << "a capsule of 2·10¹² chords was made";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("capsule of radius 1000 m needs more than", 0), 0u)
        << error.what();
  }
}

// SDF's <ellipsoid>: every vertex on x²/a² + y²/b² + z²/c² = 1, each facet's centre within the
// bound of the surface point on its ray from the centre.
TEST(Scene, EllipsoidOnItsSurfaceWithinTheChordErrorBound) {
  const Vec3 radii(0.05, 0.12, 0.3);
  const double e = 0.0005;
  const TriangleMesh ellipsoid = MakeEllipsoid(radii, e);
  const auto level = [&](const Vec3& p) { return p.cwiseQuotient(radii).squaredNorm(); };
  for (const Vec3& v : ellipsoid.vertices) EXPECT_NEAR(level(v), 1.0, 1e-12);
  for (const auto& t : ellipsoid.triangles) {
    const Vec3 centre = (ellipsoid.vertices[t[0]] + ellipsoid.vertices[t[1]] +
                         ellipsoid.vertices[t[2]]) / 3;
    const Vec3 surface = centre / std::sqrt(level(centre));
    EXPECT_LT((surface - centre).norm(), e);
  }
  const Aabb b = ellipsoid.Bounds();
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(b.max[axis], radii[axis] + 1e-12);
    EXPECT_GT(b.max[axis], radii[axis] - e);
  }
  EXPECT_NEAR(b.max.z(), radii.z(), 1e-12);  // the pole
  ExpectOutwardNormals(ellipsoid);
  ExpectClosed(ellipsoid);
  EXPECT_THROW(MakeEllipsoid(Vec3(0.1, -1, 0.1), e), InputError);
  try {
    MakeEllipsoid(Vec3(1000.0, 1.0, 1.0), 1e-9);
    ADD_FAILURE() << "an ellipsoid of 2·10¹² chords was made";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("ellipsoid of radius 1000 m needs more than", 0), 0u)
        << error.what();
  }
}

TEST(Scene, PlaneFacesUp) {
  const TriangleMesh plane = MakePlane(2.0, 3.0);
  EXPECT_EQ(plane.triangles.size(), 2u);
  EXPECT_NEAR(plane.Area(), 6.0, 1e-12);
  for (const auto& t : plane.triangles) EXPECT_GT(Normal(plane, t).z(), 0.0);
  EXPECT_TRUE(plane.Bounds().max.isApprox(Vec3(1.0, 1.5, 0.0)));
}

TEST(Scene, PrimitivesRejectBadSizes) {
  EXPECT_THROW(MakeBox(Vec3(1, 0, 1)), InputError);
  EXPECT_THROW(MakeBox(Vec3(1, -1, 1)), InputError);
  EXPECT_THROW(MakeSphere(std::nan(""), 0.001), InputError);
  EXPECT_THROW(MakeSphere(1.0, 0.0), InputError);
  EXPECT_THROW(MakeCylinder(1.0, -1.0, 0.001), InputError);
  EXPECT_THROW(MakePlane(0.0, 1.0), InputError);
  // A chord error far too small for the radius would need billions of triangles.
  EXPECT_THROW(MakeSphere(1000.0, 1e-9), InputError);
}

TEST(Scene, MeshAppendTransformScale) {
  TriangleMesh mesh = MakePlane(1.0, 1.0);
  mesh.Append(MakePlane(1.0, 1.0));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.back()[0], 4u);  // indices shifted by the first mesh's 4 vertices
  mesh.Scale(Vec3(2.0, 3.0, 1.0));
  EXPECT_NEAR(mesh.Area(), 2 * 6.0, 1e-12);
  mesh.Transform(Pose::FromXyzRpy(1, 2, 3, 0, 0, kPi / 2));
  // (1, 1.5, 0) after the scale; yaw 90° maps (x, y) to (−y, x); then the shift.
  EXPECT_TRUE(HasVertexNear(mesh, Vec3(1 - 1.5, 2 + 1.0, 3)));
}

TEST(Scene, SceneCountsAndTargetBounds) {
  Scene scene;
  EXPECT_TRUE(scene.TargetBounds().IsEmpty());
  TriangleMesh target = MakeBox(Vec3(1, 1, 1));
  target.Transform(Pose::FromXyzRpy(5, 0, 0, 0, 0, 0));
  scene.objects.push_back({"wall", Role::kOccluder, MakeBox(Vec3(10, 10, 10)), {}});
  scene.objects.push_back({"part", Role::kTarget, target, {}});
  EXPECT_EQ(scene.TargetCount(), 1u);
  EXPECT_EQ(scene.TriangleCount(), 24u);
  EXPECT_TRUE(scene.TargetBounds().min.isApprox(Vec3(4.5, -0.5, -0.5)));
  EXPECT_TRUE(scene.TargetBounds().max.isApprox(Vec3(5.5, 0.5, 0.5)));
}

// ---------------------------------------------------------------------------------------------
// Mesh files

/// A unit square in z = 0 as one OBJ quad (triangulated on load) and one more triangle.
constexpr const char* kSquareObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
    "f 1 2 3 4\n"
    "f 1 2 5\n";

TEST(Scene, LoadsObjTriangulated) {
  TempDir dir;
  WriteText(dir.File("square.obj"), kSquareObj);
  const TriangleMesh mesh = LoadMeshFile(dir.File("square.obj"));
  EXPECT_EQ(mesh.triangles.size(), 3u);
  EXPECT_NEAR(mesh.Area(), 1.0 + 0.5, 1e-9);
  EXPECT_TRUE(mesh.Bounds().max.isApprox(Vec3(1, 1, 1)));
}

TEST(Scene, LoadsAsciiStl) {
  TempDir dir;
  WriteText(dir.File("tri.stl"),
            "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 2 0 0\n"
            "   vertex 0 3 0\n  endloop\n endfacet\nendsolid t\n");
  const TriangleMesh mesh = LoadMeshFile(dir.File("tri.stl"));
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_NEAR(mesh.Area(), 3.0, 1e-6);
}

TEST(Scene, LoadsAsciiPly) {
  TempDir dir;
  WriteText(dir.File("square.ply"),
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n4 0 1 2 3\n");
  const TriangleMesh mesh = LoadMeshFile(dir.File("square.ply"));
  EXPECT_EQ(mesh.triangles.size(), 2u);  // the quad, triangulated
  EXPECT_NEAR(mesh.Area(), 4.0, 1e-6);
}

// Session 9: Assimp's PLY reader fills what a file cut short lacks (faces without vertices, on
// which its triangulation aborts, or copies of the last face), so the body is walked first.
TEST(Scene, PlyBodyWalkerNamesWhatIsMissing) {
  TempDir dir;
  const auto problem = [&](const std::string& bytes) {
    WriteText(dir.File("m.ply"), bytes);
    return detail::PlyBodyProblem(dir.File("m.ply"));
  };
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string whole = header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(problem(whole), "");
  EXPECT_EQ(problem(whole.substr(0, whole.size() - 3)),  // "3 0 1": one index short
            "it ends inside element 'face' 1 of 1 declared in its header (a file cut short?)");
  EXPECT_EQ(problem(header + "0 0 0\n1 0"),
            "it ends inside element 'vertex' 2 of 3 declared in its header (a file cut short?)");
  EXPECT_EQ(problem(header + "0 0 0\n1 0 0\n0 1 0\nx 0 1 2\n"),
            "element 'face' 1: the list count 'x' is no whole number >= 0");
  // Binary: 10^12 rows of a fixed size are priced at once, not walked; a signed count of -1.
  std::string huge = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                     "property float x\nend_header\n";
  huge.append(8, '\0');
  EXPECT_EQ(problem(huge), "it ends inside element 'vertex' 3 of 1000000000000 declared in its "
                           "header (a file cut short?)");
  std::string negative = "ply\nformat binary_big_endian 1.0\nelement face 1\n"
                         "property list char int vertex_indices\nend_header\n";
  negative.push_back('\xff');
  EXPECT_EQ(problem(negative), "element 'face' 1 has a negative list count");
  // Big-endian counts: 0x0003 items of 4 bytes each, whole and one byte short.
  std::string big = "ply\nformat binary_big_endian 1.0\nelement face 1\n"
                    "property list ushort int vertex_indices\nend_header\n";
  big += std::string("\x00\x03", 2) + std::string(12, '\x01');
  EXPECT_EQ(problem(big), "");
  EXPECT_NE(problem(big.substr(0, big.size() - 1)), "");
  // Not a PLY: Assimp decides.
  EXPECT_EQ(problem("solid x\nendsolid x\n"), "");
  // A malformed header never reaches Assimp, whose PLY reader segfaulted on an unknown line and
  // looped forever without end_header (found by the mesh_file fuzzer).
  EXPECT_EQ(problem("ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n"),
            "header line 4: property type 'half' is not a PLY type (char, uchar, short, ushort, "
            "int, uint, float, double, or int8 ... float64)");
  EXPECT_EQ(problem("plY\nformat ascii 1.0\nelement vertex 4\nproperty list uchar int x"),
            "its header has no end_header line (a file cut short?)");
  EXPECT_EQ(problem(std::string("ply\0\0H\nformat ascii 1.0\nend_header\n", 35)),
            "header line 1: the first line must be `ply` alone");
  EXPECT_EQ(problem("ply\nformat binary_big_endian 1.0"),
            "its header has no end_header line (a file cut short?)");
  EXPECT_EQ(problem("PLY\nformat ascii 1.0\nelement vertex 4\npropelement face 4\nend_header\n"),
            "header line 4: 'propelement' is no PLY header keyword (format, element, property, "
            "comment, obj_info, end_header)");
}

// Session 9: Assimp runs in a child process (RunIsolated), so that its crashes and endless loops
// on broken files become input errors instead of ending vantage.
TEST(Scene, IsolatedWorkReportsCrashesLoopsAndErrors) {
  EXPECT_EQ(detail::RunIsolated([] { return std::string("bytes\0back", 10); }, "reader", 10),
            std::string("bytes\0back", 10));
  const auto error = [](const std::function<std::string()>& work, double seconds) {
    try {
      detail::RunIsolated(work, "m.ply: cannot read mesh: Assimp", seconds);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  EXPECT_EQ(error([]() -> std::string { throw InputError("m.ply: bad face"); }, 10),
            "m.ply: bad face");
  EXPECT_EQ(error(
                []() -> std::string {
                  std::fprintf(stderr, "ai_assert failure in Triangulate\n");
                  std::abort();
                },
                10),
            "m.ply: cannot read mesh: Assimp crashed on it, so the file is broken (signal 6: "
            "Aborted; it said: ai_assert failure in Triangulate)");
  EXPECT_EQ(error(
                []() -> std::string {
                  std::raise(SIGSEGV);
                  return "";
                },
                10),
            "m.ply: cannot read mesh: Assimp crashed on it, so the file is broken (signal 11: "
            "Segmentation fault)");
  EXPECT_EQ(error(
                []() -> std::string {
                  volatile uint64_t spins = 0;
                  for (;;) spins = spins + 1;
                },
                1),
            "m.ply: cannot read mesh: Assimp did not finish reading it within 1 s of CPU time (a "
            "reader looping on a broken file?)");
  EXPECT_THROW(detail::RunIsolated([]() -> std::string { throw std::logic_error("bug"); }, "r", 10),
               std::runtime_error);
}

TEST(Scene, DropsDegenerateTriangles) {
  TempDir dir;
  // The second face is collinear (zero area).
  WriteText(dir.File("mixed.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
  const TriangleMesh mesh = LoadMeshFile(dir.File("mixed.obj"));
  EXPECT_EQ(mesh.triangles.size(), 1u);
  EXPECT_TRUE(mesh.Bounds().max.isApprox(Vec3(1, 1, 0)));  // the unused vertex is gone
}

void ExpectMeshError(const std::string& path) {
  try {
    LoadMeshFile(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": cannot read mesh", 0), 0u) << message;
  }
}

// Issue 47: a binary STL is read without Assimp's child process. A unit cube's 12 facets, each
// with its own three vertices as STL stores them (one corner written as -0), must come back as
// the cube: 8 corners, area 6, volume 1 — and as exactly the mesh Assimp makes of the same
// facets written as ASCII STL (another reader of the same surface).
TEST(Scene, BinaryStlIsTheCubeAssimpReads) {
  TempDir dir;
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const auto corner = [](int i) {
    return std::array<float, 3>{i & 1 ? 1.0f : -0.0f, i & 2 ? 1.0f : 0.0f, i & 4 ? 1.0f : 0.0f};
  };
  std::vector<std::array<int, 3>> facets;
  for (const auto& q : quads) {
    facets.push_back({q[0], q[1], q[2]});
    facets.push_back({q[0], q[2], q[3]});
  }
  std::string binary(80, ' ');
  const uint32_t count = static_cast<uint32_t>(facets.size());
  binary.append(reinterpret_cast<const char*>(&count), 4);
  std::string ascii = "solid cube\n";
  for (const auto& f : facets) {
    const float normal[3] = {0, 0, 0};
    binary.append(reinterpret_cast<const char*>(normal), 12);
    ascii += " facet normal 0 0 0\n  outer loop\n";
    for (const int i : f) {
      const auto p = corner(i);
      binary.append(reinterpret_cast<const char*>(p.data()), 12);
      ascii += fmt::format("   vertex {} {} {}\n", p[0], p[1], p[2]);
    }
    binary.append(2, '\0');
    ascii += "  endloop\n endfacet\n";
  }
  ascii += "endsolid cube\n";
  ASSERT_EQ(binary.size(), 84u + 50u * 12u);
  WriteText(dir.File("cube.stl"), binary);
  WriteText(dir.File("cube_ascii.stl"), ascii);
  const TriangleMesh mesh = LoadMeshFile(dir.File("cube.stl"));
  EXPECT_EQ(mesh.vertices.size(), 8u);  // -0 and +0 are one corner
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_NEAR(mesh.Area(), 6.0, 1e-12);
  double volume = 0;  // divergence theorem over the outward facets
  for (const auto& t : mesh.triangles)
    volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
  EXPECT_NEAR(volume, 1.0, 1e-12);
  for (const Vec3& v : mesh.vertices) EXPECT_FALSE(std::signbit(v.x()));
  const TriangleMesh by_assimp = LoadMeshFile(dir.File("cube_ascii.stl"));
  EXPECT_EQ(by_assimp.vertices, mesh.vertices);
  EXPECT_EQ(by_assimp.triangles, mesh.triangles);
  // One byte more: not a binary STL by the size rule, and no ASCII one either: refused.
  WriteText(dir.File("cut.stl"), binary + " ");
  ExpectMeshError(dir.File("cut.stl"));
}

// Issue 47: a plain OBJ is read without Assimp's child process, as exactly the mesh Assimp makes
// of it. The same text with one line more that only Assimp reads (a smoothing group, which moves
// no vertex) goes to Assimp; both meshes must agree bit for bit, over numbers of every plain form:
// up to 8 integer and 20 fraction digits (Assimp keeps 15), -0, integers, zeros in front.
TEST(Scene, PlainObjIsTheMeshAssimpReads) {
  TempDir dir;
  std::mt19937_64 random(47);
  const auto digits = [&](int count) {
    std::string text;
    for (int i = 0; i < count; ++i) text += static_cast<char>('0' + random() % 10);
    return text;
  };
  const auto number = [&] {
    std::string text = random() % 2 ? "-" : "";
    text += random() % 4 ? std::to_string(random() % 3) : digits(1 + static_cast<int>(random() % 8));
    if (random() % 8) text += "." + digits(1 + static_cast<int>(random() % 20));
    return text;
  };
  std::string text = "# every plain form\r\no part\n";
  const int vertices = 900;
  for (int i = 0; i < vertices; ++i)
    text += fmt::format("v {} {} {}\n", number(), number(), i == 0 ? "-0.000" : number());
  text += "v 0.1 0.2 0.3\nv 1 2 3\nv 0.000000000000000000001 -7.0000000000000001 12345678.5\n";
  for (int f = 0; f < 1200; ++f) {
    const int a = 1 + static_cast<int>(random() % (vertices + 3));
    const int b = 1 + (a + static_cast<int>(random() % 50)) % (vertices + 3);
    const int c = 1 + (b + static_cast<int>(random() % 50)) % (vertices + 3);
    text += fmt::format("f {} {}\t{}\n", a, b, c);
  }
  WriteText(dir.File("plain.obj"), text);
  WriteText(dir.File("assimp.obj"), text + "s off\n");
  const std::optional<TriangleMesh> raw = detail::ReadPlainObj(dir.File("plain.obj"));
  ASSERT_TRUE(raw.has_value());
  EXPECT_FALSE(detail::ReadPlainObj(dir.File("assimp.obj")).has_value());
  const TriangleMesh mesh = ScaledMesh(*raw, Vec3::Ones(), dir.File("plain.obj"));
  const TriangleMesh by_assimp = LoadMeshFile(dir.File("assimp.obj"));
  EXPECT_GT(mesh.triangles.size(), 1000u);
  EXPECT_EQ(by_assimp.vertices, mesh.vertices);
  EXPECT_EQ(by_assimp.triangles, mesh.triangles);
  EXPECT_EQ(LoadMeshFile(dir.File("plain.obj")).vertices, mesh.vertices);
  // Forms left to Assimp; Assimp's own reading of "1.5" and "-0.25" is the plain one.
  for (const char* word : {"1e3", "+1", ".5", "1.", "nan", "inf", "0x1", "1.5a", "", "-"})
    EXPECT_FALSE(detail::PlainObjNumber(word).has_value()) << word;
  EXPECT_EQ(detail::PlainObjNumber("1.5"), 1.5f);
  EXPECT_EQ(detail::PlainObjNumber("-0.25"), -0.25f);
}

TEST(Scene, MeshErrorsNameTheFile) {
  TempDir dir;
  ExpectMeshError(dir.File("missing.stl"));
  WriteText(dir.File("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  ExpectMeshError(dir.File("flat.obj"));
  WriteText(dir.File("points.obj"), "v 0 0 0\nv 1 0 0\n");
  ExpectMeshError(dir.File("points.obj"));
  WriteText(dir.File("garbage.stl"), "this is not a mesh\n");
  ExpectMeshError(dir.File("garbage.stl"));
  WriteText(dir.File("nan.obj"), "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ExpectMeshError(dir.File("nan.obj"));
  WriteText(dir.File("empty.stl"), "");
  ExpectMeshError(dir.File("empty.stl"));
}

/// One triangle in centimetres, Z_UP, under a node translated by 10 cm along z.
std::string ColladaTriangle(const std::string& up_axis) {
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>)" +
         up_axis + R"(</up_axis></asset>
  <library_geometries>
    <geometry id="tri"><mesh>
      <source id="pos">
        <float_array id="pos-array" count="9">0 0 0 100 0 0 0 0 200</float_array>
        <technique_common><accessor source="#pos-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#verts" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene"><node id="n"><translate>0 0 10</translate>
      <instance_geometry url="#tri"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

TEST(Scene, ColladaKeepsFileAxesAndAppliesUnit) {
  // Gazebo reads a DAE's coordinates as they are, scaled by <unit>: z stays up.
  TempDir dir;
  for (const std::string axis : {"Z_UP", "Y_UP"}) {
    WriteText(dir.File(axis + ".dae"), ColladaTriangle(axis));
    const TriangleMesh mesh = LoadMeshFile(dir.File(axis + ".dae"));
    ASSERT_EQ(mesh.triangles.size(), 1u) << axis;
    EXPECT_TRUE(HasVertexNear(mesh, Vec3(0, 0, 0.1), 1e-6)) << axis;
    EXPECT_TRUE(HasVertexNear(mesh, Vec3(1, 0, 0.1), 1e-6)) << axis;
    EXPECT_TRUE(HasVertexNear(mesh, Vec3(0, 0, 2.1), 1e-6)) << axis;
  }
}

// ---------------------------------------------------------------------------------------------
// YAML scenes

constexpr const char* kTriangleObj = "v 1 0 0\nv 0 1 0\nv 0 0 0\nf 1 2 3\n";

constexpr const char* kCompleteScene = R"(settings:
  cell_size: 0.01
  n: 2
  method: greedy
  observation_point: [0.5, 0.5, 0.2]
  random_roll: true
  seed: 42
  ransac: {iterations: 50, stop_coverage: 0.9}
  expected_candidates: 18
sensor_types:
  - id: wide
    resolution: [640, 480]
    hfov_deg: 90
    range: [0.2, 3.0]
    fps: 15
    cost: 99
  - id: calibrated
    resolution: [100, 80]
    intrinsics: [120, 110, 49.5, 40.5]
    range: [0.1, 2]
  - id: cheap_kinect
    base: kinect_xbox_360
    cost: 10
objects:
  - name: crate
    role: target
    box: {size: [0.2, 0.4, 0.6]}
    pose: {xyz: [1, 2, 3], rpy: [0, 0, 1.5707963267948966]}
  - name: part
    role: occluder
    mesh: {file: meshes/tri.obj, scale: [2, 3, 4]}
    pose: {xyz: [0, 0, 1], rpy: [0, 0, 1.5707963267948966]}
  - name: flipped
    mesh: {file: meshes/tri.obj}
    pose: {quaternion: [0.7071067811865476, 0.7071067811865476, 0, 0]}
  - name: ball
    sphere: {radius: 0.05}
  - name: can
    cylinder: {radius: 0.03, length: 0.1}
populations:
  - name: above
    type: wide
    distribution: random
    count: 5
    box: {size: [1, 2, 0.5]}
    pose: {xyz: [0, 0, 2], rpy: [0, 0, 0.3]}
  - name: ring
    type: kinect_xbox_360
    distribution: uniform
    count: 4
    cylinder: {radius: 1.5, length: 0.2}
  - name: wall
    type: calibrated
    distribution: grid
    rows: 2
    cols: 3
    step: [0.1, 0.2, 0]
  - name: rail
    type: cheap_kinect
    distribution: linear-y
    count: 3
    box: {size: [0.1, 1, 0.1]}
sensors:
  - name: fixed
    type: azure_kinect_wfov
    position: [0, 0, 2]
    orientation: {rpy: [0, 1.5707963267948966, 0]}
  - name: free
    type: wide
    position: [1, 0, 2]
)";

/// Writes the complete scene and its mesh into `dir`, returns the scene's path.
std::string WriteCompleteScene(const TempDir& dir) {
  WriteText(dir.File("meshes/tri.obj"), kTriangleObj);
  WriteText(dir.File("scene.yaml"), kCompleteScene);
  return dir.File("scene.yaml");
}

const SceneObject& ObjectNamed(const Problem& problem, const std::string& name) {
  for (const SceneObject& object : problem.scene.objects) {
    if (object.name == name) return object;
  }
  throw std::runtime_error("no object " + name);
}

TEST(YamlScene, ReadsSettings) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  EXPECT_EQ(p.source, dir.File("scene.yaml"));
  EXPECT_DOUBLE_EQ(p.cell_size, 0.01);
  EXPECT_EQ(p.selection.n, 2);
  EXPECT_EQ(p.selection.method, Method::kGreedy);
  EXPECT_TRUE(p.observation_point.isApprox(Vec3(0.5, 0.5, 0.2)));
  EXPECT_TRUE(p.random_roll);
  EXPECT_EQ(p.seed, 42u);
  EXPECT_EQ(p.selection.ransac_iterations, 50);
  EXPECT_DOUBLE_EQ(p.selection.ransac_stop_coverage, 0.9);
  ASSERT_TRUE(p.expected_candidates.has_value());
  EXPECT_EQ(*p.expected_candidates, 18);
}

TEST(YamlScene, BoxPoseRotatesThenTranslates) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  const SceneObject& crate = ObjectNamed(p, "crate");
  EXPECT_TRUE(crate.is_target());
  // Yaw 90° swaps the x and y extents (0.2 ↔ 0.4); then the box is centred at (1, 2, 3).
  const Aabb b = crate.mesh.Bounds();
  EXPECT_TRUE(b.min.isApprox(Vec3(1 - 0.2, 2 - 0.1, 3 - 0.3), 1e-9));
  EXPECT_TRUE(b.max.isApprox(Vec3(1 + 0.2, 2 + 0.1, 3 + 0.3), 1e-9));
}

// Issue 16: degrees beside radians, stacking without arithmetic, and candidates that look at the
// part when no observation point is given.
TEST(YamlScene, RpyDegreesAndOnAndTheDefaultObservationPoint) {
  TempDir dir;
  WriteText(dir.File("stack.yaml"),
            "objects:\n"
            "  - {name: table, box: {size: [1, 1, 0.1]}, pose: {xyz: [0, 0, 0.5]}}\n"
            "  - name: part\n"
            "    role: target\n"
            "    on: table\n"
            "    box: {size: [0.2, 0.1, 0.3]}\n"
            "    pose: {xyz: [0.2, 0, 0.01], rpy_deg: [0, 0, 90]}\n");
  const Problem p = LoadYamlScene(dir.File("stack.yaml"));
  // Yaw 90° swaps the x and y extents; the table's top is at 0.55, the gap 0.01.
  const Aabb b = ObjectNamed(p, "part").mesh.Bounds();
  EXPECT_TRUE(b.min.isApprox(Vec3(0.2 - 0.05, -0.1, 0.56), 1e-9)) << b.min.transpose();
  EXPECT_TRUE(b.max.isApprox(Vec3(0.2 + 0.05, 0.1, 0.86), 1e-9)) << b.max.transpose();
  // No settings.observation_point: the centre of the target's box, with a note saying so.
  EXPECT_TRUE(p.observation_point.isApprox(Vec3(0.2, 0, 0.71), 1e-9))
      << p.observation_point.transpose();
  ASSERT_EQ(p.notes.size(), 1u);
  EXPECT_NE(p.notes[0].find("observation_point not given"), std::string::npos) << p.notes[0];
}

TEST(YamlScene, MeshIsScaledThenPosed) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  const TriangleMesh& part = ObjectNamed(p, "part").mesh;
  ASSERT_EQ(part.triangles.size(), 1u);
  // (1,0,0) → scale (2,0,0) → yaw 90° (0,2,0) → +(0,0,1); (0,1,0) → (0,3,0) → (−3,0,0) → (−3,0,1).
  EXPECT_TRUE(HasVertexNear(part, Vec3(0, 2, 1), 1e-9));
  EXPECT_TRUE(HasVertexNear(part, Vec3(-3, 0, 1), 1e-9));
  EXPECT_TRUE(HasVertexNear(part, Vec3(0, 0, 1), 1e-9));
  EXPECT_FALSE(ObjectNamed(p, "part").is_target());
  // Quaternion [w, x, y, z] of 90° about x: +y goes to +z.
  const TriangleMesh& flipped = ObjectNamed(p, "flipped").mesh;
  EXPECT_TRUE(HasVertexNear(flipped, Vec3(0, 0, 1), 1e-9));
  EXPECT_TRUE(HasVertexNear(flipped, Vec3(1, 0, 0), 1e-9));
  EXPECT_EQ(ObjectNamed(p, "flipped").role, Role::kOccluder);  // the default role
}

// One mesh file placed three times (scale 1, 2, then 1 again): each instance keeps its own scale
// and pose although the scaled mesh is made once per file and scale (ScaledMeshCache).
TEST(YamlScene, OneMeshAtTwoScalesKeepsEachInstancesScale) {
  TempDir dir;
  WriteText(dir.File("meshes/tri.obj"), kTriangleObj);
  WriteText(dir.File("three.yaml"),
            "objects:\n"
            "  - {name: a, role: target, mesh: {file: meshes/tri.obj}}\n"
            "  - {name: b, mesh: {file: meshes/tri.obj, scale: 2}, pose: {xyz: [5, 0, 0]}}\n"
            "  - {name: c, mesh: {file: meshes/tri.obj}, pose: {xyz: [0, 5, 0]}}\n");
  const Problem p = LoadYamlScene(dir.File("three.yaml"));
  // The triangle (0,0,0), (1,0,0), (0,1,0): doubled and shifted by 5 in x; as it is, by 5 in y.
  for (const Vec3& v : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}) {
    EXPECT_TRUE(HasVertexNear(ObjectNamed(p, "a").mesh, v, 1e-12)) << v.transpose();
    EXPECT_TRUE(HasVertexNear(ObjectNamed(p, "b").mesh, 2 * v + Vec3(5, 0, 0), 1e-12));
    EXPECT_TRUE(HasVertexNear(ObjectNamed(p, "c").mesh, v + Vec3(0, 5, 0), 1e-12));
  }
  for (const char* name : {"a", "b", "c"}) EXPECT_EQ(ObjectNamed(p, name).mesh.triangles.size(), 1u);
}

TEST(YamlScene, PrimitivesUseTenthOfTheCellAsChordError) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  const double r = 0.05, e = 0.01 / 10;
  const double area = ObjectNamed(p, "ball").mesh.Area();
  EXPECT_LT(area, 4 * kPi * r * r);
  EXPECT_GT(area, 4 * kPi * (r - e) * (r - e));
  // r (1 − cos(π/n)) < 0.001 with r = 0.03: π/n < acos(1 − 1/30) = 0.25892 → n > 12.13 → 13 rim
  // vertices on each cap.
  int rim = 0;
  for (const Vec3& v : ObjectNamed(p, "can").mesh.vertices) {
    if (std::abs(v.z() - 0.05) < 1e-12 && std::abs(v.head<2>().norm() - 0.03) < 1e-12) ++rim;
  }
  EXPECT_EQ(rim, 13);
}

/// A ball and a can, both targets, read with cell size `cell`.
std::string BallAndCan(const std::string& cell) {
  return "settings: {cell_size: " + cell + R"(}
objects:
  - name: ball
    role: target
    sphere: {radius: 0.05}
  - name: can
    role: target
    cylinder: {radius: 0.04, length: 0.1}
)";
}

TEST(YamlScene, CellSizeOptionTessellatesLikeTheFilesCellSize) {
  // The bug: --cell-size landed after the primitives were tessellated with the file's F / 10.
  TempDir dir;
  WriteText(dir.File("coarse.yaml"), BallAndCan("0.01"));
  WriteText(dir.File("fine.yaml"), BallAndCan("0.0025"));
  LoadOptions options;
  options.cell_size = 0.0025;
  const Problem overridden = LoadYamlScene(dir.File("coarse.yaml"), options);
  const Problem fine = LoadYamlScene(dir.File("fine.yaml"));
  EXPECT_EQ(overridden.cell_size, 0.0025);
  EXPECT_EQ(test::SceneDifference(overridden.scene, fine.scene), "");
  // r (1 − cos(π/n)) < F / 10 with r = 0.04: F = 0.0025: π/n < acos(0.99375) = 0.111862 →
  // n > 28.08 → 29 rim vertices on each cap; F = 0.01 (the file's): acos(0.975) = 0.224075 → 15.
  EXPECT_EQ(test::RimVertices(ObjectNamed(overridden, "can").mesh, 0.05, 0.04), 29);
  const Problem coarse = LoadYamlScene(dir.File("coarse.yaml"));
  EXPECT_EQ(test::RimVertices(ObjectNamed(coarse, "can").mesh, 0.05, 0.04), 15);
}

TEST(YamlScene, CellSizeOptionMustBeAPositiveLength) {
  TempDir dir;
  WriteText(dir.File("scene.yaml"), BallAndCan("0.01"));
  for (const double bad : {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity()}) {
    LoadOptions options;
    options.cell_size = bad;
    try {
      LoadProblem(dir.File("scene.yaml"), options);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--cell-size: cell_size = ", 0), 0u) << e.what();
    }
  }
}

TEST(YamlScene, ReadsSensorTypes) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  const SensorType* wide = p.FindType("wide");
  ASSERT_NE(wide, nullptr);
  EXPECT_EQ(wide->width, 640);
  EXPECT_EQ(wide->height, 480);
  EXPECT_NEAR(wide->fx, 320.0, 1e-9);  // 640 / (2 tan 45°)
  EXPECT_NEAR(wide->fy, 320.0, 1e-9);  // square pixels without vfov
  EXPECT_DOUBLE_EQ(wide->cx, 320.0);
  EXPECT_DOUBLE_EQ(wide->cy, 240.0);
  EXPECT_DOUBLE_EQ(wide->near, 0.2);
  EXPECT_DOUBLE_EQ(wide->far, 3.0);
  EXPECT_DOUBLE_EQ(wide->fps, 15);
  EXPECT_DOUBLE_EQ(wide->cost, 99);
  const SensorType* calibrated = p.FindType("calibrated");
  ASSERT_NE(calibrated, nullptr);
  EXPECT_DOUBLE_EQ(calibrated->fx, 120);
  EXPECT_DOUBLE_EQ(calibrated->fy, 110);
  EXPECT_DOUBLE_EQ(calibrated->cx, 49.5);
  EXPECT_DOUBLE_EQ(calibrated->cy, 40.5);
  const SensorType* cheap = p.FindType("cheap_kinect");
  ASSERT_NE(cheap, nullptr);
  EXPECT_DOUBLE_EQ(cheap->cost, 10);
  EXPECT_EQ(cheap->width, 640);
  EXPECT_DOUBLE_EQ(cheap->near, 0.4);  // SENSORS.md's Kinect 360 range
  EXPECT_DOUBLE_EQ(cheap->far, 4.0);
  // Catalog types that populations and sensors name are in the list too.
  EXPECT_NE(p.FindType("kinect_xbox_360"), nullptr);
  EXPECT_NE(p.FindType("azure_kinect_wfov"), nullptr);
  EXPECT_EQ(p.FindType("zed"), nullptr);
}

TEST(YamlScene, DerivedTypeWithNewResolutionKeepsFieldOfView) {
  TempDir dir;
  WriteText(dir.File("s.yaml"), R"(sensor_types:
  - id: half
    base: kinect_xbox_360
    resolution: [320, 240]
  - id: vfov_only
    resolution: [200, 100]
    hfov: 1.0
    vfov_deg: 60
    range: [0.5, 1]
objects:
  - {name: a, role: target, box: {size: [1, 1, 1]}}
)");
  const Problem p = LoadYamlScene(dir.File("s.yaml"));
  const SensorType* half = p.FindType("half");
  ASSERT_NE(half, nullptr);
  EXPECT_NEAR(half->fx, 320 / (2 * std::tan(0.994838 / 2)), 1e-9);  // SENSORS.md hfov
  EXPECT_NEAR(half->fy, half->fx, 1e-9);
  EXPECT_DOUBLE_EQ(half->cx, 160);
  const SensorType* v = p.FindType("vfov_only");
  ASSERT_NE(v, nullptr);
  EXPECT_NEAR(v->fx, 200 / (2 * std::tan(0.5)), 1e-9);
  EXPECT_NEAR(v->fy, 100 / (2 * std::tan(kPi / 6)), 1e-9);
}

TEST(YamlScene, ReadsPopulations) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  ASSERT_EQ(p.populations.size(), 4u);
  const Population& above = p.populations[0];
  EXPECT_EQ(above.name, "above");
  EXPECT_EQ(above.sensor_type, "wide");
  EXPECT_EQ(above.region, RegionShape::kBox);
  EXPECT_EQ(above.distribution, Distribution::kRandom);
  EXPECT_EQ(above.count, 5);
  EXPECT_TRUE(above.box_size.isApprox(Vec3(1, 2, 0.5)));
  EXPECT_TRUE(above.pose.position.isApprox(Vec3(0, 0, 2)));
  EXPECT_TRUE(
      (above.pose.rotation * Vec3::UnitX()).isApprox(Vec3(std::cos(0.3), std::sin(0.3), 0), 1e-12));
  EXPECT_EQ(above.file, dir.File("scene.yaml"));
  EXPECT_EQ(above.line, 41);  // the line of `- name: above`

  const Population& ring = p.populations[1];
  EXPECT_EQ(ring.region, RegionShape::kCylinder);
  EXPECT_EQ(ring.distribution, Distribution::kUniform);
  EXPECT_DOUBLE_EQ(ring.radius, 1.5);
  EXPECT_DOUBLE_EQ(ring.length, 0.2);
  EXPECT_EQ(ring.count, 4);
  EXPECT_TRUE(ring.pose.position.isZero());

  const Population& wall = p.populations[2];
  EXPECT_EQ(wall.distribution, Distribution::kGrid);
  EXPECT_EQ(wall.region, RegionShape::kNone);
  EXPECT_EQ(wall.rows, 2);
  EXPECT_EQ(wall.cols, 3);
  EXPECT_TRUE(wall.step.isApprox(Vec3(0.1, 0.2, 0)));

  EXPECT_EQ(p.populations[3].distribution, Distribution::kLinearY);
  EXPECT_EQ(p.populations[3].sensor_type, "cheap_kinect");
}

TEST(YamlScene, ReadsExplicitSensors) {
  TempDir dir;
  const Problem p = LoadYamlScene(WriteCompleteScene(dir));
  ASSERT_EQ(p.sensors.size(), 2u);
  const ExplicitSensor& fixed = p.sensors[0];
  EXPECT_EQ(fixed.name, "fixed");
  EXPECT_EQ(fixed.sensor_type, "azure_kinect_wfov");
  EXPECT_FALSE(fixed.look_at);
  EXPECT_TRUE(fixed.pose.position.isApprox(Vec3(0, 0, 2)));
  // Pitch 90° turns the body's x (forward) down to −z.
  EXPECT_TRUE((fixed.pose.rotation * Vec3::UnitX()).isApprox(Vec3(0, 0, -1), 1e-12));
  EXPECT_EQ(fixed.line, 64);  // the line of `- name: fixed`
  EXPECT_TRUE(p.sensors[1].look_at);
}

TEST(YamlScene, TargetOptionOverridesRoles) {
  TempDir dir;
  LoadOptions options;
  options.targets = {"ball", "can"};
  const Problem p = LoadYamlScene(WriteCompleteScene(dir), options);
  EXPECT_EQ(p.scene.TargetCount(), 2u);
  EXPECT_FALSE(ObjectNamed(p, "crate").is_target());
  EXPECT_TRUE(ObjectNamed(p, "ball").is_target());
}

TEST(YamlScene, UnknownTargetOptionIsAnError) {
  TempDir dir;
  LoadOptions options;
  options.targets = {"bal"};
  try {
    LoadYamlScene(WriteCompleteScene(dir), options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'ball'"), std::string::npos) << e.what();
  }
}

TEST(YamlScene, LoadProblemDispatchesByExtension) {
  TempDir dir;
  WriteText(dir.File("meshes/tri.obj"), kTriangleObj);
  WriteText(dir.File("scene.YML"), kCompleteScene);
  EXPECT_EQ(LoadProblem(dir.File("scene.YML")).scene.objects.size(), 5u);
  WriteText(dir.File("scene.txt"), kCompleteScene);
  EXPECT_THROW(LoadProblem(dir.File("scene.txt")), InputError);
  EXPECT_THROW(LoadProblem(dir.File("absent.yaml")), InputError);
}

TEST(YamlScene, ExampleSceneLoads) {
  const Problem p =
      LoadProblem(std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml");
  EXPECT_EQ(p.scene.TargetCount(), 1u);
  EXPECT_EQ(p.selection.n, 3);
  EXPECT_DOUBLE_EQ(p.cell_size, 0.005);
  int candidates = static_cast<int>(p.sensors.size());
  for (const Population& population : p.populations) {
    candidates += population.distribution == Distribution::kGrid ? population.rows * population.cols
                                                                 : population.count;
  }
  EXPECT_GE(candidates, 60);
  EXPECT_LE(candidates, 100);
  // The target lies within every sensor type's range from the observation point's height.
  const Aabb target = p.scene.TargetBounds();
  EXPECT_FALSE(target.IsEmpty());
  EXPECT_LT((target.max - target.min).maxCoeff(), 0.2);
}

TEST(YamlScene, DocumentedFullExampleLoads) {
  // docs/scene-format.md's "Full example" must stay a valid scene.
  const std::string docs =
      test::ReadText(std::string(VANTAGE_SOURCE_DIR) + "/docs/scene-format.md");
  const size_t section = docs.find("## Full example");
  ASSERT_NE(section, std::string::npos);
  const size_t begin = docs.find("```yaml\n", section);
  ASSERT_NE(begin, std::string::npos);
  const size_t end = docs.find("```", begin + 8);
  ASSERT_NE(end, std::string::npos);
  TempDir dir;
  WriteText(dir.File("scenes/example.yaml"), docs.substr(begin + 8, end - begin - 8));
  WriteText(dir.File("meshes/small_motor.obj"),
            test::ReadText(std::string(VANTAGE_SOURCE_DIR) + "/examples/meshes/small_motor.obj"));
  const Problem p = LoadYamlScene(dir.File("scenes/example.yaml"));
  EXPECT_EQ(p.scene.TargetCount(), 1u);
  EXPECT_EQ(p.populations.size(), 3u);
  EXPECT_EQ(p.sensors.size(), 2u);
  // The gear block's quaternion is a yaw of 0.4 rad, as in examples/scenes/bin_picking_cell.yaml.
  const Aabb gear = ObjectNamed(p, "gear_block").mesh.Bounds();
  const double half_extent = 0.025 * (std::cos(0.4) + std::sin(0.4));
  EXPECT_NEAR(gear.max.x() - 0.10, half_extent, 1e-5);
}

// ---------------------------------------------------------------------------------------------
// Errors: `file:line: what — how`, collected and thrown once

struct BadScene {
  const char* name;
  const char* yaml;
  int line;              ///< expected line of the (first) message
  const char* fragment;  ///< expected in the message
};

/// A valid scene's tail that bad inputs can be prefixed to (starts on the input's next line).
constexpr const char* kValidObjects =
    "objects:\n"
    "  - {name: part, role: target, box: {size: [0.1, 0.1, 0.1]}}\n";

const BadScene kBadScenes[] = {
    {"malformed_flow", "settings:\n  observation_point: [1, 2, 3]]\n", 2, "malformed YAML"},
    {"bad_indentation", "settings:\n  cell_size: 0.005\n   n: 3\n", 3, "malformed YAML"},
    {"tab_indentation", "settings:\n  cell_size: 0.005\n\tn: 3\n", 3, "malformed YAML"},
    {"unknown_setting", "settings:\n  cel_size: 0.005\n", 2, "did you mean 'cell_size'?"},
    {"unknown_top_key", "setings:\n  n: 3\n", 1, "did you mean 'settings'?"},
    {"cell_size_zero", "settings:\n  cell_size: 0\n", 2, "settings.cell_size"},
    {"cell_size_negative", "settings:\n  cell_size: -0.005\n", 2, "must be positive"},
    {"cell_size_string", "settings:\n  cell_size: fine\n", 2, "expected a number, got 'fine'"},
    {"cell_size_nan", "settings:\n  cell_size: .nan\n", 2, "finite"},
    {"cell_size_missing_value", "settings:\n  cell_size:\n  n: 2\n", 2, "expected a number"},
    {"n_zero", "settings:\n  n: 0\n", 2, "settings.n"},
    {"n_fraction", "settings:\n  n: 2.5\n", 2, "whole number"},
    {"stop_coverage_percent", "settings:\n  ransac: {stop_coverage: 80}\n", 2, "[0, 1]"},
    // The selection settings read from their rows (scene_settings.hpp): the messages as the
    // readers spelled them per key before.
    {"stop_coverage_message", "settings:\n  ransac: {stop_coverage: 80}\n", 2,
     "settings.ransac.stop_coverage = 80 is a fraction — give a value in [0, 1] (e.g. 0.8 for "
     "80 %)"},
    {"ransac_iterations_zero", "settings:\n  ransac:\n    iterations: 0\n", 3,
     "settings.ransac.iterations = 0 is too small — give at least 1"},
    {"ransac_unknown_key", "settings:\n  ransac: {iteration: 5}\n", 2,
     "unknown key 'iteration' in settings.ransac — did you mean 'iterations'?"},
    {"goal_above_one", "settings:\n  goal: 1.5\n", 2,
     "settings.goal = 1.5 is a coverage fraction — give a value in (0, 1], e.g. 0.9 for 90 %"},
    {"goal_zero", "settings:\n  goal: 0\n", 2, "settings.goal = 0 is a coverage fraction"},
    {"k_zero", "settings:\n  k: 0\n", 2, "settings.k = 0 is too small — give at least 1"},
    {"budget_negative", "settings:\n  budget: -3\n", 2,
     "settings.budget = -3 must be >= 0 — the most the sensors may cost together"},
    {"two_objectives", "settings:\n  goal: 0.5\n  k: 2\n", 3,
     "settings.goal, settings.k >= 2 and settings.budget are separate objectives — give only "
     "one of them"},
    {"method_unknown_far", "settings:\n  method: zzzzzzzz\n", 2,
     "settings.method 'zzzzzzzz' is unknown — valid: 'best', 'ransac', 'greedy', 'local', "
     "'exact', 'all'"},
    {"unknown_method", "settings:\n  method: gredy\n", 2, "did you mean 'greedy'?"},
    {"random_roll_not_bool", "settings:\n  random_roll: maybe\n", 2, "true or false"},
    {"observation_point_short", "settings:\n  observation_point: [1, 2]\n", 2, "3 numbers"},
    {"duplicate_key", "settings:\n  n: 2\n  n: 3\n", 3, "appears twice"},
    {"empty_file", "", 1, "empty"},
    {"scene_is_a_list", "- a\n- b\n", 1, "must be a mapping"},
    {"no_objects_key", "settings:\n  n: 2\n", 1, "has no 'objects'"},
    {"objects_not_a_list", "objects: 5\n", 1, "must be a list"},
    {"objects_empty", "objects: []\n", 1, "objects is empty"},
    {"no_target", "objects:\n  - {name: a, box: {size: [1, 1, 1]}}\n", 1, "no object is a target"},
    {"object_without_name", "objects:\n  - {role: target, box: {size: [1, 1, 1]}}\n", 2,
     "has no 'name'"},
    {"object_without_shape", "objects:\n  - name: a\n    role: target\n", 2, "exactly one shape"},
    {"object_two_shapes",
     "objects:\n  - name: a\n    role: target\n    box: {size: [1, 1, 1]}\n"
     "    sphere: {radius: 1}\n",
     5, "exactly one shape"},
    {"object_bad_role", "objects:\n  - name: a\n    role: targt\n    box: {size: [1, 1, 1]}\n", 3,
     "did you mean 'target'?"},
    {"duplicate_object",
     "objects:\n  - {name: a, role: target, box: {size: [1, 1, 1]}}\n"
     "  - {name: a, box: {size: [1, 1, 1]}}\n",
     3, "used twice"},
    {"box_zero_size", "objects:\n  - name: a\n    role: target\n    box: {size: [1, 0, 1]}\n", 4,
     "positive"},
    {"box_nan_size",
     "objects:\n  - name: a\n    role: target\n    box:\n      size: [1, .nan, 1]\n", 5, "finite"},
    {"sphere_negative_radius",
     "objects:\n  - name: a\n    role: target\n    sphere: {radius: -1}\n", 4, "must be positive"},
    {"cylinder_without_length",
     "objects:\n  - name: a\n    role: target\n    cylinder: {radius: 1}\n", 4, "has no 'length'"},
    {"missing_mesh_file",
     "objects:\n  - name: a\n    role: target\n    mesh: {file: nowhere/part.stl}\n", 4,
     "not found"},
    {"mesh_negative_scale",
     "objects:\n  - name: a\n    role: target\n    mesh: {file: x.obj, scale: -1}\n", 4,
     "must be positive"},
    {"pose_rpy_and_quaternion",
     "objects:\n  - name: a\n    role: target\n    box: {size: [1, 1, 1]}\n    pose:\n"
     "      rpy: [0, 0, 0]\n      quaternion: [1, 0, 0, 0]\n",
     7, "keep one"},
    {"pose_zero_quaternion",
     "objects:\n  - name: a\n    role: target\n    box: {size: [1, 1, 1]}\n"
     "    pose: {quaternion: [0, 0, 0, 0]}\n",
     5, "zero"},
    {"pose_unknown_key",
     "objects:\n  - name: a\n    role: target\n    box: {size: [1, 1, 1]}\n"
     "    pose: {xzy: [0, 0, 0]}\n",
     5, "did you mean 'xyz'?"},
    {"unknown_sensor_id",
     "populations:\n  - name: p\n    type: kinect_xbox_361\n    count: 3\n"
     "    box: {size: [1, 1, 1]}\n",
     3, "did you mean 'kinect_xbox_360'?"},
    {"unknown_sensor_id_far", "sensors:\n  - name: s\n    type: lidar\n    position: [0, 0, 1]\n",
     3, "kinect_xbox_360"},
    // A long id typed without its vendor prefix is too many edits for a third of its length.
    {"unknown_sensor_id_without_vendor",
     "sensors:\n  - name: s\n    type: realsense_d435\n    position: [0, 0, 1]\n", 3,
     "did you mean 'intel_realsense_d435'?"},
    {"pose_rpy_deg_and_rpy",
     "objects:\n  - name: a\n    role: target\n    box: {size: [1, 1, 1]}\n    pose:\n"
     "      rpy: [0, 0, 0]\n      rpy_deg: [0, 0, 0]\n",
     7, "both rpy and rpy_deg are given — keep one"},
    {"on_unknown_object",
     "objects:\n  - name: a\n    role: target\n    on: tabel\n    box: {size: [1, 1, 1]}\n",
     4, "object 'a'.on: no object 'tabel' is listed before it"},
    {"hfov_too_wide",
     "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov_deg: 180\n"
     "    range: [0.3, 3]\n",
     4, "(0, 180)"},
    {"hfov_radians_too_wide",
     "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov: 3.5\n"
     "    range: [0.3, 3]\n",
     4, "hfov_deg"},
    {"hfov_zero",
     "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov: 0\n    range: [0.3, 3]\n", 4,
     "(0, π)"},
    {"near_above_far",
     "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov: 1\n    range: [3, 0.3]\n", 5,
     "near < far"},
    {"resolution_zero",
     "sensor_types:\n  - id: t\n    resolution: [0, 480]\n    hfov: 1\n    range: [0.3, 3]\n", 3,
     "resolution width"},
    {"type_without_range", "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov: 1\n", 2,
     "has no 'range'"},
    {"type_intrinsics_and_fov",
     "sensor_types:\n  - id: t\n    resolution: [640, 480]\n    hfov: 1\n"
     "    intrinsics: [500, 500, 320, 240]\n    range: [0.3, 3]\n",
     5, "keep one"},
    {"type_shadows_catalog", "sensor_types:\n  - id: zed\n    base: zed\n    cost: 1\n", 2,
     "catalog id"},
    {"type_unknown_base", "sensor_types:\n  - id: mine\n    base: zedd\n", 3,
     "did you mean 'zed'?"},
    {"type_negative_cost", "sensor_types:\n  - id: mine\n    base: zed\n    cost: -5\n", 4,
     "cost = -5 must be from 0 to 1e+12"},
    // Session 33: 1e308 each made two sensors cost inf, and exact's cost bound 0.
    {"type_huge_cost", "sensor_types:\n  - id: mine\n    base: zed\n    cost: 1e308\n", 4,
     "cost = 1e+308 must be from 0 to 1e+12"},
    {"population_without_count",
     "populations:\n  - name: p\n    type: zed\n    box: {size: [1, 1, 1]}\n", 2, "has no 'count'"},
    {"population_count_zero",
     "populations:\n  - name: p\n    type: zed\n    count: 0\n    box: {size: [1, 1, 1]}\n", 4,
     "count"},
    {"population_without_region", "populations:\n  - name: p\n    type: zed\n    count: 3\n", 2,
     "needs one region"},
    {"population_box_negative",
     "populations:\n  - name: p\n    type: zed\n    count: 3\n    box: {size: [1, -1, 1]}\n", 5,
     "positive"},
    {"population_bad_distribution",
     "populations:\n  - name: p\n    type: zed\n    distribution: randm\n    count: 3\n"
     "    box: {size: [1, 1, 1]}\n",
     4, "did you mean 'random'?"},
    {"cylinder_linear",
     "populations:\n  - name: rail\n    type: zed\n    distribution: linear-x\n    count: 3\n"
     "    cylinder: {radius: 1, length: 1}\n",
     6, "population 'rail'"},
    {"cylinder_grid",
     "populations:\n  - name: wall\n    type: zed\n    distribution: grid\n    rows: 2\n"
     "    cols: 2\n    step: [1, 1, 0]\n    cylinder: {radius: 1, length: 1}\n",
     8, "population 'wall'"},
    {"grid_without_rows",
     "populations:\n  - name: g\n    type: zed\n    distribution: grid\n    cols: 2\n"
     "    step: [1, 1, 0]\n",
     2, "has no 'rows'"},
    {"grid_zero_cols",
     "populations:\n  - name: g\n    type: zed\n    distribution: grid\n    rows: 2\n    cols: 0\n"
     "    step: [1, 1, 0]\n",
     6, "cols"},
    {"rows_without_grid",
     "populations:\n  - name: p\n    type: zed\n    count: 3\n    rows: 2\n"
     "    box: {size: [1, 1, 1]}\n",
     5, "grid"},
    {"sensor_without_position", "sensors:\n  - name: s\n    type: zed\n", 2, "has no 'position'"},
    {"sensor_position_string", "sensors:\n  - name: s\n    type: zed\n    position: here\n", 4,
     "3 numbers"},
    {"sensor_empty_orientation",
     "sensors:\n  - name: s\n    type: zed\n    position: [0, 0, 1]\n    orientation: {}\n", 5,
     "has no 'rpy'"},
};

class BadYaml : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadYaml, ThrowsWithFileAndLine) {
  const BadScene& bad = GetParam();
  TempDir dir;
  const std::string path = dir.File("bad.yaml");
  std::string text = bad.yaml;
  // Scenes that declare no objects get a valid list after their own lines, so that the expected
  // error is the only one.
  const std::set<std::string> without_objects = {"empty_file", "scene_is_a_list", "no_objects_key"};
  if (text.find("objects") == std::string::npos && !without_objects.count(bad.name)) {
    text += kValidObjects;
  }
  WriteText(path, text);
  try {
    LoadYamlScene(path);
    FAIL() << "no error for " << bad.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    const std::string prefix = path + ":" + std::to_string(bad.line) + ": ";
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << bad.name << ": " << message;
    EXPECT_NE(message.find(bad.fragment), std::string::npos) << bad.name << ": " << message;
    EXPECT_NE(message.find(" — "), std::string::npos)
        << bad.name << ": says how to fix: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(Scene,
                         BadYaml,
                         ::testing::ValuesIn(kBadScenes),
                         [](const ::testing::TestParamInfo<BadScene>& info) {
                           return std::string(info.param.name);
                         });

// Every selection setting's row (scene_settings.hpp) is a key the YAML reader allows and reads:
// a valid value lands in its member with its line, a word in its place is refused naming the key.
TEST(YamlScene, EverySelectionSettingRowIsReadAtItsKey) {
  for (const SceneSelectionSetting& setting : kSceneSelectionSettings) {
    const std::string key(setting.yaml_key);
    const bool in_ransac = key.starts_with("ransac.");
    const auto scene = [&](const std::string& value) {
      return in_ransac ? fmt::format("settings:\n  ransac:\n    {}: {}\n", key.substr(7), value)
                       : fmt::format("settings:\n  {}: {}\n", key, value);
    };
    const int line = in_ransac ? 3 : 2;
    const bool is_count = std::holds_alternative<int SelectionSettings::*>(setting.member);
    const bool is_method =
        std::holds_alternative<std::optional<Method> SelectionSettings::*>(setting.member);
    TempDir dir;
    const std::string path = dir.File("s.yaml");
    WriteText(path, scene(is_count ? "3" : is_method ? "local" : "0.25") + kValidObjects);
    const Problem problem = LoadYamlScene(path);
    const SelectionSettings& selection = problem.selection;
    std::visit(
        [&](auto member) {
          using Held = std::decay_t<decltype(selection.*member)>;
          if constexpr (std::is_same_v<Held, int>)
            EXPECT_EQ(selection.*member, 3) << key;
          else if constexpr (std::is_same_v<Held, std::optional<Method>>)
            EXPECT_EQ(selection.*member, Method::kLocal) << key;
          else
            EXPECT_EQ(selection.*member, 0.25) << key;
        },
        setting.member);
    EXPECT_EQ(selection.lines.at(std::string(setting.field)), line) << key;
    WriteText(path, scene("zz") + kValidObjects);
    try {
      LoadYamlScene(path);
      ADD_FAILURE() << key << ": a word accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(fmt::format("{}:{}: settings.{}", path, line, key), 0), 0u)
          << message;
    }
  }
}

TEST(YamlScene, CollectsEveryProblemBeforeThrowing) {
  TempDir dir;
  WriteText(dir.File("two.yaml"),
            "settings:\n  cell_size: -1\n  n: 0\nobjects:\n"
            "  - {name: a, role: target, box: {size: [1, 1, 1]}}\n");
  try {
    LoadYamlScene(dir.File("two.yaml"));
    FAIL();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(dir.File("two.yaml") + ":2: "), std::string::npos) << message;
    EXPECT_NE(message.find("\n" + dir.File("two.yaml") + ":3: "), std::string::npos) << message;
  }
}

TEST(YamlScene, BrokenMeshFileIsReportedAtItsLine) {
  TempDir dir;
  WriteText(dir.File("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  WriteText(dir.File("s.yaml"),
            "objects:\n  - name: a\n    role: target\n"
            "    mesh: {file: flat.obj}\n");
  try {
    LoadYamlScene(dir.File("s.yaml"));
    FAIL();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(dir.File("s.yaml") + ":4: ", 0), 0u) << message;
    EXPECT_NE(message.find("cannot read mesh"), std::string::npos) << message;
  }
}

TEST(YamlScene, NeverCrashesOnMutatedInput) {
  // Every single-character deletion and a few replacements of a complete scene: each either
  // loads or throws InputError, nothing else.
  TempDir dir;
  const std::string path = WriteCompleteScene(dir);
  const std::string original = kCompleteScene;
  const std::string replacements = "[]{}:-,#&*!|>'\"%@` \t\n0";
  size_t errors = 0, loads = 0;
  for (size_t i = 0; i < original.size(); i += 4) {
    for (int variant = 0; variant < 2; ++variant) {
      std::string text = original;
      if (variant == 0) {
        text.erase(i, 1);
      } else {
        text[i] = replacements[i % replacements.size()];
      }
      WriteText(path, text);
      try {
        LoadYamlScene(path);
        ++loads;
      } catch (const InputError&) {
        ++errors;
      } catch (const std::exception& e) {
        ADD_FAILURE() << "offset " << i << " variant " << variant << ": " << e.what();
      }
    }
  }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(loads, 0u);
}

}  // namespace
}  // namespace vantage
