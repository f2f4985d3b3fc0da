// Select: runs the methods on the merged matrix and scores their answers (SYSTEM.md, stage 5).
//
// Every method works on one detail::CoverageMatrix, built once per Select call: reference cells
// that exactly the same candidates see are merged into one weighted element and cells nobody
// sees are dropped, which keeps coverage exact and shrinks typical instances by orders of
// magnitude. Coverage and paper_coverage of every answer are then recomputed by
// CoverageEvaluator from the observations themselves, never taken from a method's bookkeeping.
#include "vantage/select.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;

// In "all", `exact` runs for every n only on instances of at most this many candidates, each run
// limited to the smaller of options.time_limit and kAllExactSeconds, so that "all" stays
// interactive; `--method exact` alone has no size cap and the full time limit.
constexpr size_t kAllExactMaxCandidates = 2000;
constexpr double kAllExactSeconds = 10.0;

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

Selection Scored(const CoverageEvaluator& evaluator,
                 Method method,
                 std::vector<uint32_t> chosen,
                 double seconds) {
  Selection s;
  s.method = MethodName(method);
  s.n = static_cast<int>(chosen.size());
  s.chosen = std::move(chosen);
  s.coverage = evaluator.Coverage(s.chosen);
  s.paper_coverage = evaluator.PaperCoverage(s.chosen);
  s.seconds = seconds;
  return s;
}

// Greedy, local search and exact for one n, each built on the one before (local starts from
// greedy's answer, exact is warm-started from local's), so each one's seconds include the
// earlier steps it needed, as if it had run alone.
class Pipeline {
 public:
  Pipeline(const CoverageEvaluator& evaluator,
           const detail::CoverageMatrix& matrix,
           double setup_seconds)
      : evaluator_(evaluator), matrix_(matrix), setup_seconds_(setup_seconds) {}

  Selection Ransac(const SelectOptions& options, int n) const {
    const Clock::time_point start = Clock::now();
    std::vector<uint32_t> chosen =
        detail::RansacChoice(matrix_, static_cast<size_t>(n), options.ransac_iterations,
                             options.ransac_stop_coverage, options.seed);
    return Scored(evaluator_, Method::kRansac, std::move(chosen),
                  setup_seconds_ + SecondsSince(start));
  }

  Selection Greedy(int n) {
    const Clock::time_point start = Clock::now();
    greedy_ = detail::GreedyComplete(matrix_, {}, static_cast<size_t>(n));
    greedy_seconds_ = setup_seconds_ + SecondsSince(start);
    return Scored(evaluator_, Method::kGreedy, greedy_, greedy_seconds_);
  }

  /// After Greedy(n).
  Selection Local() {
    const Clock::time_point start = Clock::now();
    local_ = detail::LocalSearch(matrix_, greedy_);
    local_seconds_ = greedy_seconds_ + SecondsSince(start);
    return Scored(evaluator_, Method::kLocal, local_, local_seconds_);
  }

  /// After Local().
  Selection Exact(double time_limit) const {
    const Clock::time_point start = Clock::now();
    const detail::ExactResult exact =
        detail::SolveExact(matrix_, local_.size(), local_, time_limit);
    if (!exact.proven_optimal && !exact.note.empty()) {
      Logger()->warn("exact, n = {}: {}; reporting the best answer found and an upper bound",
                     local_.size(), exact.note);
    } else if (!exact.note.empty()) {
      Logger()->debug("exact, n = {}: {}", local_.size(), exact.note);
    }
    Selection s =
        Scored(evaluator_, Method::kExact, exact.chosen, local_seconds_ + SecondsSince(start));
    s.upper_bound = std::max(Fraction(exact.upper_bound, matrix_.reference_size()), s.coverage);
    s.proven_optimal = exact.proven_optimal;
    return s;
  }

 private:
  const CoverageEvaluator& evaluator_;
  const detail::CoverageMatrix& matrix_;
  double setup_seconds_;
  std::vector<uint32_t> greedy_;
  std::vector<uint32_t> local_;
  double greedy_seconds_ = 0;
  double local_seconds_ = 0;
};

void ValidateN(int n, size_t candidate_count) {
  SelectOptions options;
  options.n = n;
  options.Validate(candidate_count);
}

}  // namespace

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
  Selection s = Scored(evaluator, Method::kBest, {best}, 0);
  // The best single candidate is the optimum for n = 1.
  s.upper_bound = s.coverage;
  s.proven_optimal = true;
  s.seconds = SecondsSince(start);
  return s;
}

Selection SelectRansac(const CoverageEvaluator& evaluator, const SelectOptions& options) {
  const Clock::time_point start = Clock::now();
  options.Validate(evaluator.observations().size());
  const detail::CoverageMatrix matrix(evaluator.observations(), evaluator.reference_size());
  Selection s = Pipeline(evaluator, matrix, 0).Ransac(options, options.n);
  s.seconds = SecondsSince(start);
  return s;
}

Selection SelectGreedy(const CoverageEvaluator& evaluator, int n) {
  const Clock::time_point start = Clock::now();
  ValidateN(n, evaluator.observations().size());
  const detail::CoverageMatrix matrix(evaluator.observations(), evaluator.reference_size());
  Selection s = Pipeline(evaluator, matrix, 0).Greedy(n);
  s.seconds = SecondsSince(start);
  return s;
}

std::vector<Selection> Select(std::span<const Observation> observations,
                              size_t reference_size,
                              const SelectOptions& options) {
  options.Validate(observations.size());
  const CoverageEvaluator evaluator(observations, reference_size);
  if (options.method == Method::kBest) return {SelectBest(evaluator)};

  const Clock::time_point start = Clock::now();
  const detail::CoverageMatrix matrix(observations, reference_size);
  const double setup_seconds = SecondsSince(start);
  Logger()->debug("select: {} candidates, {} of {} reference cells seen, merged into {} elements",
                  matrix.candidate_count(), matrix.seen_weight(), reference_size,
                  matrix.element_count());
  Pipeline pipeline(evaluator, matrix, setup_seconds);

  switch (options.method) {
    case Method::kRansac:
      return {pipeline.Ransac(options, options.n)};
    case Method::kGreedy:
      return {pipeline.Greedy(options.n)};
    case Method::kLocal:
      pipeline.Greedy(options.n);
      return {pipeline.Local()};
    case Method::kExact:
      pipeline.Greedy(options.n);
      pipeline.Local();
      return {pipeline.Exact(options.time_limit)};
    case Method::kBest:
    case Method::kAll:
      break;
  }

  std::vector<Selection> results{SelectBest(evaluator)};
  const bool run_exact = observations.size() <= kAllExactMaxCandidates;
  if (!run_exact) {
    Logger()->info("select: exact skipped in 'all' ({} candidates > {}); use --method exact",
                   observations.size(), kAllExactMaxCandidates);
  }
  for (int n = 1; n <= options.n; ++n) {
    results.push_back(pipeline.Ransac(options, n));
    results.push_back(pipeline.Greedy(n));
    results.push_back(pipeline.Local());
    if (run_exact)
      results.push_back(pipeline.Exact(std::min(options.time_limit, kAllExactSeconds)));
  }
  return results;
}

}  // namespace vantage
