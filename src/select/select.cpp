// Select: runs the methods on the merged matrix and scores their answers (SYSTEM.md, stage 5).
//
// The further objectives (set cover, k-coverage, budget) run the same methods on the same matrix
// with their own greedy, local search and MILP (methods.hpp); their answers are scored under
// their own metric (k-coverage counts a cell once k chosen sensors see it).
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

// Greedy, local search and exact for one n (or one goal, or one budget), each built on the one
// before (local starts from greedy's answer, exact is warm-started from local's, or from greedy's
// for set cover), so each one's seconds include the earlier steps it needed, as if it had run
// alone. Scores are recomputed from the observations under the objective's metric.
class Pipeline final : public detail::MethodSteps<Selection> {
 public:
  Pipeline(const CoverageEvaluator& evaluator,
           const detail::CoverageMatrix& matrix,
           const SelectOptions& options,
           double setup_seconds)
      : evaluator_(evaluator),
        matrix_(matrix),
        options_(options),
        objective_(options.objective()),
        k_(detail::Threshold(options)),
        setup_seconds_(setup_seconds) {}

  Selection Best() override { return SelectBest(evaluator_); }

  /// Best's row heads the table of plain coverage (n = 1 is its optimum).
  std::optional<Selection> TableHead() override {
    if (objective_ != Objective::kCoverage) return std::nullopt;
    return SelectBest(evaluator_);
  }

  /// k-coverage needs n >= k (below it nothing counts).
  size_t FirstN() const override {
    return objective_ == Objective::kKCoverage ? static_cast<size_t>(k_) : 1;
  }

  bool ParallelExact() const override { return true; }

  Selection Ransac(size_t n, int iterations) override {
    const Clock::time_point start = Clock::now();
    std::vector<uint32_t> chosen;
    if (objective_ == Objective::kSetCover || objective_ == Objective::kBudget) {
      // No n to draw: each draw is a random order taken until the goal or the budget stops it.
      detail::FittedDraws fit;
      fit.threshold = k_;
      fit.costs = objective_ == Objective::kBudget ? std::span<const double>(options_.costs)
                                                   : GoalCosts();
      if (objective_ == Objective::kBudget) fit.budget = *options_.budget;
      if (objective_ == Objective::kSetCover)
        fit.goal_cells = detail::GoalCells(*options_.goal, matrix_.reference_size());
      chosen = detail::RansacFitted(matrix_, fit, iterations, options_.ransac_stop_coverage,
                                    options_.seed);
      // Every order reaches a goal that all candidates reach; a budget's draws add nothing only
      // where nothing affordable sees anything: greedy's answer then.
      if (chosen.empty()) chosen = detail::GreedyBudget(matrix_, options_.costs, *options_.budget);
    } else {
      chosen = detail::RansacChoice(detail::CellScorer(matrix_, k_), static_cast<size_t>(n),
                                    iterations, options_.ransac_stop_coverage, options_.seed);
    }
    return Scored(Method::kRansac, std::move(chosen), setup_seconds_ + SecondsSince(start));
  }

  Selection Greedy(size_t n) override {
    const Clock::time_point start = Clock::now();
    switch (objective_) {
      case Objective::kSetCover:
        greedy_ = detail::GreedyToGoal(matrix_, detail::GoalCells(*options_.goal, matrix_.reference_size()),
                                       k_, GoalCosts());
        break;
      case Objective::kBudget:
        greedy_ = detail::GreedyBudget(matrix_, options_.costs, *options_.budget);
        break;
      case Objective::kKCoverage:
      case Objective::kMinPoints:  // the matrix's point counts make it the min-points greedy
        greedy_ = detail::KGreedyComplete(matrix_, {}, static_cast<size_t>(n), k_);
        break;
      case Objective::kCoverage:
        greedy_ = detail::GreedyComplete(detail::CellScorer(matrix_), {}, static_cast<size_t>(n));
        break;
    }
    greedy_seconds_ = setup_seconds_ + SecondsSince(start);
    local_ = greedy_;
    local_seconds_ = greedy_seconds_;
    return Scored(Method::kGreedy, greedy_, greedy_seconds_);
  }

