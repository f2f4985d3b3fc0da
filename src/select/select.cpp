// Select: runs the methods on the merged matrix and scores their answers (SYSTEM.md, stage 5).
//
// Every objective but a goal runs the methods on the model (constrained.cpp's ConstrainedMethods:
// the plain greedy, local search, RANSAC and one exact solve where no rule or kept sensor
// restricts it); a plain goal runs GoalSteps below; a goal with rules or kept sensors, and a
// budget counted k times or in points, the states' model on one state. Each runs in RunMethods'
// order, and answers are scored under their own metric (k-coverage counts a cell once k chosen
// sensors see it).
//
// Every method works on one detail::CoverageMatrix, built once per Select call: reference cells
// that exactly the same candidates see are merged into one weighted element and cells nobody
// sees are dropped, which keeps coverage exact and shrinks typical instances by orders of
// magnitude. Coverage and paper_coverage of every answer are then recomputed by
// CoverageEvaluator from the observations themselves, never taken from a method's bookkeeping.
#include "vantage/select.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>

#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/run_methods.hpp"
#include "vantage/error.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;


double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double Fraction(uint64_t cells, size_t reference_size) {
  return reference_size ? static_cast<double>(cells) / static_cast<double>(reference_size) : 0.0;
}

std::shared_ptr<spdlog::logger> Logger() {
  auto logger = spdlog::get("vantage");
  return logger ? logger : spdlog::default_logger();
}

// Goal of set cover in whole cells: the fewest cells whose share of R reaches the goal (at
// least one, so that the answer has a sensor).

// The methods for a goal on the plain matrix (no rule, no kept sensor; those goals are the
// states' model's): greedy to the goal, RANSAC's orders taken until it, and exact from greedy's
// answer (SolveSetCover; with a threshold or costs the goal MILP). Every other objective runs on
// ConstrainedMethods (SelectConstrained). Scores are recomputed from the observations under the
// objective's metric.
class GoalSteps final : public detail::MethodSteps<Selection> {
 public:
  GoalSteps(const CoverageEvaluator& evaluator,
            const detail::CoverageMatrix& matrix,
            const SelectOptions& options,
            double setup_seconds)
      : evaluator_(evaluator),
        matrix_(matrix),
        options_(options),
        k_(detail::Threshold(options)),
        goal_cells_(detail::GoalCells(*options.goal, matrix.reference_size())),
        setup_seconds_(setup_seconds) {}

  Selection Best() override { return SelectBest(evaluator_); }
  std::optional<Selection> TableHead() override { return std::nullopt; }
  size_t FirstN() const override { return 1; }

  /// No n to draw: each draw is a random order taken until the goal is reached.
  Selection Ransac(size_t, int iterations) override {
    const Clock::time_point start = Clock::now();
    detail::FittedDraws fit;
    fit.threshold = k_;
    fit.costs = GoalCosts();
    fit.goal_cells = goal_cells_;
    std::vector<uint32_t> chosen = detail::RansacFitted(
        matrix_, fit, iterations, options_.ransac_stop_coverage, options_.seed);
    return Scored(Method::kRansac, std::move(chosen), setup_seconds_ + SecondsSince(start));
  }

  Selection Greedy(size_t) override {
    const Clock::time_point start = Clock::now();
    local_ = detail::GreedyToGoal(matrix_, goal_cells_, k_, GoalCosts());
    local_seconds_ = setup_seconds_ + SecondsSince(start);
    return Scored(Method::kGreedy, local_, local_seconds_);
  }

  /// A goal has no local search (SelectOptions::Validate refuses it).
  Selection Local() override {
    VANTAGE_CHECK(false);
    return {};
  }

  /// After Greedy: runs at once, never in lanes.
  std::function<detail::ExactDone<Selection>(double)> Exact() override {
    return [this](double seconds) { return detail::ExactDone<Selection>{GoalExact(seconds), {}}; };
  }

  /// Exact for a goal, from greedy's answer.
  Selection GoalExact(double time_limit) const {
    const Clock::time_point start = Clock::now();
    if (k_ >= 2 || matrix_.has_counts() || options_.minimize_cost)
      return ThresholdGoal(time_limit, start);
    const detail::SetCoverResult exact =
        detail::SolveSetCover(matrix_, goal_cells_, local_, time_limit);
    LogNote(exact.proven_optimal, exact.note);
    Selection s = Scored(Method::kExact, exact.chosen, local_seconds_ + SecondsSince(start));
    s.n_lower_bound = static_cast<int>(exact.lower_bound);
    s.proven_optimal = exact.proven_optimal;
    return s;
  }

