// Exact selection over the states of a scene (issue 14; objective_bounds.hpp, SolveExactStates).
//
// On the stacked matrix (an element belongs to one state s, weight w_e cells of R_s), with
// x_i = candidate i chosen and y_e = element e covered:
//
//   mean:  max sum_e w_e / (S |R_s(e)|) y_e
//   min:   max t  s.t.  t <= sum_{e in s} w_e / |R_s| y_e  for every state s
//   both:  y_e <= sum_{i sees e} x_i,  sum_i x_i <= n,  x binary, y and t in [0, 1].
//
// This is the selection MILP of milp.hpp with the mean or min value (its reductions: dominated
// candidates dropped, elements seen by one kept candidate folded into its column); CBC solves it
// in a child process within the time limit. The
// bound when it cannot finish is the Lagrangian of a weighted coverage LP (objective_bounds.cpp)
// with integer weights rounded up from G a_s w_e / |R_s|: for any a >= 0 with sum_s a_s >= 1,
// min_s f_s <= sum_s a_s f_s (and the mean is a = 1/S), so the bound over G is a bound on the
// aggregate whatever a is; for min, several a are tried (exponentiated-gradient steps away from
// the states the relaxation favours).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "select/cbc_answer.hpp"
#include "select/milp.hpp"
#include "select/methods.hpp"
#include "select/objective_bounds.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

using Clock = std::chrono::steady_clock;

// The bound's scale: aggregates (<= 1) in units of 2^-40; rounding each weight up costs at most
// one unit per element.
constexpr double kScale = 1099511627776.0;  // 2^40
// Min: state multipliers tried, and the first exponentiated-gradient rate (then decaying).
constexpr int kMinRounds = 8;
constexpr double kStartRate = 4.0;
constexpr double kRateDecay = 0.7;
// Share of the time limit for the bound tried before CBC.
constexpr double kFirstBoundShare = 0.1;
// An answer within this much of the bound (a fraction of R) is reported proven optimal.
constexpr double kProofTolerance = 1e-9;


// The Lagrangian bound on the aggregate (a fraction) for state multipliers a (sum >= 1 after
// normalising; see the top of this file), and the subproblem's chosen candidates.
struct StatesBound {
  double bound = std::numeric_limits<double>::infinity();
  std::vector<uint32_t> chosen;
};

StatesBound BoundForMultipliers(const CoverageMatrix& matrix,
                                const std::vector<double>& multipliers,
                                size_t n,
                                const std::vector<uint32_t>& start,
                                double seconds) {
  double total = 0;
  for (const double a : multipliers) total += a;
  CoverageLp lp = CardinalityLp(matrix, n);
  // Normalised, then nudged up so that round-off cannot leave the sum below 1.
  std::vector<long double> factor(multipliers.size());
  for (size_t s = 0; s < multipliers.size(); ++s) {
    factor[s] = static_cast<long double>(multipliers[s]) / total * (1 + 1e-15L) *
                static_cast<long double>(kScale) /
                static_cast<long double>(matrix.StateReferenceSize(s));
  }
  Bitset covered = matrix.EmptySet();
  for (const uint32_t c : start) matrix.AddTo(c, &covered);
  uint64_t target = 0;
  for (size_t s = 0; s < multipliers.size(); ++s) {
    for (uint32_t e = matrix.StateBegin(s); e < matrix.StateBegin(s + 1); ++e) {
      // Each long double step errs by at most 2^-64 relative: 2^-60 more rounds up for sure.
      const long double w = factor[s] * matrix.Weight(e) * (1 + std::ldexp(1.0L, -60));
      lp.weights[e] = static_cast<uint64_t>(std::ceil(w));
      if (Contains(covered, e)) target += lp.weights[e];
    }
  }
  StatesBound result;
  const int steps = LpBoundSteps(matrix, seconds);
  if (steps == 0) return result;
  const CoverageLpBound bound = BoundCoverageLp(lp, target, steps, seconds);
  result.bound = static_cast<double>(bound.upper_bound) / kScale;
  result.chosen = bound.chosen;
  return result;
}

}  // namespace

