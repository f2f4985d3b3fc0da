// Mounting tolerance (issue 46): coverage over perturbed layouts, each sensor re-traced.
#include "vantage/pose_tolerance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage {

void PoseToleranceOptions::Validate() const {
  if (!(position >= 0 && position <= 1))
    throw InputError(fmt::format(
        "--pose-tolerance: the position tolerance {} m must lie in [0, 1] m — e.g. 0.02,2 for "
        "2 cm and 2 degrees",
        position));
  if (!(angle_deg >= 0 && angle_deg <= 90))
    throw InputError(fmt::format(
        "--pose-tolerance: the angle tolerance {} deg must lie in [0, 90] degrees — e.g. 0.02,2 "
        "for 2 cm and 2 degrees",
        angle_deg));
  if (samples < 1 || samples > 10000)
    throw InputError(
        fmt::format("--pose-samples {} must lie in [1, 10000] — e.g. 64", samples));
}

uint64_t SensorKey(const std::string& name) {
  uint64_t hash = 14695981039346656037ull;
  for (const char c : name) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

Pose PerturbedPose(const Pose& planned, const PoseToleranceOptions& options, uint64_t key,
                   uint32_t sample) {
  Rng rng(options.seed, Stream::kPoseTolerance, key, sample);
  // A uniform direction (z uniform in [-1, 1], azimuth uniform) for the offset and the axis.
  const auto direction = [&rng] {
    const double z = rng.Uniform(-1.0, 1.0);
    const double phi = rng.Uniform(0.0, 2.0 * std::numbers::pi);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  const Vec3 offset = direction() * options.position * std::cbrt(rng.Uniform01());
  const Vec3 axis = direction();
  const double angle = rng.Uniform01() * options.angle_deg * std::numbers::pi / 180.0;
  Pose pose = planned;
  pose.position += offset;
  pose.rotation = (planned.rotation * Quat(Eigen::AngleAxisd(angle, axis))).normalized();
  return pose;
}

PoseTolerance AssessPoseTolerance(const VisibilityFile& data, const std::vector<Selection>& results,
                                  const RayScene& rays, const ObserveOptions& observe,
                                  const PoseToleranceOptions& options) {
  options.Validate();
  const auto samples = static_cast<uint32_t>(options.samples);
  // Each sensor any result chose is traced once per sample, whichever results share it: the
  // pool holds its planned observation, then its perturbed ones.
  std::map<uint32_t, uint32_t> slot;  // candidate -> its place among the sensors traced
  std::vector<Candidate> perturbed;
  for (const Selection& s : results) {
    for (uint32_t c : s.chosen) {
      if (!slot.emplace(c, static_cast<uint32_t>(slot.size())).second) continue;
      for (uint32_t sample = 0; sample < samples; ++sample) {
        Candidate moved = data.candidates.at(c);
        moved.world_from_body =
            PerturbedPose(moved.world_from_body, options, SensorKey(moved.name), sample);
        perturbed.push_back(std::move(moved));
      }
    }
  }
  ObserveOptions traced = observe;
  traced.quality = data.quality;
  traced.progress = nullptr;
  std::vector<Observation> pool = Observe(rays, data.reference, perturbed, traced);
  const auto sensors = static_cast<uint32_t>(slot.size());
  // The planned observations in the sensors' places (the map iterates by candidate index, which
  // is not the order the results first chose them in).
  std::vector<uint32_t> by_place(slot.size());
  for (const auto& [candidate, place] : slot) by_place[place] = candidate;
  for (uint32_t candidate : by_place) pool.push_back(data.observations.at(candidate));
  const CoverageEvaluator evaluator(pool, data.reference.size());
  const auto planned = [&](uint32_t c) { return sensors * samples + slot.at(c); };
  const auto moved = [&](uint32_t c, uint32_t sample) { return slot.at(c) * samples + sample; };

  PoseTolerance tolerance;
  tolerance.options = options;
  for (size_t index = 0; index < results.size(); ++index) {
    const Selection& s = results[index];
    PoseSpread spread;
    spread.result = static_cast<int>(index);
    std::vector<uint32_t> layout;
    for (uint32_t c : s.chosen) layout.push_back(planned(c));
    spread.nominal = evaluator.CoverageUnder(layout, s.k, s.min_points);
    std::vector<double> coverage;
    for (uint32_t sample = 0; sample < samples; ++sample) {
      for (size_t i = 0; i < s.chosen.size(); ++i) layout[i] = moved(s.chosen[i], sample);
      coverage.push_back(evaluator.CoverageUnder(layout, s.k, s.min_points));
    }
    double sum = 0;
    for (double c : coverage) sum += c;
    spread.mean = coverage.empty() ? spread.nominal : sum / static_cast<double>(coverage.size());
    std::sort(coverage.begin(), coverage.end());
    const size_t rank = static_cast<size_t>(std::ceil(0.05 * static_cast<double>(samples)));
    spread.p5 = coverage.at(std::max<size_t>(rank, 1) - 1);
    spread.worst = coverage.front();
    // One sensor off at a time, the others as planned.
    for (size_t i = 0; i < s.chosen.size(); ++i) {
      for (size_t j = 0; j < s.chosen.size(); ++j) layout[j] = planned(s.chosen[j]);
      double alone = 0;
      for (uint32_t sample = 0; sample < samples; ++sample) {
        layout[i] = moved(s.chosen[i], sample);
        alone += evaluator.CoverageUnder(layout, s.k, s.min_points);
      }
      spread.sensor_loss.push_back(spread.nominal - alone / samples);
    }
    // Ties: the first chosen.
    const auto costliest = std::max_element(spread.sensor_loss.begin(), spread.sensor_loss.end());
    if (costliest != spread.sensor_loss.end())
      spread.costliest = s.chosen[static_cast<size_t>(costliest - spread.sensor_loss.begin())];
    tolerance.results.push_back(std::move(spread));
  }
  return tolerance;
}

}  // namespace vantage
