// The Lagrangian bound of a weighted coverage LP (objective_bounds.hpp), for k-coverage, budget,
// set cover and selection over states (issue 14).
//
// The LP: max sum_e w_e y_e s.t. k y_e <= sum_{i sees e} x_i, x, y in [0, 1], plus a cardinality
// or a knapsack row on x. Relaxing the coverage rows with lambda_e = mu_e / k >= 0:
//
//   L(mu) = sum_e max(0, w_e - mu_e) + max_x sum_i x_i r_i / k,  r_i = sum_{e in row i} mu_e,
//
// an upper bound for every mu >= 0 (mu above w never helps, so mu stays in [0, w]). The max over
// x is the n largest r_i, or the fractional knapsack, whose LP dual gives, for any theta >= 0,
// theta B + sum_i max(0, r_i - theta c_i) >= it. Only L evaluated exactly is a proof: mu is
// truncated to fixed point and summed in 128-bit integers, the knapsack dual in long double with
// its worst-case round-off added.
//
// Over states (StatesLagrangianBound), on the stacked matrix (an element belongs to one state s,
// weight w_e cells of R_s): the same LP with integer weights rounded up from G a_s w_e / |R_s|.
// For any a >= 0 with sum_s a_s >= 1, min_s f_s <= sum_s a_s f_s (and the mean is a = 1/S), so
// the bound over G is a bound on the aggregate whatever a is; for min, several a are tried
// (exponentiated-gradient steps away from the states the relaxation favours).
#include "select/objective_bounds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "select/methods.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

__extension__ typedef unsigned __int128 Wide;

// Fixed-point bits of the multipliers in the exact evaluation (weights stay below 2^40, so a
// scaled weight fits in 64 bits and a row sum in 128).
constexpr int kFixedBits = 20;
// Polyak step scale: from kStartStepScale (methods.hpp, as maximum coverage's bound), halved
// after kPatience steps without a better bound; the search ends below kMinStepScale.
constexpr double kMinStepScale = 1e-6;
constexpr int kPatience = 25;
// Steps: as many as fit at this many row nonzeros per second, at most kMaxSteps, none when fewer
// than kMinSteps fit (the same pace as maximum coverage's bound, exact.cpp).
constexpr double kNonzerosPerSecond = 2e8;
constexpr double kMaxSteps = 1000;
constexpr double kMinSteps = 10;
// Shares of the time limit: the bound after a solver (the solver used the rest), set cover's
// lower bound (the rest settles the sensor counts above it).
constexpr double kTightenTimeShare = 0.9;
constexpr double kSetCoverTimeShare = 0.25;

// The candidates an answer may contain: all, or those within the budget.
std::vector<uint32_t> UsableCandidates(const CoverageLp& lp) {
  std::vector<uint32_t> usable;
  for (uint32_t i = 0; i < lp.matrix->candidate_count(); ++i) {
    if (lp.costs.empty() || lp.costs[i] <= lp.budget) usable.push_back(i);
  }
  return usable;
}

// The fractional knapsack of values r (>= 0) over `usable` within the budget: x (per candidate,
// 0 outside `usable`) and the critical ratio theta (0 when everything fits), at which the dual
// theta B + sum max(0, r_i - theta c_i) equals the knapsack LP.
long double FractionalKnapsack(std::span<const long double> r,
                               const CoverageLp& lp,
                               std::span<const uint32_t> usable,
                               std::vector<double>* x) {
  std::vector<uint32_t> order(usable.begin(), usable.end());
  // By r / c, largest first (free ones first of all), compared without dividing; ties: index.
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const long double left = r[a] * lp.costs[b];
    const long double right = r[b] * lp.costs[a];
    return left != right ? left > right : a < b;
  });
  x->assign(lp.matrix->candidate_count(), 0.0);
  double left = lp.budget;
  for (const uint32_t i : order) {
    if (r[i] <= 0) break;
    if (lp.costs[i] <= left) {
      (*x)[i] = 1.0;
      left -= lp.costs[i];
      continue;
    }
    (*x)[i] = left / lp.costs[i];
    return r[i] / lp.costs[i];
  }
  return 0;
}

// The weights the LP counts (an element seen by fewer than k usable candidates: none) and the
// usable seers of each element.
struct Prepared {
  std::vector<uint32_t> usable;
  std::vector<uint64_t> weights;
  std::vector<uint32_t> seers;
};

