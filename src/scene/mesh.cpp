// Triangle meshes: the scene's geometry, the primitives of SDF and YAML scenes (tessellated with
// a bounded chord error, SYSTEM.md "coverage metric"), and mesh files read through Assimp.
#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <filesystem>
#include <cmath>
#include <cctype>
#include <cstring>
#include <optional>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scene/plain_obj.hpp"
#include "scene/ply_body.hpp"
#include "scene/scaled_mesh_cache.hpp"
#include "scene/step_reader.hpp"
#include "util/isolated.hpp"
#include "util/module_places.hpp"
#include "util/run_files.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/mesh_weld.hpp"
#include "vantage/scene.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;
/// Above this many segments per circle a primitive would need billions of triangles: the chord
/// error is absurdly small for its radius (a typo in a radius or in the cell size).
constexpr int kMaxSegments = 20'000;
/// A triangle whose doubled area is below this share of its longest edge squared is degenerate
/// (collinear to rounding), as well as one with two equal indices.
constexpr double kDegenerateRatio = 1e-12;

double TriangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

bool IsDegenerate(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double doubled_area = (b - a).cross(c - a).norm();
  const double longest_squared =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !(doubled_area > kDegenerateRatio * longest_squared);
}

void CheckPositive(double value, const char* what, const char* shape) {
  if (!std::isfinite(value) || value <= 0) {
    throw InputError(fmt::format("{} {} = {} must be a positive length [m] — fix the {}", shape,
                                 what, value, shape));
  }
}

/// The refusal of a shape whose tessellation would pass kMaxSegments around a circle.
InputError TooManySegments(const char* shape, double radius, double max_chord_error) {
  return InputError(fmt::format(
      "{} of radius {:g} m needs more than {} segments for a chord error of {:g} m (a tenth of "
      "the cell size) — check the radius, or give a larger cell size",
      shape, radius, kMaxSegments, max_chord_error));
}

/// Smallest n >= 3 for which a circle of `radius` cut into n chords deviates from its polygon by
/// less than `max_chord_error`: r (1 − cos(π / n)) < e (the sagitta of one chord).
int SegmentsFor(double radius, double max_chord_error, const char* shape) {
  CheckPositive(max_chord_error, "chord error", shape);
  const double ratio = max_chord_error / radius;
  int n = 3;
  if (ratio < 2.0) {
    const double half_angle = std::acos(1.0 - ratio);
    const double estimate = std::floor(kPi / half_angle) + 1.0;
    if (!(estimate <= kMaxSegments)) throw TooManySegments(shape, radius, max_chord_error);
    n = std::max(3, static_cast<int>(estimate));
  }
  // The closed form may land one short after rounding: step up until the rule holds.
  while (radius * (1.0 - std::cos(kPi / n)) >= max_chord_error) ++n;
  return n;
}

/// Largest distance between a triangle with vertices on a sphere of `radius` (centred at the
/// origin) and that sphere: r − (distance of the triangle's plane), the plane's distance being
/// sqrt(r² − R²) for the triangle's circumradius R. An upper bound of the true deviation.
double SphereDeviation(const Vec3& a, const Vec3& b, const Vec3& c, double radius) {
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  const double area = TriangleArea(a, b, c);
  if (area <= 0) return radius;
  const double circumradius = ab * bc * ca / (4.0 * area);
  return radius - std::sqrt(std::max(0.0, radius * radius - circumradius * circumradius));
}

/// Vertex of a UV sphere at ring `ring` (0 = north pole, rings = south pole) and slice `slice`.
Vec3 SpherePoint(double radius, int ring, int rings, int slice, int slices) {
  const double polar = kPi * ring / rings;
  const double azimuth = 2.0 * kPi * slice / slices;
  return radius * Vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                       std::cos(polar));
}

/// Largest deviation of a UV sphere's facets from the sphere: every slice is the same by
/// symmetry, so one column suffices. The triangles are those MakeSphere builds: a fan at each
/// pole, and quads (a, b, c, d) split into (a, b, c) and (a, c, d) in between.
double UvSphereDeviation(double radius, int rings, int slices) {
  double worst = 0;
  for (int ring = 0; ring < rings; ++ring) {
    const Vec3 a = SpherePoint(radius, ring, rings, 0, slices);
    const Vec3 b = SpherePoint(radius, ring + 1, rings, 0, slices);
    const Vec3 c = SpherePoint(radius, ring + 1, rings, 1, slices);
    const Vec3 d = SpherePoint(radius, ring, rings, 1, slices);
    if (ring == 0) {
      worst = std::max(worst, SphereDeviation(a, b, c, radius));  // a = d: north pole
    } else if (ring + 1 == rings) {
      worst = std::max(worst, SphereDeviation(a, b, d, radius));  // b = c: south pole
    } else {
      worst = std::max({worst, SphereDeviation(a, b, c, radius), SphereDeviation(a, c, d, radius)});
    }
  }
  return worst;
}

