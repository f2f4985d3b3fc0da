// One camera on an arm (issue 45): each result's tour (select/tour: the order, from the motion
// times computed here from the arm), --cycle-time's greedy choice, and the checks of the tour's
// options before any ray.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/tour.hpp"

namespace vantage {

void ArmTourOptions::Validate() const {
  if (cycle_time && !(std::isfinite(*cycle_time) && *cycle_time > 0))
    throw InputError(AtPlace("--cycle-time", 0,
                             fmt::format("{} is not a positive number of seconds — give e.g. "
                                         "--cycle-time 20",
                                         *cycle_time)));
  if (joint_speed && !(std::isfinite(*joint_speed) && *joint_speed > 0))
    throw InputError(AtPlace("--joint-speed", 0,
                             fmt::format("{} is not a positive speed [rad/s or m/s] — give e.g. "
                                         "--joint-speed 1.0",
                                         *joint_speed)));
  if (frames < 1 || frames > 100000)
    throw InputError(AtPlace("--frames", 0,
                             fmt::format("{} is not a number of frames from 1 to 100000", frames)));
  if (!(std::isfinite(plan_seconds) && plan_seconds > 0 && plan_seconds <= 3600))
    throw InputError(AtPlace("--plan-time", 0,
                             fmt::format("{} is not a number of seconds in (0, 3600] — give e.g. "
                                         "--plan-time 2",
                                         plan_seconds)));
  if (!(std::isfinite(resolution) && resolution > 0 && resolution <= 1))
    throw InputError(AtPlace("--motion-resolution", 0,
                             fmt::format("{} is not a step in (0, 1] [rad or m]", resolution)));
}

namespace detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

const ArmSetup* SetupOf(const std::vector<ArmSetup>& arms, const Candidate& candidate) {
  if (!candidate.arm) return nullptr;
  for (const ArmSetup& arm : arms)
    if (arm.population == candidate.population) return &arm;
  return nullptr;
}

std::vector<double> Speeds(const ArmSetup& arm, const ArmTourOptions& options) {
  std::vector<double> speeds = arm.speeds;
  if (options.joint_speed) std::fill(speeds.begin(), speeds.end(), *options.joint_speed);
  return speeds;
}

/// Motion times among `views` (candidate indices, all on `arm`) and home, optimistic: the
/// straight move's time, its collision not yet checked (LazyTour checks what a tour uses).
TourTimes StraightTimes(const std::vector<Candidate>& candidates,
                        const std::vector<uint32_t>& views, const ArmSetup& arm,
                        const ArmTourOptions& options) {
  const std::vector<double> speeds = Speeds(arm, options);
  const size_t n = views.size();
  const auto configuration = [&](size_t k) -> const std::vector<double>& {
    return k == n ? arm.home : candidates[views[k]].arm->joints;
  };
  TourTimes times;
  times.motion.assign(n + 1, std::vector<double>(n + 1, 0.0));
  for (size_t a = 0; a <= n; ++a)
    for (size_t b = a + 1; b <= n; ++b)
      times.motion[a][b] = times.motion[b][a] =
          MotionSeconds(configuration(a), configuration(b), speeds);
  for (uint32_t view : views) {
    const double fps = candidates[view].sensor.fps;
    times.acquisition.push_back(fps > 0 ? options.frames / fps : 0.0);
  }
  return times;
}

/// A checked move, by pair of stops (lower index first): its time (straight, planned around a
/// collision, or +inf) and, when planned, the waypoints between the two stops (lower to higher).
struct MoveVerdict {
  double seconds = 0;
  bool planned = false;
  std::vector<std::vector<double>> via;
};
using MoveVerdicts = std::map<std::pair<size_t, size_t>, MoveVerdict>;

/// What the moves among `views` (candidate indices) and home are checked with.
struct MoveChecker {
  const std::vector<Candidate>& candidates;
  const std::vector<uint32_t>& views;
  const ArmSetup& arm;
  const ArmTourOptions& options;
  uint64_t seed;
  MoveVerdicts verdicts;

  size_t home() const { return views.size(); }
  const std::vector<double>& Configuration(size_t k) const {
    return k == home() ? arm.home : candidates[views[k]].arm->joints;
  }
  /// The planner's stream for a pair: the candidates' indices (home: 2^32 - 1), the same pair
  /// the same stream whatever the views' order.
  uint64_t Stream(size_t a, size_t b) const {
    const auto id = [&](size_t k) -> uint64_t { return k == home() ? 0xFFFFFFFFu : views[k]; };
    return (id(a) << 32) | id(b);
  }

