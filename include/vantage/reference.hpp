#pragma once
/// The reference set R: every half-open cell [kF, (k+1)F)³ that the targets' surface passes
/// through, computed exactly by triangle–cell overlap (SYSTEM.md, coverage metric).
#include <cstdint>
#include <string>
#include <vector>

#include "vantage/scene.hpp"

namespace vantage {

struct ReferenceOptions {
  double cell_size = 0.005;  ///< F [m], > 0
  /// --exposed-only: leave the unexposed cells (ComputeExposure) out of R, so that coverage
  /// counts only surface some viewpoint could see. Off: the paper's metric, every cell.
  bool exposed_only = false;
  /// Throws InputError naming the field when cell_size is not a positive finite number.
  void Validate() const;
};

struct Reference {
  double cell_size = 0.005;
  std::vector<uint64_t> keys;  ///< packed voxel keys (PackVoxel), sorted ascending, unique
  /// The target parts: the scene's target objects by name (one part per distinct name), in
  /// scene order.
  std::vector<std::string> part_names;
  /// Per key, its part (an index into part_names): of the targets whose surface passes through
  /// the cell, the first in scene order, so every cell belongs to exactly one part. Empty when
  /// not known (a reference built by hand, a visibility file before format 6).
  std::vector<uint32_t> part_of;
  /// Per key, 1 when the cell is exposed, 0 when no viewpoint can see it (ComputeExposure).
  /// Empty when not computed (the targets' box spans more than kMaxExposureGridCells cells).
  std::vector<uint8_t> exposed;
  /// --exposed-only: the unexposed cells were left out of `keys`; `left_out` counts them per
  /// part (as many entries as part_names).
  bool exposed_only = false;
  std::vector<uint64_t> left_out;

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
///
/// Triangles within a cell on every axis each count one cell or more although a fine mesh's
/// neighbours share their cells (a 200 k-triangle cell was estimated 28× its |R|). With
/// `fine_triangles_by_cell`, those triangles count instead the distinct cells of their bounding
/// boxes (≤ 8 each; the triangle lies in its box, so this still bounds their cells), at the
/// price of O(triangles) memory and a sort: for a second look when the plain estimate refuses.
double EstimateReferenceCells(const Scene& scene, double cell_size,
                              bool fine_triangles_by_cell = false);

/// The largest grid (cells of the targets' box, two cells of margin around it) that
/// ComputeExposure fills: one byte per cell.
inline constexpr uint64_t kMaxExposureGridCells = uint64_t{1} << 26;
/// Cells of that grid for this scene and cell size (0 without targets), for memory estimates.
uint64_t ExposureGridCells(const Scene& scene, double cell_size);

/// Which of R's cells some viewpoint could see, found from the geometry alone (no candidate
/// takes part): per key of `reference`, 1 when a cell of free space that reaches beyond the
/// targets' box touches the cell (one of its 26 neighbours), 0 otherwise. Every object's surface
/// (targets and occluders) blocks free space, and so does the inside of every closed object. A
/// face resting on another object, or enclosed by others, is unexposed; gaps narrower than about
/// one cell count as contact. Empty when the grid would exceed kMaxExposureGridCells.
/// Deterministic whatever the thread count.
std::vector<uint8_t> ComputeExposure(const Scene& scene, const Reference& reference);

/// R of every target object of the scene, with its cells' parts and exposure (with
/// options.exposed_only, the unexposed cells left out). Throws InputError when the scene has no
/// target, when a target lies outside the packable range, or (exposed_only) when the exposure
/// grid would be too large.
Reference BuildReference(const Scene& scene, const ReferenceOptions& options);

}  // namespace vantage
