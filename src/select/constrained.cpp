// Selection under installation constraints (docs/constraints.md): feasibility of a set, and
// greedy, local search and RANSAC restricted to feasible sets; the MILP is exact_constrained.cpp.
#include "select/constrained.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

using Clock = std::chrono::steady_clock;

// As Select's "all" (select.cpp): exact for every n only up to this many candidates, each run
// limited to the smaller of the time limit and these seconds.

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::shared_ptr<spdlog::logger> Logger() {
  auto logger = spdlog::get("vantage");
  return logger ? logger : spdlog::default_logger();
}

bool SortedHas(const std::vector<uint32_t>& sorted, uint32_t value) {
  return std::binary_search(sorted.begin(), sorted.end(), value);
}

}  // namespace

Feasibility::Feasibility(std::span<const Observation> observations,
                         const InstallConstraints& constraints)
    : conflicts_(constraints.conflicts),
      conflicts_of_(observations.size()),
      neighbours_(observations.size()),
      has_calibration_(constraints.calibration.has_value()) {
  for (const Conflict& c : conflicts_) {
    conflicts_of_[c.a].push_back(c.b);
    conflicts_of_[c.b].push_back(c.a);
  }
  for (std::vector<uint32_t>& list : conflicts_of_) std::sort(list.begin(), list.end());
  if (!has_calibration_) return;
  std::vector<uint32_t> all(observations.size());
  std::iota(all.begin(), all.end(), 0U);
  for (const OverlapEdge& e : OverlapGraph(observations, all, constraints.calibration)) {
    neighbours_[e.a].push_back(e.b);
    neighbours_[e.b].push_back(e.a);
  }
  for (std::vector<uint32_t>& list : neighbours_) std::sort(list.begin(), list.end());
}

bool Feasibility::InConflict(uint32_t a, uint32_t b) const { return SortedHas(conflicts_of_[a], b); }

bool Feasibility::Joined(uint32_t a, uint32_t b) const { return SortedHas(neighbours_[a], b); }

bool Feasibility::CanAdd(std::span<const uint32_t> set, uint32_t candidate) const {
  bool is_joined = !has_calibration_ || set.empty();
  for (const uint32_t s : set) {
    if (s == candidate || InConflict(s, candidate)) return false;
    if (!is_joined && Joined(s, candidate)) is_joined = true;
  }
  return is_joined;
}

bool Feasibility::IsConnected(std::span<const uint32_t> set) const {
  if (set.size() <= 1) return true;
  std::vector<bool> reached(set.size(), false);
  std::vector<size_t> stack{0};
  reached[0] = true;
  size_t count = 1;
  while (!stack.empty()) {
    const size_t p = stack.back();
    stack.pop_back();
    for (size_t q = 0; q < set.size(); ++q) {
      if (!reached[q] && Joined(set[p], set[q])) {
        reached[q] = true;
        ++count;
        stack.push_back(q);
      }
    }
  }
  return count == set.size();
}

bool Feasibility::IsFeasible(std::span<const uint32_t> set) const {
  for (size_t p = 0; p < set.size(); ++p) {
    for (size_t q = p + 1; q < set.size(); ++q) {
      if (set[p] == set[q] || InConflict(set[p], set[q])) return false;
    }
  }
  return !has_calibration_ || IsConnected(set);
}

std::vector<uint32_t> ConstrainedGreedy(const CoverageMatrix& matrix, const Feasibility& feasible,
                                        size_t n) {
  std::vector<uint32_t> chosen;
  Bitset covered = matrix.EmptySet();
  while (chosen.size() < n) {
    ThrowIfInterrupted();
    int64_t best = -1;
    uint64_t best_gain = 0;
    for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
      if (!feasible.CanAdd(chosen, c)) continue;
      const uint64_t gain = matrix.Gain(c, covered);
      if (best < 0 || gain > best_gain) {
        best = c;
        best_gain = gain;
      }
    }
    if (best < 0) break;  // nothing fits any more
    chosen.push_back(static_cast<uint32_t>(best));
    matrix.AddTo(static_cast<uint32_t>(best), &covered);
  }
  return chosen;
}

std::vector<uint32_t> ConstrainedLocal(const CoverageMatrix& matrix, const Feasibility& feasible,
                                       std::vector<uint32_t> chosen, size_t n) {
  VANTAGE_CHECK(feasible.IsFeasible(chosen) && chosen.size() <= n);
  uint64_t current = matrix.CoveredWeight(chosen);
  std::vector<uint32_t> trial;
  for (;;) {
    ThrowIfInterrupted();
    // The best move of this pass: position p replaced by c (p = size: c added).
    uint64_t best = current;
    size_t best_p = 0;
    int64_t best_c = -1;
    for (size_t p = 0; p <= chosen.size(); ++p) {
      if (p == chosen.size() && chosen.size() >= n) break;
      std::vector<uint32_t> others = chosen;
      if (p < chosen.size()) others.erase(others.begin() + static_cast<std::ptrdiff_t>(p));
      Bitset covered = matrix.EmptySet();
      for (const uint32_t o : others) matrix.AddTo(o, &covered);
      const uint64_t base = matrix.SetWeight(covered);
      for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
        if (std::find(chosen.begin(), chosen.end(), c) != chosen.end()) continue;
        const uint64_t cells = base + matrix.Gain(c, covered);
        if (cells <= best) continue;
        trial = others;
        trial.push_back(c);
        if (!feasible.IsFeasible(trial)) continue;
        best = cells;
        best_p = p;
        best_c = c;
      }
    }
    if (best_c < 0) return chosen;
    if (best_p == chosen.size()) {
      chosen.push_back(static_cast<uint32_t>(best_c));
    } else {
      chosen[best_p] = static_cast<uint32_t>(best_c);
    }
    current = best;
  }
}

