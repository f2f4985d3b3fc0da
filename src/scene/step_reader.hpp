#pragma once
// CAD in (issue 46): STEP (.step, .stp) and IGES (.iges, .igs) read with OpenCASCADE, each solid
// meshed by BRepMesh. Only src/scene/module/occt_reader.cpp includes OpenCASCADE: it is the shared
// module libvantage_cad.so, which ReadCadFile loads in its child process (issue 47).
#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vantage/scene.hpp"

namespace vantage::detail {

/// One solid of a CAD file, placed where its assembly puts it, in metres (the file's own unit
/// converted by OpenCASCADE).
struct CadPart {
  /// The product's name (XCAF); a product placed several times, or holding several solids, gets
  /// "#2", "#3"... after the first; "solid_K" when the file names none.
  std::string name;
  TriangleMesh mesh;
  /// The part's surface colour in the file (linear RGB in [0, 1]), when it has one.
  std::optional<std::array<double, 3>> colour;
};

/// The chord deflection [m] of a CAD file read where no cell size is known (ReadMeshFile's
/// dispatch: a URDF's or a Python caller's mesh); the scene readers give a quarter cell.
inline constexpr double kDefaultCadDeflection = 1e-3;

/// Whether `path` names a CAD file by its extension (.step, .stp, .iges, .igs; any case).
bool IsCadFile(const std::string& path);

/// The file's extension in lower case (".STEP" -> ".step"). Inline: the CAD module, a separate
/// shared library, needs it as well as the scene stage.
inline std::string LowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}
/// Whether the file is IGES by its extension (.iges, .igs; any case); else it is read as STEP.
inline bool IsIgesFile(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".iges" || extension == ".igs";
}

/// Every solid of the file (a shape without solids: its faces as one part), meshed with a chord
/// deflection of `deflection` metres (every mesh vertex lies on the surface, no point of the
/// surface is farther than `deflection` from the mesh). In a child process (RunIsolated), as
/// Assimp's readers are. InputError "PATH: ..." for a file that is missing, unreadable, broken
/// (naming the entity, "#N", where OpenCASCADE says which) or without any meshable face.
std::vector<CadPart> ReadCadFile(const std::string& path, double deflection);

/// All parts of ReadCadFile as one mesh (a YAML `mesh:` or an SDF `<mesh><uri>` naming a CAD file).
TriangleMesh ReadCadMesh(const std::string& path, double deflection);

}  // namespace vantage::detail
