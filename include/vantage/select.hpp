#pragma once
/// Selection of the constellation from the visibility matrix (SYSTEM.md, stage 5).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/observe.hpp"

namespace vantage {

enum class Method { kBest, kRansac, kGreedy, kLocal, kExact, kAll };

/// "best", "ransac", ... ; ParseMethod throws InputError listing the valid names.
std::string MethodName(Method method);
Method ParseMethod(const std::string& name);

struct SelectOptions {
  int n = 1;  ///< sensors wanted, 1 <= n <= candidates
  Method method = Method::kAll;
  int ransac_iterations = 1000;       ///< I of Algorithm 2
  double ransac_stop_coverage = 1.0;  ///< C of Algorithm 2, fraction
  uint64_t seed = 1;
  double time_limit = 60;  ///< seconds, for exact
  /// Throws InputError naming the field.
  void Validate(size_t candidate_count) const;
};

struct Selection {
  std::string method;
  int n = 0;
  std::vector<uint32_t> chosen;  ///< candidate indices, in the order chosen
  double coverage = 0;           ///< |∪O ∩ R| / |R|
  double paper_coverage = 0;     ///< |∪O| / |R|
  std::optional<double> upper_bound;
  bool proven_optimal = false;
  double seconds = 0;
};

/// Coverage of unions of observation sets.
class CoverageEvaluator {
 public:
  CoverageEvaluator(std::span<const Observation> observations, size_t reference_size);
  /// Number of reference cells seen by the union of `chosen`.
  size_t CoveredCount(std::span<const uint32_t> chosen) const;
  double Coverage(std::span<const uint32_t> chosen) const;
  double PaperCoverage(std::span<const uint32_t> chosen) const;
  size_t reference_size() const { return reference_size_; }
  /// The observation sets it evaluates (one per candidate, in candidate order).
  std::span<const Observation> observations() const { return observations_; }

 private:
  std::span<const Observation> observations_;
  size_t reference_size_;
};

/// Runs `options.method`; kAll gives best (n = 1), then ransac and greedy (and the other
/// methods) for every n from 1 to options.n. Deterministic for a seed.
std::vector<Selection> Select(std::span<const Observation> observations, size_t reference_size,
                              const SelectOptions& options);

/// Single methods, each for exactly options.n sensors.
Selection SelectBest(const CoverageEvaluator& evaluator);
Selection SelectRansac(const CoverageEvaluator& evaluator, const SelectOptions& options);
Selection SelectGreedy(const CoverageEvaluator& evaluator, int n);

}  // namespace vantage
