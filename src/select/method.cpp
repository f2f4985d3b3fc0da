// Objective names and SelectOptions::Validate (SYSTEM.md, Select); method names are in
// util/settings.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "select/model.hpp"
#include "vantage/error.hpp"
#include "vantage/select.hpp"
#include "vantage/sensors.hpp"

namespace vantage {
namespace {

// The objective's own fields, and whether the method applies to it.
void ValidateObjective(const SelectOptions& o, size_t candidate_count) {
  // A cell counts by one threshold (k seers, or min_points points), whatever the objective: the
  // goal's share, the budget's coverage or n sensors' coverage counts such cells.
  if (o.k >= 2 && o.min_points) {
    const char* what = o.goal     ? "a goal counts"
                       : o.budget ? "a budget's coverage counts"
                                  : "coverage counts";
    throw FieldError({"min_points", "k"},
                     fmt::format("{} cells seen by k sensors or cells with min_points points — "
                                 "give --k or --min-points, not both",
                                 what));
  }
  if (o.minimize_cost && !o.goal)
    throw FieldError({"minimize_cost"},
                     "the cheapest layout is asked of a coverage goal — give --goal with "
                     "--cheapest");
  if (o.goal && o.budget) {
    throw FieldError({"goal", "budget"},
                     "goal and budget are separate objectives — give only one of --goal, "
                     "--budget (--goal with --cheapest asks for the cheapest layout that "
                     "reaches it)");
  }
  if (o.min_points) {
    if (*o.min_points < 1)
      throw FieldError({"min_points"}, "min_points = 0 must be at least 1 point per cell");
  }
  if (o.k < 1) throw FieldError({"k"}, fmt::format("k = {} must be at least 1", o.k));
  if (o.goal && !(*o.goal > 0.0 && *o.goal <= 1.0)) {
    throw FieldError({"goal"}, fmt::format(
        "goal = {} is a coverage fraction — give a value in (0, 1], e.g. 0.9 for 90 %", *o.goal));
  }
  if ((o.goal || o.budget) && static_cast<size_t>(o.k) > candidate_count) {
    throw FieldError({"k"}, fmt::format("k = {} is above the {} candidates: no cell can be seen "
                                        "{} times — lower --k",
                                        o.k, candidate_count, o.k));
  }
  if (o.minimize_cost) {
    if (o.costs.size() != candidate_count) {
      throw InputError(fmt::format("the cheapest layout needs one cost per candidate: {} costs "
                                   "for {} candidates",
                                   o.costs.size(), candidate_count));
    }
    for (const double c : o.costs) {
      if (!(c >= 0.0 && c <= kMaxUnitCost))
        throw FieldError({"costs"},
                         fmt::format("sensor cost {} must be from 0 to {:g}", c, kMaxUnitCost));
    }
  }
  if (o.budget) {
    if (!(*o.budget >= 0.0) || !std::isfinite(*o.budget))
      throw FieldError({"budget"}, fmt::format("budget = {} must be a number >= 0", *o.budget));
    if (o.costs.size() != candidate_count) {
      throw InputError(
          fmt::format("budget needs one cost per candidate: {} costs for {} candidates",
                      o.costs.size(), candidate_count));
    }
    double cheapest = std::numeric_limits<double>::infinity();
    for (const double c : o.costs) {
      if (!(c >= 0.0 && c <= kMaxUnitCost))
        throw FieldError({"costs"},
                         fmt::format("sensor cost {} must be from 0 to {:g}", c, kMaxUnitCost));
      cheapest = std::min(cheapest, c);
    }
    if (*o.budget < cheapest) {
      throw FieldError(
          {"budget"},
          fmt::format("budget {:g} is below the cheapest candidate's cost {:g} — raise --budget",
                      *o.budget, cheapest));
    }
  }
  const detail::SelectionKind kind = detail::KindFor(o);
  if (kind.limit == detail::SelectionKind::Limit::kSensors && o.n < kind.k) {
    throw FieldError({"n", "k"}, fmt::format(
        "n = {} is below k = {}: a cell counts only once k chosen sensors see it — raise -n to at "
        "least {}",
        o.n, o.k, o.k));
  }
  // The methods that apply are the kind's (KindFor, beside the model).
  if (kind.Applies(o.method)) return;
  const std::vector<Method>& allowed = kind.methods;
  std::string names;
  for (const Method m : allowed) names += (names.empty() ? "" : ", ") + MethodName(m);
  throw FieldError({"method", "goal", "k", "budget"},
                   fmt::format("method '{}' does not apply to the {} objective — use one of {}",
                               MethodName(o.method), ObjectiveName(kind.objective), names));
}

}  // namespace

std::string ObjectiveName(Objective objective) {
  switch (objective) {
    case Objective::kCoverage:
      return "coverage";
    case Objective::kSetCover:
      return "set-cover";
    case Objective::kKCoverage:
      return "k-coverage";
    case Objective::kBudget:
      return "budget";
    case Objective::kMinPoints:
      return "min-points";
  }
  VANTAGE_CHECK(false);
  return "";
}

Objective SelectOptions::objective() const {
  if (goal) return Objective::kSetCover;
  if (budget) return Objective::kBudget;
  if (k >= 2) return Objective::kKCoverage;
  if (min_points) return Objective::kMinPoints;
  return Objective::kCoverage;
}

void SelectOptions::Validate(size_t candidate_count) const {
  if (candidate_count == 0) {
    throw FieldError({"n"}, fmt::format("n = {} but there are no candidates to select from", n));
  }
  if (n < 1 || static_cast<size_t>(n) > candidate_count) {
    throw FieldError(
        {"n"}, fmt::format("n = {} is out of range: there are {} candidates, so n must be "
                    "between 1 and {}",
                    n, candidate_count, candidate_count));
  }
  if (ransac_iterations < 1) {
    throw FieldError({"ransac_iterations"},
                     fmt::format("ransac_iterations = {} must be at least 1", ransac_iterations));
  }
  if (!(ransac_stop_coverage >= 0.0 && ransac_stop_coverage <= 1.0)) {
    throw FieldError({"ransac_stop_coverage"},
                     fmt::format("ransac_stop_coverage = {} must be a fraction in [0, 1]",
                                 ransac_stop_coverage));
  }
  // The deadline is a steady-clock time point in nanoseconds (int64: 292 years); far beyond
  // the cap the conversion overflowed.
  if (!(time_limit >= kMinTimeLimit) || !(time_limit <= kMaxTimeLimit)) {
    throw FieldError({"time_limit"},
                     fmt::format("time_limit = {} s must be a number of seconds from {:g} "
                                 "(1 ms) to {:g} (11.6 days)",
                                 time_limit, kMinTimeLimit, kMaxTimeLimit));
  }
  ValidateObjective(*this, candidate_count);
  constraints.Validate(candidate_count);
  std::vector<uint32_t> sorted = fixed;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end() ||
      (!sorted.empty() && sorted.back() >= candidate_count)) {
    throw FieldError({"fixed"}, "fixed: the kept candidates must be distinct candidate indices");
  }
  if (fixed.empty()) return;
  const detail::SelectionKind kind = detail::KindFor(*this);
  if (kind.limit == detail::SelectionKind::Limit::kSensors &&
      static_cast<size_t>(n) < fixed.size()) {
    throw FieldError({"n"}, fmt::format("n = {} is below the {} sensors kept — give n >= {}", n,
                                        fixed.size(), fixed.size()));
  }
  if (budget && costs.size() == candidate_count) {
    double kept_cost = 0;
    for (const uint32_t i : fixed) kept_cost += costs[i];
    if (kept_cost > *budget) {
      throw FieldError({"budget"}, fmt::format("budget = {:g} is below the {:g} that the kept "
                                               "sensors cost",
                                               *budget, kept_cost));
    }
  }
  if (method == Method::kBest && static_cast<size_t>(n) != fixed.size() + 1 &&
      kind.Applies(Method::kBest)) {
    throw FieldError({"method", "n"},
                     fmt::format("method best adds one sensor to the {} kept — give n = {}",
                                 fixed.size(), fixed.size() + 1));
  }
}

}  // namespace vantage
