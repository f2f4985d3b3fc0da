#include "candidates/kmeans.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

/// Index of the nearest centroid; strictly nearer wins, so ties keep the lower index (Gazebo's
/// ClosestCentroid compares `d < min`).
uint32_t Nearest(const Vec3& p, const std::vector<Vec3>& centroids) {
  double best = std::numeric_limits<double>::infinity();
  uint32_t best_index = 0;
  for (size_t c = 0; c < centroids.size(); ++c) {
    const double d = (p - centroids[c]).squaredNorm();
    if (d < best) {
      best = d;
      best_index = static_cast<uint32_t>(c);
    }
  }
  return best_index;
}

}  // namespace

std::vector<Vec3> KMeans(std::span<const Vec3> points, int k, int max_iterations) {
  VANTAGE_CHECK(k >= 1 && static_cast<size_t>(k) <= points.size());
  VANTAGE_CHECK(max_iterations >= 1);
  const auto cluster_count = static_cast<size_t>(k);

  // Gazebo: "Choose a random observation ... Note: This is not really random": the first k.
  std::vector<Vec3> centroids(points.begin(), points.begin() + k);
  std::vector<uint32_t> labels(points.size(), 0);
  std::vector<Vec3> sums(cluster_count);
  std::vector<int64_t> counts(cluster_count);
  const size_t stop_threshold = points.size() >> 10;

  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    std::fill(sums.begin(), sums.end(), Vec3::Zero());
    std::fill(counts.begin(), counts.end(), 0);
    size_t changed = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const uint32_t label = Nearest(points[i], centroids);
      if (labels[i] != label) {
        labels[i] = label;
        ++changed;
      }
      sums[label] += points[i];
      ++counts[label];
    }

    bool reseeded = false;
    std::vector<bool> is_empty(cluster_count, false);
    for (size_t c = 0; c < cluster_count; ++c) {
      if (counts[c] > 0) {
        centroids[c] = sums[c] / static_cast<double>(counts[c]);
      } else {
        is_empty[c] = true;
      }
    }
    // Gazebo would leave 0/0 here; move an empty cluster to the worst-served point instead.
    std::vector<bool> is_taken(points.size(), false);
    for (size_t c = 0; c < cluster_count; ++c) {
      if (!is_empty[c]) continue;
      double worst = -1.0;
      size_t worst_index = 0;
      for (size_t i = 0; i < points.size(); ++i) {
        if (is_taken[i]) continue;
        const double d = (points[i] - centroids[labels[i]]).squaredNorm();
        if (d > worst) {
          worst = d;
          worst_index = i;
        }
      }
      is_taken[worst_index] = true;
      centroids[c] = points[worst_index];
      reseeded = true;
    }

    if (changed <= stop_threshold && !reseeded) break;
  }
  return centroids;
}

}  // namespace vantage::detail
