#include <algorithm>

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
  // Each worker holds one image's 8-byte voxel keys with their 4-byte pixel runs, and while
  // sorting them 16-byte (key, pixels) pairs (all pixels in the worst case).
  estimate.hit_buffers = largest_image * 28 * std::max<size_t>(threads, 1);
  estimate.selection = candidates.size() * ((reference_size + 63) / 64) * 8;
  return estimate;
}

}  // namespace vantage