/// Appends the triangle (a, b, c) and (a, c, d) of a quad given counter-clockwise from outside.
void AddQuad(TriangleMesh* mesh, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  mesh->triangles.push_back({a, b, c});
  mesh->triangles.push_back({a, c, d});
}

/// Keeps one vertex per position (STL and other files repeat a vertex for every face; equality is
/// exact, so the surface is unchanged) and drops the vertices no triangle uses, so that Bounds()
/// describes the surface. Each position keeps its smallest index, found through a hash of its
/// bits in one pass (the full sort this replaced was half the load of a 53 k-triangle STL); the
/// kept vertices are numbered in the order the triangles first use them. Faster than
/// aiProcess_JoinIdenticalVertices, which also compares normals and would keep STL's per-face
/// copies anyway. The `count` positions are at(i); `triangles` are renumbered, the kept vertices
/// returned.
template <class At>
std::vector<Vec3> CompactVerticesOf(size_t count, const At& at,
                                    std::vector<std::array<uint32_t, 3>>* triangles) {
  // The vertices are finite: ReadMeshFile and WorldPointProblem refuse the others.
  const std::vector<uint32_t> same_as = FirstEqualPositions(count, at);
  constexpr uint32_t kUnused = UINT32_MAX;
  std::vector<uint32_t> new_index(count, kUnused);
  std::vector<Vec3> kept;
  for (auto& triangle : *triangles) {
    for (uint32_t& index : triangle) {
      index = same_as[index];
      if (new_index[index] == kUnused) {
        new_index[index] = static_cast<uint32_t>(kept.size());
        kept.push_back(at(index));
      }
      index = new_index[index];
    }
  }
  return kept;
}

[[noreturn]] void FailMesh(const std::string& path, const std::string& what) {
  throw InputError(fmt::format(
      "{}: cannot read mesh: {} — check the file exists and is STL/DAE/OBJ/PLY or another "
      "format Assimp reads, with at least one non-degenerate triangle",
      path, what));
}

}  // namespace

Aabb TriangleMesh::Bounds() const {
  Aabb box;
  for (const Vec3& v : vertices) box.Extend(v);
  return box;
}

double TriangleMesh::Area() const {
  double area = 0;
  for (const auto& t : triangles)
    area += TriangleArea(vertices[t[0]], vertices[t[1]], vertices[t[2]]);
  return area;
}

void TriangleMesh::Append(const TriangleMesh& other) {
  const auto shift = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + shift, t[1] + shift, t[2] + shift});
}

void TriangleMesh::Transform(const Pose& pose) {
  for (Vec3& v : vertices) v = pose * v;
}

void TriangleMesh::Scale(const Vec3& scale) {
  for (Vec3& v : vertices) v = v.cwiseProduct(scale);
}

size_t Scene::TargetCount() const {
  size_t count = 0;
  for (const SceneObject& object : objects) count += object.is_target() ? 1 : 0;
  return count;
}

uint64_t TriangleMesh::Bytes() const {
  return vertices.size() * sizeof(Vec3) + triangles.size() * sizeof(triangles[0]);
}

size_t Scene::TriangleCount() const {
  size_t count = 0;
  for (const SceneObject& object : objects) count += object.mesh.triangles.size();
  return count;
}

Aabb Scene::TargetBounds() const {
  Aabb box;
  for (const SceneObject& object : objects) {
    if (object.is_target()) box.Extend(object.mesh.Bounds());
  }
  return box;
}

