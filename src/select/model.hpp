#pragma once
/// The selection model: what every exact solve is asked (SYSTEM.md, Select). Cells carry weights
/// and a threshold (seen by k sensors, or min_points pixels' hits), grouped by state and valued as
/// one state's cells or the mean, minimum or sum over states; candidates carry costs. The
/// objective is the most value within a capacity (n sensors, or a budget with costs), or the
/// least cost that reaches a goal; kept candidates are fixed, and the rules (conflicting pairs,
/// calibration connectivity) restrict the sets. milp.hpp builds it as one MILP; exact.cpp's
/// SolveExactModel is the one exact driver over it.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "vantage/select.hpp"
#include "vantage/select_states.hpp"

namespace vantage::detail {

class Feasibility;

/// What kind of question `options` ask, decided once here (KindFor) and read by Validate (the
/// methods that apply), Threshold and ModelFor (what a cell needs), the scorers (how an answer is
/// scored and named) and RunMethods (which methods "all" runs): a new combination of the existing
/// terms changes this and Validate's refusals, not those readers.
struct SelectionKind {
  Objective objective = Objective::kCoverage;  ///< its name in report.json (ObjectiveName)
  /// What a cell needs to count: `k` seers, or (counted in points) min_points pixels' hits.
  int threshold = 1;
  /// The k an answer is scored with: seers a cell needs (1 when it is counted in points).
  int k = 1;
  std::optional<uint32_t> min_points;  ///< counted in points: the points a cell needs
  /// What bounds an answer: n sensors (the coverage kinds: "all" runs every n from `k`), a
  /// budget, or a goal to reach at the least count or cost.
  enum class Limit { kSensors, kBudget, kGoal } limit = Limit::kSensors;
  std::vector<Method> methods;  ///< the methods that apply (Method::kAll among them)
  /// Select runs it on the states' model with the scene as its one state (over_states.cpp:
  /// every goal, and a budget counted k times or in points), not on the cells' methods
  /// (constrained.cpp).
  bool on_one_state = false;
  bool Applies(Method method) const;
};

/// The kind `options` ask (any options: Validate reads it before it has accepted them).
SelectionKind KindFor(const SelectOptions& options);

/// One selection question over `matrix` and its rules.
struct SelectionModel {
  const CoverageMatrix* matrix = nullptr;
  int threshold = 1;  ///< what a class needs to count: seers (k) or, with counts, points
  /// How the states' cells are valued (kAggregations' row: its shape and cell weights); null:
  /// one state's cells.
  const Aggregation* over = nullptr;
  /// Per candidate: the budget row's coefficients (maximise) or the prices a goal minimises;
  /// empty: unit (n sensors, the fewest sensors).
  std::span<const double> costs;
  /// Maximise within sum_i r_i x_i <= capacity (n, or the budget with `costs`).
  double capacity = 0;
  /// Minimise cost reaching this value instead: cells (one state's), a weighted sum (a fraction)
  /// or each state's share (a minimum).
  std::optional<double> goal;
  std::span<const uint32_t> fixed;     ///< kept sensors: x = 1
  const Feasibility* rules = nullptr;  ///< conflicts and connectivity, or none
};

/// The fewest cells whose share of R (`reference_size` cells) reaches `goal` (at least one).
uint64_t GoalCells(double goal, size_t reference_size);

/// The model `options` ask on `matrix` (the one translation from options to model): the
/// threshold (k, or min points), `over` (null: one state's cells), the costs where a budget or
/// `--cheapest` prices the sets, the capacity (`n` sensors, or the budget), the goal (in cells
/// for one state's cells, else the fraction itself), the kept sensors and `rules`.
SelectionModel ModelFor(const SelectOptions& options, const CoverageMatrix& matrix,
                        const Aggregation* over, size_t n, const Feasibility* rules);

/// What exact found for a SelectionModel.
struct ExactAnswer {
  std::vector<uint32_t> chosen;  ///< never worse than the start
  /// Maximise: >= the optimum's value (cells, or an aggregate over states, a fraction), and >=
  /// chosen's. Goal: <= the least cost (the count with unit costs) of any set that reaches it.
  double bound = 0;
  bool proven_optimal = false;
  std::string note;  ///< why a solver was not used, failed or stopped
};

/// What the caller knows beyond the model.
struct ExactHints {
  /// A bound on the optimum from elsewhere (maximise): the unconstrained problem's, valid under
  /// rules and kept sensors because they only remove sets. In cells it is the cheap bound (the
  /// start meeting it is the answer); over states it joins the bound at the end.
  std::optional<double> known_bound;
  /// k-coverage: search small instances exhaustively (tests turn it off to reach the MILP).
  bool may_enumerate = true;
};

/// Exact selection on `model` from `start` (feasible, within the capacity or reaching the goal)
/// within `time_limit` seconds (exact.cpp): the bound the model's kind has before CBC, the model
/// as one MILP in CBC's child process (milp.hpp), CBC's answer checked in integers and against
/// the rules, and the bound the kind adds after CBC (branch and bound on the Lagrangian for
/// maximum coverage, the LP bound for k-coverage and budgets, the states' Lagrangian). A goal of
/// cells with no rule and no kept sensor runs the set-cover search instead (SolveSetCover; with
/// a threshold or costs orbital branching and the goal MILP). Never returns an answer worse than
/// `start`.
ExactAnswer SolveExactModel(const SelectionModel& model,
                            const std::vector<uint32_t>& start,
                            double time_limit,
                            const ExactHints& hints = {});

}  // namespace vantage::detail