std::vector<uint32_t> ConstrainedRansac(const CoverageMatrix& matrix, const Feasibility& feasible,
                                        size_t n, int iterations, double stop_coverage,
                                        uint64_t seed) {
  const size_t m = matrix.candidate_count();
  std::vector<uint32_t> order(m);
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best, drawn(n);
  uint64_t best_cells = 0;
  const double total = static_cast<double>(std::max<size_t>(matrix.reference_size(), 1));
  for (int i = 0; i < iterations; ++i) {
    if (!best.empty() && static_cast<double>(best_cells) / total >= stop_coverage) break;
    if (i % 64 == 0) ThrowIfInterrupted();
    RansacDraw(seed, static_cast<uint64_t>(i), n, &order, &drawn);
    if (!feasible.IsFeasible(drawn)) continue;  // rejected draw
    const uint64_t cells = matrix.CoveredWeight(drawn);
    if (best.empty() || cells > best_cells) {
      best = drawn;
      best_cells = cells;
    }
  }
  return best;
}

namespace {

// The methods for one n, each built on the one before as Select's Pipeline does (local from
// greedy's answer, exact warm-started from local's), seconds including the steps each needed.
class ConstrainedPipeline {
 public:
  ConstrainedPipeline(const CoverageEvaluator& evaluator, const CoverageMatrix& matrix,
                      const Feasibility& feasible, const SelectOptions& options,
                      double setup_seconds)
      : evaluator_(evaluator),
        matrix_(matrix),
        feasible_(feasible),
        options_(options),
        setup_seconds_(setup_seconds) {}

  Selection Ransac(size_t n) {
    const Clock::time_point start = Clock::now();
    std::vector<uint32_t> chosen =
        ConstrainedRansac(matrix_, feasible_, n, options_.ransac_iterations,
                          options_.ransac_stop_coverage, options_.seed);
    if (chosen.empty()) {
      Logger()->warn(
          "ransac, n = {}: none of its {} draws satisfies the constraints; reporting the "
          "constrained greedy answer",
          n, options_.ransac_iterations);
      chosen = ConstrainedGreedy(matrix_, feasible_, n);
    }
    return Scored(Method::kRansac, std::move(chosen), setup_seconds_ + SecondsSince(start));
  }

  Selection Greedy(size_t n) {
    const Clock::time_point start = Clock::now();
    n_ = n;
    greedy_ = ConstrainedGreedy(matrix_, feasible_, n);
    if (greedy_.size() < n) {
      Logger()->warn("greedy, n = {}: only {} sensors satisfy the constraints together", n,
                     greedy_.size());
    }
    greedy_seconds_ = setup_seconds_ + SecondsSince(start);
    local_ = greedy_;
    local_seconds_ = greedy_seconds_;
    return Scored(Method::kGreedy, greedy_, greedy_seconds_);
  }

  /// After Greedy(n). The unconstrained local search's answer too, when it is feasible and covers
  /// more (constraints that do not bind then change nothing).
  Selection Local() {
    const Clock::time_point start = Clock::now();
    local_ = ConstrainedLocal(matrix_, feasible_, greedy_, n_);
    free_local_.clear();
    if (n_ <= matrix_.candidate_count()) {
      free_local_ = LocalSearch(CellScorer(matrix_), GreedyComplete(CellScorer(matrix_), {}, n_));
      if (feasible_.IsFeasible(free_local_) &&
          matrix_.CoveredWeight(free_local_) > matrix_.CoveredWeight(local_))
        local_ = free_local_;
    }
    local_seconds_ = greedy_seconds_ + SecondsSince(start);
    return Scored(Method::kLocal, local_, local_seconds_);
  }