TriangleMesh MakeBox(const Vec3& size) {
  CheckPositive(size.x(), "size x", "box");
  CheckPositive(size.y(), "size y", "box");
  CheckPositive(size.z(), "size z", "box");
  const Vec3 h = size / 2.0;
  TriangleMesh mesh;
  // Vertex i has x = ±h.x by bit 0, y by bit 1, z by bit 2.
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(),
                               i & 4 ? h.z() : -h.z());
  }
  // Each face counter-clockwise seen from outside, so normals point out.
  AddQuad(&mesh, 0, 2, 3, 1);  // -z
  AddQuad(&mesh, 4, 5, 7, 6);  // +z
  AddQuad(&mesh, 0, 1, 5, 4);  // -y
  AddQuad(&mesh, 2, 6, 7, 3);  // +y
  AddQuad(&mesh, 0, 4, 6, 2);  // -x
  AddQuad(&mesh, 1, 3, 7, 5);  // +x
  return mesh;
}

namespace {

// MakeSphere's UV sphere; `odd_rings`: no ring on the equator (MakeCapsule cuts it there);
// `shape` names what it becomes in the limits' messages.
TriangleMesh UvSphere(double radius, double max_chord_error, bool odd_rings, const char* shape) {
  // Slices by the chord rule on the equator, rings by the same rule on a meridian (half a
  // circle); then refine both until the facets' deviation, not only the edges', is below the
  // bound (a quad's centre lies deeper than its edges).
  const auto rings_for = [odd_rings](int slices) {
    const int rings = std::max(2, (slices + 1) / 2);
    return odd_rings && rings % 2 == 0 ? rings + 1 : rings;  // more rings: a smaller deviation
  };
  int slices = SegmentsFor(radius, max_chord_error, shape);
  int rings = rings_for(slices);
  while (UvSphereDeviation(radius, rings, slices) >= max_chord_error) {
    slices += std::max(1, slices / 8);
    rings = rings_for(slices);
    if (slices > kMaxSegments) throw TooManySegments(shape, radius, max_chord_error);
  }
  // Bound the whole mesh, not only a circle: slices x rings grows with the square (fuzzing found
  // cell_size 1e-7 asking for 2·10⁸ triangles).
  constexpr int64_t kMaxTriangles = 10'000'000;
  if (int64_t{2} * slices * rings > kMaxTriangles) {
    throw InputError(fmt::format("{} of radius {:g} m needs {} triangles for a chord error of "
                                 "{:g} m (a tenth of the cell size), above {} — check the radius, or "
                                 "give a larger cell size",
                                 shape, radius, int64_t{2} * slices * rings, max_chord_error,
                                 kMaxTriangles));
  }
  TriangleMesh mesh;
  mesh.vertices.push_back(Vec3(0, 0, radius));  // north pole: index 0
  for (int ring = 1; ring < rings; ++ring) {
    for (int slice = 0; slice < slices; ++slice) {
      mesh.vertices.push_back(SpherePoint(radius, ring, rings, slice, slices));
    }
  }
  const auto south = static_cast<uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back(Vec3(0, 0, -radius));
  const auto at = [&](int ring, int slice) {
    return static_cast<uint32_t>(1 + (ring - 1) * slices + slice % slices);
  };
  for (int slice = 0; slice < slices; ++slice) {
    mesh.triangles.push_back({0, at(1, slice), at(1, slice + 1)});
    for (int ring = 1; ring + 1 < rings; ++ring) {
      AddQuad(&mesh, at(ring, slice), at(ring + 1, slice), at(ring + 1, slice + 1),
              at(ring, slice + 1));
    }
    mesh.triangles.push_back({south, at(rings - 1, slice + 1), at(rings - 1, slice)});
  }
  return mesh;
}

}  // namespace

TriangleMesh MakeSphere(double radius, double max_chord_error) {
  CheckPositive(radius, "radius", "sphere");
  return UvSphere(radius, max_chord_error, false, "sphere");
}

TriangleMesh MakeCapsule(double radius, double length, double max_chord_error) {
  CheckPositive(radius, "radius", "capsule");
  CheckPositive(length, "length", "capsule");
  // A sphere with an odd number of rings has none on its equator: moving its halves apart by
  // `length` stretches the band of quads across the equator into the side wall. A wall facet has
  // the corners' radius and the centre's depth of that band's quads on the sphere, so it deviates
  // from the cylinder exactly as they did from the sphere: below the bound.
  TriangleMesh mesh = UvSphere(radius, max_chord_error, true, "capsule");
  for (Vec3& v : mesh.vertices) v.z() += v.z() > 0 ? length / 2 : -length / 2;
  return mesh;
}

