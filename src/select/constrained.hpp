#pragma once
/// Selection under installation constraints (vantage/constraints.hpp, docs/constraints.md):
/// greedy, local search, RANSAC and the MILP of maximum coverage restricted to feasible sets —
/// no conflicting pair chosen, and with a calibration rule a connected overlap graph.
#include <cstdint>
#include <span>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/constraints.hpp"
#include "vantage/select.hpp"

namespace vantage::detail {

/// Which sets of candidates the constraints allow.
class Feasibility {
 public:
  Feasibility(std::span<const Observation> observations, const InstallConstraints& constraints);
  size_t candidate_count() const { return conflicts_of_.size(); }
  bool has_calibration() const { return has_calibration_; }
  /// Whether a and b may not both be chosen.
  bool InConflict(uint32_t a, uint32_t b) const;
  /// Whether a and b are joined in the overlap graph (calibration rule).
  bool Joined(uint32_t a, uint32_t b) const;
  /// Sorted neighbours of `candidate` in the overlap graph (empty without a calibration rule).
  const std::vector<uint32_t>& Neighbours(uint32_t candidate) const {
    return neighbours_[candidate];
  }
  /// The conflict pairs (a < b).
  std::span<const Conflict> conflicts() const { return conflicts_; }
  /// Whether `set` + `candidate` keeps every conflict out and (with a calibration rule, `set`
  /// not empty) joins `candidate` to a member of `set`.
  bool CanAdd(std::span<const uint32_t> set, uint32_t candidate) const;
  /// No conflicting pair in `set`, and its overlap graph connected (with a calibration rule).
  bool IsFeasible(std::span<const uint32_t> set) const;

 private:
  bool IsConnected(std::span<const uint32_t> set) const;
  std::vector<Conflict> conflicts_;
  std::vector<std::vector<uint32_t>> conflicts_of_;
  std::vector<std::vector<uint32_t>> neighbours_;
  bool has_calibration_ = false;
};

/// Greedy under the constraints: each step adds the feasible candidate (Feasibility::CanAdd) of
/// largest gain (ties: lower index), zero gains included, up to n; stops early, with fewer
/// sensors, when no candidate can be added.
std::vector<uint32_t> ConstrainedGreedy(const CoverageMatrix& matrix, const Feasibility& feasible,
                                        size_t n);

/// Best-improvement local search under the constraints from the feasible `start`: moves are
/// adding a candidate (while fewer than n) and 1-swaps, each kept only when the set stays
/// feasible and covers strictly more; ties go to the earlier position, then the lower index.
std::vector<uint32_t> ConstrainedLocal(const CoverageMatrix& matrix, const Feasibility& feasible,
                                       std::vector<uint32_t> start, size_t n);

/// Algorithm 2 with the draws of RansacChoice (RansacDraw), infeasible draws rejected (they count
/// as iterations). Empty when no draw was feasible.
std::vector<uint32_t> ConstrainedRansac(const CoverageMatrix& matrix, const Feasibility& feasible,
                                        size_t n, int iterations, double stop_coverage,
                                        uint64_t seed);

/// Maximum coverage of at most n sensors under the constraints as a MILP solved by CBC (the
/// coverage MILP of exact.cpp plus x_a + x_b <= 1 per conflict and, with a calibration rule, a
/// single-commodity flow over the overlap edges), warm-started from the feasible `start`.
/// upper_bound is the least of CBC's bound and the unconstrained bounds (GreedyUpperBound, the
/// Lagrangian), all valid because constraints only lower the optimum. Never worse than `start`.
ExactResult SolveExactConstrained(const CoverageMatrix& matrix, const Feasibility& feasible,
                                  size_t n, const std::vector<uint32_t>& start, double time_limit);

/// Select for options whose `constraints` are not empty (the coverage objective): the same
/// methods and order as Select, each under the constraints.
std::vector<Selection> SelectConstrained(std::span<const Observation> observations,
                                         size_t reference_size, const SelectOptions& options);

/// CoverageCurve under the constraints: greedy and local at every n from 1 to last_n that
/// `results` lacks.
std::vector<Selection> ConstrainedCurve(std::span<const Observation> observations,
                                        size_t reference_size, const SelectOptions& options,
                                        const std::vector<Selection>& results, int last_n);

/// The draw `iteration` of RANSAC (ransac.cpp): n distinct candidates of order->size(); `order`
/// must hold the identity permutation and is restored.
void RansacDraw(uint64_t seed, uint64_t iteration, size_t n, std::vector<uint32_t>* order,
                std::vector<uint32_t>* drawn);

}  // namespace vantage::detail
