#pragma once
/// Selection over the states of a changing scene (issue 9; the states themselves are
/// scene_states.hpp). The same candidates observe every state; selection maximises the mean or
/// the worst case of the per-state coverage, or the coverage of all states' cells together. Each
/// state has its own reference set R_s and its own visibility matrix; the matrices simply stack
/// (docs/scene-format.md, States).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vantage/visibility.hpp"
#include "vantage/select.hpp"

namespace vantage {

/// What selection over states maximises (`--over-states NAME`): one row of kAggregations each.
enum class OverStates { kMean, kMin, kSum };

/// How an aggregation combines the states' covered cells c_s, each cell of state s weighing
/// ω_s: their weighted sum Σ_s ω_s c_s over its most Σ_s ω_s |R_s| (a fraction), or the least
/// ω_s c_s with ties broken by that weighted sum.
enum class AggregateShape { kWeightedSum, kMinimum };

/// A cell's weight ω_s in its state, numerator / denominator, whole numbers: scores compare
/// exactly in units of 1 / lcm(denominators) (StatesScorer).
struct CellWeight {
  uint64_t numerator = 1;
  uint64_t denominator = 1;
};

/// x ω = x · p / q, multiplied first: every reader weighs in this one order, so all agree to the
/// bit (x · (p / q) rounds differently).
constexpr double Weighted(double x, CellWeight w) {
  return x * static_cast<double>(w.numerator) / static_cast<double>(w.denominator);
}

/// ω_s = 1 / |R_s|: each state's share c_s / |R_s| counts alike (0 for an empty R_s).
constexpr CellWeight ShareOfItsState(uint64_t state_cells) {
  return state_cells ? CellWeight{1, state_cells} : CellWeight{0, 1};
}
/// ω_s = 1: every cell of every state counts alike.
constexpr CellWeight EveryCellAlike(uint64_t) { return CellWeight{1, 1}; }

/// One aggregation over states: how every reader and writer names it, and what selection
/// computes for it (the scorer, the MILP and the bounds read its shape and weights, never its
/// value). A new aggregation is a value of OverStates and its row.
struct Aggregation {
  OverStates value;
  std::string_view name;  ///< --over-states NAME, Python over_states='NAME', report.json
  std::string_view help;  ///< its words in --over-states' help, after the previous row's
  /// The summary's word: coverages are "the PHRASE of the states' coverages".
  std::string_view phrase;
  AggregateShape shape;
  CellWeight (*weight)(uint64_t state_cells);  ///< ω_s of a state of |R_s| cells
};

/// Every aggregation, the default (the first) first, in the order help and errors list them.
inline constexpr std::array<Aggregation, 3> kAggregations = {{
    {OverStates::kMean, "mean", "the mean", "mean", AggregateShape::kWeightedSum,
     ShareOfItsState},
    {OverStates::kMin, "min", " or the worst (min) coverage over them", "worst",
     AggregateShape::kMinimum, ShareOfItsState},
    // Σ_s c_s / Σ_s |R_s|: the mean weighted by |R_s|.
    {OverStates::kSum, "sum",
     ", or the coverage of all their cells together (sum: a larger state weighs more)",
     "cell-weighted mean (all their cells together)", AggregateShape::kWeightedSum,
     EveryCellAlike},
}};

/// The row of `over`.
const Aggregation& AggregationOf(OverStates over);
/// Every value, in kAggregations' order.
std::vector<OverStates> OverStatesValues();
/// A row's name; InputError naming `--over-states` and listing the names otherwise.
OverStates ParseOverStates(const std::string& name);
std::string OverStatesName(OverStates over);

namespace detail {
constexpr std::string_view kOverStatesHelpHead = "a scene with states: maximise ";
constexpr size_t kOverStatesHelpSize = [] {
  size_t size = kOverStatesHelpHead.size() + std::string_view(" (default )").size() +
                kAggregations.front().name.size();
  for (const Aggregation& row : kAggregations) size += row.help.size();
  return size;
}();
// The rows' words, joined once at compile time into --over-states' help.
constexpr std::array<char, kOverStatesHelpSize> kOverStatesHelpText = [] {
  std::array<char, kOverStatesHelpSize> text{};
  size_t at = 0;
  const auto put = [&](std::string_view words) {
    for (const char c : words) text[at++] = c;
  };
  put(kOverStatesHelpHead);
  for (const Aggregation& row : kAggregations) put(row.help);
  put(" (default ");
  put(kAggregations.front().name);
  put(")");
  return text;
}();
}  // namespace detail

/// --over-states' help (and the Python keyword's): the rows' words.
inline constexpr std::string_view kOverStatesHelp(detail::kOverStatesHelpText.data(),
                                                  detail::kOverStatesHelpText.size());

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
