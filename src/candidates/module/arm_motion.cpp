// A move of the arm around what its straight joint-space segment hits (issue 45): OMPL's
// RRT-Connect in the joint space within the URDF limits, the FCL checks as state validity, then
// a greedy shortcut. Deterministic: the sampler is seeded per move and nearest neighbours are
// searched exactly (linear scan: a plan holds a few thousand states at most).
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/datastructures/NearestNeighborsLinear.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "vantage/arm.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

/// OMPL's uniform sampler with its generator seeded by us, not by the process-wide seed
/// generator (whose order depends on which thread plans first).
class SeededSampler : public ob::RealVectorStateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint_fast32_t seed)
      : ob::RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

}  // namespace

PlannedMotion PlanMotion(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                         const std::vector<double>& from, const std::vector<double>& to,
                         const std::vector<double>& speeds, const MotionPlanOptions& options) {
  VANTAGE_CHECK(from.size() == to.size() && from.size() == kinematics.joint_names().size());
  VANTAGE_CHECK(options.resolution > 0 && options.max_samples > 0);
  // OMPL's progress lines are not vantage's log: set before any OMPL object exists (set at the
  // planner's setup, "Planner range detected" still reached stdout, into the summary).
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  ompl::msg::noOutputHandler();
  PlannedMotion motion;
  const auto is_free = [&](const std::vector<double>& q) {
    return collisions.Check(kinematics.LinkPosesAt(q)) == ArmCollision::kNone;
  };
  if (!is_free(from) || !is_free(to)) return motion;

  // The planned joints: those the arm moves, and any other that differs between the ends.
  std::vector<size_t> planned = kinematics.moved();
  for (size_t i = 0; i < from.size(); ++i)
    if (from[i] != to[i] && std::find(planned.begin(), planned.end(), i) == planned.end())
      planned.push_back(i);
  std::sort(planned.begin(), planned.end());
  if (planned.empty()) {
    motion.found = true;
    motion.waypoints = {from, to};
    motion.seconds = 0;
    return motion;
  }
  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(planned.size()));
  ob::RealVectorBounds bounds(static_cast<unsigned>(planned.size()));
  for (size_t k = 0; k < planned.size(); ++k) {
    const size_t i = planned[k];
    auto [lo, hi] = kinematics.limits()[i];
    // A joint without limits (continuous) may turn half a turn beyond either end.
    if (!std::isfinite(lo)) lo = std::min(from[i], to[i]) - std::numbers::pi;
    if (!std::isfinite(hi)) hi = std::max(from[i], to[i]) + std::numbers::pi;
    bounds.setLow(static_cast<unsigned>(k), std::min({lo, from[i], to[i]}));
    bounds.setHigh(static_cast<unsigned>(k), std::max({hi, from[i], to[i]}));
  }
  space->setBounds(bounds);
  const auto seed = static_cast<std::uint_fast32_t>(
      Rng(options.seed, Stream::kArmPlan, options.stream).NextU64() & 0xFFFFFFFFu);
  space->setStateSamplerAllocator([seed](const ob::StateSpace* s) -> ob::StateSamplerPtr {
    return std::make_shared<SeededSampler>(s, seed == 0 ? 1 : seed);
  });
  // OMPL checks a motion every longest-valid-segment of Euclidean joint distance; that step in
  // any one joint is at most as long, so every joint moves at most `resolution` between checks.
  space->setLongestValidSegmentFraction(
      std::min(1.0, options.resolution / space->getMaximumExtent()));

  const auto full = [&](const ob::State* state) {
    std::vector<double> q = from;
    const auto* values = state->as<ob::RealVectorStateSpace::StateType>()->values;
    for (size_t k = 0; k < planned.size(); ++k) q[planned[k]] = values[k];
    return q;
  };
  auto information = std::make_shared<ob::SpaceInformation>(space);
  information->setStateValidityChecker([&](const ob::State* state) {
    return information->satisfiesBounds(state) && is_free(full(state));
  });
  information->setup();
  ob::ScopedState<> start(space), goal(space);
  for (size_t k = 0; k < planned.size(); ++k) {
    start[static_cast<unsigned>(k)] = from[planned[k]];
    goal[static_cast<unsigned>(k)] = to[planned[k]];
  }
  auto problem = std::make_shared<ob::ProblemDefinition>(information);
  problem->setStartAndGoalStates(start, goal);
  og::RRTConnect planner(information);
  planner.setNearestNeighbors<ompl::NearestNeighborsLinear>();
  planner.setProblemDefinition(problem);
  planner.setup();

  // The sample budget ends the search (the same on every machine); the time limit is a net.
  size_t iterations = 0;
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(options.time_limit));
  const ob::PlannerTerminationCondition stop([&] {
    if (++iterations > options.max_samples) return true;
    if (std::chrono::steady_clock::now() > deadline) {
      motion.stopped_by_time = true;
      return true;
    }
    return false;
  });
  const ob::PlannerStatus status = planner.solve(stop);
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return motion;
  motion.stopped_by_time = false;
  auto* path = problem->getSolutionPath()->as<og::PathGeometric>();
  std::vector<std::vector<double>> raw;
  for (const ob::State* state : path->getStates()) raw.push_back(full(state));
  raw.front() = from;
  raw.back() = to;

  // Shortcut: from each waypoint straight to the farthest later one whose segment is free (a
  // deterministic stand-in for OMPL's PathSimplifier, whose generator cannot be seeded per call).
  motion.waypoints.push_back(from);
  for (size_t at = 0; at + 1 < raw.size();) {
    size_t next = at + 1;
    for (size_t j = raw.size() - 1; j > at + 1; --j) {
      if (StraightMotionIsFree(kinematics, collisions, raw[at], raw[j], options.resolution)) {
        next = j;
        break;
      }
    }
    // RRT-Connect's own segments were checked at OMPL's step; check them at ours too.
    if (next == at + 1 &&
        !StraightMotionIsFree(kinematics, collisions, raw[at], raw[next], options.resolution))
      return PlannedMotion{};
    motion.waypoints.push_back(raw[next]);
    at = next;
  }
  motion.seconds = 0;
  for (size_t k = 0; k + 1 < motion.waypoints.size(); ++k)
    motion.seconds += MotionSeconds(motion.waypoints[k], motion.waypoints[k + 1], speeds);
  motion.found = true;
  return motion;
}

}  // namespace vantage