  void LogNote(bool proven_optimal, const std::string& note) const {
    const std::string what = fmt::format("exact ({})", ObjectiveName(Objective::kSetCover));
    if (!proven_optimal && !note.empty()) {
      Logger()->warn("{}: {}; reporting the best answer found and a bound", what, note);
    } else if (!note.empty()) {
      Logger()->debug("{}: {}", what, note);
    }
  }

  /// Exact for a goal with a threshold (k >= 2, min_points) or minimising cost: the goal MILP
  /// from greedy's answer, with the cheap bound where CBC gives none. The cheapest cover of every
  /// cell goes to OrbitalSetCover first (where it applies), then to the MILP unless proven.
  Selection ThresholdGoal(double time_limit, Clock::time_point start) const {
    const uint64_t goal_cells = goal_cells_;
    const auto price = [&](const std::vector<uint32_t>& chosen) {
      return options_.minimize_cost ? detail::TotalCost(options_.costs, chosen)
                                    : static_cast<double>(chosen.size());
    };
    std::vector<uint32_t> chosen = local_;
    detail::OrbitalSetCoverResult orbital;
    double milp_seconds = time_limit;
    if (options_.minimize_cost && k_ == 1 && !matrix_.has_counts() &&
        goal_cells == matrix_.seen_weight()) {
      // Every cell at the least cost: orbital branching first where the instance is symmetric.
      orbital = detail::OrbitalSetCover(matrix_, options_.costs, local_, 0,
                                        detail::kOrbitalTimeShare * time_limit);
      if (price(orbital.chosen) < price(chosen)) chosen = orbital.chosen;
      milp_seconds = time_limit - SecondsSince(start);
    }
    detail::GoalResult milp;
    if (!orbital.proven_optimal) {
      milp = detail::SolveGoalMilp(matrix_, k_, GoalCosts(), goal_cells, chosen, milp_seconds);
    }
    if (!milp.chosen.empty() && price(milp.chosen) < price(chosen)) chosen = milp.chosen;
    const bool proven = milp.proven_optimal || orbital.proven_optimal;
    LogNote(proven,
            orbital.applied ? orbital.note + (milp.note.empty() ? "" : "; " + milp.note)
                            : milp.note);
    Selection s = Scored(Method::kExact, chosen, local_seconds_ + SecondsSince(start));
    if (options_.minimize_cost) {
      s.cost_lower_bound = std::min(std::max(milp.lower_bound, orbital.lower_bound), *s.cost);
      s.proven_optimal = proven || *s.cost <= *s.cost_lower_bound;
      if (s.proven_optimal) s.cost_lower_bound = *s.cost;
    } else {
      const size_t cheap = detail::ThresholdGoalLowerBound(matrix_, goal_cells, k_);
      const size_t lower = std::max(cheap, static_cast<size_t>(milp.lower_bound));
      s.n_lower_bound = static_cast<int>(std::min(lower, chosen.size()));
      s.proven_optimal = milp.proven_optimal || *s.n_lower_bound == s.n;
      if (s.proven_optimal) s.n_lower_bound = s.n;
    }
    return s;
  }

  /// The costs a goal minimises: the candidates' with minimize_cost, else none (unit).
  std::span<const double> GoalCosts() const {
    return options_.minimize_cost ? std::span<const double>(options_.costs)
                                  : std::span<const double>();
  }

  Selection Scored(Method method, std::vector<uint32_t> chosen, double seconds) const {
    Selection s = detail::ScoreSelection(evaluator_, std::move(chosen), MethodName(method), options_);
    s.seconds = seconds;
    if (s.budget) VANTAGE_CHECK(*s.cost <= *s.budget);
    return s;
  }
 private:
  const CoverageEvaluator& evaluator_;
  const detail::CoverageMatrix& matrix_;
  const SelectOptions& options_;
  int k_;
  uint64_t goal_cells_;
  double setup_seconds_;
  std::vector<uint32_t> local_;  // greedy's answer, where exact starts
  double local_seconds_ = 0;
};

}  // namespace

namespace detail {

int Threshold(const SelectOptions& options) {
  switch (options.objective()) {
    case Objective::kKCoverage:
      return options.k;
    case Objective::kMinPoints:
      return static_cast<int>(*options.min_points);
    case Objective::kSetCover:  // a goal or a budget of k-covered cells, or of cells with the
    case Objective::kBudget:    // points
      return options.min_points ? static_cast<int>(*options.min_points) : options.k;
    default:
      return 1;
  }
}

CoverageMatrix MatrixFor(std::span<const Observation> observations, size_t reference_size,
                         const SelectOptions& options) {
  if (!options.min_points) return CoverageMatrix(observations, reference_size);
  return CoverageMatrix(observations, reference_size, *options.min_points);
}

}  // namespace detail