TriangleMesh MakeEllipsoid(const Vec3& radii, double max_chord_error) {
  CheckPositive(radii.x(), "radius x", "ellipsoid");
  CheckPositive(radii.y(), "radius y", "ellipsoid");
  CheckPositive(radii.z(), "radius z", "ellipsoid");
  // The sphere of the largest radius squeezed along the other axes: the squeeze moves no two
  // points apart, so a facet lies as close to the ellipsoid as it lay to the sphere.
  const double largest = radii.maxCoeff();
  TriangleMesh mesh = UvSphere(largest, max_chord_error, false, "ellipsoid");
  for (Vec3& v : mesh.vertices) v = v.cwiseProduct(radii / largest);
  return mesh;
}

TriangleMesh MakeCylinder(double radius, double length, double max_chord_error) {
  CheckPositive(radius, "radius", "cylinder");
  CheckPositive(length, "length", "cylinder");
  // The side's quads are planar with their corners on the circle, so the chord rule alone bounds
  // the deviation; the caps are flat.
  const int slices = SegmentsFor(radius, max_chord_error, "cylinder");
  const double h = length / 2.0;
  TriangleMesh mesh;
  for (int slice = 0; slice < slices; ++slice) {
    const double azimuth = 2.0 * kPi * slice / slices;
    const double x = radius * std::cos(azimuth), y = radius * std::sin(azimuth);
    mesh.vertices.emplace_back(x, y, -h);  // 2·slice
    mesh.vertices.emplace_back(x, y, h);   // 2·slice + 1
  }
  const auto bottom_centre = static_cast<uint32_t>(mesh.vertices.size());
  mesh.vertices.emplace_back(0, 0, -h);
  mesh.vertices.emplace_back(0, 0, h);
  const uint32_t top_centre = bottom_centre + 1;
  for (int slice = 0; slice < slices; ++slice) {
    const auto lo = static_cast<uint32_t>(2 * slice);
    const auto next_lo = static_cast<uint32_t>(2 * ((slice + 1) % slices));
    AddQuad(&mesh, lo, next_lo, next_lo + 1, lo + 1);
    mesh.triangles.push_back({bottom_centre, next_lo, lo});
    mesh.triangles.push_back({top_centre, lo + 1, next_lo + 1});
  }
  return mesh;
}

TriangleMesh MakePlane(double size_x, double size_y) {
  CheckPositive(size_x, "size x", "plane");
  CheckPositive(size_y, "size y", "plane");
  const double hx = size_x / 2.0, hy = size_y / 2.0;
  TriangleMesh mesh;
  mesh.vertices = {Vec3(-hx, -hy, 0), Vec3(hx, -hy, 0), Vec3(hx, hy, 0), Vec3(-hx, hy, 0)};
  AddQuad(&mesh, 0, 1, 2, 3);
  return mesh;
}

