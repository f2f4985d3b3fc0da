#pragma once
/// Mounting tolerance (issue 46): how a result's coverage spreads when each sensor is mounted a
/// little off its planned pose (a bracket off by 2 cm and 2 degrees), from perturbed layouts that
/// are re-traced, beside the single-failure and field-of-view read-outs of robustness.hpp.
#include <cstdint>
#include <string>
#include <vector>

#include "vantage/observe.hpp"
#include "vantage/select.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {

/// `--pose-tolerance P,A` and `--pose-samples S`.
struct PoseToleranceOptions {
  double position = 0;   ///< P [m]: each sensor's offset lies in a ball of this radius
  double angle_deg = 0;  ///< A [deg]: each sensor turns by up to this angle about a random axis
  int samples = 64;      ///< perturbed layouts per result
  uint64_t seed = 1;     ///< the run's seed: the same layouts whatever the thread count
  /// InputError naming --pose-tolerance or --pose-samples: P outside [0, 1] m, A outside
  /// [0, 90] deg, S outside [1, 10000].
  void Validate() const;
};

/// One result's coverage over its perturbed layouts (counted as the result counts: k,
/// min_points).
struct PoseSpread {
  int result = -1;     ///< index into the run's results
  double nominal = 0;  ///< the result's coverage as planned
  double mean = 0;
  double p5 = 0;       ///< 5th percentile (nearest rank: the ceil(0.05 S)-th smallest)
  double worst = 0;
  /// Per chosen sensor (chosen order), the mean coverage lost when it alone is mounted off.
  std::vector<double> sensor_loss;
  uint32_t costliest = 0;  ///< candidate index of the sensor whose error alone costs the most
};

struct PoseTolerance {
  PoseToleranceOptions options;
  std::vector<PoseSpread> results;  ///< one per assessed result, in result order
};

/// The pose of a sensor in perturbed layout `sample`: an offset uniform in the ball of radius
/// options.position, then a turn about a uniformly random axis (through the sensor) by an angle
/// uniform in [0, options.angle_deg]. Drawn from (seed, `key`, sample) alone; AssessPoseTolerance
/// keys a sensor by its name (SensorKey), so a sensor is off by the same amount in every result
/// and in every command (`select` and `evaluate` of the same layout agree).
Pose PerturbedPose(const Pose& planned, const PoseToleranceOptions& options, uint64_t key,
                   uint32_t sample);
/// FNV-1a 64 of a sensor's name: its key for PerturbedPose.
uint64_t SensorKey(const std::string& name);

/// The spread of every result of `results` over `data` (the visibility file of the scene whose
/// RayScene is `rays`), each chosen sensor re-traced once per sample with `observe` (the data's
/// quality filter). Tolerance 0 gives every sample the nominal coverage. Deterministic.
PoseTolerance AssessPoseTolerance(const VisibilityFile& data, const std::vector<Selection>& results,
                                  const RayScene& rays, const ObserveOptions& observe,
                                  const PoseToleranceOptions& options);

}  // namespace vantage
