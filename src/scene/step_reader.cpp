// STEP and IGES files (issue 46). OpenCASCADE itself is in a shared module of its own
// (src/scene/module/occt_reader.cpp, libvantage_cad.so), loaded only in the child process that
// reads a CAD file (issue 47: a run reading none starts without OpenCASCADE's libraries).
#include "scene/step_reader.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

#include "util/isolated.hpp"
#include "util/module_places.hpp"
#include "util/run_files.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw InputError(fmt::format("{}: {}", path, what));
}

// The module's entry: vantage_read_cad in occt_reader.cpp.
using CadModuleEntry = int (*)(const char* path, double deflection, std::string* parts,
                               std::string* failure);

// Loads the module (in the child process: the parent never maps OpenCASCADE) and returns its entry.
// It lies beside the binary (or the Python module), in lib/vantage/ once installed, or in the build
// folder (ModulePlaces).
CadModuleEntry LoadCadModule() {
  std::string tried;
  const std::optional<std::filesystem::path> place = FirstModulePlace(
      ModulePlaces(reinterpret_cast<const void*>(&ReadCadFile), VANTAGE_CAD_MODULE_NAME,
                   VANTAGE_CAD_MODULE_FROM_BIN, VANTAGE_CAD_MODULE_BUILT),
      &tried);
  if (!place) {
    throw InputError(fmt::format(
        "cannot read STEP or IGES files: the CAD reader {} is not installed (looked at {})",
        VANTAGE_CAD_MODULE_NAME, tried));
  }
  void* module = dlopen(place->c_str(), RTLD_NOW | RTLD_LOCAL);
  if (module == nullptr) {
    throw InputError(fmt::format("cannot load the CAD reader {}: {}", place->string(), dlerror()));
  }
  if (void* entry = dlsym(module, "vantage_read_cad")) return reinterpret_cast<CadModuleEntry>(entry);
  throw InputError(fmt::format("{} is not vantage's CAD reader (no vantage_read_cad)", place->string()));
}

std::vector<CadPart> PartsFromBytes(const std::string& bytes) {
  std::vector<CadPart> parts;
  size_t at = 0;
  const auto get = [&](void* p, size_t n) {
    VANTAGE_CHECK(at + n <= bytes.size());
    if (n) std::memcpy(p, bytes.data() + at, n);
    at += n;
  };
  while (at < bytes.size()) {
    uint64_t header[4];
    get(header, sizeof(header));
    CadPart part;
    part.name.resize(header[0]);
    get(part.name.data(), header[0]);
    std::array<double, 3> colour;
    get(colour.data(), sizeof(colour));
    if (header[3]) part.colour = colour;
    part.mesh.vertices.resize(header[1]);
    for (Vec3& v : part.mesh.vertices) get(v.data(), 3 * sizeof(double));
    part.mesh.triangles.resize(header[2]);
    get(part.mesh.triangles.data(), header[2] * sizeof(part.mesh.triangles[0]));
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace

bool IsCadFile(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".step" || extension == ".stp" || IsIgesFile(path);
}

std::vector<CadPart> ReadCadFile(const std::string& path, double deflection) {
  NoteInputFile(path, "CAD file");
  VANTAGE_CHECK(deflection > 0 && std::isfinite(deflection));
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    Fail(path, "it is a folder, not a CAD file (name the .step file in it)");
  if (!std::filesystem::is_regular_file(path, error))
    Fail(path, "it is missing or not a regular file (a device or a pipe?)");
  // In a child process, as Assimp's readers: a broken file must not crash vantage. CPU time: a
  // minute, and 20 s per MiB (STEP's text is slower to parse than a mesh).
  const double mib = static_cast<double>(std::filesystem::file_size(path, error)) / (1 << 20);
  std::vector<CadPart> parts = PartsFromBytes(RunIsolated(
      [&] {
        const CadModuleEntry read = LoadCadModule();
        std::string bytes;
        std::string failure;
        if (read(path.c_str(), deflection, &bytes, &failure) != 0) throw InputError(failure);
        return bytes;
      },
      fmt::format("{}: cannot read CAD file: OpenCASCADE", path), 60.0 + 20.0 * mib));
  for (const CadPart& part : parts) {
    for (const Vec3& v : part.mesh.vertices)
      if (!v.allFinite()) Fail(path, fmt::format("part '{}' has a vertex that is not finite", part.name));
  }
  return parts;
}

TriangleMesh ReadCadMesh(const std::string& path, double deflection) {
  TriangleMesh mesh;
  for (const CadPart& part : ReadCadFile(path, deflection)) mesh.Append(part.mesh);
  return mesh;
}

}  // namespace vantage::detail