Prepared Prepare(const CoverageLp& lp) {
  const CoverageMatrix& matrix = *lp.matrix;
  Prepared p;
  p.usable = UsableCandidates(lp);
  p.seers.assign(matrix.element_count(), 0);
  for (const uint32_t i : p.usable) {
    for (const uint32_t e : matrix.Row(i)) ++p.seers[e];
  }
  p.weights = lp.weights;
  for (uint32_t e = 0; e < matrix.element_count(); ++e) {
    if (p.seers[e] < lp.k) p.weights[e] = 0;
  }
  return p;
}

// floor(L(mu)) exactly (see the top of this file).
uint64_t ExactValue(const CoverageLp& lp, const Prepared& p, std::span<const double> mu) {
  const CoverageMatrix& matrix = *lp.matrix;
  const auto scale = static_cast<double>(uint64_t{1} << kFixedBits);
  std::vector<uint64_t> fixed(matrix.element_count());
  Wide rest = 0;  // sum_e (w_e - mu_e), scaled
  for (uint32_t e = 0; e < matrix.element_count(); ++e) {
    const uint64_t w = p.weights[e] << kFixedBits;
    const double scaled = std::floor(mu[e] * scale);
    fixed[e] = !(scaled > 0)                      ? 0
               : scaled >= static_cast<double>(w) ? w
                                                  : static_cast<uint64_t>(scaled);
    rest += w - fixed[e];
  }
  std::vector<Wide> rows(matrix.candidate_count(), 0);
  for (const uint32_t i : p.usable) {
    for (const uint32_t e : matrix.Row(i)) rows[i] += fixed[e];
  }
  Wide chosen = 0;  // max_x sum_i x_i r_i, scaled (k times the x part of L)
  if (lp.costs.empty()) {
    std::vector<Wide> usable_rows;
    for (const uint32_t i : p.usable) usable_rows.push_back(rows[i]);
    const size_t n = std::min(lp.n, usable_rows.size());
    std::nth_element(usable_rows.begin(), usable_rows.begin() + static_cast<std::ptrdiff_t>(n),
                     usable_rows.end(), std::greater<>());
    for (size_t j = 0; j < n; ++j) chosen += usable_rows[j];
  } else {
    std::vector<long double> r(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) r[i] = static_cast<long double>(rows[i]);
    std::vector<double> x;
    const long double theta = FractionalKnapsack(r, lp, p.usable, &x);
    long double dual = theta * static_cast<long double>(lp.budget);
    long double magnitude = dual;
    for (const uint32_t i : p.usable) {
      const long double price = theta * static_cast<long double>(lp.costs[i]);
      dual += std::max<long double>(0, r[i] - price);
      magnitude += r[i] + price;
    }
    // Each conversion, product and sum errs by at most 2^-63 of the magnitude summed so far.
    const long double slack =
        magnitude * (static_cast<long double>(p.usable.size()) + 8) * std::ldexp(1.0L, -60);
    chosen = static_cast<Wide>(std::ceil(dual + slack)) + 1;
  }
  const Wide total = rest * lp.k + chosen;
  return static_cast<uint64_t>(total / (static_cast<Wide>(lp.k) << kFixedBits));
}

// States (StatesLagrangianBound): the bound's scale and the min's multipliers.
// The bound's scale: aggregates (<= 1) in units of 2^-40; rounding each weight up costs at most
// one unit per element.
constexpr double kScale = 1099511627776.0;  // 2^40
// Min: state multipliers tried, and the first exponentiated-gradient rate (then decaying).
constexpr int kMinRounds = 8;
constexpr double kStartRate = 4.0;
constexpr double kRateDecay = 0.7;

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

std::vector<uint64_t> CellWeights(const CoverageMatrix& matrix) {
  std::vector<uint64_t> weights(matrix.element_count());
  for (uint32_t e = 0; e < matrix.element_count(); ++e) weights[e] = matrix.Weight(e);
  return weights;
}

CoverageLp CardinalityLp(const CoverageMatrix& matrix, size_t n, int k) {
  CoverageLp lp;
  lp.matrix = &matrix;
  lp.weights = CellWeights(matrix);
  lp.k = static_cast<uint32_t>(k);
  lp.n = n;
  return lp;
}

CoverageLp BudgetLp(const CoverageMatrix& matrix, std::span<const double> costs, double budget) {
  CoverageLp lp;
  lp.matrix = &matrix;
  lp.weights = CellWeights(matrix);
  lp.costs = costs;
  lp.budget = budget;
  return lp;
}

int LpBoundSteps(const CoverageMatrix& matrix, double seconds) {
  size_t nonzeros = 1;
  for (const std::vector<uint32_t>& row : matrix.rows()) nonzeros += row.size();
  const double steps =
      std::min(kMaxSteps, seconds * kNonzerosPerSecond / static_cast<double>(nonzeros));
  return steps >= kMinSteps ? static_cast<int>(steps) : 0;
}