namespace {

// Assimp is in a module of its own (src/scene/module/assimp_reader.cpp, libvantage_assimp.so),
// loaded only in the child process that reads a mesh with it (issue 47: its 40 k relocations were
// two thirds of every process start's); the entry is vantage_read_mesh there.
using MeshModuleEntry = int (*)(const char* path, TriangleMesh* raw, std::string* problem);

// Where the module lies (ModulePlaces), found in this process so that a missing one is an
// internal error naming the places looked at.
std::filesystem::path MeshModulePlace() {
  std::string tried;
  const std::optional<std::filesystem::path> place = detail::FirstModulePlace(
      detail::ModulePlaces(reinterpret_cast<const void*>(&ReadMeshFile),
                           VANTAGE_ASSIMP_MODULE_NAME, VANTAGE_ASSIMP_MODULE_FROM_BIN,
                           VANTAGE_ASSIMP_MODULE_BUILT),
      &tried);
  if (!place)
    throw InternalError(fmt::format("cannot read meshes with Assimp: the mesh reader {} is not "
                                    "installed (looked at {})",
                                    VANTAGE_ASSIMP_MODULE_NAME, tried));
  return *place;
}

/// Assimp's import of `path` (PlyBodyProblem already checked) through the module at `module`
/// (in the child process): the raw triangles, or FailMesh.
TriangleMesh ImportWithModule(const std::filesystem::path& module, const std::string& path) {
  void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw std::runtime_error(fmt::format("cannot load the mesh reader {}: {}", module.string(),
                                         dlerror()));
  const auto entry = reinterpret_cast<MeshModuleEntry>(dlsym(handle, "vantage_read_mesh"));
  if (entry == nullptr)
    throw std::runtime_error(fmt::format("{} is not vantage's mesh reader", module.string()));
  TriangleMesh raw;
  std::string problem;
  const int status = entry(path.c_str(), &raw, &problem);
  if (status == 1) FailMesh(path, problem);
  if (status != 0) throw std::runtime_error(problem);
  return raw;
}

/// The bytes of `mesh` (vertex and triangle counts, then their values) for the trip out of the
/// child process of RunIsolated, and back.
std::string MeshBytes(const TriangleMesh& mesh) {
  const uint64_t counts[2] = {mesh.vertices.size(), mesh.triangles.size()};
  std::string bytes(reinterpret_cast<const char*>(counts), sizeof(counts));
  for (const Vec3& v : mesh.vertices) bytes.append(reinterpret_cast<const char*>(v.data()), 24);
  for (const auto& t : mesh.triangles)
    bytes.append(reinterpret_cast<const char*>(t.data()), sizeof(t));
  return bytes;
}

TriangleMesh MeshFromBytes(const std::string& bytes) {
  uint64_t counts[2] = {0, 0};
  VANTAGE_CHECK(bytes.size() >= sizeof(counts));
  std::memcpy(counts, bytes.data(), sizeof(counts));
  VANTAGE_CHECK(bytes.size() == sizeof(counts) + counts[0] * 24 + counts[1] * 12);
  TriangleMesh mesh;
  mesh.vertices.resize(counts[0]);
  mesh.triangles.resize(counts[1]);
  const char* at = bytes.data() + sizeof(counts);
  for (Vec3& v : mesh.vertices) {
    std::memcpy(v.data(), at, 24);
    at += 24;
  }
  for (auto& t : mesh.triangles) {
    std::memcpy(t.data(), at, sizeof(t));
    at += sizeof(t);
  }
  return mesh;
}

/// Whether `path` ends in `extension` (lower case, with its dot), in any case.
bool HasExtension(const std::string& path, std::string_view extension) {
  std::string own = std::filesystem::path(path).extension().string();
  for (char& c : own) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return own == extension;
}

/// A binary STL read here, without Assimp's child process: the file is a fixed layout (an
/// 80-byte header, a triangle count n, 50 bytes per triangle) recognised by the size rule Assimp's
/// own STL reader uses (84 + 50 n bytes exactly, STLImporter::IsBinarySTL), so no content can make
/// this read go wrong. The triangles come out as Assimp gives them: three float vertices each, in
/// file order, with Assimp's identity node transform's + 0 (which turns -0 into +0). Empty when
/// the file is not such an STL, or holds no triangle (Assimp reads those, and words the refusal).
std::optional<TriangleMesh> ReadBinaryStl(const std::string& path) {
  if (!HasExtension(path, ".stl")) return std::nullopt;
  std::string bytes;
  if (!detail::ReadWholeFile(path, &bytes)) return std::nullopt;
  constexpr size_t kHeader = 84, kPerTriangle = 50;
  if (bytes.size() < kHeader) return std::nullopt;
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, sizeof(count));
  if (count == 0 || bytes.size() != kHeader + kPerTriangle * static_cast<size_t>(count))
    return std::nullopt;
  TriangleMesh mesh;
  mesh.vertices.resize(3 * static_cast<size_t>(count));
  mesh.triangles.resize(count);
  const char* at = bytes.data() + kHeader;
  for (uint32_t t = 0; t < count; ++t, at += kPerTriangle) {
    float corners[9];  // after the facet's normal (12 bytes); 2 attribute bytes follow
    std::memcpy(corners, at + 12, sizeof(corners));
    for (uint32_t k = 0; k < 3; ++k) {
      mesh.vertices[3 * t + k] = Vec3(corners[3 * k] + 0.0f, corners[3 * k + 1] + 0.0f,
                                      corners[3 * k + 2] + 0.0f);
    }
    mesh.triangles[t] = {3 * t, 3 * t + 1, 3 * t + 2};
  }
  return mesh;
}

}  // namespace

