#pragma once
/// Following a changing scene with one camera on an arm (issue 45, active perception): one view
/// per state in time order, solved exactly by dynamic programming (src/select/track.cpp).
/// Selection's side: numbers only (coverages per state and view, motion times between views).
#include <cstdint>
#include <optional>
#include <vector>

namespace vantage {

/// Following a changing scene with one arm camera (active perception): per state, in time
/// order, one view. `coverage[s][v]` the coverage view v gives in state s (-inf or NaN: not
/// allowed there); `motion` as TourTimes' (n + 1) × (n + 1), index n home, +inf unconnected.
struct TrackProblem {
  std::vector<std::vector<double>> coverage;  ///< states × views
  std::vector<std::vector<double>> motion;    ///< (views + 1)², home last
  /// The penalty per second of motion subtracted from the summed coverage (>= 0).
  double seconds_weight = 0;
  /// When set: the move between consecutive states (and from home to the first) must take at
  /// most this many seconds [s]; moves beyond it are not allowed.
  std::optional<double> max_move_seconds;
  bool start_at_home = true;  ///< the first move is from home (counted in the penalty)
};

/// One view per state: the sequence and its value (Σ coverage − weight · Σ move seconds).
struct Track {
  std::vector<uint32_t> views;     ///< per state
  std::vector<double> move_seconds;  ///< per state: the move that reaches its view (0 for the
                                     ///< first without start_at_home)
  double coverage = 0;             ///< summed over the states
  double value = 0;                ///< coverage − weight · Σ move_seconds
  bool feasible = false;           ///< false: no sequence obeys the moves' limits
};

/// The exact best sequence by dynamic programming over (state, view): best[s][v] = coverage[s][v]
/// + max_u (best[s-1][u] − weight · motion[u][v]); O(S · V²). Ties keep the lower view index
/// (deterministic). InternalError on inconsistent sizes.
Track SolveTrack(const TrackProblem& problem);

}  // namespace vantage
