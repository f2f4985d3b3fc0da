// The arm's tour (issue 45): Held–Karp's dynamic programme over subsets for the exact order of a
// few views, 2-opt and Or-opt moves from nearest-neighbour beyond; and the greedy choice of
// views within a cycle time.
#include "vantage/tour.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A move's time as the heuristics compare it: an unconnected move costs more than any sum of
/// connected ones, so that they are avoided first.
double Weight(double seconds) { return std::isfinite(seconds) ? seconds : 1e12; }

/// Held–Karp: best[S][j] the fastest path from home through the views of S ending at j.
std::vector<uint32_t> HeldKarp(const TourTimes& times, std::span<const uint32_t> subset) {
  const size_t n = subset.size();
  const size_t home = times.views();
  const auto move = [&](size_t a, size_t b) { return Weight(times.motion[a][b]); };
  const size_t states = size_t{1} << n;
  std::vector<double> best(states * n, kInf);
  std::vector<uint8_t> previous(states * n, 0xFF);
  for (size_t j = 0; j < n; ++j) best[(size_t{1} << j) * n + j] = move(home, subset[j]);
  for (size_t set = 1; set < states; ++set) {
    for (size_t j = 0; j < n; ++j) {
      if (!(set & (size_t{1} << j))) continue;
      const double here = best[set * n + j];
      if (here == kInf) continue;
      for (size_t k = 0; k < n; ++k) {
        if (set & (size_t{1} << k)) continue;
        const size_t next = set | (size_t{1} << k);
        const double through = here + move(subset[j], subset[k]);
        // Ties keep the smaller predecessor (scanned in order): deterministic.
        if (through < best[next * n + k]) {
          best[next * n + k] = through;
          previous[next * n + k] = static_cast<uint8_t>(j);
        }
      }
    }
  }
  const size_t all = states - 1;
  size_t last = 0;
  double shortest = kInf;
  for (size_t j = 0; j < n; ++j) {
    const double total = best[all * n + j] + move(subset[j], home);
    if (total < shortest) {
      shortest = total;
      last = j;
    }
  }
  std::vector<uint32_t> order;
  for (size_t set = all, j = last; set != 0;) {
    order.push_back(static_cast<uint32_t>(j));
    const size_t before = previous[set * n + j];
    set &= ~(size_t{1} << j);
    j = before;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

/// The closed walk's weight: home, the views of `order` (positions into subset), home.
double WalkWeight(const TourTimes& times, std::span<const uint32_t> subset,
                  const std::vector<uint32_t>& order) {
  const size_t home = times.views();
  double total = 0;
  size_t at = home;
  for (uint32_t k : order) {
    total += Weight(times.motion[at][subset[k]]);
    at = subset[k];
  }
  return total + Weight(times.motion[at][home]);
}

/// Nearest neighbour from home, then 2-opt (reverse a stretch) and Or-opt (move a run of 1 to 3
/// views elsewhere) while either improves by more than a nanosecond.
std::vector<uint32_t> LocalSearch(const TourTimes& times, std::span<const uint32_t> subset) {
  const size_t n = subset.size();
  const size_t home = times.views();
  std::vector<uint32_t> order;
  std::vector<bool> used(n, false);
  size_t at = home;
  for (size_t step = 0; step < n; ++step) {
    size_t pick = n;
    for (size_t k = 0; k < n; ++k) {
      if (used[k]) continue;
      if (pick == n || Weight(times.motion[at][subset[k]]) < Weight(times.motion[at][subset[pick]]))
        pick = k;
    }
    used[pick] = true;
    order.push_back(static_cast<uint32_t>(pick));
    at = subset[pick];
  }
  double current = WalkWeight(times, subset, order);
  // A move's change in weight is found in O(1) from the walk's prefix sums (forward and
  // backward), and only a move that may improve is built and weighed as before: the same moves
  // in the same order are accepted, without an O(n) copy and walk per move tried (-n 200 on an
  // arm scene spent minutes here). `screen` covers the sums' round-off, far below a nanosecond
  // for tours of seconds (1e12 per unconnected move lets more through, each then weighed).
  std::vector<size_t> walk(n + 2);
  std::vector<double> forward(n + 2), backward(n + 2);
  const auto w = [&](size_t a, size_t b) { return Weight(times.motion[a][b]); };
  for (bool improved = true; improved;) {
    improved = false;
    ThrowIfInterrupted();
    walk[0] = walk[n + 1] = home;
    for (size_t k = 0; k < n; ++k) walk[k + 1] = subset[order[k]];
    forward[0] = backward[0] = 0;
    for (size_t t = 0; t <= n; ++t) {
      forward[t + 1] = forward[t] + w(walk[t], walk[t + 1]);
      backward[t + 1] = backward[t] + w(walk[t + 1], walk[t]);
    }
    const double screen = -1e-9 + 1e-9 * std::max(1.0, current);
    // 2-opt: order[i..j] reversed, walk positions a = i + 1 .. b = j + 1.
    for (size_t i = 0; i < n && !improved; ++i) {
      for (size_t j = i + 1; j < n && !improved; ++j) {
        const size_t a = i + 1, b = j + 1;
        const double change = w(walk[a - 1], walk[b]) + w(walk[a], walk[b + 1]) -
                              w(walk[a - 1], walk[a]) - w(walk[b], walk[b + 1]) +
                              (backward[b] - backward[a]) - (forward[b] - forward[a]);
        if (change >= screen) continue;
        std::vector<uint32_t> candidate = order;
        std::reverse(candidate.begin() + static_cast<long>(i), candidate.begin() + static_cast<long>(j) + 1);
        const double weight = WalkWeight(times, subset, candidate);
        if (weight < current - 1e-9) {
          order = std::move(candidate);
          current = weight;
          improved = true;
        }
      }
    }
    // Or-opt: order[i..i+length-1] (walk positions a .. e) moved before rest[at_pos], where rest
    // is the order without it, reversed or not.
    for (size_t length = 1; length <= 3 && !improved; ++length) {
      for (size_t i = 0; i + length <= n && !improved; ++i) {
        const size_t a = i + 1, e = i + length;
        const size_t p = walk[a - 1], q = walk[e + 1];
        const double removed = w(p, q) - w(p, walk[a]) - w(walk[e], q);
        const size_t rest_size = n - length;
        // rest[r] is order[r] before the run and order[r + length] after it.
        const auto rest_node = [&](size_t r) { return walk[(r < i ? r : r + length) + 1]; };
        for (size_t at_pos = 0; at_pos <= rest_size && !improved; ++at_pos) {
          if (at_pos == i) continue;
          const size_t u = at_pos == 0 ? home : rest_node(at_pos - 1);
          const size_t v = at_pos == rest_size ? home : rest_node(at_pos);
          for (const bool reversed : {false, true}) {
            const size_t first = reversed ? walk[e] : walk[a], last = reversed ? walk[a] : walk[e];
            const double change =
                removed - w(u, v) + w(u, first) + w(last, v) +
                (reversed ? (backward[e] - backward[a]) - (forward[e] - forward[a]) : 0.0);
            if (change >= screen) continue;
            std::vector<uint32_t> run(order.begin() + static_cast<long>(i),
                                      order.begin() + static_cast<long>(i + length));
            std::vector<uint32_t> candidate = order;
            candidate.erase(candidate.begin() + static_cast<long>(i),
                            candidate.begin() + static_cast<long>(i + length));
            if (reversed) std::reverse(run.begin(), run.end());
            candidate.insert(candidate.begin() + static_cast<long>(at_pos), run.begin(), run.end());
            const double weight = WalkWeight(times, subset, candidate);
            if (weight < current - 1e-9) {
              order = std::move(candidate);
              current = weight;
              improved = true;
              break;
            }
          }
        }
      }
    }
  }
  return order;
}

}  // namespace

void TourTimes::Check() const {
  const size_t n = acquisition.size();
  VANTAGE_CHECK(motion.size() == n + 1);
  for (const auto& row : motion) {
    VANTAGE_CHECK(row.size() == n + 1);
    for (double t : row) VANTAGE_CHECK(t >= 0);  // NaN fails too
  }
  for (double t : acquisition) VANTAGE_CHECK(t >= 0 && std::isfinite(t));
}

double TourSeconds(const TourTimes& times, std::span<const uint32_t> order) {
  const size_t home = times.views();
  double total = 0;
  size_t at = home;
  for (uint32_t view : order) {
    total += times.motion[at][view] + times.acquisition[view];
    at = view;
  }
  return total + times.motion[at][home];
}

Tour SolveTour(const TourTimes& times, std::span<const uint32_t> subset, size_t exact_limit) {
  times.Check();
  Tour tour;
  if (subset.empty()) {
    tour.exact = true;
    return tour;
  }
  VANTAGE_CHECK(exact_limit <= 20);
  const bool exact = subset.size() <= exact_limit;
  const std::vector<uint32_t> positions =
      exact ? HeldKarp(times, subset) : LocalSearch(times, subset);
  for (uint32_t k : positions) tour.order.push_back(subset[k]);
  tour.method = exact ? "held-karp" : "2-opt+or-opt";
  tour.exact = exact;
  for (uint32_t view : tour.order) tour.acquisition_seconds += times.acquisition[view];
  tour.total_seconds = TourSeconds(times, tour.order);
  tour.motion_seconds = tour.total_seconds - tour.acquisition_seconds;
  return tour;
}

CycleTimeResult MostCoverageWithinCycleTime(const TourTimes& times,
                                            std::span<const Observation> observations,
                                            size_t reference_size, double cycle_seconds,
                                            size_t exact_limit) {
  times.Check();
  VANTAGE_CHECK(observations.size() == times.views());
  CycleTimeResult result;
  std::vector<bool> seen(reference_size, false);
  std::vector<bool> taken(times.views(), false);
  size_t covered = 0;
  for (;;) {
    ThrowIfInterrupted();
    // Views by the cells they add, most first (ties: lower index); the first whose tour fits.
    std::vector<std::pair<size_t, uint32_t>> gains;
    for (uint32_t v = 0; v < times.views(); ++v) {
      if (taken[v]) continue;
      size_t gain = 0;
      for (uint32_t cell : observations[v].reference_indices) gain += seen[cell] ? 0 : 1;
      if (gain > 0) gains.emplace_back(gain, v);
    }
    std::sort(gains.begin(), gains.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    bool added = false;
    for (const auto& [gain, view] : gains) {
      std::vector<uint32_t> subset = result.chosen;
      subset.push_back(view);
      // A lower bound first: the out-and-back of the view alone (triangle inequality).
      const size_t home = times.views();
      if (times.motion[home][view] + times.acquisition[view] + times.motion[view][home] >
          cycle_seconds)
        continue;
      Tour tour = SolveTour(times, subset, exact_limit);
      if (!tour.connected() || tour.total_seconds > cycle_seconds) continue;
      result.chosen = std::move(subset);
      result.tour = std::move(tour);
      taken[view] = true;
      for (uint32_t cell : observations[view].reference_indices) {
        covered += seen[cell] ? 0 : 1;
        seen[cell] = true;
      }
      added = true;
      break;
    }
    if (!added) break;
  }
  result.coverage =
      reference_size == 0 ? 0.0 : static_cast<double>(covered) / static_cast<double>(reference_size);
  return result;
}

}  // namespace vantage