CoverageLpBound BoundCoverageLp(const CoverageLp& lp,
                                uint64_t target,
                                int max_iterations,
                                double time_limit) {
  const CoverageMatrix& matrix = *lp.matrix;
  VANTAGE_CHECK(lp.k >= 1 && lp.weights.size() == matrix.element_count() &&
                (lp.costs.empty() ? lp.n >= 1 : lp.costs.size() == matrix.candidate_count()));
  const auto start_time = std::chrono::steady_clock::now();
  const Prepared p = Prepare(lp);
  const size_t elements = matrix.element_count();
  const auto k = static_cast<double>(lp.k);
  // Start: each element's weight shared among its usable seers, k shares covering it.
  std::vector<double> mu(elements);
  for (uint32_t e = 0; e < elements; ++e) {
    mu[e] = p.seers[e] == 0 ? 0.0
                            : static_cast<double>(p.weights[e]) *
                                  std::min(1.0, k / static_cast<double>(p.seers[e]));
  }
  std::vector<double> best_mu = mu;
  double best = std::numeric_limits<double>::infinity();
  CoverageLpBound result;
  std::vector<long double> rows(matrix.candidate_count(), 0);
  std::vector<double> x(matrix.candidate_count(), 0.0);
  std::vector<double> covered(elements);
  std::vector<double> step(elements);
  std::vector<uint32_t> order;
  double scale = kStartStepScale;
  int stale = 0;
  for (int it = 0; it < max_iterations && scale >= kMinStepScale; ++it) {
    ThrowIfInterrupted();
    if (SecondsSince(start_time) > time_limit) break;
    ++result.iterations;
    double value = 0;
    for (uint32_t e = 0; e < elements; ++e) value += static_cast<double>(p.weights[e]) - mu[e];
    for (const uint32_t i : p.usable) {
      double r = 0;
      for (const uint32_t e : matrix.Row(i)) r += mu[e];
      rows[i] = r;
    }
    // The subproblem's x.
    if (lp.costs.empty()) {
      order = p.usable;
      const size_t n = std::min(lp.n, order.size());
      std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n), order.end(),
                       [&](uint32_t a, uint32_t b) {
                         return rows[a] > rows[b] || (rows[a] == rows[b] && a < b);
                       });
      std::fill(x.begin(), x.end(), 0.0);
      for (size_t j = 0; j < n; ++j) x[order[j]] = 1.0;
    } else {
      FractionalKnapsack(rows, lp, p.usable, &x);
    }
    for (const uint32_t i : p.usable) value += x[i] * static_cast<double>(rows[i]) / k;
    if (value < best - 1e-9) {
      best = value;
      best_mu = mu;
      result.chosen.clear();
      for (const uint32_t i : p.usable) {
        if (x[i] > 0) result.chosen.push_back(i);
      }
      stale = 0;
    } else if (++stale >= kPatience) {
      scale /= 2;
      stale = 0;
    }
    if (best < static_cast<double>(target) + 0.5) break;  // the exact value decides below
    // dL/dmu_e = (sum of x over e's seers) / k - 1, projected onto [0, w].
    std::fill(covered.begin(), covered.end(), 0.0);
    for (const uint32_t i : p.usable) {
      if (x[i] == 0) continue;
      for (const uint32_t e : matrix.Row(i)) covered[e] += x[i];
    }
    double norm = 0;
    for (uint32_t e = 0; e < elements; ++e) {
      double g = covered[e] / k - 1.0;
      if ((g > 0 && mu[e] <= 0) || (g < 0 && mu[e] >= static_cast<double>(p.weights[e]))) g = 0;
      step[e] = g;
      norm += g * g;
    }
    if (norm == 0) break;  // mu is optimal
    const double t = scale * (value - static_cast<double>(target)) / norm;
    for (uint32_t e = 0; e < elements; ++e) {
      mu[e] = std::clamp(mu[e] - t * step[e], 0.0, static_cast<double>(p.weights[e]));
    }
  }
  result.upper_bound = ExactValue(lp, p, best_mu);
  return result;
}

