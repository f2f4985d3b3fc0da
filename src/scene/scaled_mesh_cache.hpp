// ScaledMesh once per file and scale, for the scene readers (YAML and SDF) that place one model
// many times.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "vantage/scene.hpp"

namespace vantage::detail {

/// The instances of one model (four gearboxes, a bin of parts) copy its scaled mesh instead of
/// checking and welding it again (ScaledMesh's vertex weld was 3 % of a Gazebo world's run).
class ScaledMeshCache {
 public:
  /// ScaledMesh(raw, scale, path), computed at the first call for (path, scale); throws as it
  /// does (and again at the next call: a failure is not kept).
  const TriangleMesh& Get(const TriangleMesh& raw, const Vec3& scale, const std::string& path);

 private:
  std::map<std::pair<std::string, std::array<uint64_t, 3>>, TriangleMesh> meshes_;  // scale's bits
};

}  // namespace vantage::detail
