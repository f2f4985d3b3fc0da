// Changing scenes (issue 9): selection over the states of a scene.
//
// Every state s has its own reference set R_s and one observation set per candidate. Selection
// keeps, per state, one bitset over R_s per candidate (the visibility matrices stacked) and
// scores a set of candidates by its covered counts c_s. The aggregate of c_s / |R_s| (mean or
// min) is compared exactly: every fraction is put on the common denominator L = lcm(|R_s|)
// (fixed point 2^-62 when L does not fit), so scores are whole numbers and no floating-point
// summation order can change a choice. Reported coverages are recomputed from the observations
// by CoverageEvaluator, never taken from this bookkeeping.
#include "vantage/select_states.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <limits>
#include <numeric>
#include <string_view>

#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;
__extension__ typedef __int128 Int;  // exact scores: up to S · L < 2^127

}  // namespace

OverStates ParseOverStates(const std::string& name) {
  if (name == "mean") return OverStates::kMean;
  if (name == "min") return OverStates::kMin;
  throw InputError(fmt::format("--over-states '{}' is unknown — use mean or min", name));
}

std::string OverStatesName(OverStates over) { return over == OverStates::kMean ? "mean" : "min"; }

// ----- selection over states -------------------------------------------------------------------

namespace {

/// Lexicographic score: primary (mean: the sum of the fractions; min: the least fraction), then
/// secondary (min: the sum; mean: 0), each in whole units of 1 / L.
struct Score {
  Int primary = -1;
  Int secondary = -1;
  bool operator>(const Score& o) const {
    return primary != o.primary ? primary > o.primary : secondary > o.secondary;
  }
};

using Bitset = std::vector<uint64_t>;

Int Gcd(Int a, Int b) {
  while (b != 0) {
    const Int t = a % b;
    a = b;
    b = t;
  }
  return a;
}

class StackedMatrix {
 public:
  StackedMatrix(std::span<const StateObservations> states, OverStates over) : over_(over) {
    candidates_ = states.front().observations.size();
    for (const StateObservations& state : states) {
      const size_t r = state.reference_size;
      const size_t words = (r + 63) / 64;
      words_.push_back(words);
      std::vector<uint64_t> bits(candidates_ * words, 0);
      for (size_t c = 0; c < candidates_; ++c) {
        for (const uint32_t index : state.observations[c].reference_indices) {
          if (index >= r) {
            throw InputError(fmt::format("--over-states: state '{}': candidate {} sees reference "
                                         "cell {} but the state's R has {} cells",
                                         state.name, c, index, r));
          }
          bits[c * words + index / 64] |= uint64_t{1} << (index % 64);
        }
      }
      bits_.push_back(std::move(bits));
      sizes_.push_back(r);
    }
    // Common denominator L = lcm(|R_s|) when S · L fits comfortably, else fixed point 2^62.
    constexpr Int kLimit = Int{1} << 96;
    Int lcm = 1;
    for (const size_t r : sizes_) {
      const Int next = lcm / Gcd(lcm, static_cast<Int>(r)) * static_cast<Int>(r);
      if (next > kLimit) {
        lcm = 0;
        break;
      }
      lcm = next;
    }
    exact_ = lcm != 0;
    for (const size_t r : sizes_) {
      unit_.push_back(exact_ ? lcm / static_cast<Int>(r) : 0);
    }
  }

  size_t state_count() const { return sizes_.size(); }
  size_t candidate_count() const { return candidates_; }
  size_t Words(size_t s) const { return words_[s]; }
  const uint64_t* Row(size_t s, size_t c) const { return bits_[s].data() + c * words_[s]; }

  /// Fraction c / |R_s| in units of 1 / L (exact), or floor(c · 2^62 / |R_s|).
  Int Units(size_t s, uint64_t count) const {
    if (exact_) return static_cast<Int>(count) * unit_[s];
    return (static_cast<Int>(count) << 62) / static_cast<Int>(sizes_[s]);
  }

  Score ScoreOf(std::span<const uint64_t> counts) const {
    Int sum = 0, least = 0;
    for (size_t s = 0; s < counts.size(); ++s) {
      const Int u = Units(s, counts[s]);
      sum += u;
      least = s == 0 ? u : std::min(least, u);
    }
    if (over_ == OverStates::kMean) return Score{sum, 0};
    return Score{least, sum};
  }

  /// Per state, the union of the rows of `chosen` except position `skip` (-1: none).
  std::vector<Bitset> Union(std::span<const uint32_t> chosen, ptrdiff_t skip) const {
    std::vector<Bitset> sets;
    for (size_t s = 0; s < state_count(); ++s) {
      Bitset set(words_[s], 0);
      for (size_t i = 0; i < chosen.size(); ++i) {
        if (static_cast<ptrdiff_t>(i) == skip) continue;
        const uint64_t* row = Row(s, chosen[i]);
        for (size_t w = 0; w < set.size(); ++w) set[w] |= row[w];
      }
      sets.push_back(std::move(set));
    }
    return sets;
  }