namespace {

void ValidateN(int n, size_t candidate_count) {
  SelectOptions options;
  options.n = n;
  options.Validate(candidate_count);
}

// Min-points needs every observation's point counts (visibility files before format 4 have none).
void RequirePointCounts(std::span<const Observation> observations) {
  for (const Observation& o : observations) {
    if (!o.has_point_counts()) {
      throw FieldError({"min_points"},
                       "min_points needs the pixel counts per cell, which these observations do "
                       "not carry — observe the scene again with this vantage");
    }
  }
}

}  // namespace

namespace detail {

Selection ScoreSelection(const CoverageEvaluator& evaluator, std::vector<uint32_t> chosen,
                         const std::string& method, const SelectOptions& options) {
  const Objective objective = options.objective();
  // A goal and a budget count cells seen k times too (--k with --goal or --budget).
  const int k = objective == Objective::kKCoverage || objective == Objective::kSetCover ||
                        objective == Objective::kBudget
                    ? options.k
                    : 1;
  Selection s;
  s.method = method;
  s.n = static_cast<int>(chosen.size());
  s.chosen = std::move(chosen);
  s.coverage = evaluator.Coverage(s.chosen, k);
  s.paper_coverage = evaluator.PaperCoverage(s.chosen, k);
  if (options.min_points) {
    // Counts are kept for R's cells only: the keys outside R count as seen (docs/constraints.md).
    const double outside = s.paper_coverage - s.coverage;
    s.coverage = evaluator.PointCoverage(s.chosen, *options.min_points);
    s.paper_coverage = s.coverage + outside;
    s.min_points = options.min_points;
  }
  s.objective = ObjectiveName(objective);
  s.k = k;
  if (objective == Objective::kSetCover) {
    s.goal = options.goal;
    if (options.minimize_cost) s.cost = TotalCost(options.costs, s.chosen);
  }
  if (objective == Objective::kBudget) {
    s.budget = options.budget;
    s.cost = TotalCost(options.costs, s.chosen);
  }
  return s;
}

}  // namespace detail

Selection SelectBest(const CoverageEvaluator& evaluator) {
  const Clock::time_point start = Clock::now();
  const std::span<const Observation> observations = evaluator.observations();
  ValidateN(1, observations.size());
  uint32_t best = 0;
  for (uint32_t i = 1; i < observations.size(); ++i) {
    // Strict: ties keep the lower index. reference_indices are unique indices into R.
    if (observations[i].reference_indices.size() > observations[best].reference_indices.size())
      best = i;
  }
  Selection s;
  s.method = MethodName(Method::kBest);
  s.n = 1;
  s.chosen = {best};
  s.coverage = evaluator.Coverage(s.chosen);
  s.paper_coverage = evaluator.PaperCoverage(s.chosen);
  // The best single candidate is the optimum for n = 1.
  s.upper_bound = s.coverage;
  s.proven_optimal = true;
  s.seconds = SecondsSince(start);
  return s;
}

Selection SelectRansac(const CoverageEvaluator& evaluator, const SelectOptions& options) {
  SelectOptions ransac = options;
  ransac.method = Method::kRansac;
  return Select(evaluator.observations(), evaluator.reference_size(), ransac).front();
}

Selection SelectGreedy(const CoverageEvaluator& evaluator, int n) {
  ValidateN(n, evaluator.observations().size());
  SelectOptions options;
  options.n = n;
  options.method = Method::kGreedy;
  return Select(evaluator.observations(), evaluator.reference_size(), options).front();
}

