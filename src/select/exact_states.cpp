// Exact selection over the states of a scene (issue 14; objective_bounds.hpp, SolveExactStates).
//
// On the stacked matrix (an element belongs to one state s, weight w_e cells of R_s), with
// x_i = candidate i chosen and y_e = element e covered:
//
//   mean:  max sum_e w_e / (S |R_s(e)|) y_e
//   min:   max t  s.t.  t <= sum_{e in s} w_e / |R_s| y_e  for every state s
//   both:  y_e <= sum_{i sees e} x_i,  sum_i x_i <= n,  x binary, y and t in [0, 1].
//
// Dominated candidates are dropped and elements seen by one kept candidate fold into its column
// (as exact.cpp does for one state); CBC solves it in a child process within the time limit. The
// bound when it cannot finish is the Lagrangian of a weighted coverage LP (objective_bounds.cpp)
// with integer weights rounded up from G a_s w_e / |R_s|: for any a >= 0 with sum_s a_s >= 1,
// min_s f_s <= sum_s a_s f_s (and the mean is a = 1/S), so the bound over G is a bound on the
// aggregate whatever a is; for min, several a are tried (exponentiated-gradient steps away from
// the states the relaxation favours).
#include <coin/Cbc_C_Interface.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>

#include "select/cbc_answer.hpp"
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


// CBC's result as the child process reports it: its bound, whether it proved, and the x values.
struct StatesCbcAnswer {
  double bound = std::numeric_limits<double>::quiet_NaN();
  bool proven_optimal = false;
  bool has_solution = false;
  std::vector<uint32_t> chosen;  // x columns at 1
};

// The child's answer (cbc_answer.hpp) as this file uses it.
StatesCbcAnswer ToStatesAnswer(const CbcAnswer& decoded) {
  StatesCbcAnswer answer;
  answer.bound = decoded.bound;
  answer.proven_optimal = decoded.proven_optimal;
  answer.has_solution = decoded.has_solution;
  for (const int q : decoded.chosen_columns) answer.chosen.push_back(static_cast<uint32_t>(q));
  return answer;
}

