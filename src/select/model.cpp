#include "select/model.hpp"

#include <algorithm>
#include <cmath>

#include "select/methods.hpp"

namespace vantage::detail {

uint64_t GoalCells(double goal, size_t reference_size) {
  const double cells = std::ceil(goal * static_cast<double>(reference_size) - 1e-9);
  return std::max<uint64_t>(1, static_cast<uint64_t>(std::max(0.0, cells)));
}

SelectionModel ModelFor(const SelectOptions& options, const CoverageMatrix& matrix,
                        ModelValue value, size_t n, const Feasibility* rules) {
  SelectionModel model;
  model.matrix = &matrix;
  model.threshold = Threshold(options);
  model.value = value;
  if (options.budget || options.minimize_cost) model.costs = options.costs;
  model.capacity = options.budget ? *options.budget : static_cast<double>(n);
  if (options.goal) {
    model.goal = value == ModelValue::kCells
                     ? static_cast<double>(GoalCells(*options.goal, matrix.reference_size()))
                     : *options.goal;
  }
  model.fixed = options.fixed;
  model.rules = rules;
  return model;
}

}  // namespace vantage::detail
