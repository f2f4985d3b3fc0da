#pragma once
/// The one order in which the methods run (SYSTEM.md, Select): `--method` picks one, and `all`
/// runs them side by side — per n, best's row first where there is one, then RANSAC, greedy and
/// local, and exact from local's answer in AllExactTime's lanes; for a goal greedy and exact; for
/// a budget greedy, local and exact. Every way of selecting (plain cells, under installation
/// rules or with kept sensors, over the states of a scene) runs its methods through RunMethods,
/// so the order, the time rules and the iteration rules are stated once, here.
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>

#include "vantage/select.hpp"

namespace vantage::detail {


/// One exact run's answer, and what it has to say, logged once every lane is done (in n order).
template <class Result>
struct ExactDone {
  Result result;
  std::function<void()> log;
};

/// The methods of one way of selecting, on one model: each step built on the one before (local
/// from greedy's answer; exact from local's, or greedy's for a goal), seconds including the steps
/// it needed. n is ignored where the objective has none (a goal, a budget).
template <class Result>
class MethodSteps {
 public:
  virtual ~MethodSteps() = default;
  /// `--method best`: the best single candidate (or single addition to the kept sensors),
  /// proven optimal for its n. Throws InputError where none exists.
  virtual Result Best() = 0;
  /// The row that heads `all`'s table (best's, where the objective has one), or none.
  virtual std::optional<Result> TableHead() = 0;
  /// The smallest n `all`'s table runs (k for k-coverage; past the kept sensors and their chain).
  virtual size_t FirstN() const = 0;
  virtual Result Ransac(size_t n, int iterations) = 0;
  virtual Result Greedy(size_t n) = 0;
  /// After Greedy(n).
  virtual Result Local() = 0;
  /// Exact from the answer of the last step (Local, or Greedy for a goal), as a job that runs
  /// later, within the seconds it is given; safe on another thread when ParallelExact().
  virtual std::function<ExactDone<Result>(double seconds)> Exact() = 0;
  /// Whether `all`'s exact runs may share AllExactTime's lanes (else one lane, n after n).
  virtual bool ParallelExact() const { return false; }
};

/// The results `options.method` asks for, from `steps`, in report order. `began`: when the
/// selection began (the matrix included), so that `--time-limit` bounds the whole method.
template <class Result>
std::vector<Result> RunMethods(MethodSteps<Result>& steps, const SelectOptions& options,
                               size_t candidates, std::chrono::steady_clock::time_point began);

}  // namespace vantage::detail