  /// Per state, |set ∪ row(candidate)|.
  void CountsWith(const std::vector<Bitset>& sets, uint32_t candidate, uint64_t* counts) const {
    for (size_t s = 0; s < state_count(); ++s) {
      const uint64_t* row = Row(s, candidate);
      const Bitset& set = sets[s];
      uint64_t count = 0;
      for (size_t w = 0; w < set.size(); ++w) count += std::popcount(set[w] | row[w]);
      counts[s] = count;
    }
  }

  /// Per state, |∪ rows of chosen|.
  std::vector<uint64_t> CountsOfSet(std::span<const uint32_t> chosen) const {
    const std::vector<Bitset> sets = Union(chosen, -1);
    std::vector<uint64_t> counts(state_count());
    for (size_t s = 0; s < state_count(); ++s) {
      uint64_t count = 0;
      for (const uint64_t word : sets[s]) count += std::popcount(word);
      counts[s] = count;
    }
    return counts;
  }

  Score ScoreOfSet(std::span<const uint32_t> chosen) const { return ScoreOf(CountsOfSet(chosen)); }

  /// The aggregate as a fraction (for RANSAC's stop test only; choices compare Scores).
  double AggregateOf(std::span<const uint64_t> counts) const {
    double sum = 0, least = 1;
    for (size_t s = 0; s < counts.size(); ++s) {
      const double fraction = static_cast<double>(counts[s]) / static_cast<double>(sizes_[s]);
      sum += fraction;
      least = std::min(least, fraction);
    }
    return over_ == OverStates::kMean ? sum / static_cast<double>(counts.size()) : least;
  }