size_t SetCoverLpLowerBound(const CoverageMatrix& matrix,
                            uint64_t goal_cells,
                            size_t lower,
                            size_t upper,
                            double time_limit) {
  VANTAGE_CHECK(goal_cells >= 1 && lower >= 1 && lower <= upper);
  const auto start_time = std::chrono::steady_clock::now();
  time_limit *= kSetCoverTimeShare;
  CoverageLp lp = CardinalityLp(matrix, lower);
  // Bisection: too_few sensors are proven too few, enough reach the goal (or are not disproved).
  size_t too_few = lower - 1, enough = upper;
  int probes = 1;
  for (size_t span = upper - lower + 1; span > 1; span /= 2) ++probes;
  while (enough - too_few > 1) {
    const double left = time_limit - SecondsSince(start_time);
    const int steps = LpBoundSteps(matrix, left / probes);
    if (steps == 0) break;
    lp.n = too_few + (enough - too_few) / 2;
    const CoverageLpBound bound = BoundCoverageLp(lp, goal_cells - 1, steps, left / probes);
    if (bound.upper_bound < goal_cells) {
      too_few = lp.n;
    } else {
      enough = lp.n;
    }
    probes = std::max(1, probes - 1);
  }
  return too_few + 1;
}

void TightenByLpBound(const CoverageLp& lp,
                      uint64_t cells,
                      std::chrono::steady_clock::time_point start,
                      double time_limit,
                      double* upper_bound) {
  if (static_cast<double>(cells) == *upper_bound) return;
  const double seconds = kTightenTimeShare * (time_limit - SecondsSince(start));
  const int steps = LpBoundSteps(*lp.matrix, seconds);
  if (steps == 0) return;
  const CoverageLpBound bound = BoundCoverageLp(lp, cells, steps, seconds);
  if (static_cast<double>(bound.upper_bound) < *upper_bound)
    *upper_bound = static_cast<double>(std::max(bound.upper_bound, cells));
}

double StatesLagrangianBound(const CoverageMatrix& matrix,
                             OverStates over,
                             size_t n,
                             const std::vector<uint32_t>& start,
                             double seconds) {
  const auto begin = std::chrono::steady_clock::now();
  const size_t states = matrix.state_count();
  // A weighted sum weighs state s's share by ω_s |R_s| (the mean: alike; the sum: |R_s|), a
  // minimum starts there too and moves the multipliers towards the states it covers least.
  const Aggregation& aggregation = AggregationOf(over);
  std::vector<double> multipliers(states);
  for (size_t s = 0; s < states; ++s) {
    const size_t size = matrix.StateReferenceSize(s);
    multipliers[s] = Weighted(static_cast<double>(size), aggregation.weight(size));
  }
  const bool minimum = aggregation.shape == AggregateShape::kMinimum;
  const int rounds = minimum && states > 1 ? kMinRounds : 1;
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

double RowSumGoalBound(const StatesScorer& scorer, std::span<const double> costs, double goal,
                       std::span<const uint32_t> fixed) {
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t states = matrix.state_count();
  const StateTally kept = scorer.Covered(fixed);
  const auto cost_of = [&](uint32_t c) { return costs.empty() ? 1.0 : costs[c]; };
  double kept_cost = 0;
  for (const uint32_t f : fixed) kept_cost += cost_of(f);
  // The cheapest fractional choice of others whose values (value(c)) sum to `need`.
  const auto knapsack = [&](double need, const auto& value) {
    if (need <= 0) return 0.0;
    struct Item {
      double value, cost;
    };
    std::vector<Item> items;
    for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
      if (std::find(fixed.begin(), fixed.end(), c) != fixed.end()) continue;
      const double v = value(c);
      if (v > 0) items.push_back({v, cost_of(c)});
    }
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
      return a.value * b.cost > b.value * a.cost;  // value per cost, free ones first
    });
    double total = 0;
    for (const Item& item : items) {
      if (item.value >= need) return total + item.cost * need / item.value;
      need -= item.value;
      total += item.cost;
    }
    return std::numeric_limits<double>::infinity();  // unreachable
  };
  // Slack below the goal: GoalReached's 1e-9 and some round-off, so the bound stays proven.
  const double target = goal - 1e-9 - 1e-12;
  double others = 0;
  if (scorer.aggregation().shape == AggregateShape::kWeightedSum) {
    const auto share = [&](const StateTally& t) { return scorer.Fraction(t); };
    others = knapsack(target - share(kept) - 1e-12,
                      [&](uint32_t c) { return share(scorer.RowWeight(c)); });
  } else {
    for (size_t st = 0; st < states; ++st) {
      const double r = static_cast<double>(matrix.StateReferenceSize(st));
      others = std::max(others, knapsack(target * r - static_cast<double>(kept[st]) - 1e-9,
                                         [&](uint32_t c) {
                                           return static_cast<double>(scorer.RowWeight(c)[st]);
                                         }));
    }
  }
  if (!std::isfinite(others)) others = 0;  // only round-off: a start reaches the goal
  if (costs.empty()) others = std::ceil(others - 1e-9);
  return kept_cost + std::max(0.0, others);
}

}  // namespace vantage::detail
