// The geometry of a visual: <box>, <cylinder>, <sphere> and <plane> built as meshes (primitives
// tessellated with a chord error below F / 10, SYSTEM.md), <mesh> files loaded once each and
// scaled; capsules and ellipsoids tessellated too; a target of another shape is an error, an
// occluder of one is left out with a warning (GAZEBO.md, "Poses and geometry").
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>

#include "scene/sdf/loader.hpp"
#include "scene/step_reader.hpp"
#include "scene/sdf/text.hpp"

namespace vantage::detail::gazebo {
namespace {

/// The plane of Gazebo's MeshManager::CreatePlane: z axis = normal, y axis = normal ×
/// (1, 0, 0) (or × (0, 1, 0) when parallel), x axis = y × z; size along x and y. `normal` is a
/// unit vector (UnitDirection).
Quat PlaneRotation(const Vec3& normal) {
  const Vec3& z = normal;
  Vec3 y = z.cross(Vec3::UnitX());
  if (y.squaredNorm() < 1e-12) y = z.cross(Vec3::UnitY());
  y.normalize();
  const Vec3 x = y.cross(z);
  Mat3 rotation;
  rotation.col(0) = x;
  rotation.col(1) = y;
  rotation.col(2) = z;
  return Quat(rotation).normalized();
}

}  // namespace

const TriangleMesh* Loader::LoadMesh(const std::string& path, const Doc& doc, int line) {
  const auto it = meshes_.find(path);
  if (it != meshes_.end()) return it->second.get();
  std::unique_ptr<TriangleMesh> mesh;
  try {
    // A CAD file is meshed to a quarter cell (issue 46; step_reader.hpp).
    mesh = std::make_unique<TriangleMesh>(detail::IsCadFile(path)
                                              ? detail::ReadCadMesh(path, problem_.cell_size / 4.0)
                                              : ReadMeshFile(path));
  } catch (const InputError& e) {
    Error(doc, line, fmt::format("<mesh> cannot be loaded: {}", e.what()));
  }
  const TriangleMesh* result = mesh.get();
  meshes_[path] = std::move(mesh);
  return result;
}

std::optional<TriangleMesh> Loader::GeometryOf(const VisualRecord& visual, bool is_target) {
  if (!visual.element) return MakePlane(kGroundPlaneSize, kGroundPlaneSize);
  const Doc& doc = *visual.doc;
  const XmlElement* geometry = visual.element->Child("geometry");
  std::string what = fmt::format("visual '{}' of model '{}'", visual.name, visual.model);
  if (doc.xml.path != visual.site.file)
    what += fmt::format(" (included at {}:{})", visual.site.file, visual.site.line);
  if (!geometry || geometry->children.empty()) {
    Error(doc, visual.element->line,
          fmt::format("{} has no <geometry> — add <box>, <cylinder>, <sphere>, <plane> or <mesh>",
                      what));
    return std::nullopt;
  }
  const XmlElement& shape = geometry->children.front();
  // SDF's chord error rule for primitives (SYSTEM.md): below F / 10.
  const double chord = problem_.cell_size / 10.0;
  if (shape.name == "box" || shape.name == "ellipsoid") {  // three positive numbers
    const bool box = shape.name == "box";
    const XmlElement* size = shape.Child(box ? "size" : "radii");
    if (!size) {
      Error(doc, shape.line,
            box ? "<box> has no <size> — add <size>sx sy sz</size>"
                : "<ellipsoid> has no <radii> — add <radii>rx ry rz</radii>");
      return std::nullopt;
    }
    const auto v = Vector(doc, *size, true, box ? "1 1 1" : "0.5 0.3 0.2");
    if (!v) return std::nullopt;
    return box ? MakeBox(*v) : MakeEllipsoid(*v, chord);
  }
  if (shape.name == "cylinder" || shape.name == "sphere" || shape.name == "capsule") {
    const bool has_length = shape.name != "sphere";
    const XmlElement* radius = shape.Child("radius");
    const XmlElement* length = shape.Child("length");
    if (!radius || (has_length && !length)) {
      Error(doc, shape.line,
            fmt::format("<{}> needs <radius>{}", shape.name, has_length ? " and <length>" : ""));
      return std::nullopt;
    }
    const auto r = PositiveNumber(doc, *radius, "0.5");
    if (!has_length) {
      if (!r) return std::nullopt;
      return MakeSphere(*r, chord);
    }
    const auto l = PositiveNumber(doc, *length, "1");
    if (!r || !l) return std::nullopt;
    return shape.name == "cylinder" ? MakeCylinder(*r, *l, chord) : MakeCapsule(*r, *l, chord);
  }
  if (shape.name == "plane") {
    Vec3 normal = Vec3::UnitZ();
    double sx = 1;
    double sy = 1;
    if (const XmlElement* e = shape.Child("normal")) {
      const auto v = Vector(doc, *e, false, "0 0 1");
      if (!v) return std::nullopt;
      const std::optional<Vec3> unit = UnitDirection(*v, 1e-12);
      if (!unit) {
        Error(doc, e->line,
              "<normal> is zero (shorter than 1e-12) — give a direction, e.g. "
              "<normal>0 0 1</normal>");
        return std::nullopt;
      }
      normal = *unit;
    }
    if (const XmlElement* e = shape.Child("size")) {
      const auto v = Numbers(doc, *e, 2, "100 100");
      if (!v) return std::nullopt;
      if ((*v)[0] <= 0 || (*v)[1] <= 0) {
        Error(doc, e->line,
              fmt::format("<size> '{}' of <plane> must be two positive lengths [m]", e->Trimmed()));
        return std::nullopt;
      }
      sx = (*v)[0];
      sy = (*v)[1];
    }
    TriangleMesh mesh = MakePlane(sx, sy);
    mesh.Transform(Pose{Vec3::Zero(), PlaneRotation(normal)});
    return mesh;
  }
  if (shape.name == "mesh") {
    const XmlElement* uri = shape.Child("uri");
    if (!uri || uri->Trimmed().empty()) {
      Error(doc, shape.line, "<mesh> has no <uri> — add <uri>model://NAME/meshes/FILE</uri>");
      return std::nullopt;
    }
    Vec3 scale = Vec3::Ones();
    if (const XmlElement* e = shape.Child("scale")) {
      const auto v = Vector(doc, *e, true, "1 1 1");
      if (!v) return std::nullopt;
      scale = *v;
    }
    if (shape.Child("submesh")) {
      Note(AtPlace(doc.xml.path, shape.line,
                   fmt::format("{}: <submesh> is not applied, the whole mesh is used", what)));
    }
    std::string text = uri->Trimmed();
    std::optional<std::string> path = ResolveResourceUri(text, doc);
    if (!path) {  // a folder or device is found: LoadMesh says what it is
      Error(doc, uri->line,
            fmt::format("<mesh><uri> '{}' of {} not found (model path: {}) — check the file "
                        "name, or add its model folder's parent with --model-path",
                        text, what, model_dirs_.empty() ? "empty" : Join(model_dirs_, ", ")));
      return std::nullopt;
    }
    const TriangleMesh* mesh = LoadMesh(*path, doc, uri->line);
    if (!mesh) return std::nullopt;
    // Scaled before the vertices are checked and degenerate triangles dropped (issue 15).
    try {
      return scaled_meshes_.Get(*mesh, scale, *path);
    } catch (const InputError& e) {
      Error(doc, uri->line, fmt::format("<mesh> of {}: {}", what, e.what()));
      return std::nullopt;
    }
  }
  if (shape.name == "empty") return TriangleMesh{};
  // <polyline>, <heightmap>: a target without its surface has no coverage to measure; an
  // occluder left out makes the coverage too high, which the report says in its notes and the
  // log as a warning (it was an [info] line).
  if (is_target) {
    Error(doc, shape.line,
          fmt::format("{} is a target, but its <{}> geometry is not supported — give it as a "
                      "<mesh>, or a <box>, <cylinder>, <sphere>, <capsule> or <ellipsoid>",
                      what, shape.name));
    return std::nullopt;
  }
  const std::string note =
      AtPlace(doc.xml.path, shape.line,
              fmt::format("{}: <{}> geometry is not supported: this occluder is left out, so the "
                          "coverage is what the cameras would see without it — give it as a <mesh>",
                          what, shape.name));
  Warn(note);
  return TriangleMesh{};
}

}  // namespace vantage::detail::gazebo