// The MILP of the top of this file, warm-started from `start`; nullopt (with `note`) when it is
// too large for the time limit or CBC does not answer.
std::optional<StatesCbcAnswer> RunStatesCbc(const CoverageMatrix& matrix,
                                            OverStates over,
                                            size_t n,
                                            const std::vector<uint32_t>& start,
                                            double time_limit,
                                            std::string* note) {
  const auto m = static_cast<int>(matrix.candidate_count());
  const auto elements = static_cast<int>(matrix.element_count());
  const auto states = static_cast<int>(matrix.state_count());
  const bool by_min = over == OverStates::kMin;
  // Element values w_e / |R_s| (min) or that over S (mean).
  std::vector<double> value(elements);
  for (int s = 0; s < states; ++s) {
    const double unit = 1.0 / static_cast<double>(matrix.StateReferenceSize(s)) /
                        (by_min ? 1.0 : static_cast<double>(states));
    for (uint32_t e = matrix.StateBegin(s); e < matrix.StateBegin(s + 1); ++e)
      value[e] = matrix.Weight(e) * unit;
  }
  // CBC's objective in about cells of the largest state (its tolerances suit magnitudes >= 1).
  size_t largest = 1;
  for (int s = 0; s < states; ++s) largest = std::max(largest, matrix.StateReferenceSize(s));
  const double objective_scale = static_cast<double>(largest) * (by_min ? 1.0 : states);
  // Reduction (as for plain coverage, exact.cpp): a candidate whose stacked row is inside
  // another's (strictly, or equal at a higher index) is dominated — every state's coverage is
  // monotone, so dropping them keeps an optimum of "at most n" for both aggregates — and an
  // element seen by one kept candidate folds into that candidate's column.
  std::vector<std::vector<uint32_t>> seers(elements);
  for (int i = 0; i < m; ++i) {
    for (const uint32_t e : matrix.Row(static_cast<uint32_t>(i))) seers[e].push_back(i);
  }
  std::vector<int> dominator(m, -1);  // -1: kept
  for (int i = 0; i < m; ++i) {
    const std::vector<uint32_t>& row = matrix.Row(static_cast<uint32_t>(i));
    if (row.empty()) {
      dominator[i] = m;  // sees nothing: never needed
      continue;
    }
    const uint32_t rarest = *std::min_element(row.begin(), row.end(), [&](uint32_t a, uint32_t b) {
      return seers[a].size() < seers[b].size();
    });
    for (const uint32_t j : seers[rarest]) {
      const size_t size_j = matrix.Row(j).size();
      if (static_cast<int>(j) == i || size_j < row.size()) continue;
      if ((size_j > row.size() || static_cast<int>(j) < i) &&
          matrix.IsSubset(static_cast<uint32_t>(i), j)) {
        dominator[i] = static_cast<int>(j);
        break;
      }
    }
  }
  std::vector<uint32_t> kept;
  std::vector<int> column_of(m, -1);
  for (int i = 0; i < m; ++i) {
    if (dominator[i] >= 0) continue;
    column_of[i] = static_cast<int>(kept.size());
    kept.push_back(static_cast<uint32_t>(i));
  }
  if (kept.size() <= n) {  // all kept candidates fit: nothing covers more
    StatesCbcAnswer answer;
    answer.proven_optimal = answer.has_solution = true;
    answer.chosen = kept;
    return answer;
  }
  std::vector<int> kept_seers(elements, 0), y_of(elements, -1);
  int y_count = 0;
  for (int e = 0; e < elements; ++e) {
    for (const uint32_t i : seers[e]) kept_seers[e] += column_of[i] >= 0 ? 1 : 0;
    if (kept_seers[e] >= 2) y_of[e] = y_count++;
  }
  std::vector<int> state_of(elements);
  for (int st = 0; st < states; ++st) {
    for (uint32_t e = matrix.StateBegin(st); e < matrix.StateBegin(st + 1); ++e) state_of[e] = st;
  }
  // Columns: x (kept), y (elements seen by >= 2 kept), t (min). Rows: coupling (y), cardinality,
  // states (min).
  const auto x_count = static_cast<int>(kept.size());
  const int columns = x_count + y_count + (by_min ? 1 : 0);
  const int rows = y_count + 1 + (by_min ? states : 0);
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> indices;
  std::vector<double> coefficients;
  std::vector<double> objective(columns, 0.0);
  for (int q = 0; q < x_count; ++q) {
    std::vector<double> own(states, 0.0);  // folded elements, per state
    for (const uint32_t e : matrix.Row(kept[q])) {
      if (y_of[e] >= 0) {
        indices.push_back(y_of[e]);
        coefficients.push_back(-1.0);
      } else {
        own[state_of[e]] += value[e];
      }
    }
    indices.push_back(y_count);
    coefficients.push_back(1.0);
    for (int st = 0; st < states; ++st) {
      if (own[st] == 0) continue;
      if (by_min) {
        indices.push_back(y_count + 1 + st);
        coefficients.push_back(-own[st]);
      } else {
        objective[q] += own[st] * objective_scale;
      }
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
  }
  for (int e = 0; e < elements; ++e) {
    if (y_of[e] < 0) continue;
    indices.push_back(y_of[e]);
    coefficients.push_back(1.0);
    if (by_min) {
      indices.push_back(y_count + 1 + state_of[e]);
      coefficients.push_back(-value[e]);
    } else {
      objective[x_count + y_of[e]] = value[e] * objective_scale;
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
  }
  if (by_min) {
    for (int st = 0; st < states; ++st) {
      indices.push_back(y_count + 1 + st);
      coefficients.push_back(1.0);
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective[columns - 1] = objective_scale;
  }
  const double max_nonzeros = CbcMaxNonzeros(time_limit);
  if (static_cast<double>(indices.size()) > max_nonzeros) {
    *note = fmt::format(
        "MILP over states with {} nonzeros is too large for a {:.3g} s time limit (at most "
        "{:.0f}); CBC not run",
        indices.size(), time_limit, max_nonzeros);
    return std::nullopt;
  }
  const std::vector<double> column_lower(columns, 0.0), column_upper(columns, 1.0);
  std::vector<double> row_lower(rows, -std::numeric_limits<double>::max());
  std::vector<double> row_upper(rows, 0.0);
  row_upper[y_count] = static_cast<double>(n);

  const CbcModelPtr model(Cbc_newModel());
  if (!model) {
    *note = "CBC could not create a model";
    return std::nullopt;
  }
  Cbc_Model* cbc = model.get();
  Cbc_loadProblem(cbc, columns, rows, starts.data(), indices.data(), coefficients.data(),
                  column_lower.data(), column_upper.data(), objective.data(), row_lower.data(),
                  row_upper.data());
  for (int q = 0; q < x_count; ++q) Cbc_setInteger(cbc, q);
  Cbc_setObjSense(cbc, -1);
  Cbc_setLogLevel(cbc, 0);
  Cbc_setParameter(cbc, "timeMode", "elapsed");
  Cbc_setMaximumSeconds(cbc, kCbcTimeShare * time_limit);
  // Aggregates are fractions with no common grain worth relying on: prove to round-off only.
  Cbc_setAllowableGap(cbc, 1e-10 * objective_scale);
  Cbc_setAllowableFractionGap(cbc, 0.0);
  // Warm start on every column (CBC completes a partial one by an LP that ignores its limit):
  // the start, each dominated sensor replaced by a kept one that sees all it sees.
  std::vector<double> start_values(columns, 0.0);
  Bitset covered = matrix.EmptySet();
  for (uint32_t c : start) {
    while (dominator[c] >= 0 && dominator[c] < m) c = static_cast<uint32_t>(dominator[c]);
    if (column_of[c] < 0) continue;
    start_values[column_of[c]] = 1.0;
    matrix.AddTo(c, &covered);
  }
  std::vector<double> state_value(states, 0.0);
  for (int e = 0; e < elements; ++e) {
    if (!Contains(covered, static_cast<uint32_t>(e))) continue;
    if (y_of[e] >= 0) start_values[x_count + y_of[e]] = 1.0;
    state_value[state_of[e]] += value[e];
  }
  if (by_min) start_values[columns - 1] = *std::min_element(state_value.begin(), state_value.end());
  std::vector<int> start_columns(columns);
  for (int q = 0; q < columns; ++q) start_columns[q] = q;
  Cbc_setMIPStartI(cbc, columns, start_columns.data(), start_values.data());

  const std::optional<CbcAnswer> solved =
      SolveInChild(cbc, x_count, kCbcKillShare * time_limit, note);
  if (!solved) return std::nullopt;
  StatesCbcAnswer answer = ToStatesAnswer(*solved);
  for (uint32_t& c : answer.chosen) c = kept[c];
  answer.bound /= objective_scale;
  if (!answer.proven_optimal) *note = "not proved optimal: CBC stopped at its time limit";
  return answer;
}

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
  const std::optional<StatesCbcAnswer> answer =
      RunStatesCbc(matrix, over, n, start, time_limit - SecondsSince(begin), &result.note);
  if (answer) {
    if (std::isfinite(answer->bound)) cbc_bound = answer->bound;
    if (answer->has_solution && answer->chosen.size() <= n) {
      std::vector<uint32_t> padded = GreedyComplete(scorer, answer->chosen, n);
      const StatesScorer::Score padded_score = scorer.ScoreOf(scorer.Covered(padded));
      if (score < padded_score) {
        result.chosen = std::move(padded);
        score = padded_score;
      }
      // CBC's optimum is no better than what we hold: its proof covers our answer.
      cbc_proved = answer->proven_optimal;
    }
  }
  const double aggregate = scorer.Fraction(scorer.Covered(result.chosen));
  bound = std::min(bound, cbc_proved ? aggregate : cbc_bound);
  if (!answer) {  // CBC did not run or failed: its time is left for the bound
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
