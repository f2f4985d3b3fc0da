#pragma once
/// The reference set R: every half-open cell [kF, (k+1)F)³ that the targets' surface passes
/// through, computed exactly by triangle–cell overlap (SYSTEM.md, coverage metric).
#include <cstdint>
#include <vector>

#include "vantage/scene.hpp"

namespace vantage {

struct ReferenceOptions {
  double cell_size = 0.005;  ///< F [m], > 0
  /// Throws InputError naming the field when cell_size is not a positive finite number.
  void Validate() const;
};

struct Reference {
  double cell_size = 0.005;
  std::vector<uint64_t> keys;  ///< packed voxel keys (PackVoxel), sorted ascending, unique

  size_t size() const { return keys.size(); }
  /// Index of a packed key in `keys`, or -1.
  int64_t IndexOf(uint64_t key) const;
};

/// Cells touched by one triangle (closed triangle against half-open cells), appended unsorted.
void AppendTriangleCells(const Vec3& a, const Vec3& b, const Vec3& c, double cell_size,
                         std::vector<uint64_t>* keys);

/// Throws InputError when the targets reach beyond the cells that PackVoxel can index at this
/// cell size (BuildReference checks it too).
void CheckTargetsFitGrid(const Scene& scene, double cell_size);

/// About how many cells BuildReference appends for the targets' triangles before it removes the
/// duplicates (|R| is at most this, in practice): per triangle, area · (|nx| + |ny| + |nz|) / F²
/// for the cells its plane crosses, √3 · perimeter / F for its edges, plus one. Takes
/// O(triangles) time and allocates nothing, so a cell size too fine for the memory can be
/// refused before R is built. 0 when cell_size is not a positive finite number.
double EstimateReferenceCells(const Scene& scene, double cell_size);

/// R of every target object of the scene. Throws InputError when the scene has no target or
/// when a target lies outside the packable range.
Reference BuildReference(const Scene& scene, const ReferenceOptions& options);

}  // namespace vantage
