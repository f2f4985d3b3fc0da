#include "select/model.hpp"

#include <algorithm>
#include <cmath>

#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {

uint64_t GoalCells(double goal, size_t reference_size) {
  const double cells = std::ceil(goal * static_cast<double>(reference_size) - 1e-9);
  return std::max<uint64_t>(1, static_cast<uint64_t>(std::max(0.0, cells)));
}

SelectionKind KindFor(const SelectOptions& options) {
  SelectionKind kind;
  kind.objective = options.objective();
  // A goal or a budget counts cells seen k times, or cells with the points, as n sensors do.
  kind.min_points = options.min_points;
  kind.k = options.min_points ? 1 : options.k;
  kind.threshold = options.min_points ? static_cast<int>(*options.min_points) : options.k;
  // A budget with min_points 1 too: counted in points, though the threshold is 1.
  kind.on_one_state =
      options.goal || (options.budget && (options.k >= 2 || options.min_points.has_value()));
  switch (kind.objective) {
    case Objective::kCoverage:
      kind.methods = {Method::kBest,  Method::kRansac, Method::kGreedy,
                      Method::kLocal, Method::kExact,  Method::kAll};
      break;
    case Objective::kSetCover:
      kind.limit = SelectionKind::Limit::kGoal;
      kind.methods = {Method::kRansac, Method::kGreedy, Method::kExact, Method::kAll};
      break;
    case Objective::kBudget:
      kind.limit = SelectionKind::Limit::kBudget;
      kind.methods = {Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact,
                      Method::kAll};
      break;
    case Objective::kKCoverage:
    case Objective::kMinPoints:
      kind.methods = {Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact,
                      Method::kAll};
      break;
  }
  return kind;
}

bool SelectionKind::Applies(Method method) const {
  return std::find(methods.begin(), methods.end(), method) != methods.end();
}

int Threshold(const SelectOptions& options) { return KindFor(options).threshold; }

SelectionModel ModelFor(const SelectOptions& options, const CoverageMatrix& matrix,
                        const Aggregation* over, size_t n, const Feasibility* rules) {
  SelectionModel model;
  model.matrix = &matrix;
  model.threshold = Threshold(options);
  model.over = over;
  if (options.budget || options.minimize_cost) model.costs = options.costs;
  model.capacity = options.budget ? *options.budget : static_cast<double>(n);
  if (options.goal) {
    model.goal = over == nullptr
                     ? static_cast<double>(GoalCells(*options.goal, matrix.reference_size()))
                     : *options.goal;
  }
  model.fixed = options.fixed;
  model.rules = rules;
  return model;
}

}  // namespace vantage::detail