  /// After Greedy(n).
  Selection Local() override {
    const Clock::time_point start = Clock::now();
    detail::LocalOptions local;
    if (objective_ == Objective::kBudget) {
      local.costs = options_.costs;
      local.budget = *options_.budget;
    }
    local_ = objective_ == Objective::kMinPoints
                 ? detail::PointsLocalSearch(matrix_, greedy_, k_)
                 : detail::LocalSearch(detail::CellScorer(matrix_, k_), greedy_, local);
    local_seconds_ = greedy_seconds_ + SecondsSince(start);
    return Scored(Method::kLocal, local_, local_seconds_);
  }

  /// After Local() (or Greedy(n) for set cover): a goal's exact at once (never in lanes), the
  /// others from a copy of local's answer, const and touching no member state, so that `all`'s
  /// lanes run them at once.
  std::function<detail::ExactDone<Selection>(double)> Exact() override {
    if (objective_ == Objective::kSetCover)
      return [this](double seconds) { return detail::ExactDone<Selection>{GoalExact(seconds), {}}; };
    return [this, start = local_, start_seconds = local_seconds_](double seconds) {
      auto note = std::make_shared<ExactNote>();
      Selection s = ExactFrom(start, start_seconds, seconds, note.get());
      return detail::ExactDone<Selection>{
          std::move(s), [this, n = start.size(), note] {
            LogNote(n, note->proven_optimal, note->text);
          }};
    };
  }

  /// Exact for a goal, from greedy's answer.
  Selection GoalExact(double time_limit) const {
    const Clock::time_point start = Clock::now();
    if (k_ >= 2 || matrix_.has_counts() || options_.minimize_cost)
      return ThresholdGoal(time_limit, start);
    const detail::SetCoverResult exact = detail::SolveSetCover(
        matrix_, detail::GoalCells(*options_.goal, matrix_.reference_size()), local_, time_limit);
    LogNote(local_.size(), exact.proven_optimal, exact.note);
    Selection s = Scored(Method::kExact, exact.chosen, local_seconds_ + SecondsSince(start));
    s.n_lower_bound = static_cast<int>(exact.lower_bound);
    s.proven_optimal = exact.proven_optimal;
    return s;
  }

  /// What exact found to say, logged by the caller (in n order where lanes ran at once).
  struct ExactNote {
    bool proven_optimal = false;
    std::string text;
  };

  /// Exact (coverage, k-coverage, min points or budget) warm-started from `start`, found in
  /// `start_seconds`. Const and touching no member state: `all`'s lanes run it at once.
  Selection ExactFrom(const std::vector<uint32_t>& start, double start_seconds, double time_limit,
                      ExactNote* note) const {
    const Clock::time_point begin = Clock::now();
    const detail::SelectionModel model =
        detail::ModelFor(options_, matrix_, detail::ModelValue::kCells, start.size(), nullptr);
    detail::ExactAnswer exact = detail::SolveExactModel(model, start, time_limit);
    note->proven_optimal = exact.proven_optimal;
    note->text = std::move(exact.note);
    Selection s = Scored(Method::kExact, exact.chosen, start_seconds + SecondsSince(begin));
    s.upper_bound = std::max(
        Fraction(static_cast<uint64_t>(exact.bound), matrix_.reference_size()), s.coverage);
    s.proven_optimal = exact.proven_optimal;
    return s;
  }

  const std::vector<uint32_t>& local() const { return local_; }
  double local_seconds() const { return local_seconds_; }

