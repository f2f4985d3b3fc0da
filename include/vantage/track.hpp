#pragma once
/// Following a changing scene with one camera on an arm (issue 45, active perception): one view
/// per state in time order, solved exactly by dynamic programming (src/select/track.cpp).
/// Selection's side: numbers only (coverages per state and view, motion times between views).
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

namespace vantage {

/// Following a changing scene with one arm camera (active perception): per state, in time
/// order, one view. `coverage[s][v]` the coverage view v gives in state s (-inf or NaN: not
/// allowed there); `motion` as TourTimes' (n + 1) × (n + 1), index n home, +inf unconnected.
struct TrackProblem {
  std::vector<std::vector<double>> coverage;  ///< states × views
  std::vector<std::vector<double>> motion;    ///< (views + 1)², home last
  /// Per state (empty, or one map per state): the moves into state s whose time is not
  /// `motion`'s — (from, to) → seconds, from = n for home — e.g. a move checked in the scenes
  /// of the two states it joins and planned around a collision there (+inf: unconnected).
  std::vector<std::map<std::pair<uint32_t, uint32_t>, double>> state_moves;
  /// Per view (empty: 0): its acquisition time [s], counted against `state_interval`.
  std::vector<double> acquisition;
  /// The penalty per second of motion subtracted from the summed coverage (>= 0).
  double seconds_weight = 0;
  /// When set: the states are this many seconds apart [s], a view taken at the start of its
  /// state, so between consecutive states the acquisition at the earlier view and the move to
  /// the next must fit: acquisition[u] + move(u, v) <= state_interval. The move from home to
  /// the first state's view is made before the states begin (not limited).
  std::optional<double> state_interval;
  bool start_at_home = true;  ///< the first move is from home (counted in the penalty)

  /// The time of the move from `from` to `to` into state `state` [s] (from = n: home).
  double MoveSeconds(size_t state, uint32_t from, uint32_t to) const;
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
/// + max_u (best[s-1][u] − weight · move(s, u, v)); O(S · V²). Exact because the value is a sum
/// of terms each of which depends on one state's view and the move into it. Ties keep the lower
/// view index (deterministic). InternalError on inconsistent sizes.
Track SolveTrack(const TrackProblem& problem);

}  // namespace vantage
