#pragma once
/// Gazebo's k-means (gazebo/math/Kmeans.cc, gz-math src/Kmeans.cc), used by the `uniform`
/// population distributions (GAZEBO.md): Lloyd iterations from the first k observations.
#include <span>
#include <vector>

#include "vantage/types.hpp"

namespace vantage::detail {

/// Safety cap on Lloyd iterations; Gazebo has none (Lloyd's method always terminates, but the
/// cap bounds the time on adversarial inputs). Reached only in pathological cases.
constexpr int kKMeansMaxIterations = 1000;

/// Clusters `points` into `k` clusters and returns the k centroids, in cluster order.
///
/// Gazebo's algorithm, step for step:
/// - initial centroids = the first k observations (not random: Gazebo's own shortcut);
/// - every label starts at 0; each pass assigns each point to its nearest centroid (strictly
///   nearer wins, so ties go to the lower cluster index) and counts the labels that changed;
/// - centroids become the means of their points;
/// - passes repeat while more than `points.size() >> 10` labels changed (so below 1024 points
///   it runs to a fixed point).
/// One deviation: where Gazebo divides by zero for a cluster left empty (a NaN centroid), the
/// cluster is re-seeded at the point farthest from its centroid (ties to the lower index) and
/// another pass runs. Deterministic: no random draw at all.
/// Requires 1 <= k <= points.size() (InternalError otherwise; callers report the user error).
std::vector<Vec3> KMeans(std::span<const Vec3> points,
                         int k,
                         int max_iterations = kKMeansMaxIterations);

}  // namespace vantage::detail