 private:
  OverStates over_;
  size_t candidates_ = 0;
  std::vector<size_t> sizes_;
  std::vector<size_t> words_;
  std::vector<std::vector<uint64_t>> bits_;  ///< per state: candidates × words
  bool exact_ = true;
  std::vector<Int> unit_;
};

/// Greedy for n sensors: each step the candidate whose addition scores highest (ties: lowest
/// index). The answer for n is the first n of the answer for any larger n.
std::vector<uint32_t> GreedyChoice(const StackedMatrix& m, size_t n) {
  std::vector<uint32_t> chosen;
  std::vector<bool> taken(m.candidate_count(), false);
  std::vector<uint64_t> counts(m.state_count());
  while (chosen.size() < n) {
    const std::vector<Bitset> sets = m.Union(chosen, -1);
    Score best;
    int64_t best_candidate = -1;
    for (uint32_t c = 0; c < m.candidate_count(); ++c) {
      if (taken[c]) continue;
      m.CountsWith(sets, c, counts.data());
      const Score score = m.ScoreOf(counts);
      if (best_candidate < 0 || score > best) {
        best = score;
        best_candidate = c;
      }
    }
    VANTAGE_CHECK(best_candidate >= 0);
    chosen.push_back(static_cast<uint32_t>(best_candidate));
    taken[static_cast<size_t>(best_candidate)] = true;
  }
  return chosen;
}

/// The paper's Algorithm 2 over states: the same draws as RansacChoice (RansacDraw), each kept
/// only when its aggregate score is strictly better; stops once the best aggregate reaches
/// `stop_coverage`. With one state it returns exactly what RansacChoice does.
std::vector<uint32_t> RansacChoice(const StackedMatrix& m, size_t n, const SelectOptions& options) {
  std::vector<uint32_t> order(m.candidate_count());
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> drawn, best;
  std::vector<uint64_t> best_counts;
  Score best_score;
  for (int i = 0; i < options.ransac_iterations &&
                  (best.empty() || m.AggregateOf(best_counts) < options.ransac_stop_coverage);
       ++i) {
    detail::RansacDraw(options.seed, static_cast<uint64_t>(i), n, &order, &drawn);
    std::vector<uint64_t> counts = m.CountsOfSet(drawn);
    const Score score = m.ScoreOf(counts);
    if (best.empty() || score > best_score) {
      best = drawn;
      best_counts = std::move(counts);
      best_score = score;
    }
  }
  return best;
}

/// 1-swap local search from `start`: each round applies the best strictly improving swap
/// (position ascending, then candidate ascending, first best kept) until none improves.
std::vector<uint32_t> LocalChoice(const StackedMatrix& m, std::vector<uint32_t> chosen) {
  std::vector<uint64_t> counts(m.state_count());
  Score current = m.ScoreOfSet(chosen);
  constexpr int kMaxRounds = 100'000;  // each round strictly improves; a guard only
  for (int round = 0; round < kMaxRounds; ++round) {
    std::vector<bool> taken(m.candidate_count(), false);
    for (const uint32_t c : chosen) taken[c] = true;
    Score best = current;
    ptrdiff_t best_position = -1;
    uint32_t best_candidate = 0;
    for (size_t i = 0; i < chosen.size(); ++i) {
      const std::vector<Bitset> rest = m.Union(chosen, static_cast<ptrdiff_t>(i));
      for (uint32_t c = 0; c < m.candidate_count(); ++c) {
        if (taken[c]) continue;
        m.CountsWith(rest, c, counts.data());
        const Score score = m.ScoreOf(counts);
        if (score > best) {
          best = score;
          best_position = static_cast<ptrdiff_t>(i);
          best_candidate = c;
        }
      }
    }
    if (best_position < 0) break;
    chosen[static_cast<size_t>(best_position)] = best_candidate;
    current = best;
  }
  return chosen;
}

double Aggregate(const std::vector<double>& values, OverStates over) {
  if (over == OverStates::kMin) return *std::min_element(values.begin(), values.end());
  double sum = 0;
  for (const double v : values) sum += v;  // state order: the same every time
  return sum / static_cast<double>(values.size());
}

StateSelection Scored(std::span<const StateObservations> states,
                      OverStates over,
                      Method method,
                      std::vector<uint32_t> chosen,
                      double seconds) {
  StateSelection result;
  for (const StateObservations& state : states) {
    const CoverageEvaluator evaluator(state.observations, state.reference_size);
    result.state_coverage.push_back(evaluator.Coverage(chosen));
    result.state_paper_coverage.push_back(evaluator.PaperCoverage(chosen));
  }
  Selection& s = result.selection;
  s.method = MethodName(method);
  s.n = static_cast<int>(chosen.size());
  s.chosen = std::move(chosen);
  s.coverage = Aggregate(result.state_coverage, over);
  s.paper_coverage = Aggregate(result.state_paper_coverage, over);
  s.seconds = seconds;
  s.objective = ObjectiveName(Objective::kCoverage);
  return result;
}

void Validate(std::span<const StateObservations> states, const SelectOptions& options) {
  if (options.method == Method::kExact) {
    throw InputError(fmt::format("method '{}' is not available with --over-states — use best, "
                                 "ransac, greedy, local or all",
                                 MethodName(options.method)));
  }
  const Objective objective = options.objective();
  if (objective != Objective::kCoverage) {
    throw InputError(fmt::format("the {} objective (--goal, --k, --budget) is not available with "
                                 "--over-states — states maximise coverage; drop one of them",
                                 ObjectiveName(objective)));
  }
  if (states.empty()) throw InputError("--over-states: there are no states to select over");
  const size_t candidates = states.front().observations.size();
  for (const StateObservations& state : states) {
    if (state.observations.size() != candidates) {
      throw InputError(fmt::format("--over-states: state '{}' has {} observations but state '{}' "
                                   "has {} — every state needs one per candidate",
                                   state.name, state.observations.size(),
                                   states.front().name, candidates));
    }
    if (state.reference_size == 0) {
      throw InputError(fmt::format("--over-states: state '{}' has an empty reference set (no "
                                   "target surface)",
                                   state.name));
    }
  }
  options.Validate(candidates);
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

std::vector<StateSelection> SelectOverStates(std::span<const StateObservations> states,
                                             OverStates over,
                                             const SelectOptions& options) {
  Validate(states, options);
  const Clock::time_point start = Clock::now();
  const StackedMatrix matrix(states, over);
  const double setup = SecondsSince(start);
  std::vector<StateSelection> results;

  const auto best = [&] {
    const Clock::time_point t = Clock::now();
    StateSelection s = Scored(states, over, Method::kBest, GreedyChoice(matrix, 1),
                              setup + SecondsSince(t));
    // The best single candidate is the optimum for n = 1.
    s.selection.upper_bound = s.selection.coverage;
    s.selection.proven_optimal = true;
    return s;
  };
  const auto greedy_and_local = [&](size_t n, bool greedy, bool local) {
    const Clock::time_point t = Clock::now();
    std::vector<uint32_t> chosen = GreedyChoice(matrix, n);
    const double greedy_seconds = setup + SecondsSince(t);
    if (greedy) results.push_back(Scored(states, over, Method::kGreedy, chosen, greedy_seconds));
    if (local) {
      const Clock::time_point l = Clock::now();
      std::vector<uint32_t> improved = LocalChoice(matrix, std::move(chosen));
      results.push_back(Scored(states, over, Method::kLocal, std::move(improved),
                               greedy_seconds + SecondsSince(l)));
    }
  };
  const auto ransac = [&](size_t k) {
    const Clock::time_point t = Clock::now();
    std::vector<uint32_t> chosen = RansacChoice(matrix, k, options);
    return Scored(states, over, Method::kRansac, std::move(chosen), setup + SecondsSince(t));
  };
  const auto n = static_cast<size_t>(options.n);
  switch (options.method) {
    case Method::kBest:
      results.push_back(best());
      break;
    case Method::kGreedy:
      greedy_and_local(n, true, false);
      break;
    case Method::kLocal:
      greedy_and_local(n, false, true);
      break;
    case Method::kRansac:
      results.push_back(ransac(n));
      break;
    case Method::kAll:
      results.push_back(best());
      for (size_t k = 1; k <= n; ++k) {
        results.push_back(ransac(k));
        greedy_and_local(k, true, true);
      }
      break;
    case Method::kExact:
      VANTAGE_CHECK(false);  // rejected by Validate
  }
  return results;
}

}  // namespace vantage
