// libFuzzer target: a mesh file as vantage reads it (Assimp behind vantage's own checks). The
// first byte picks the extension (Assimp chooses its reader by it and by the content), the rest
// is the file. Session 9 found by hand that a PLY cut short made Debian's Assimp assert and abort
// (exit 134): the reader targets never fed a mesh's own bytes. An InputError is the expected
// outcome for bad input; anything else (an abort, a sanitizer report in vantage's code, a
// timeout, an out-of-memory) is a bug. Assimp itself is not instrumented: the coverage that
// guides this target is vantage's, the crashes found are anyone's.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/scene.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static constexpr std::array<const char*, 4> kExtensions = {".ply", ".stl", ".obj", ".dae"};
  if (size == 0) return 0;
  const std::string path = vantage::fuzz::WriteInput(
      std::string("scenes/mesh") + kExtensions[data[0] % kExtensions.size()], data + 1, size - 1);
  try {
    const vantage::TriangleMesh mesh = vantage::LoadMeshFile(path);
    // A mesh that loads is usable: triangles index its vertices, and every vertex is finite.
    VANTAGE_CHECK(!mesh.triangles.empty());
    for (const auto& t : mesh.triangles) {
      for (const uint32_t i : t) VANTAGE_CHECK(i < mesh.vertices.size());
    }
    for (const vantage::Vec3& v : mesh.vertices) VANTAGE_CHECK(v.allFinite());
  } catch (const vantage::InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