  /// Checks the moves of `order` (home first and last) at the resolution; a move whose straight
  /// segment collides is planned around (OMPL), its time the planned path's, or +inf when the
  /// planner fails. Returns whether no time of `times` changed (the order's times were final).
  bool Check(const std::vector<uint32_t>& order, TourTimes* times) {
    bool unchanged = true;
    size_t at = home();
    std::vector<size_t> stops(order.begin(), order.end());
    stops.push_back(home());
    for (size_t next : stops) {
      const auto key = std::minmax(at, next);
      if (!verdicts.count(key)) {
        const std::vector<double>& from = Configuration(key.first);
        const std::vector<double>& to = Configuration(key.second);
        MoveVerdict verdict;
        verdict.seconds = times->motion[key.first][key.second];
        if (!StraightMotionIsFree(*arm.kinematics, *arm.collisions, from, to,
                                  options.resolution)) {
          MotionPlanOptions plan;
          plan.resolution = options.resolution;
          plan.time_limit = options.plan_seconds;
          plan.seed = seed;
          plan.stream = Stream(key.first, key.second);
          const PlannedMotion motion =
              PlanMotion(*arm.kinematics, *arm.collisions, from, to, Speeds(arm, options), plan);
          if (motion.stopped_by_time)
            spdlog::warn("planning the move between {} and {} stopped at --plan-time {} s: the "
                         "answer may differ on a faster machine — raise --plan-time",
                         Name(key.first), Name(key.second), options.plan_seconds);
          verdict.seconds = motion.seconds;  // +inf when not found
          verdict.planned = motion.found;
          if (motion.found)
            verdict.via.assign(motion.waypoints.begin() + 1, motion.waypoints.end() - 1);
          // Planned or not, the move is slower than its straight time was taken to be.
          times->motion[key.first][key.second] = times->motion[key.second][key.first] =
              verdict.seconds;
          unchanged = false;
        }
        verdicts.emplace(key, std::move(verdict));
      }
      at = next;
    }
    return unchanged;
  }

  /// The waypoints of the move from stop `a` to stop `b` (ends excluded), in that direction,
  /// with when each is reached.
  ArmVia Via(size_t a, size_t b) const {
    ArmVia via;
    const auto found = verdicts.find(std::minmax(a, b));
    if (found == verdicts.end()) return via;
    via.waypoints = found->second.via;
    if (a > b) std::reverse(via.waypoints.begin(), via.waypoints.end());
    const std::vector<double> speeds = Speeds(arm, options);
    const std::vector<double>* previous = &Configuration(a);
    double t = 0;
    for (const auto& q : via.waypoints) {
      t += MotionSeconds(*previous, q, speeds);
      via.seconds.push_back(t);
      previous = &q;
    }
    return via;
  }