namespace {

// Whether `options` is a question GoalSteps and SelectConstrained do not ask, and
// the states' model (over_states.cpp) does, with the scene as its one state: a budget counted k
// times or in points, and a goal with kept sensors or under installation rules (every goal
// there is the one model's: kept sensors fixed at 1, a threshold per cell, costs, the rules).
bool OnOneStateOfTheModel(const SelectOptions& o) {
  const bool threshold = o.k >= 2 || o.min_points.has_value();
  if (o.budget && threshold) return true;
  return o.goal && (!o.fixed.empty() || !o.constraints.empty());
}

// Those combinations on the scene as one state: with one state the states' mean is the state's
// coverage (in units of 1 / |R|, exact), so the answers, bounds and proofs of SelectOverStates
// are those of the one state's problem. Each answer is scored again here, as every Select
// answer is (ScoreSelection: coverage, k, cost, goal or budget), its bounds and proof kept.
std::vector<Selection> SelectOnOneState(std::span<const Observation> observations,
                                        size_t reference_size, const SelectOptions& options) {
  if (options.min_points) RequirePointCounts(observations);
  const CoverageEvaluator evaluator(observations, reference_size);
  if (reference_size == 0) {
    throw InputError(options.goal ? fmt::format("goal {:g} is above the 0.0000 that all {} "
                                                "candidates reach together: R is empty — lower "
                                                "--goal, or give the scene a target",
                                                *options.goal, observations.size())
                                  : "R is empty: a budget counted k times or in points has no "
                                    "cell to count — give the scene a target");
  }
  const StateObservations state{"", reference_size, observations};
  std::vector<StateSelection> answers =
      SelectOverStates(std::span<const StateObservations>(&state, 1), OverStates::kMean, options);
  std::vector<Selection> results;
  for (StateSelection& answer : answers) {
    const Selection& from = answer.selection;
    Selection s = detail::ScoreSelection(evaluator, from.chosen, from.method, options);
    s.seconds = from.seconds;
    if (from.upper_bound) s.upper_bound = std::max(*from.upper_bound, s.coverage);
    s.n_lower_bound = from.n_lower_bound;
    s.cost_lower_bound = from.cost_lower_bound;
    s.proven_optimal = from.proven_optimal;
    results.push_back(std::move(s));
  }
  return results;
}

}  // namespace

std::vector<Selection> Select(std::span<const Observation> observations,
                              size_t reference_size,
                              const SelectOptions& options) {
  options.Validate(observations.size());
  if (OnOneStateOfTheModel(options)) return SelectOnOneState(observations, reference_size, options);
  const CoverageEvaluator evaluator(observations, reference_size);
  // With kept sensors, SelectConstrained adds the best single one.
  if (options.method == Method::kBest && options.fixed.empty()) return {SelectBest(evaluator)};
  if (options.min_points) RequirePointCounts(observations);
  // Every objective but a goal: the methods on the model (ConstrainedMethods), with or without
  // rules and kept sensors.
  if (!options.goal) return detail::SelectConstrained(observations, reference_size, options);

  const Clock::time_point start = Clock::now();
  const detail::CoverageMatrix matrix = detail::MatrixFor(observations, reference_size, options);
  const double setup_seconds = SecondsSince(start);
  Logger()->debug("select: {} candidates, {} of {} reference cells seen, merged into {} elements",
                  matrix.candidate_count(), matrix.seen_weight(), reference_size,
                  matrix.element_count());
  const uint64_t goal_cells = detail::GoalCells(*options.goal, reference_size);
  // What all candidates reach together, counted as the goal counts (k seers, or the points).
  const int threshold = detail::Threshold(options);
  std::vector<uint32_t> everyone(matrix.candidate_count());
  for (uint32_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  const uint64_t reachable = threshold == 1 && !matrix.has_counts()
                                 ? matrix.seen_weight()
                                 : detail::KCoveredWeight(matrix, everyone, threshold);
  if (goal_cells > reachable) {
    const std::string counted =
        options.min_points ? fmt::format(" (cells holding {} points)", *options.min_points)
        : options.k >= 2   ? fmt::format(" (cells seen {} times)", options.k)
                           : std::string();
    const std::string reach =
        fmt::format("goal {:g} is above the {:.4f}{} that all {} candidates reach together",
                    *options.goal, Fraction(reachable, reference_size), counted,
                    observations.size());
    throw InputError(options.goal_source == "--goal"
                         ? reach + " — lower --goal"
                         : fmt::format("{}: {} — lower the scene's goal, or give a lower --goal",
                                       options.goal_source, reach));
  }
  GoalSteps steps(evaluator, matrix, options, setup_seconds);
  return detail::RunMethods<Selection>(steps, options, observations.size(), start);
}

std::vector<Selection> CoverageCurve(std::span<const Observation> observations,
                                     size_t reference_size, const SelectOptions& options,
                                     const std::vector<Selection>& results, int up_to) {
  const Objective objective = options.objective();
  if (objective == Objective::kSetCover || objective == Objective::kBudget) return {};
  int last_n = up_to;
  for (const Selection& s : results) last_n = std::max(last_n, s.n);
  last_n = std::min(last_n, static_cast<int>(observations.size()));
  const int first_n = objective == Objective::kKCoverage ? options.k : 1;
  if (last_n < first_n) return {};
  if (options.min_points) RequirePointCounts(observations);
  return detail::ConstrainedCurve(observations, reference_size, options, results, first_n,
                                  last_n);
}

}  // namespace vantage