double StatesLagrangianBound(const CoverageMatrix& matrix,
                             OverStates over,
                             size_t n,
                             const std::vector<uint32_t>& start,
                             double seconds) {
  const Clock::time_point begin = Clock::now();
  const size_t states = matrix.state_count();
  std::vector<double> multipliers(states, 1.0);
  const int rounds = over == OverStates::kMin && states > 1 ? kMinRounds : 1;
  double best = std::numeric_limits<double>::infinity();
  double rate = kStartRate;
  for (int round = 0; round < rounds; ++round) {
    const double left = (seconds - SecondsSince(begin)) / (rounds - round);
    const StatesBound bound = BoundForMultipliers(matrix, multipliers, n, start, left);
    best = std::min(best, bound.bound);
    if (bound.chosen.empty()) break;
    // Exponentiated gradient on a: d bound / d a_s is (about) the share of state s the
    // subproblem's answer covers; weight moves towards the states it covers least.
    Bitset covered = matrix.EmptySet();
    for (const uint32_t c : bound.chosen) matrix.AddTo(c, &covered);
    std::vector<double> share(states, 0.0);
    for (size_t s = 0; s < states; ++s) {
      uint64_t cells = 0;
      for (uint32_t e = matrix.StateBegin(s); e < matrix.StateBegin(s + 1); ++e)
        if (Contains(covered, e)) cells += matrix.Weight(e);
      share[s] = static_cast<double>(cells) / static_cast<double>(matrix.StateReferenceSize(s));
    }
    const double spread = *std::max_element(share.begin(), share.end()) -
                          *std::min_element(share.begin(), share.end());
    if (!(spread > 0)) break;
    double total = 0;
    for (size_t s = 0; s < states; ++s) {
      multipliers[s] *= std::exp(-rate * (share[s] - share.front()) / spread);
      total += multipliers[s];
    }
    for (double& a : multipliers) a /= total;
    rate *= kRateDecay;
  }
  return best;
}

StatesExactResult SolveExactStates(const CoverageMatrix& matrix,
                                   OverStates over,
                                   size_t n,
                                   const std::vector<uint32_t>& start,
                                   double time_limit) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count() && start.size() == n);
  const Clock::time_point begin = Clock::now();
  const StatesScorer scorer(matrix, over);
  StatesExactResult result;
  result.chosen = start;
  StatesScorer::Score score = scorer.ScoreOf(scorer.Covered(start));
  if (n == 1) {  // the best single candidate is the optimum
    result.chosen = {BestCandidate(scorer)};
    result.upper_bound = scorer.Fraction(scorer.Covered(result.chosen));
    result.proven_optimal = true;
    return result;
  }
  // A first bound in a small share of the time: when it proves the start, CBC is not needed.
  double bound = StatesLagrangianBound(matrix, over, n, start, kFirstBoundShare * time_limit);
  const double start_aggregate = scorer.Fraction(scorer.Covered(start));
  if (bound - start_aggregate <= kProofTolerance) {
    result.upper_bound = start_aggregate;
    result.proven_optimal = true;
    return result;
  }
  double cbc_bound = std::numeric_limits<double>::infinity();
  bool cbc_proved = false;
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.value = over == OverStates::kMin ? MilpValue::kMin : MilpValue::kMean;
  milp.capacity = static_cast<double>(n);
  const MilpAnswer answer = SolveSelectionMilp(milp, start, time_limit - SecondsSince(begin));
  result.note = answer.note;
  const bool cbc_ran = answer.proven_optimal || !answer.chosen.empty() ||
                       std::isfinite(answer.bound);
  if (std::isfinite(answer.bound)) cbc_bound = answer.bound;
  if (!answer.chosen.empty() && answer.chosen.size() <= n) {
    std::vector<uint32_t> padded = GreedyComplete(scorer, answer.chosen, n);
    const StatesScorer::Score padded_score = scorer.ScoreOf(scorer.Covered(padded));
    if (score < padded_score) {
      result.chosen = std::move(padded);
      score = padded_score;
    }
    // CBC's optimum is no better than what we hold: its proof covers our answer.
    cbc_proved = answer.proven_optimal;
  }
  const double aggregate = scorer.Fraction(scorer.Covered(result.chosen));
  bound = std::min(bound, cbc_proved ? aggregate : cbc_bound);
  if (!cbc_ran) {  // CBC did not run or failed: its time is left for the bound
    const double left = kCbcKillShare * (time_limit - SecondsSince(begin));
    bound = std::min(bound, StatesLagrangianBound(matrix, over, n, result.chosen, left));
  }
  if (!std::isfinite(bound)) {  // no time for anything: every candidate together bounds it
    std::vector<uint32_t> everyone(matrix.candidate_count());
    for (uint32_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
    bound = scorer.Fraction(scorer.Covered(everyone));
  }
  result.upper_bound = std::max(bound, aggregate);
  result.proven_optimal = cbc_proved || result.upper_bound - aggregate <= kProofTolerance;
  if (result.proven_optimal) {
    result.upper_bound = aggregate;
    result.note.clear();
  }
  return result;
}

}  // namespace vantage::detail
