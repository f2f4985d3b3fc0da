#pragma once
/// Selection over the states of a changing scene (issue 9; the states themselves are
/// scene_states.hpp). The same candidates observe every state; selection maximises the mean or
/// the worst case of the per-state coverage, or the coverage of all states' cells together. Each
/// state has its own reference set R_s and its own visibility matrix; the matrices simply stack
/// (docs/scene-format.md, States).
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "vantage/visibility.hpp"
#include "vantage/select.hpp"

namespace vantage {

/// What selection over states maximises (`--over-states mean|min|sum`): the mean of the states'
/// coverages, the least of them, or the sum: all states' cells counted together,
/// Σ_s covered_s / Σ_s |R_s| (the mean weighted by |R_s|: a larger state weighs more).
enum class OverStates { kMean, kMin, kSum };
/// "mean", "min" or "sum"; InputError naming `--over-states` and listing them otherwise.
OverStates ParseOverStates(const std::string& name);
std::string OverStatesName(OverStates over);

/// The observations of one state (non-owning): one Observation per candidate, the candidates in
/// the same order in every state, indices into the state's reference set R_s of
/// `reference_size` cells.
struct StateObservations {
  std::string name;
  size_t reference_size = 0;
  std::span<const Observation> observations;
};

/// A selection scored over states.
struct StateSelection {
  /// coverage = the aggregate (mean, min or sum over states) of |∪O_s ∩ R_s| / |R_s|;
  /// paper_coverage = the same aggregate of each state's |∪O_s| / |R_s| (keys outside R_s
  /// included); objective = "coverage".
  Selection selection;
  std::vector<double> state_coverage;        ///< |∪O_s ∩ R_s| / |R_s| per state, in state order
  std::vector<double> state_paper_coverage;  ///< |∪O_s| / |R_s| per state, in state order
};

/// Selection maximising the aggregate over states of the coverage, with Select's own methods
/// (the aggregate is what they maximise): best (n = 1: the single candidate with the best
/// aggregate), ransac (Algorithm 2's draws, as Select's, each kept when its aggregate is strictly
/// better), greedy (adds the candidate that raises the aggregate most; ties: for min the larger
/// mean, then the lowest index), local (greedy, then the best 1-swap while the aggregate
/// improves), exact (a MILP solved by CBC within options.time_limit, warm-started from local, with
/// a proven upper_bound on the aggregate and proven_optimal; when CBC cannot finish, the bound is
/// a Lagrangian relaxation's, LP strength), all (best, then ransac, greedy and local for every n
/// from 1 to options.n; exact is not part of it over states).
/// Aggregates are compared exactly (whole numbers of cells per state, on a common denominator);
/// deterministic, single-threaded.
/// k-coverage, point density (min_points), installation constraints and kept sensors
/// (options.fixed: in every answer, first; x fixed at 1 in the MILP) run the same methods on
/// ConstrainedMethods over the states' scorer.
/// A goal (options.goal: the fewest sensors, or with minimize_cost the cheapest, whose aggregate
/// reaches it; for min every state's coverage) and a budget (options.budget with costs) run the
/// cost-aware states greedy (StatesCostGreedy), RANSAC fitted to the goal or budget, local search
/// (budget) and exact (one MILP), with kept sensors and constraints too.
/// InputError for a goal above what all candidates (or, under constraints, any feasible set)
/// reach; for no state, states with different candidate counts, an empty R_s, or indices beyond R_s;
/// and for what SelectOptions::Validate rejects.
/// `calibration_cells`: the observations in whose common cells two sensors join under a
/// calibration rule (options.constraints); empty: the first state's (the cell as installed).
/// Groups that split one R (--over-parts) give the whole R's.
std::vector<StateSelection> SelectOverStates(std::span<const StateObservations> states,
                                             OverStates over,
                                             const SelectOptions& options,
                                             std::span<const Observation> calibration_cells = {});

/// `chosen` named `method`, scored over the states as SelectOverStates scores its answers (the
/// aggregate, each state's coverage in state_coverage, the objective's fields); seconds 0, no
/// bound. For refinement over states.
Selection ScoreChosenOverStates(std::span<const StateObservations> states, OverStates over,
                                std::vector<uint32_t> chosen, const std::string& method,
                                const SelectOptions& options);

/// Swap local search over the states from the feasible `start` (ConstrainedLocal with the states'
/// scorer: adds while n or the budget allows, and 1-swaps that raise the aggregate), under
/// options' constraints, with the kept sensors (options.fixed) first and never swapped out; never
/// worse than `start`. Not for a goal.
std::vector<uint32_t> ImproveOverStatesBySwaps(std::span<const StateObservations> states,
                                               OverStates over, std::vector<uint32_t> start,
                                               const SelectOptions& options);

}  // namespace vantage