namespace detail {

// Assimp's fast_atof, as plain_obj.hpp describes it.
std::optional<float> PlainObjNumber(std::string_view word) {
  static constexpr double kScale[16] = {0.0,     1e-1,  1e-2,  1e-3,  1e-4,  1e-5,  1e-6,  1e-7,
                                        1e-8,    1e-9,  1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};
  size_t at = 0;
  const bool negative = !word.empty() && word[0] == '-';
  if (negative) ++at;
  const auto digit = [&](size_t k) { return k < word.size() && word[k] >= '0' && word[k] <= '9'; };
  if (!digit(at)) return std::nullopt;
  uint64_t whole = 0;
  size_t count = 0;
  for (; digit(at); ++at, ++count) whole = whole * 10 + static_cast<uint64_t>(word[at] - '0');
  if (count > 18) return std::nullopt;
  float value = static_cast<float>(whole);
  if (at < word.size()) {
    if (word[at] != '.' || !digit(at + 1)) return std::nullopt;
    ++at;
    uint64_t fraction = 0;
    size_t digits = 0;
    for (; digit(at); ++at) {
      if (digits == 15) continue;  // digits past the 15th are read over
      fraction = fraction * 10 + static_cast<uint64_t>(word[at] - '0');
      ++digits;
    }
    if (at != word.size()) return std::nullopt;
    value += static_cast<float>(static_cast<double>(fraction) * kScale[digits]);
  }
  return negative ? -value : value;
}

std::optional<TriangleMesh> ReadPlainObj(const std::string& path) {
  if (!HasExtension(path, ".obj")) return std::nullopt;
  std::string text;
  if (!detail::ReadWholeFile(path, &text)) return std::nullopt;
  std::vector<Vec3> positions;
  TriangleMesh mesh;
  bool named = false;
  std::string_view rest(text);
  std::vector<std::string_view> words;
  while (!rest.empty()) {
    const size_t end = rest.find('\n');
    std::string_view line = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    words.clear();
    for (size_t at = 0; at < line.size();) {
      if (line[at] == ' ' || line[at] == '\t') {
        ++at;
        continue;
      }
      const size_t stop = line.find_first_of(" \t", at);
      const size_t length = stop == std::string_view::npos ? line.size() - at : stop - at;
      words.push_back(line.substr(at, length));
      at += length;
    }
    if (words.empty()) continue;
    if (words[0][0] == '#') continue;  // a comment line
    for (const std::string_view word : words) {
      for (const char c : word)
        if (static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e)
          return std::nullopt;  // control or non-ASCII bytes: Assimp's call
    }
    if (words[0] == "o") {
      if (named || !mesh.triangles.empty() || words.size() != 2) return std::nullopt;
      named = true;
    } else if (words[0] == "v") {
      if (words.size() != 4) return std::nullopt;
      float xyz[3];
      for (int a = 0; a < 3; ++a) {
        const std::optional<float> value = PlainObjNumber(words[1 + a]);
        if (!value) return std::nullopt;
        xyz[a] = *value;
      }
      positions.emplace_back(xyz[0] + 0.0f, xyz[1] + 0.0f, xyz[2] + 0.0f);
    } else if (words[0] == "f") {
      if (words.size() != 4) return std::nullopt;
      std::array<uint32_t, 3> corners{};
      for (int k = 0; k < 3; ++k) {
        const std::string_view word = words[1 + k];
        uint64_t index = 0;
        if (word.size() > 9) return std::nullopt;
        for (const char c : word) {
          if (c < '0' || c > '9') return std::nullopt;
          index = index * 10 + static_cast<uint64_t>(c - '0');
        }
        if (index == 0 || index > positions.size()) return std::nullopt;
        corners[k] = static_cast<uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(positions[index - 1]);
      }
      mesh.triangles.push_back(corners);
    } else {
      return std::nullopt;
    }
  }
  if (mesh.triangles.empty()) return std::nullopt;
  return mesh;
}

}  // namespace detail

