#include "select/run_methods.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "select/methods.hpp"
#include "select/model.hpp"
#include "vantage/select_states.hpp"

namespace vantage::detail {

namespace {

// One exact run of `all`: its job, and its place in the results.
template <class Result>
struct ExactRun {
  std::function<ExactDone<Result>(double)> job;
  size_t slot = 0;
  std::function<void()> log;
};

// `all`'s exact runs in AllExactTime's lanes: each lane (the calling thread and lanes - 1 more)
// takes the smallest n not yet started, with its share of the lane's time.
template <class Result>
void RunExactLanes(size_t lanes, double time_limit, std::vector<ExactRun<Result>>* runs,
                   std::vector<Result>* results) {
  if (runs->empty()) return;
  std::atomic<size_t> next{0};
  std::vector<std::exception_ptr> failures(lanes);
  const auto lane = [&](size_t which) {
    try {
      AllExactTime time(time_limit);
      for (size_t j; (j = next.fetch_add(1)) < runs->size();) {
        ExactRun<Result>& run = (*runs)[j];
        const auto start = std::chrono::steady_clock::now();
        ExactDone<Result> done = run.job(time.Share(runs->size() - j, lanes));
        (*results)[run.slot] = std::move(done.result);
        run.log = std::move(done.log);
        time.Spend(SecondsSince(start));
      }
    } catch (...) {
      failures[which] = std::current_exception();
      next = runs->size();  // the other lanes start nothing more
    }
  };
  std::vector<std::thread> others;
  for (size_t which = 1; which < lanes; ++which) others.emplace_back(lane, which);
  lane(0);
  for (std::thread& t : others) t.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
}

}  // namespace

template <class Result>
std::vector<Result> RunMethods(MethodSteps<Result>& steps, const SelectOptions& options,
                               size_t candidates, std::chrono::steady_clock::time_point began) {
  const SelectionKind kind = KindFor(options);
  const bool local = kind.Applies(Method::kLocal);
  const auto n = static_cast<size_t>(options.n);
  const double limit = options.time_limit;
  const auto exact_now = [&](double seconds) {
    ExactDone<Result> done = steps.Exact()(seconds);
    if (done.log) done.log();
    return std::move(done.result);
  };
  switch (options.method) {
    case Method::kBest:
      return {steps.Best()};
    case Method::kRansac:
      return {steps.Ransac(n, options.ransac_iterations)};
    case Method::kGreedy:
      return {steps.Greedy(n)};
    case Method::kLocal:
      steps.Greedy(n);
      return {steps.Local()};
    case Method::kExact:
      steps.Greedy(n);
      if (local) steps.Local();
      // The time limit bounds the whole method: the matrix, greedy and local it started from
      // count (at least a tenth of the limit is left to exact itself).
      return {exact_now(std::max(0.1 * limit, limit - SecondsSince(began)))};
    case Method::kAll:
      break;
  }

  // "all" for one goal or one budget: no n to vary.
  if (kind.limit != SelectionKind::Limit::kSensors) {
    std::vector<Result> results{steps.Greedy(n)};
    if (local) results.push_back(steps.Local());
    results.push_back(exact_now(limit));
    return results;
  }

  // Per n: best's row, then RANSAC (AllRansacShare's iterations), greedy and local for every n
  // (deterministic), then exact from each n's local answer in AllExactTime's lanes, each result
  // in its n's place.
  std::vector<Result> results;
  if (std::optional<Result> head = steps.TableHead()) results.push_back(std::move(*head));
  const AllExactTime exact_time(candidates, limit, options.n);
  if (!exact_time.runs()) {
    spdlog::info("select: exact skipped in 'all' ({} candidates > {}); use --method exact",
                   candidates, AllExactTime::kMaxCandidates);
  }
  std::vector<ExactRun<Result>> exact_runs;
  for (size_t k = steps.FirstN(); k <= n; ++k) {
    results.push_back(steps.Ransac(
        k, AllRansacShare::Iterations(options.ransac_iterations, static_cast<int>(k), options.n)));
    results.push_back(steps.Greedy(k));
    results.push_back(steps.Local());
    if (!exact_time.runs()) continue;
    exact_runs.push_back({steps.Exact(), results.size(), {}});
    results.emplace_back();
  }
  const size_t threads =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  const size_t lanes =
      steps.ParallelExact() ? AllExactTime::Lanes(threads, exact_runs.size()) : 1;
  RunExactLanes(lanes, limit, &exact_runs, &results);
  for (const ExactRun<Result>& run : exact_runs)
    if (run.log) run.log();
  return results;
}

template std::vector<Selection> RunMethods(MethodSteps<Selection>&, const SelectOptions&, size_t,
                                           std::chrono::steady_clock::time_point);
template std::vector<StateSelection> RunMethods(MethodSteps<StateSelection>&,
                                                const SelectOptions&, size_t,
                                                std::chrono::steady_clock::time_point);

}  // namespace vantage::detail
