// The LP relaxation of maximum coverage with CLP (see lp_bound.hpp).
//
// CLP's lambda is a floating-point answer, so it is projected onto [0, w] (any such lambda gives
// a valid bound through EvaluateExactly: round-off in CLP costs strength, never correctness).
#include "select/lp_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "select/cbc_module.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::max();  // CLP's COIN_DBL_MAX

}  // namespace

ClpCoverageLp::ClpCoverageLp(const LagrangianProblem& problem)
    : weights_(problem.weights.begin(), problem.weights.end()),
      column_of_element_(problem.weights.size(), -1),
      rows_(problem.rows.size()),
      slots_(problem.slots) {
  std::vector<uint32_t> seers(weights_.size(), 0);
  for (const std::vector<uint32_t>& row : problem.rows) {
    for (const uint32_t e : row) ++seers[e];
  }
  // Columns: lambda_e of the elements seen twice or more, then pi_i per row, then mu.
  std::vector<std::vector<int>> rows_of_element(weights_.size());
  std::vector<double> own(rows_, 0.0);
  for (size_t i = 0; i < rows_; ++i) {
    for (const uint32_t e : problem.rows[i]) {
      if (weights_[e] != 0 && seers[e] >= 2) {
        rows_of_element[e].push_back(static_cast<int>(i));
      } else {
        own[i] += weights_[e];
      }
    }
  }
  std::vector<int> starts{0};
  std::vector<int> indices;
  std::vector<double> values;
  std::vector<double> objective;
  std::vector<double> upper;
  int columns = 0;
  for (size_t e = 0; e < weights_.size(); ++e) {
    if (rows_of_element[e].empty()) continue;
    column_of_element_[e] = columns++;
    for (const int i : rows_of_element[e]) {
      indices.push_back(i);
      values.push_back(-1.0);
    }
    starts.push_back(static_cast<int>(indices.size()));
    objective.push_back(-1.0);
    upper.push_back(weights_[e]);
  }
  for (size_t i = 0; i < rows_; ++i) {
    indices.push_back(static_cast<int>(i));
    values.push_back(1.0);
    starts.push_back(static_cast<int>(indices.size()));
    objective.push_back(1.0);
    upper.push_back(kInfinity);
    ++columns;
  }
  for (size_t i = 0; i < rows_; ++i) {
    indices.push_back(static_cast<int>(i));
    values.push_back(1.0);
  }
  starts.push_back(static_cast<int>(indices.size()));
  objective.push_back(static_cast<double>(problem.slots));
  upper.push_back(kInfinity);
  ++columns;
  const std::vector<double> lower(columns, 0.0);
  const std::vector<double> row_upper(rows_, kInfinity);
  model_.reset(Cbc().clp_new(columns, static_cast<int>(rows_), starts.data(), indices.data(),
                             values.data(), lower.data(), upper.data(), objective.data(),
                             own.data(), row_upper.data()));
  for (size_t e = 0; e < weights_.size(); ++e) {
    if (column_of_element_[e] >= 0) constant_ += weights_[e];
  }
}

ClpCoverageLp::~ClpCoverageLp() = default;

void ClpCoverageLp::Deleter::operator()(ClpHandle* model) const { Cbc().clp_delete(model); }

ClpLpSolution ClpCoverageLp::Solve(double seconds, std::span<const double> start) {
  const CbcModuleApi& clp = Cbc();
  ClpHandle* model = model_.get();
  ClpLpSolution solution;
  const int columns_total = clp.clp_number_columns(model);
  const bool warm = !start.empty() && rows_ > 0;
  if (warm) {
    // A feasible point of L at `start`: lambda, mu = the slots-th largest r_i, pi_i = the rest.
    std::vector<double> point(columns_total, 0.0);
    for (size_t e = 0; e < weights_.size(); ++e) {
      if (column_of_element_[e] >= 0)
        point[column_of_element_[e]] = std::clamp(start[e], 0.0, static_cast<double>(weights_[e]));
    }
    std::vector<double> product(rows_, 0.0);
    clp.clp_times(model, point.data(), product.data());
    const double* row_lower = clp.clp_row_lower(model);
    std::vector<double> r(rows_);
    for (size_t i = 0; i < rows_; ++i) r[i] = row_lower[i] - product[i];
    std::vector<double> sorted = r;
    std::sort(sorted.begin(), sorted.end(), std::greater<>());
    const double mu = slots_ == 0 ? sorted.front() : (slots_ <= rows_ ? sorted[slots_ - 1] : 0.0);
    const size_t pi0 = columns_total - 1 - rows_;
    for (size_t i = 0; i < rows_; ++i) point[pi0 + i] = std::max(0.0, r[i] - mu);
    point[columns_total - 1] = std::max(0.0, mu);
    std::copy(point.begin(), point.end(), clp.clp_primal_column_solution(model));
  }
  clp.clp_set_maximum_wall_seconds(model, std::max(seconds, 1e-3));
  clp.clp_set_maximum_seconds(model, std::max(seconds, 1e-3));
  // CLP stops at the end of an iteration once an interrupt is requested (Solve then throws
  // Interrupted): its time limit can be tens of seconds, and a stage must stop within a fraction
  // of one.
  clp.clp_stop_when(model, [] { return InterruptRequested(); });
  // From a start the basis is unknown but the point is feasible and near the optimum: a values
  // pass of primal simplex (on the 450-candidate bench world, N = 10, from 1,000 subgradient
  // steps: 6,101 iterations in 5.7 s, against 9,969 in 39 s for dual simplex from scratch).
  // Without one, dual simplex from the last basis.
  if (warm) {
    clp.clp_primal(model, 1);
  } else {
    clp.clp_dual(model);
  }
  ThrowIfInterrupted();
  solution.optimal = clp.clp_status(model) == 0;
  solution.objective = clp.clp_objective_value(model) + constant_;
  solution.iterations = clp.clp_number_iterations(model);
  const double* columns = clp.clp_primal_column_solution(model);
  solution.lambda.resize(weights_.size());
  for (size_t e = 0; e < weights_.size(); ++e) {
    const auto w = static_cast<double>(weights_[e]);
    const int c = column_of_element_[e];
    // NaN (a failed solve) fails both comparisons and becomes w: still a valid multiplier.
    const double value = c < 0 ? w : columns[c];
    solution.lambda[e] = value >= 0 && value <= w ? value : (value < 0 ? 0.0 : w);
  }
  // x_i: the duals of the rows pi_i + mu >= sum lambda (the primal LP's x).
  const double* duals = clp.clp_dual_row_solution(model);
  solution.x.resize(rows_);
  for (size_t i = 0; i < rows_; ++i) solution.x[i] = std::abs(duals[i]);
  return solution;
}

}  // namespace vantage::detail
