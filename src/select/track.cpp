// Following a changing scene with one arm camera (issue 45): the best view per state by dynamic
// programming over (state, view), exact: the value of a sequence is a sum of terms that each
// depend on one state's view and the move from the previous one.
#include "vantage/track.hpp"

#include <cmath>
#include <limits>

#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

double TrackProblem::MoveSeconds(size_t state, uint32_t from, uint32_t to) const {
  if (state < state_moves.size() && !state_moves[state].empty()) {
    const auto found = state_moves[state].find({from, to});
    if (found != state_moves[state].end()) return found->second;
  }
  return motion[from][to];
}

Track SolveTrack(const TrackProblem& problem) {
  const size_t states = problem.coverage.size();
  const size_t n = problem.motion.empty() ? 0 : problem.motion.size() - 1;
  VANTAGE_CHECK(problem.motion.size() == n + 1);
  for (const auto& row : problem.motion) VANTAGE_CHECK(row.size() == n + 1);
  for (const auto& row : problem.coverage) VANTAGE_CHECK(row.size() == n);
  VANTAGE_CHECK(problem.state_moves.empty() || problem.state_moves.size() == states);
  VANTAGE_CHECK(problem.acquisition.empty() || problem.acquisition.size() == n);
  VANTAGE_CHECK(problem.seconds_weight >= 0 && std::isfinite(problem.seconds_weight));
  Track track;
  if (states == 0) {
    track.feasible = true;
    return track;
  }
  const size_t home = n;
  const auto allowed = [&](double coverage) { return std::isfinite(coverage); };
  // A move's time into `state`, or nullopt when it is not allowed (unconnected, or the
  // acquisition before it and the move do not fit the time between two states).
  const auto move = [&](size_t state, size_t from, size_t to) -> std::optional<double> {
    const double seconds = problem.MoveSeconds(state, static_cast<uint32_t>(from),
                                               static_cast<uint32_t>(to));
    if (!std::isfinite(seconds)) return std::nullopt;
    if (state > 0 && problem.state_interval) {
      const double acquiring = problem.acquisition.empty() ? 0.0 : problem.acquisition[from];
      if (acquiring + seconds > *problem.state_interval) return std::nullopt;
    }
    return seconds;
  };
  // best[s][v]: the largest value of states 0..s ending at v; -inf: unreachable.
  std::vector<std::vector<double>> best(states, std::vector<double>(n, -kInf));
  std::vector<std::vector<uint32_t>> previous(states, std::vector<uint32_t>(n, 0));
  for (size_t v = 0; v < n; ++v) {
    if (!allowed(problem.coverage[0][v])) continue;
    double cost = 0;
    if (problem.start_at_home) {
      const auto seconds = move(0, home, v);
      if (!seconds) continue;
      cost = problem.seconds_weight * *seconds;
    }
    best[0][v] = problem.coverage[0][v] - cost;
  }
  for (size_t s = 1; s < states; ++s) {
    ThrowIfInterrupted();
    for (size_t v = 0; v < n; ++v) {
      if (!allowed(problem.coverage[s][v])) continue;
      for (size_t u = 0; u < n; ++u) {
        if (best[s - 1][u] == -kInf) continue;
        const auto seconds = move(s, u, v);
        if (!seconds) continue;
        const double value = best[s - 1][u] - problem.seconds_weight * *seconds;
        if (value > best[s][v]) {  // strict: ties keep the lower u
          best[s][v] = value;
          previous[s][v] = static_cast<uint32_t>(u);
        }
      }
      if (best[s][v] > -kInf) best[s][v] += problem.coverage[s][v];
    }
  }
  size_t last = n;
  for (size_t v = 0; v < n; ++v)
    if (best[states - 1][v] > -kInf && (last == n || best[states - 1][v] > best[states - 1][last]))
      last = v;
  if (last == n) return track;
  track.feasible = true;
  track.value = best[states - 1][last];
  track.views.assign(states, 0);
  for (size_t s = states, v = last; s-- > 0;) {
    track.views[s] = static_cast<uint32_t>(v);
    if (s > 0) v = previous[s][v];
  }
  for (size_t s = 0; s < states; ++s) {
    const uint32_t v = track.views[s];
    track.coverage += problem.coverage[s][v];
    const double seconds =
        s > 0 ? problem.MoveSeconds(s, track.views[s - 1], v)
              : (problem.start_at_home ? problem.MoveSeconds(0, static_cast<uint32_t>(home), v)
                                       : 0.0);
    track.move_seconds.push_back(seconds);
  }
  return track;
}

}  // namespace vantage