TriangleMesh ReadMeshFile(const std::string& path) {
  if (detail::IsCadFile(path)) return detail::ReadCadMesh(path, detail::kDefaultCadDeflection);
  detail::NoteInputFile(path, "mesh file");
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    FailMesh(path, "it is a folder, not a mesh file (name the mesh file in it)");
  if (!std::filesystem::is_regular_file(path, error))
    FailMesh(path, "it is missing or not a regular file (a device or a pipe?)");
  if (const std::string problem = detail::PlyBodyProblem(path); !problem.empty())
    FailMesh(path, problem);
  if (std::optional<TriangleMesh> stl = ReadBinaryStl(path)) {
    for (const Vec3& v : stl->vertices) {
      if (!v.allFinite()) FailMesh(path, "it has a vertex that is not finite (NaN or infinity)");
    }
    return std::move(*stl);
  }
  if (std::optional<TriangleMesh> obj = detail::ReadPlainObj(path)) return std::move(*obj);
  // In a child process: Assimp's readers crash on some broken files (the mesh_file fuzzer found
  // a segfault in its PLY header parser within seconds), and a crash there must not end vantage.
  // CPU time: a minute, and 10 s per MiB (Assimp reads about 10 MiB of STL a second here).
  const double mib = static_cast<double>(std::filesystem::file_size(path, error)) / (1 << 20);
  const std::filesystem::path reader = MeshModulePlace();
  TriangleMesh raw = MeshFromBytes(detail::RunIsolated(
      [&] { return MeshBytes(ImportWithModule(reader, path)); },
      fmt::format("{}: cannot read mesh: Assimp", path),
      60.0 + 10.0 * mib));
  if (raw.triangles.empty()) FailMesh(path, "it holds no triangles");
  for (const Vec3& v : raw.vertices) {
    if (!v.allFinite()) FailMesh(path, "it has a vertex that is not finite (NaN or infinity)");
  }
  return raw;
}

namespace {

/// ScaledMesh of `raw` without changing it: each scaled vertex is computed where it is read (the
/// same product as TriangleMesh::Scale's), so the raw mesh is neither copied nor scaled in place
/// (issue 47: ScaledMeshCache copied the 53 k-triangle STL's 158 k vertices, 4.4 MB, to scale
/// them, and ScaledMesh then moved and welded the copy).
TriangleMesh ScaledOf(const TriangleMesh& raw, const Vec3& scale, const std::string& path) {
  const std::vector<Vec3>& raw_vertices = raw.vertices;
  const auto at = [&](uint32_t i) -> Vec3 { return raw_vertices[i].cwiseProduct(scale); };
  // Every vertex is checked before any triangle is dropped: a vertex far out makes its triangles
  // slivers, which were dropped as degenerate, so the mesh lost them without a word (issue 15).
  // The vertices all within reach (the usual case) need no look at the triangles; otherwise the
  // first one a triangle uses, in the triangles' order, is named.
  const bool all_within = std::all_of(raw_vertices.begin(), raw_vertices.end(), [&](const Vec3& v) {
    const Vec3 scaled = v.cwiseProduct(scale);
    return scaled.allFinite() && (scaled.array().abs() <= kMaxWorldCoordinate).all();
  });
  if (!all_within) {
    for (const auto& t : raw.triangles) {
      for (const uint32_t index : t) {
        const std::string beyond = WorldPointProblem(at(index));
        if (beyond.empty()) continue;
        throw InputError(fmt::format(
            "{}: a vertex of the mesh{} lies at {} — check the file's units and the scale", path,
            scale == Vec3::Ones() ? "" : " (scale applied)", beyond));
      }
    }
  }
  TriangleMesh mesh;
  mesh.triangles.reserve(raw.triangles.size());
  for (const auto& t : raw.triangles) {
    if (!IsDegenerate(at(t[0]), at(t[1]), at(t[2]))) mesh.triangles.push_back(t);
  }
  if (mesh.triangles.empty()) FailMesh(path, "every triangle is degenerate (zero area)");
  mesh.vertices = CompactVerticesOf(raw_vertices.size(), at, &mesh.triangles);
  return mesh;
}

}  // namespace

TriangleMesh ScaledMesh(TriangleMesh raw, const Vec3& scale, const std::string& path) {
  return ScaledOf(raw, scale, path);
}

TriangleMesh LoadMeshFile(const std::string& path, const Vec3& scale) {
  return ScaledMesh(ReadMeshFile(path), scale, path);
}

const TriangleMesh& detail::ScaledMeshCache::Get(const TriangleMesh& raw, const Vec3& scale,
                                         const std::string& path) {
  std::pair<std::string, std::array<uint64_t, 3>> key{
      path,
      {std::bit_cast<uint64_t>(scale.x()), std::bit_cast<uint64_t>(scale.y()),
       std::bit_cast<uint64_t>(scale.z())}};
  auto it = meshes_.find(key);
  if (it == meshes_.end()) it = meshes_.emplace(std::move(key), ScaledOf(raw, scale, path)).first;
  return it->second;
}