  void LogNote(size_t n, bool proven_optimal, const std::string& note) const {
    std::string what = fmt::format("exact, n = {}", n);
    if (objective_ == Objective::kKCoverage) what += fmt::format(", k = {}", k_);
    if (objective_ == Objective::kMinPoints) what += fmt::format(", min points = {}", k_);
    if (objective_ == Objective::kSetCover || objective_ == Objective::kBudget)
      what = fmt::format("exact ({})", ObjectiveName(objective_));
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
    const uint64_t goal_cells = detail::GoalCells(*options_.goal, matrix_.reference_size());
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
    LogNote(local_.size(), proven,
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
  Objective objective_;
  int k_;
  double setup_seconds_;
  std::vector<uint32_t> greedy_;
  std::vector<uint32_t> local_;
  double greedy_seconds_ = 0;
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
  const Clock::time_point start = Clock::now();
  options.Validate(evaluator.observations().size());
  if (options.min_points) RequirePointCounts(evaluator.observations());
  const detail::CoverageMatrix matrix =
      detail::MatrixFor(evaluator.observations(), evaluator.reference_size(), options);
  Selection s =
      Pipeline(evaluator, matrix, options, 0).Ransac(options.n, options.ransac_iterations);
  s.seconds = SecondsSince(start);
  return s;
}

Selection SelectGreedy(const CoverageEvaluator& evaluator, int n) {
  const Clock::time_point start = Clock::now();
  ValidateN(n, evaluator.observations().size());
  const detail::CoverageMatrix matrix(evaluator.observations(), evaluator.reference_size());
  SelectOptions options;
  options.n = n;
  Selection s = Pipeline(evaluator, matrix, options, 0).Greedy(n);
  s.seconds = SecondsSince(start);
  return s;
}

namespace {

// Whether `options` is a question select.cpp's pipeline and SelectConstrained do not ask, and
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
  const bool is_constrained = !options.constraints.empty();

  const Clock::time_point start = Clock::now();
  const detail::CoverageMatrix matrix = detail::MatrixFor(observations, reference_size, options);
  const double setup_seconds = SecondsSince(start);
  Logger()->debug("select: {} candidates, {} of {} reference cells seen, merged into {} elements",
                  matrix.candidate_count(), matrix.seen_weight(), reference_size,
                  matrix.element_count());
  Pipeline pipeline(evaluator, matrix, options, setup_seconds);
  const Objective objective = options.objective();
  if (objective == Objective::kSetCover) {
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
  }
  if (is_constrained || !options.fixed.empty())
    return detail::SelectConstrained(observations, reference_size, options);

  return detail::RunMethods<Selection>(pipeline, options, observations.size(), start);
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
  if (!options.constraints.empty() || !options.fixed.empty()) {
    if (options.min_points) RequirePointCounts(observations);
    return detail::ConstrainedCurve(observations, reference_size, options, results, first_n,
                                    last_n);
  }
  const auto has = [&](const std::string& method, int n) {
    return std::any_of(results.begin(), results.end(), [&](const Selection& s) {
      return s.method == method && s.n == n && s.k == (objective == Objective::kKCoverage ? options.k : 1);
    });
  };
  std::vector<Selection> curve;
  if (last_n < first_n) return curve;
  const CoverageEvaluator evaluator(observations, reference_size);
  const Clock::time_point start = Clock::now();
  if (options.min_points) RequirePointCounts(observations);
  const detail::CoverageMatrix matrix = detail::MatrixFor(observations, reference_size, options);
  Pipeline pipeline(evaluator, matrix, options, SecondsSince(start));
  const std::string greedy = MethodName(Method::kGreedy), local = MethodName(Method::kLocal);
  for (int n = first_n; n <= last_n; ++n) {
    const bool want_greedy = !has(greedy, n), want_local = !has(local, n);
    if (!want_greedy && !want_local) continue;
    Selection g = pipeline.Greedy(n);  // local starts from greedy's answer
    if (want_greedy) curve.push_back(std::move(g));
    if (want_local) curve.push_back(pipeline.Local());
  }
  return curve;
}

}  // namespace vantage
