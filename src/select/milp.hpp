#pragma once
/// The selection model (model.hpp) as one MILP, built in one place for every objective exact
/// solves and solved by CBC in a child process (cbc_answer.hpp). With x_i = candidate i chosen and y_c = class c
/// counted (a class: elements that the same candidates see, merged where that keeps the model
/// exact):
///
///   threshold   T y_c <= sum_{i sees c} min(count_ic, T) x_i   (T = 1 coverage, k seers, or
///                                                               min_points pixels' hits)
///   value       v_c = w_c cells (one state), w_c / (S |R_s|) (mean over states), w_c / |R_s|
///               (min over states: per state s, its share sum_{c in s} v_c y_c), w_c / sum_s |R_s|
///               (sum over states: every state's cells alike)
///   maximise    sum_c v_c y_c           (min: max t, t <= each state's share)
///     s.t.      sum_i r_i x_i <= capacity      (r = 1: n sensors; r = cost: a budget)
///   or minimise sum_i cost_i x_i (unit: the fewest sensors)
///     s.t.      sum_c v_c y_c >= goal          (min: each state's share >= goal)
///   kept        x_i = 1
///   conflicts   x_a + x_b <= 1
///   connected   a single-commodity flow along the overlap edges (both directions), nd the most
///               sensors an answer holds:
///                 sum_i r_i = 1, r_i <= x_i              one root among the chosen
///                 s_i <= nd r_i, sum_i s_i = sum_i x_i   it supplies one unit per chosen sensor
///                 out_i - in_i = s_i - x_i               every chosen sensor keeps one
///                 out_i, in_i <= (nd - 1) x_i            flow only through chosen sensors
///               r binary, s and f >= 0: a flow exists exactly when every chosen sensor is reached
///               from the root along edges between chosen sensors (the chosen graph is connected).
///
/// Reductions, each keeping an optimum: candidates that see nothing (or cost more than the budget)
/// are left out unless kept; with T = 1 and no rules, dominated candidates too (a superset at no
/// higher cost: Dominated); with T = 1 a class seen by one candidate folds into its x (a_i x_i);
/// one state without point counts re-merges classes over the candidates left.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "select/model.hpp"

namespace vantage::detail {

/// What CBC answered for a SelectionModel.
struct MilpAnswer {
  std::vector<uint32_t> chosen;  ///< candidates at 1; empty when CBC gave no solution
  /// CBC's bound on the objective in the model's units: cells, an aggregate (a fraction) or a
  /// cost; NaN when none.
  double bound = std::numeric_limits<double>::quiet_NaN();
  bool proven_optimal = false;
  std::string note;  ///< why CBC was not run, failed or stopped
};

/// Whether every value is a whole number (then a cost objective is too, and CBC may stop within 1
/// of its bound).
inline bool AllWhole(std::span<const double> values) {
  for (const double v : values)
    if (v != std::floor(v)) return false;
  return true;
}

/// Per candidate, whether another sees a superset at no higher cost and is strictly better (a
/// strict superset, or cheaper) or equal at a lower index; candidates that see nothing too. Dropping
/// them all keeps an optimum of n sensors, a budget and a goal (the reductions above). `costs`
/// empty: unit.
std::vector<bool> DominatedCandidates(const CoverageMatrix& matrix, std::span<const double> costs);

/// Builds `milp` as the MILP above, warm-starts it from `start` (dominated members replaced by a
/// kept superset), and solves it with CBC within `time_limit` seconds (CBC's share and kill time:
/// cbc_answer.hpp). A model too large for the limit is not run. When every candidate left fits
/// the capacity (no rules), they are the answer, proven, without CBC. A failure of CBC's (not an
/// interrupt) is a note. SolveExactModel (model.hpp) checks the answer in integers.
MilpAnswer SolveSelectionMilp(const SelectionModel& milp, const std::vector<uint32_t>& start,
                              double time_limit);

}  // namespace vantage::detail
