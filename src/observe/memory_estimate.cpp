#include <algorithm>

#include "observe/cell_sets.hpp"
#include "vantage/observe.hpp"

namespace vantage {

MemoryEstimate EstimateMemory(const Scene& scene, size_t reference_size,
                              std::span<const Candidate> candidates, size_t threads) {
  MemoryEstimate estimate;
  // Embree: float vertices and indices plus a BVH of about 64 bytes per triangle.
  estimate.scene = scene.TriangleCount() * (12 + 64) + scene.TriangleCount() * 12;
  // RayScene's own copy of the targets in double, for the exact hit points (RayBatch::point).
  for (const SceneObject& object : scene.objects) {
    if (object.is_target()) estimate.scene += object.mesh.Bytes();
  }
  uint64_t largest_image = 0;
  for (const Candidate& c : candidates) {
    const uint64_t pixels = static_cast<uint64_t>(std::max<int64_t>(c.sensor.PixelCount(), 0));
    largest_image = std::max(largest_image, pixels);
    // A candidate sees at most min(pixels, |R|) cells of R: 4 bytes each and a 2-byte point
    // count, plus outside keys.
    estimate.observations += std::min<uint64_t>(pixels, reference_size) * 6 + 64;
  }
  // Each worker holds its cell sets (cell_sets.hpp): marks over R for every measured pixel, those
  // passing the quality filter and those the ideal pinhole counts, the pixel counts of one of
  // them, the touched lists and outside keys at their worst (every pixel outside R); and a
  // spare set for a worker that picks up a second candidate while it waits in Embree. R's hash
  // of keys is shared.
  const uint64_t per_worker = detail::CellSet::Bytes(reference_size, largest_image, true) +
                              2 * detail::CellSet::Bytes(reference_size, largest_image, false);
  estimate.hit_buffers = per_worker * (std::max<size_t>(threads, 1) + 1) +
                         detail::CellIndex::Bytes(reference_size);
  estimate.selection = candidates.size() * ((reference_size + 63) / 64) * 8;
  return estimate;
}

}  // namespace vantage
