#pragma once
/// The tour of one camera on an arm (issue 45; src/select/tour.cpp): the order in which the arm
/// takes a set of views, starting and ending at its home configuration, and how long it takes.
/// Selection's side of it: numbers only (motion times between views, acquisition times, the
/// views' observation sets); the pipeline computes the times from the arm (arm.hpp).
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "vantage/visibility.hpp"

namespace vantage {

/// Motion times between n views and home, and each view's acquisition time.
struct TourTimes {
  /// (n + 1) × (n + 1) [s]: motion[i][j] the move from view i to view j, index n is home;
  /// +inf where the move is not connected (its straight segment collides). Symmetric.
  std::vector<std::vector<double>> motion;
  std::vector<double> acquisition;  ///< per view [s] (frames / the sensor's fps)
  size_t views() const { return acquisition.size(); }
  /// InternalError unless the sizes agree and times are >= 0 (inf allowed for motion).
  void Check() const;
};

/// Where the exact order stops: Held–Karp is O(2^n n²).
inline constexpr size_t kMaxExactTourViews = 12;

/// An order of views and its time.
struct Tour {
  std::vector<uint32_t> order;  ///< indices of `subset` (SolveTour's), in visiting order
  double motion_seconds = 0;
  double acquisition_seconds = 0;
  double total_seconds = 0;     ///< +inf when some move of the order is unconnected
  /// "held-karp" (exact: no order of these views is faster) or "2-opt+or-opt" (a local
  /// optimum from nearest-neighbour), or "none" for no view.
  std::string method = "none";
  bool exact = false;
  bool connected() const { return total_seconds < std::numeric_limits<double>::infinity(); }
};

/// The fastest order of the views `subset` (indices into `times`) from home back to home:
/// Held–Karp when subset.size() <= exact_limit (exact), else 2-opt + Or-opt. Deterministic.
Tour SolveTour(const TourTimes& times, std::span<const uint32_t> subset,
               size_t exact_limit = kMaxExactTourViews);

/// The time of a given order (home first and last) [s].
double TourSeconds(const TourTimes& times, std::span<const uint32_t> order);

/// --cycle-time: views chosen greedily by the coverage they add (|∪O ∩ R|, `observations`' R
/// indices, R of `reference_size` cells) as long as the tour of the chosen, re-solved after each
/// addition, fits `cycle_seconds`. The coverage is a greedy answer (no bound is claimed); the
/// tour is exact where Tour::exact says so. `seconds_used` and `coverage` describe the result.
struct CycleTimeResult {
  std::vector<uint32_t> chosen;  ///< in the order added
  Tour tour;
  double coverage = 0;
};
CycleTimeResult MostCoverageWithinCycleTime(const TourTimes& times,
                                            std::span<const Observation> observations,
                                            size_t reference_size, double cycle_seconds,
                                            size_t exact_limit = kMaxExactTourViews);

}  // namespace vantage
