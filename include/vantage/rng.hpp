#pragma once
/// Deterministic random streams keyed by (seed, purpose, index): no shared generator, so results
/// do not depend on thread scheduling or on the standard library (STYLE.md, determinism).
#include <cstdint>

namespace vantage {

enum class Stream : uint64_t {
  kPopulation = 1,
  kRoll = 2,
  kRansac = 3,
  kKMeans = 4,
  kRefine = 5,  ///< refine.hpp: which poses of a sensor's pool are traced
  kArm = 6,     ///< arm.hpp: random joint-space views
  kArmIk = 7,   ///< arm.hpp: the restarts of inverse kinematics
  kArmPlan = 8, ///< arm.hpp: the planner's samples around a colliding move (PlanMotion)
  kPoseTolerance = 9,  ///< pose_tolerance.hpp: each sensor's perturbed poses
  kTest = 99,
};

/// SplitMix64-seeded xoshiro256** generator.
class Rng {
 public:
  Rng(uint64_t seed, Stream stream, uint64_t index, uint64_t sub_index = 0);
  uint64_t NextU64();
  /// Uniform in [0, 1) with 53 random bits.
  double Uniform01();
  /// Uniform in [a, b).
  double Uniform(double a, double b) { return a + (b - a) * Uniform01(); }
  /// Uniform integer in [0, n), n > 0, without modulo bias.
  uint64_t Below(uint64_t n);

 private:
  uint64_t s_[4];
};

}  // namespace vantage