  /// After Local() (or Greedy).
  Selection Exact(double time_limit) const {
    const Clock::time_point start = Clock::now();
    ExactResult exact;
    bool solved = false;
    if (free_local_.size() == n_) {
      // The unconstrained optimum (half the time): when it is feasible it is the constrained one,
      // proof included; else its bound still bounds the constrained optimum.
      ExactResult free = SolveExact(matrix_, n_, free_local_, 0.5 * time_limit);
      if (feasible_.IsFeasible(free.chosen) &&
          matrix_.CoveredWeight(free.chosen) >= matrix_.CoveredWeight(local_)) {
        exact = std::move(free);
        solved = true;
      } else {
        exact = SolveExactConstrained(matrix_, feasible_, n_, local_,
                                      std::max(0.1, time_limit - SecondsSince(start)));
        const uint64_t cells = matrix_.CoveredWeight(exact.chosen);
        exact.upper_bound = std::max(cells, std::min(exact.upper_bound, free.upper_bound));
        exact.proven_optimal = exact.upper_bound == cells;
        solved = true;
      }
    }
    if (!solved) exact = SolveExactConstrained(matrix_, feasible_, n_, local_, time_limit);
    if (!exact.proven_optimal && !exact.note.empty()) {
      Logger()->warn("exact, n = {} (constrained): {}; reporting the best answer found and a bound",
                     n_, exact.note);
    } else if (!exact.note.empty()) {
      Logger()->debug("exact, n = {} (constrained): {}", n_, exact.note);
    }
    Selection s = Scored(Method::kExact, exact.chosen, local_seconds_ + SecondsSince(start));
    const double reference = static_cast<double>(std::max<size_t>(matrix_.reference_size(), 1));
    s.upper_bound = std::max(static_cast<double>(exact.upper_bound) / reference, s.coverage);
    s.proven_optimal = exact.proven_optimal;
    return s;
  }

  Selection Scored(Method method, std::vector<uint32_t> chosen, double seconds) const {
    VANTAGE_CHECK(feasible_.IsFeasible(chosen));
    Selection s = ScoreSelection(evaluator_, std::move(chosen), MethodName(method), options_);
    s.seconds = seconds;
    return s;
  }

 private:
  const CoverageEvaluator& evaluator_;
  const CoverageMatrix& matrix_;
  const Feasibility& feasible_;
  const SelectOptions& options_;
  double setup_seconds_;
  size_t n_ = 0;
  std::vector<uint32_t> greedy_;
  std::vector<uint32_t> local_;
  std::vector<uint32_t> free_local_;  // unconstrained local search's answer for n_
  double greedy_seconds_ = 0;
  double local_seconds_ = 0;
};

}  // namespace

std::vector<Selection> SelectConstrained(std::span<const Observation> observations,
                                         size_t reference_size, const SelectOptions& options) {
  VANTAGE_CHECK(options.objective() == Objective::kCoverage && options.fixed.empty());
  const CoverageEvaluator evaluator(observations, reference_size);
  // One sensor alone breaks no constraint: best is the plain best single candidate.
  if (options.method == Method::kBest) return {SelectBest(evaluator)};
  const Clock::time_point start = Clock::now();
  const CoverageMatrix matrix(observations, reference_size);
  const Feasibility feasible(observations, options.constraints);
  const double setup_seconds = SecondsSince(start);
  ConstrainedPipeline pipeline(evaluator, matrix, feasible, options, setup_seconds);
  const auto n = static_cast<size_t>(options.n);
  switch (options.method) {
    case Method::kRansac:
      return {pipeline.Ransac(n)};
    case Method::kGreedy:
      return {pipeline.Greedy(n)};
    case Method::kLocal:
      pipeline.Greedy(n);
      return {pipeline.Local()};
    case Method::kExact:
      pipeline.Greedy(n);
      pipeline.Local();
      return {pipeline.Exact(options.time_limit)};
    case Method::kBest:
    case Method::kAll:
      break;
  }
  std::vector<Selection> results{SelectBest(evaluator)};
  // Shared as for plain selection (select.cpp), so `help optimize`'s time rule holds here too.
  AllExactTime exact_time(observations.size(), options.time_limit, static_cast<int>(n));
  for (size_t k = 1; k <= n; ++k) {
    results.push_back(pipeline.Ransac(k));
    results.push_back(pipeline.Greedy(k));
    results.push_back(pipeline.Local());
    if (!exact_time.runs()) continue;
    const Clock::time_point exact_start = Clock::now();
    results.push_back(pipeline.Exact(exact_time.Share(static_cast<int>(k))));
    exact_time.Spend(SecondsSince(exact_start));
  }
  return results;
}

std::vector<Selection> ConstrainedCurve(std::span<const Observation> observations,
                                        size_t reference_size, const SelectOptions& options,
                                        const std::vector<Selection>& results, int last_n) {
  const auto has = [&](const std::string& method, int n) {
    return std::any_of(results.begin(), results.end(),
                       [&](const Selection& s) { return s.method == method && s.n == n; });
  };
  const CoverageEvaluator evaluator(observations, reference_size);
  const CoverageMatrix matrix(observations, reference_size);
  const Feasibility feasible(observations, options.constraints);
  ConstrainedPipeline pipeline(evaluator, matrix, feasible, options, 0);
  const std::string greedy = MethodName(Method::kGreedy), local = MethodName(Method::kLocal);
  std::vector<Selection> curve;
  for (int n = 1; n <= last_n; ++n) {
    const bool want_greedy = !has(greedy, n), want_local = !has(local, n);
    if (!want_greedy && !want_local) continue;
    Selection g = pipeline.Greedy(static_cast<size_t>(n));
    if (want_greedy) curve.push_back(std::move(g));
    if (want_local) curve.push_back(pipeline.Local());
  }
  return curve;
}

}  // namespace vantage::detail
