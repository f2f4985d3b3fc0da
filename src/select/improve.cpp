// Selection's entry points for the assess stage: scoring a given constellation and improving it
// by swaps, so that refinement re-selects through selection's own code instead of its internals.
#include <algorithm>

#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/select.hpp"

namespace vantage {

Selection ScoreChosen(const CoverageEvaluator& evaluator, std::vector<uint32_t> chosen,
                      const std::string& method, const SelectOptions& options) {
  return detail::ScoreSelection(evaluator, std::move(chosen), method, options);
}

std::vector<uint32_t> ImproveBySwaps(std::span<const Observation> observations,
                                     size_t reference_size, std::vector<uint32_t> start,
                                     const SelectOptions& options) {
  const detail::SelectionKind kind = detail::KindFor(options);
  VANTAGE_CHECK(kind.limit != detail::SelectionKind::Limit::kGoal);
  const bool budget = kind.limit == detail::SelectionKind::Limit::kBudget;
  const detail::CoverageMatrix matrix = detail::MatrixFor(observations, reference_size, options);
  // A budget counted k times or in points has no swap search of its own: ConstrainedLocal's,
  // which scores every trial by the threshold (no constraints: every set is feasible).
  const bool budget_threshold = budget && kind.threshold > 1;
  if (!options.constraints.empty() || !options.fixed.empty() || budget_threshold) {
    // Swaps that keep the installation constraints and the kept sensors (first, never swapped
    // out), as method local under them.
    const detail::Feasibility feasible(observations, options.constraints);
    const std::vector<uint32_t>& fixed = options.fixed;
    std::erase_if(start, [&](uint32_t c) {
      return std::find(fixed.begin(), fixed.end(), c) != fixed.end();
    });
    start.insert(start.begin(), fixed.begin(), fixed.end());
    detail::Capacity capacity;
    capacity.n = static_cast<size_t>(options.n);
    if (budget) {
      capacity.n = matrix.candidate_count();
      capacity.costs = options.costs;
      capacity.budget = *options.budget;
    }
    return detail::ConstrainedLocal(detail::CellScorer(matrix, kind.threshold),
                                    feasible, std::move(start), capacity, fixed.size());
  }
  if (kind.min_points && !budget)
    return detail::PointsLocalSearch(matrix, std::move(start), kind.threshold);
  detail::LocalOptions local;
  if (budget) {
    local.costs = options.costs;
    local.budget = *options.budget;
  }
  return detail::LocalSearch(detail::CellScorer(matrix, kind.k), std::move(start), local);
}

}  // namespace vantage
