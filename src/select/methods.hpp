#pragma once
/// The selection methods on the merged matrix (SYSTEM.md, Select). Each returns candidate indices
/// in the order chosen; coverages are counted in reference cells (element weights).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "select/coverage_matrix.hpp"

namespace vantage::detail {

/// The candidate that sees the most cells; ties go to the lower index. Needs >= 1 candidate.
uint32_t BestCandidate(const CoverageMatrix& matrix);

/// The paper's Algorithm 2: up to `iterations` random n-subsets, iteration i drawn from
/// Rng(seed, Stream::kRansac, i); keeps a subset only when strictly better; stops once the best
/// reaches `stop_coverage` (a fraction of |R|). The first draw is always kept, so the answer has
/// n sensors even when every draw covers nothing.
std::vector<uint32_t> RansacChoice(
    const CoverageMatrix& matrix, size_t n, int iterations, double stop_coverage, uint64_t seed);

/// Lazy greedy maximum coverage from the start set `chosen` up to n sensors: each step adds the
/// candidate of largest gain (ties: lower index); once nothing adds anything, the lowest-index
/// unused candidates fill up to n.
std::vector<uint32_t> GreedyComplete(const CoverageMatrix& matrix,
                                     std::vector<uint32_t> chosen,
                                     size_t n);

/// Best-improvement 1-swap local search from `chosen`: repeatedly makes the swap (one chosen out,
/// one unused in, in place) that adds the most cells, until no swap adds any. Ties go to the
/// earlier position, then to the lower candidate index. Deterministic, never worse than `chosen`.
std::vector<uint32_t> LocalSearch(const CoverageMatrix& matrix, std::vector<uint32_t> chosen);

/// Cheap upper bound on the cells any n sensors can cover (submodularity): the cells of `chosen`
/// plus the n largest gains over them, at most the cells seen by anyone.
uint64_t SimpleUpperBound(const CoverageMatrix& matrix, std::span<const uint32_t> chosen, size_t n);

struct ExactResult {
  std::vector<uint32_t> chosen;
  uint64_t upper_bound = 0;  ///< cells; >= the cells chosen covers
  bool proven_optimal = false;
  std::string note;  ///< why the solver was not used or failed; empty when it ran normally
};

/// Maximum coverage as a MILP solved by CBC, warm-started from `start` (n sensors). The model is
/// shrunk first: dominated candidates are dropped (with "at most n" sensors that loses nothing;
/// the answer is padded back to n), elements are re-merged over the remaining candidates, and
/// elements that only one candidate sees go into that candidate's objective. If CBC fails the
/// answer is `start` with SimpleUpperBound. Never returns fewer cells than `start` covers.
ExactResult SolveExact(const CoverageMatrix& matrix,
                       size_t n,
                       const std::vector<uint32_t>& start,
                       double time_limit);

}  // namespace vantage::detail