  std::string Name(size_t k) const {
    return k == home() ? std::string("home") : candidates[views[k]].name;
  }
};

/// The tour of `views` with every move it uses checked: solve on optimistic times, check the
/// moves it uses (planning around those that collide), solve again until the answer's moves
/// all have their final times (or it needs an unconnected one). Optimal where Held–Karp ran:
/// an unchecked move's straight time is never more than its final time (a planned path is no
/// faster than the straight move: MotionSeconds is a norm).
Tour LazyTour(MoveChecker* checker, TourTimes* times) {
  std::vector<uint32_t> all(checker->views.size());
  for (uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  for (;;) {
    Tour tour = SolveTour(*times, all);
    if (!tour.connected()) return tour;
    if (checker->Check(tour.order, times)) return tour;
  }
}

ArmTour TourOf(const std::vector<Candidate>& candidates, const std::vector<uint32_t>& views,
               const ArmSetup& arm, const ArmTourOptions& options, uint64_t seed) {
  TourTimes times = StraightTimes(candidates, views, arm, options);
  MoveChecker checker{candidates, views, arm, options, seed, {}};
  const Tour tour = LazyTour(&checker, &times);
  ArmTour out;
  out.robot = arm.robot;
  out.population = arm.population;
  out.joint_names = arm.kinematics->joint_names();
  out.home = arm.home;
  out.resolution = options.resolution;
  out.tour = tour;
  size_t at = views.size();
  for (uint32_t k : tour.order) {
    out.views.push_back(views[k]);
    out.configurations.push_back(candidates[views[k]].arm->joints);
    out.move_seconds.push_back(times.motion[at][k]);
    out.move_via.push_back(checker.Via(at, k));
    out.acquisition_seconds.push_back(times.acquisition[k]);
    at = k;
  }
  out.return_seconds = times.motion[at][views.size()];
  out.return_via = checker.Via(at, views.size());
  for (const auto& [pair, verdict] : checker.verdicts) {
    out.unconnected_pairs += std::isfinite(verdict.seconds) ? 0 : 1;
    out.planned_pairs += verdict.planned ? 1 : 0;
  }
  // The tour's indices are the views' candidate indices.
  for (uint32_t& k : out.tour.order) k = views[k];
  return out;
}

}  // namespace

void CheckArmTourInputs(const std::vector<ArmSetup>& arms, const ArmTourOptions& options) {
  options.Validate();
  for (const ArmSetup& arm : arms) {
    if (options.joint_speed) break;
    const auto& names = arm.kinematics->joint_names();
    for (size_t i : arm.kinematics->moved()) {
      if (arm.speeds[i] > 0) continue;
      throw InputError(AtPlace("--joint-speed", 0,
                               fmt::format("joint '{}' of robot '{}' (population '{}') has no "
                                           "<limit velocity> — the tour cannot be timed; give "
                                           "it in the URDF or pass --joint-speed",
                                           names[i], arm.robot, arm.population)));
    }
  }
}

void AddArmTours(const std::vector<Candidate>& candidates, const std::vector<ArmSetup>& arms,
                 const ArmTourOptions& options, Report* report) {
  if (arms.empty()) return;
  report->tours.assign(report->results.size(), std::nullopt);
  for (size_t r = 0; r < report->results.size(); ++r) {
    const Selection& result = report->results[r];
    // The views on the arm of the result's first arm view (one camera, one arm).
    const ArmSetup* arm = nullptr;
    std::vector<uint32_t> views;
    for (uint32_t i : result.chosen) {
      const ArmSetup* of = SetupOf(arms, candidates[i]);
      if (!of) continue;
      if (!arm) arm = of;
      if (of->robot == arm->robot) views.push_back(i);
    }
    if (!arm) continue;
    report->tours[r] = TourOf(candidates, views, *arm, options, report->seed);
    const ArmTour& tour = *report->tours[r];
    spdlog::info("{} n={}: tour of {} views {:.2f} s ({:.2f} s moving, {:.2f} s acquiring; {}{})",
                 result.method, result.n, views.size(), tour.tour.total_seconds,
                 tour.tour.motion_seconds, tour.tour.acquisition_seconds, tour.tour.method,
                 tour.tour.connected() ? "" : "; some move is unconnected");
  }
}

Selection CycleTimeSelection(const VisibilityFile& data, const std::vector<ArmSetup>& arms,
                             const ArmTourOptions& options, uint64_t seed) {
  VANTAGE_CHECK(options.cycle_time.has_value());
  const auto start = std::chrono::steady_clock::now();
  // The views of the first arm, with their observations.
  const ArmSetup* arm = nullptr;
  std::vector<uint32_t> views;
  for (uint32_t i = 0; i < data.candidates.size(); ++i) {
    const ArmSetup* of = SetupOf(arms, data.candidates[i]);
    if (!of) continue;
    if (!arm) arm = of;
    if (of->robot == arm->robot) views.push_back(i);
  }
  if (!arm)
    throw InputError(AtPlace("--cycle-time", 0,
                             "no candidate is on an arm — --cycle-time times an arm's tour; add "
                             "an `arm` population (docs/arm.md)"));
  std::vector<Observation> observations;
  for (uint32_t i : views) observations.push_back(data.observations[i]);
  TourTimes times = StraightTimes(data.candidates, views, *arm, options);
  MoveChecker checker{data.candidates, views, *arm, options, seed, {}};
  CycleTimeResult result;
  for (;;) {
    result = MostCoverageWithinCycleTime(times, observations, data.reference.size(),
                                         *options.cycle_time);
    if (result.chosen.empty()) break;
    if (checker.Check(result.tour.order, &times)) break;
  }
  Selection selection;
  selection.method = "cycle-time";
  selection.objective = "cycle-time";
  for (uint32_t k : result.chosen) selection.chosen.push_back(views[k]);
  selection.n = static_cast<int>(selection.chosen.size());
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  selection.coverage = evaluator.Coverage(selection.chosen);
  selection.paper_coverage = evaluator.PaperCoverage(selection.chosen);
  selection.seconds = SecondsSince(start);
  return selection;
}

}  // namespace detail
}  // namespace vantage
