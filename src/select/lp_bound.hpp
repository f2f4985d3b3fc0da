// The LP relaxation of maximum coverage, solved by CLP, as a source of Lagrangian multipliers
// (issue 14). CLP works in floating point, so its optimum is not a proof by itself: its duals of
// the coverage rows, projected onto [0, w], are multipliers of the Lagrangian relaxation
// (lagrangian.cpp), and EvaluateExactly turns them into a proven bound, which equals the LP
// optimum up to the multipliers' truncation when CLP's duals are optimal.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "select/methods.hpp"

namespace vantage::detail {

struct ClpHandle;  // cbc_module.hpp

/// What ClpCoverageLp::Solve found.
struct ClpLpSolution {
  bool optimal = false;        ///< CLP reported an optimal basis (else stopped by its time limit)
  double objective = 0;        ///< CLP's LP value, in floating point: not a proof
  std::vector<double> lambda;  ///< per element: the multiplier, in [0, w_e]
  std::vector<double> x;       ///< per row: the LP's x_i (the duals of the rows)
  int iterations = 0;          ///< simplex iterations
};

/// The LP relaxation of a LagrangianProblem in its dual form, which is the Lagrangian dual:
///
///   min  slots mu + sum_i pi_i + sum_e (w_e - lambda_e)
///   s.t. pi_i + mu >= sum_{e in row i} lambda_e,   0 <= lambda_e <= w_e,  pi, mu >= 0,
///
/// one row per candidate (a basis of hundreds, not of the ~15 k elements of the primal form),
/// its optimum the LP optimum of max coverage. Elements of weight 0 or seen by one row get
/// lambda_e = w_e, optimal for them (a row's lower bound then carries their weight). Held in a
/// ClpSimplex (in the CBC module, cbc_module.hpp) so that a later Solve starts from the last
/// basis.
class ClpCoverageLp {
 public:
  explicit ClpCoverageLp(const LagrangianProblem& problem);
  ~ClpCoverageLp();
  ClpCoverageLp(const ClpCoverageLp&) = delete;
  ClpCoverageLp& operator=(const ClpCoverageLp&) = delete;

  /// Solves within `seconds` (wall clock): from `start` (multipliers per element, e.g. the
  /// subgradient's) by a primal values pass, else by dual simplex from the current basis.
  ClpLpSolution Solve(double seconds, std::span<const double> start = {});

 private:
  struct Deleter {
    void operator()(ClpHandle* model) const;
  };
  std::unique_ptr<ClpHandle, Deleter> model_;
  std::vector<uint32_t> weights_;   // the problem's, per element
  std::vector<int> column_of_element_;  // LP column of each element's lambda, -1 if none
  size_t rows_ = 0;                     // LP rows: one per problem row
  size_t slots_ = 0;
  double constant_ = 0;                 // sum of w_e over the lambda columns
};

}  // namespace vantage::detail