namespace {

/// Whether some triangle of `mesh` keeps an area once its vertices are floats, as Embree stores
/// them: a target of 1e-12 m collapses to a point there, gets reference cells (sampled in double)
/// and is never hit, a silent 0 % (issue 15).
bool HasFloatTriangle(const TriangleMesh& mesh) {
  // Through a volatile: GCC 12.2's SLP vectoriser folds a vectorised pair of (double)(float)
  // round trips into a plain copy (seen at -O2 and -O3), so x and y kept their doubles.
  const auto rounded = [](double x) {
    volatile float f = static_cast<float>(x);
    return static_cast<double>(f);
  };
  const auto as_float = [&](uint32_t i) {
    const Vec3& v = mesh.vertices[i];
    return Vec3(rounded(v.x()), rounded(v.y()), rounded(v.z()));
  };
  return std::any_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const auto& t) {
    return !IsDegenerate(as_float(t[0]), as_float(t[1]), as_float(t[2]));
  });
}

/// "is 1e-300 m across: at 0.05 m from the origin the ray caster's float steps are 3.7e-09 m,
/// so every triangle collapses": why an object without float triangles cannot be ray cast.
std::string CollapseWords(const Aabb& bounds) {
  const Vec3 far = bounds.min.cwiseAbs().cwiseMax(bounds.max.cwiseAbs());
  const float at = static_cast<float>(far.maxCoeff());
  return fmt::format("is {:g} m across: at {:g} m from the origin the ray caster's float steps "
                     "are {:g} m, so every triangle collapses",
                     (bounds.max - bounds.min).maxCoeff(), far.maxCoeff(),
                     std::nextafter(at, INFINITY) - at);
}

/// Words for what is wrong with `object`'s extent, "" when nothing is.
std::string ExtentProblem(const SceneObject& object) {
  const Aabb bounds = object.mesh.Bounds();
  if (bounds.IsEmpty()) return {};
  // The corner farthest from the origin on each axis.
  const Vec3 far = bounds.min.cwiseAbs().cwiseMax(bounds.max.cwiseAbs());
  if (!WorldPointProblem(far).empty()) {
    const Vec3 reach = (bounds.max.array() >= -bounds.min.array())
                           .select(bounds.max.array(), bounds.min.array())
                           .matrix();
    return fmt::format("object '{}' reaches {} — make it smaller or move it near the origin",
                       object.name, WorldPointProblem(reach));
  }
  if (object.role == Role::kTarget && !HasFloatTriangle(object.mesh)) {
    return fmt::format("target '{}' {} and no ray can hit it — check its size and scale",
                       object.name, CollapseWords(bounds));
  }
  return {};
}

/// The object's place for a message: the state's line, else the object's own, else the scene's.
std::string PlaceOf(const SceneObject& object, const std::string& source, int state_line,
                    const std::string& state, const std::string& what) {
  if (state_line > 0) return AtPlace(source, state_line, fmt::format("state '{}': {}", state, what));
  if (!object.file.empty()) return AtPlace(object.file, object.line, what);
  return AtPlace(source, 0, what);
}

bool IsCollapsedOccluder(const SceneObject& object) {
  return object.role == Role::kOccluder && !object.mesh.triangles.empty() &&
         !HasFloatTriangle(object.mesh);
}

}  // namespace

void CheckSceneExtent(const Scene& scene, const std::string& source, int state_line,
                      const std::string& state) {
  for (const SceneObject& object : scene.objects) {
    const std::string what = ExtentProblem(object);
    // In a state, the state's changes moved or added the object: its line is the place.
    if (!what.empty()) throw InputError(PlaceOf(object, source, state_line, state, what));
  }
}

std::vector<std::string> CollapsedOccluderWarnings(const Scene& scene, const std::string& source,
                                                   int state_line, const std::string& state,
                                                   const Scene* before) {
  std::set<std::string> known;
  if (before) {
    for (const SceneObject& object : before->objects) {
      if (IsCollapsedOccluder(object)) known.insert(object.name);
    }
  }
  std::vector<std::string> warnings;
  for (const SceneObject& object : scene.objects) {
    if (!IsCollapsedOccluder(object) || known.count(object.name)) continue;
    warnings.push_back(PlaceOf(
        object, source, state_line, state,
        fmt::format("occluder '{}' {} and it hides nothing: the coverage is what the cameras "
                    "would see without it — check its size and scale",
                    object.name, CollapseWords(object.mesh.Bounds()))));
  }
  return warnings;
}

}  // namespace vantage
