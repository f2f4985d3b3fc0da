// One camera on an arm (issue 45): each result's tour (select/tour: the order, from the motion
// times computed here from the arm), --cycle-time's greedy choice, and the checks of the tour's
// options before any ray.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/robot.hpp"
#include "vantage/tour.hpp"
#include "vantage/track.hpp"

namespace vantage {

void ArmTourOptions::Validate() const {
  if (cycle_time && !(std::isfinite(*cycle_time) && *cycle_time > 0))
    throw InputError(AtPlace("--cycle-time", 0,
                             fmt::format("{} is not a positive number of seconds — give e.g. "
                                         "--cycle-time 20",
                                         *cycle_time)));
  if (joint_speed && !(*joint_speed >= kMinJointSpeed && *joint_speed <= kMaxJointSpeed))
    throw InputError(AtPlace("--joint-speed", 0,
                             fmt::format("{} is not a speed from {:g} to {:g} [rad/s or m/s] — "
                                         "give e.g. --joint-speed 1.0",
                                         *joint_speed, kMinJointSpeed, kMaxJointSpeed)));
  if (frames < 1 || frames > 100000)
    throw InputError(AtPlace("--frames", 0,
                             fmt::format("{} is not a number of frames from 1 to 100000", frames)));
  if (!(std::isfinite(plan_seconds) && plan_seconds > 0 && plan_seconds <= 3600))
    throw InputError(AtPlace("--plan-time", 0,
                             fmt::format("{} is not a number of seconds in (0, 3600] — give e.g. "
                                         "--plan-time 2",
                                         plan_seconds)));
  // Below 1e-4 a move's checks outnumber what any run can do (6 rad: 60,000 poses at 1e-4);
  // 1e-300 overflowed the step count and left moves unchecked.
  if (!(resolution >= 1e-4 && resolution <= 1))
    throw InputError(AtPlace("--motion-resolution", 0,
                             fmt::format("{} is not a step in [0.0001, 1] [rad or m]", resolution)));
  if (move_penalty && !track)
    throw InputError(AtPlace("--move-penalty", 0,
                             "only --track weighs the moves between states — add --track, or "
                             "leave --move-penalty out"));
  if (state_interval && !track)
    throw InputError(AtPlace("--state-interval", 0,
                             "only --track follows states in time — add --track, or leave "
                             "--state-interval out"));
  if (move_penalty && !(std::isfinite(*move_penalty) && *move_penalty >= 0 &&
                        *move_penalty <= 1000))
    throw InputError(AtPlace("--move-penalty", 0,
                             fmt::format("{} is not a coverage share per second in [0, 1000] — "
                                         "give e.g. --move-penalty 0.01 (one point of coverage "
                                         "per second of motion)",
                                         *move_penalty)));
  if (state_interval && !(std::isfinite(*state_interval) && *state_interval > 0 &&
                          *state_interval <= 1e6))
    throw InputError(AtPlace("--state-interval", 0,
                             fmt::format("{} is not a number of seconds in (0, 1e6] — give "
                                         "e.g. --state-interval 2",
                                         *state_interval)));
  if (track && cycle_time)
    throw InputError(AtPlace("--track", 0,
                             "--track chooses one view per state, --cycle-time views for one "
                             "tour — give one of them"));
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

/// A view's acquisition: its frames at the sensor's fps (none where no fps is given).
double AcquisitionSeconds(const Candidate& view, const ArmTourOptions& options) {
  const double fps = view.sensor.fps;
  return fps > 0 ? options.frames / fps : 0.0;
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
  for (uint32_t view : views)
    times.acquisition.push_back(AcquisitionSeconds(candidates[view], options));
  return times;
}

/// A checked move, by pair of stops (lower index first): its time (straight, planned around a
/// collision, or +inf) and, when planned, the waypoints between the two stops (lower to higher).
struct MoveVerdict {
  double seconds = 0;
  bool collided = false;  ///< the straight segment collides (seconds: the planner's, or +inf)
  bool planned = false;
  std::vector<std::vector<double>> via;
  std::string collision;  ///< what the straight segment hits first (empty when it is free)
};

/// The refusal of a tour that needs a move the planner does not connect (exit 2): at the arm's
/// population, naming the result, the robot, the two stops and what the straight move hits.
[[noreturn]] void RefuseUnconnected(const ArmSetup& arm, const std::string& result,
                                    const std::string& from, const std::string& to,
                                    const std::string& collision) {
  throw InputError(AtPlace(
      arm.file, arm.line,
      fmt::format("population '{}': the tour of {} on robot '{}' cannot be connected: the move "
                  "between {} and {} collides ({}) and the planner found no way around it — "
                  "nothing was written; move the cell's objects, allow the pair "
                  "(allowed_collisions) or change the arm's views or home",
                  arm.population, result, arm.robot, from, to, collision)));
}
using MoveVerdicts = std::map<std::pair<size_t, size_t>, MoveVerdict>;
/// The moves one arm's tours have checked in a run, by their stops' candidate indices (home:
/// 2^32 - 1) in the order the check took them, so that the same check is the same verdict: each
/// move is checked (and planned) once however many tours use it. The coverage curve's answers
/// share most of their moves: -n 50 on 2,792 joint-space views checked them again for every n.
using SharedVerdicts = std::map<std::pair<uint64_t, uint64_t>, MoveVerdict>;

/// What the moves among `views` (candidate indices) and home are checked with.
struct MoveChecker {
  const std::vector<Candidate>& candidates;
  const std::vector<uint32_t>& views;
  const ArmSetup& arm;
  const ArmTourOptions& options;
  uint64_t seed;
  MoveVerdicts verdicts;
  SharedVerdicts* shared = nullptr;  ///< other tours' checks of this arm's moves; null: none

  size_t home() const { return views.size(); }
  const std::vector<double>& Configuration(size_t k) const {
    return k == home() ? arm.home : candidates[views[k]].arm->joints;
  }
  /// The planner's stream for a pair: the candidates' indices (home: 2^32 - 1), the same pair
  /// the same stream whatever the views' order.
  uint64_t Id(size_t k) const { return k == home() ? 0xFFFFFFFFu : views[k]; }
  uint64_t Stream(size_t a, size_t b) const { return (Id(a) << 32) | Id(b); }

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
        const std::pair<uint64_t, uint64_t> ids(Id(key.first), Id(key.second));
        const auto known = shared ? shared->find(ids) : SharedVerdicts::iterator();
        MoveVerdict verdict =
            shared && known != shared->end() ? known->second : Verdict(key, *times);
        if (shared && known == shared->end()) shared->emplace(ids, verdict);
        if (verdict.collided) {
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

  /// The move between stops key.first and key.second checked at the resolution, from the first
  /// to the second; planned around (OMPL) where its straight segment collides.
  MoveVerdict Verdict(std::pair<size_t, size_t> key, const TourTimes& times) const {
    const std::vector<double>& from = Configuration(key.first);
    const std::vector<double>& to = Configuration(key.second);
    MoveVerdict verdict;
    verdict.seconds = times.motion[key.first][key.second];
    if (!StraightMotionIsFree(*arm.kinematics, *arm.collisions, from, to,
                              options.resolution, &verdict.collision)) {
      verdict.collided = true;
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
    }
    return verdict;
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
    return k == home() ? std::string("home") : fmt::format("'{}'", candidates[views[k]].name);
  }

  /// InputError (RefuseUnconnected) at the first move of `order` (home first and last) that
  /// has no time.
  [[noreturn]] void RefuseFirstUnconnected(const std::vector<uint32_t>& order,
                                           const std::string& result) const {
    size_t at = home();
    std::vector<size_t> stops(order.begin(), order.end());
    stops.push_back(home());
    for (size_t next : stops) {
      const auto found = verdicts.find(std::minmax(at, next));
      if (found != verdicts.end() && !std::isfinite(found->second.seconds))
        RefuseUnconnected(arm, result, Name(at), Name(next), found->second.collision);
      at = next;
    }
    VANTAGE_CHECK(false && "an unconnected tour without an unconnected checked move");
    std::abort();
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

/// The checked tour of `views`. When it cannot be connected: InputError (exit 2) naming `result`
/// and the move where `refuse`, else none.
std::optional<ArmTour> TourOf(const std::vector<Candidate>& candidates,
                              const std::vector<uint32_t>& views, const ArmSetup& arm,
                              const ArmTourOptions& options, uint64_t seed,
                              const std::string& result, bool refuse, SharedVerdicts* shared) {
  TourTimes times = StraightTimes(candidates, views, arm, options);
  MoveChecker checker{candidates, views, arm, options, seed, {}, shared};
  const Tour tour = LazyTour(&checker, &times);
  if (!tour.connected()) {
    if (refuse) checker.RefuseFirstUnconnected(tour.order, result);
    return std::nullopt;
  }
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

namespace {

/// How many of the nearest views CheckArmHome plans to from a home that no straight move leaves.
constexpr size_t kHomePlanTries = 16;

std::string ConfigurationWords(const ArmSetup& arm, const std::vector<double>& q) {
  std::vector<std::string> words;
  for (size_t i : arm.kinematics->moved())
    words.push_back(fmt::format("{}={:.4g}", arm.kinematics->joint_names()[i], q[i]));
  return fmt::format("{}", fmt::join(words, ", "));
}

/// --cycle-time's views: those of the first arm (its robot's, whatever their population).
std::pair<const ArmSetup*, std::vector<uint32_t>> CycleTimeViews(
    const std::vector<Candidate>& candidates, const std::vector<ArmSetup>& arms) {
  const ArmSetup* arm = nullptr;
  std::vector<uint32_t> views;
  for (uint32_t i = 0; i < candidates.size(); ++i) {
    const ArmSetup* of = SetupOf(arms, candidates[i]);
    if (!of) continue;
    if (!arm) arm = of;
    if (of->robot == arm->robot) views.push_back(i);
  }
  if (!arm)
    throw InputError(AtPlace("--cycle-time", 0,
                             "no candidate is on an arm — --cycle-time times an arm's tour; add "
                             "an `arm` population (docs/arm.md)"));
  return {arm, std::move(views)};
}

/// The quickest one-view tour (home, view k with its acquisition, home: `seconds(k)`) among the
/// `views` views that `counts` accepts: (k, seconds), or none.
template <class Seconds, class Counts>
std::optional<std::pair<size_t, double>> QuickestOneViewTour(size_t views, const Seconds& seconds,
                                                             const Counts& counts) {
  std::optional<std::pair<size_t, double>> quickest;
  for (size_t k = 0; k < views; ++k) {
    if (!counts(k)) continue;
    const double t = seconds(k);
    if (!quickest || t < quickest->second) quickest = {k, t};
  }
  return quickest;
}

/// --cycle-time's refusal when no view fits: `quickest` from QuickestOneViewTour; `which` says
/// which views were weighed.
InputError NoViewFits(const std::vector<Candidate>& candidates, const std::vector<uint32_t>& views,
                      const ArmSetup& arm, double cycle_time, const std::string& which,
                      const std::pair<size_t, double>& quickest) {
  return InputError(AtPlace(
      "--cycle-time", 0,
      fmt::format("no {} fits in {:g} s: the quickest tour of one, home -> '{}' -> home on robot "
                  "'{}' with its acquisition, takes at least {:.3f} s — give a longer --cycle-time",
                  which, cycle_time, candidates[views[quickest.first]].name, arm.robot,
                  quickest.second)));
}

/// Before any ray: a cycle time shorter than every one-view tour on straight moves (no tour is
/// quicker) can hold no view. It ran to an empty answer, "cycle-time n=0 0.00 %", saying nothing
/// of why.
void CheckCycleTimeHoldsAView(const std::vector<Candidate>& candidates,
                              const std::vector<ArmSetup>& arms, const ArmTourOptions& options) {
  const auto [arm, views] = CycleTimeViews(candidates, arms);
  // Home and back on straight moves (MotionSeconds is symmetric): the home row only, not
  // StraightTimes' every pair, which CycleTimeSelection builds after the rays.
  const std::vector<double> speeds = Speeds(*arm, options);
  const auto quickest = QuickestOneViewTour(
      views.size(),
      [&](size_t k) {
        const Candidate& view = candidates[views[k]];
        return 2 * MotionSeconds(arm->home, view.arm->joints, speeds) +
               AcquisitionSeconds(view, options);
      },
      [](size_t) { return true; });
  if (quickest && *options.cycle_time < quickest->second)
    throw NoViewFits(candidates, views, *arm, *options.cycle_time,
                     "view (on straight moves at the joints' speeds)", *quickest);
}

/// Before any ray: the arm's home must be free, and some view must be reachable from it (a tour
/// starts and ends there). A straight move to any view that is free settles it; else the
/// planner tries the kHomePlanTries nearest views. Refused when none connects and every view was
/// tried; with more views the tour's own check after selection decides (a warning says so).
void CheckArmHome(const std::vector<Candidate>& candidates, const ArmSetup& arm,
                  const ArmTourOptions& options, uint64_t seed) {
  std::string pair;
  const ArmCollision home = arm.collisions->Check(arm.kinematics->LinkPosesAt(arm.home), &pair);
  if (home != ArmCollision::kNone)
    throw InputError(AtPlace(arm.file, arm.line,
                             fmt::format("population '{}': the arm's home ({}) on robot '{}' "
                                         "collides ({}) — every tour starts and ends there; "
                                         "give `home:` a collision-free configuration",
                                         arm.population, ConfigurationWords(arm, arm.home),
                                         arm.robot, pair)));
  const std::vector<double> speeds = Speeds(arm, options);
  std::vector<std::pair<double, uint32_t>> nearest;  // (straight time, candidate)
  for (uint32_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].arm && candidates[i].population == arm.population)
      nearest.emplace_back(MotionSeconds(arm.home, candidates[i].arm->joints, speeds), i);
  std::sort(nearest.begin(), nearest.end());
  std::string hit;
  for (const auto& [seconds, i] : nearest) {
    std::string what;
    if (StraightMotionIsFree(*arm.kinematics, *arm.collisions, arm.home, candidates[i].arm->joints,
                             options.resolution, &what))
      return;
    if (hit.empty()) hit = what;
  }
  const size_t tries = std::min(nearest.size(), kHomePlanTries);
  for (size_t k = 0; k < tries; ++k) {
    MotionPlanOptions plan;
    plan.resolution = options.resolution;
    plan.time_limit = options.plan_seconds;
    plan.seed = seed;
    plan.stream = (uint64_t{nearest[k].second} << 32) | 0xFFFFFFFFu;  // the tour's stream
    if (PlanMotion(*arm.kinematics, *arm.collisions, arm.home,
                   candidates[nearest[k].second].arm->joints, speeds, plan)
            .found)
      return;
  }
  if (tries < nearest.size()) {
    spdlog::warn("population '{}': no straight move from the arm's home leaves it and the planner "
                 "reached none of the {} nearest of {} views — the tour is checked after "
                 "selection",
                 arm.population, tries, nearest.size());
    return;
  }
  throw InputError(AtPlace(arm.file, arm.line,
                           fmt::format("population '{}': the arm's home ({}) on robot '{}' is "
                                       "cut off from all {} views: every straight move from it "
                                       "collides (the nearest: {}) and the planner found no way "
                                       "around — no tour can start there; move `home:` or the "
                                       "cell's objects",
                                       arm.population, ConfigurationWords(arm, arm.home),
                                       arm.robot, nearest.size(), hit)));
}

}  // namespace

const char* ObjectiveBesideArmSelection(const SelectOptions& select,
                                        const SelectionRequest& request) {
  const ConstraintOptions& constraints = request.constraints;
  return select.goal                                    ? "a coverage goal"
         : select.budget                                ? "a budget"
         : select.k > 1                                 ? "k-coverage"
         : select.min_points                            ? "a point density"
         : constraints.interference.value_or(false) || constraints.calibration_overlap ||
                 constraints.calibration_overlap_frac
             ? "an installation constraint"
         : request.keep_existing ? "--keep-existing"
                                 : nullptr;
}

void RefuseTourOptionsWithoutArm(const ArmTourOptions& options, const std::string& why,
                                 const std::string& fix) {
  const ArmTourOptions defaults;
  const auto [flag, what] =
      options.cycle_time    ? std::pair("--cycle-time", "times an arm's tour")
      : options.joint_speed ? std::pair("--joint-speed", "times an arm's tour")
      : options.frames != defaults.frames ? std::pair("--frames", "times an arm's tour")
      : options.resolution != defaults.resolution
          ? std::pair("--motion-resolution", "checks an arm's moves")
      : options.plan_seconds != defaults.plan_seconds
          ? std::pair("--plan-time", "bounds the planning of an arm's moves")
          : std::pair<const char*, const char*>(nullptr, nullptr);
  if (flag == nullptr) return;
  throw InputError(AtPlace(flag, 0, fmt::format("{} — {} {}; {}", why, flag, what, fix)));
}

void RefuseObjectiveBesideCycleTime(const SelectOptions& select,
                                    const SelectionRequest& request) {
  const char* conflict = ObjectiveBesideArmSelection(select, request);
  if (conflict == nullptr) return;
  throw InputError(AtPlace("--cycle-time", 0,
                           fmt::format("--cycle-time chooses the views of most coverage whose "
                                       "tour fits it, which {} does not — drop one of "
                                       "--cycle-time and {}",
                                       conflict, conflict)));
}

void CheckArmTourInputs(const std::vector<Candidate>& candidates,
                        const std::vector<ArmSetup>& arms, const ArmTourOptions& options,
                        uint64_t seed) {
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
  for (const ArmSetup& arm : arms) CheckArmHome(candidates, arm, options, seed);
  if (options.cycle_time) CheckCycleTimeHoldsAView(candidates, arms, options);
}

void AddArmTours(const std::vector<Candidate>& candidates, const std::vector<ArmSetup>& arms,
                 const ArmTourOptions& options, Report* report) {
  if (arms.empty()) return;
  std::map<const ArmSetup*, SharedVerdicts> checked;  // per arm: its home and collisions
  // The tour of a selection's views on one arm (that of its first arm view); none without one.
  const auto tour_of = [&](const Selection& result, bool refuse) -> std::optional<ArmTour> {
    const ArmSetup* arm = nullptr;
    std::vector<uint32_t> views;
    for (uint32_t i : result.chosen) {
      const ArmSetup* of = SetupOf(arms, candidates[i]);
      if (!of) continue;
      if (!arm) arm = of;
      if (of->robot == arm->robot) views.push_back(i);
    }
    if (!arm) return std::nullopt;
    const std::string label = fmt::format("the result {} n={}", result.method, result.n);
    std::optional<ArmTour> tour =
        TourOf(candidates, views, *arm, options, report->seed, label, refuse, &checked[arm]);
    if (tour)
      spdlog::info("{} n={}{}: tour of {} view{} {:.2f} s ({:.2f} s moving, {:.2f} s acquiring; "
                   "{})",
                   result.method, result.n, refuse ? "" : " (curve)", views.size(),
                   views.size() == 1 ? "" : "s",
                   tour->tour.total_seconds, tour->tour.motion_seconds,
                   tour->tour.acquisition_seconds, tour->tour.method);
    return tour;
  };
  report->tours.assign(report->results.size(), std::nullopt);
  for (size_t r = 0; r < report->results.size(); ++r)
    report->tours[r] = tour_of(report->results[r], true);
  // The curve's extra answers get their tours too (the report's coverage-versus-seconds view);
  // one that cannot be connected is left without, not refused: the run's results are whole.
  report->curve_tours.assign(report->curve.size(), std::nullopt);
  for (size_t r = 0; r < report->curve.size(); ++r) {
    report->curve_tours[r] = tour_of(report->curve[r], false);
    if (!report->curve_tours[r] && !report->curve[r].chosen.empty())
      report->notes.push_back(fmt::format("the curve's {} n={}: its tour cannot be connected "
                                          "(left out of the coverage-versus-seconds view)",
                                          report->curve[r].method, report->curve[r].n));
  }
}

Selection CycleTimeSelection(const VisibilityFile& data, const std::vector<ArmSetup>& arms,
                             const ArmTourOptions& options, uint64_t seed) {
  VANTAGE_CHECK(options.cycle_time.has_value());
  const auto start = std::chrono::steady_clock::now();
  const auto [arm, views] = CycleTimeViews(data.candidates, arms);
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
  if (result.chosen.empty()) {
    // Every view that sees a target cell needs longer (its moves as checked so far, the others
    // straight: at least that long). Only views that see nothing may fit: nothing to report.
    const size_t home = views.size();
    const auto quickest = QuickestOneViewTour(
        views.size(),
        [&](size_t k) {
          return times.motion[home][k] + times.acquisition[k] + times.motion[k][home];
        },
        [&](size_t k) { return !observations[k].reference_indices.empty(); });
    if (!quickest)
      throw InputError(AtPlace("--cycle-time", 0,
                               fmt::format("none of the {} views on robot '{}' sees a target "
                                           "cell — nothing to time",
                                           views.size(), arm->robot)));
    throw NoViewFits(data.candidates, views, *arm, *options.cycle_time,
                     "view that sees the targets", *quickest);
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

namespace {

/// The scene of state `a` with state `b`'s objects added: a move between the two states must be
/// free in both (the scene changes while the arm moves).
Scene BothStates(const Scene& a, const Scene& b) {
  Scene both = a;
  both.objects.insert(both.objects.end(), b.objects.begin(), b.objects.end());
  return both;
}

/// The track's views: every candidate on the first arm's robot (candidate indices).
std::vector<uint32_t> TrackViews(const std::vector<Candidate>& candidates,
                                 const std::vector<ArmSetup>& arms) {
  std::vector<uint32_t> views;
  for (uint32_t i = 0; i < candidates.size(); ++i) {
    const ArmSetup* of = SetupOf(arms, candidates[i]);
    if (of && of->robot == arms.front().robot) views.push_back(i);
  }
  return views;
}

/// The waypoints of a planned path without its ends, each with when it is reached.
ArmVia ViaOf(const std::vector<std::vector<double>>& inner, const std::vector<double>& from,
             const std::vector<double>& speeds) {
  ArmVia via;
  via.waypoints = inner;
  const std::vector<double>* previous = &from;
  double t = 0;
  for (const auto& q : via.waypoints) {
    t += MotionSeconds(*previous, q, speeds);
    via.seconds.push_back(t);
    previous = &q;
  }
  return via;
}

}  // namespace

void PrepareArmTrack(PreparedScene* prepared, const ArmTourOptions& options) {
  if (!options.track) return;
  Problem& problem = prepared->problem;
  if (problem.states.empty())
    throw InputError(AtPlace("--track", 0,
                             "the scene has no `states:` — --track follows a changing scene, one "
                             "view per state in time order; add states (docs/scene-format.md) "
                             "or drop --track"));
  if (prepared->arms.empty())
    throw InputError(AtPlace("--track", 0,
                             "no candidate is on an arm — --track moves one arm camera from "
                             "state to state; add an `arm` population or `reach:` (docs/arm.md)"));
  const size_t states = problem.states.size();
  VANTAGE_CHECK(prepared->state_scenes.size() == states);
  const std::string robot = prepared->arms.front().robot;
  const std::vector<uint32_t> views = TrackViews(prepared->candidates, prepared->arms);
  std::vector<std::vector<bool>> free_in(states, std::vector<bool>(views.size(), false));
  for (ArmSetup& arm : prepared->arms) {
    if (arm.robot != robot) continue;
    arm.state_collisions.clear();
    for (const Scene& scene : prepared->state_scenes)
      arm.state_collisions.push_back(ArmCollisionsIn(problem, arm, scene));
    arm.state_free.assign(states, std::vector<bool>(prepared->candidates.size(), false));
  }
  // Each view in each state, against that state's cell (its own population's checks).
  for (size_t s = 0; s < states; ++s) {
    std::vector<char> free(views.size(), 0);
    std::vector<std::string> pairs(views.size());
    tbb::parallel_for(size_t{0}, views.size(), [&](size_t k) {
      if (InterruptRequested()) return;
      const Candidate& c = prepared->candidates[views[k]];
      const ArmSetup& arm = *SetupOf(prepared->arms, c);
      free[k] = arm.state_collisions[s]->Check(arm.kinematics->LinkPosesAt(c.arm->joints),
                                               &pairs[k]) == ArmCollision::kNone;
    });
    ThrowIfInterrupted();
    size_t count = 0;
    std::map<std::string, size_t> often;
    for (size_t k = 0; k < views.size(); ++k) {
      const Candidate& c = prepared->candidates[views[k]];
      for (ArmSetup& arm : prepared->arms)
        if (arm.population == c.population) arm.state_free[s][views[k]] = free[k] != 0;
      free_in[s][k] = free[k] != 0;
      count += free[k] != 0 ? 1 : 0;
      if (free[k] == 0) ++often[pairs[k]];
    }
    const SceneState& state = problem.states[s];
    const std::string file = state.file.empty() ? problem.source : state.file;
    if (count == 0) {
      const auto most = std::max_element(often.begin(), often.end(), [](const auto& a,
                                                                         const auto& b) {
        return a.second < b.second;
      });
      throw InputError(AtPlace(file, state.line,
                               fmt::format("state '{}': none of the {} views of the arm on robot "
                                           "'{}' is collision-free in this state (most often {}) "
                                           "— --track needs a view in every state; move the "
                                           "state's objects or widen the arm's views",
                                           state.name, views.size(), robot,
                                           most == often.end() ? std::string() : most->first)));
    }
    const std::string note = fmt::format("--track: state '{}': {} of {} views of the arm are "
                                         "collision-free in it",
                                         state.name, count, views.size());
    spdlog::info("{}", note);
    if (count < views.size()) prepared->notes.push_back(note);
  }
  // The moves into each state: against that state's cell and the one before it together.
  ArmSetup& first = prepared->arms.front();
  first.move_collisions = {first.state_collisions.front()};
  for (size_t s = 1; s < states; ++s)
    first.move_collisions.push_back(ArmCollisionsIn(
        problem, first, BothStates(prepared->state_scenes[s - 1], prepared->state_scenes[s])));
  // Before any ray: could any sequence obey --state-interval at the straight moves' times (no
  // move is faster)? Coverage does not matter here, only which views are allowed where.
  if (options.state_interval) {
    TrackProblem feasible;
    const TourTimes times = StraightTimes(prepared->candidates, views, first, options);
    feasible.motion = times.motion;
    feasible.acquisition = times.acquisition;
    feasible.state_interval = options.state_interval;
    feasible.coverage.assign(states, std::vector<double>(views.size(), 0.0));
    for (size_t s = 0; s < states; ++s)
      for (size_t k = 0; k < views.size(); ++k)
        if (!free_in[s][k]) feasible.coverage[s][k] = -kInf;
    if (!SolveTrack(feasible).feasible)
      throw InputError(AtPlace("--state-interval", 0,
                               fmt::format("no sequence of the arm's {} views, one per state, "
                                           "moves from each state's view to the next's within "
                                           "{} s (acquisition included, at the joints' top "
                                           "speeds) — lengthen --state-interval",
                                           views.size(), *options.state_interval)));
  }
}

void TrackSelection(const ObservedScene& observed, const ArmTourOptions& options, uint64_t seed,
                    Report* report) {
  const auto start = std::chrono::steady_clock::now();
  const VisibilityFile& data = observed.data;
  const std::vector<ArmSetup>& arms = observed.arms;
  VANTAGE_CHECK(!arms.empty() && !observed.states.empty());
  const ArmSetup& arm = arms.front();
  const std::vector<uint32_t> views = TrackViews(data.candidates, arms);
  const size_t states = observed.states.size(), n = views.size();
  VANTAGE_CHECK(arm.move_collisions.size() == states && arm.state_collisions.size() == states);
  const std::vector<double> speeds = Speeds(arm, options);
  TrackProblem problem;
  const TourTimes times = StraightTimes(data.candidates, views, arm, options);
  problem.motion = times.motion;
  problem.acquisition = times.acquisition;
  problem.seconds_weight = options.move_penalty.value_or(0.0);
  problem.state_interval = options.state_interval;
  problem.state_moves.resize(states);
  problem.coverage.assign(states, std::vector<double>(n, -kInf));
  std::vector<size_t> free_count(states, 0);
  for (size_t s = 0; s < states; ++s) {
    const ObservedState& state = observed.states[s];
    const CoverageEvaluator evaluator(state.observations, state.reference.size());
    for (size_t k = 0; k < n; ++k) {
      const ArmSetup& own = *SetupOf(arms, data.candidates[views[k]]);
      if (!own.state_free[s][views[k]]) continue;  // the arm hits this state's cell there
      ++free_count[s];
      const uint32_t one[] = {views[k]};
      problem.coverage[s][k] = evaluator.Coverage(one);
    }
  }
  const auto configuration = [&](size_t k) -> const std::vector<double>& {
    return k == n ? arm.home : data.candidates[views[k]].arm->joints;
  };
  const auto name = [&](size_t k) {
    return k == n ? std::string("home") : data.candidates[views[k]].name;
  };
  const auto id = [&](size_t k) -> uint64_t { return k == n ? 0xFFFFFFFFu : views[k]; };
  // A move checked in `collisions` at the resolution, planned around where it collides.
  const auto check = [&](size_t from, size_t to, const ArmCollisions& collisions,
                         uint64_t stream, const std::string& where) {
    MoveVerdict verdict;
    verdict.seconds = times.motion[from][to];
    if (StraightMotionIsFree(*arm.kinematics, collisions, configuration(from), configuration(to),
                             options.resolution, &verdict.collision))
      return verdict;
    MotionPlanOptions plan;
    plan.resolution = options.resolution;
    plan.time_limit = options.plan_seconds;
    plan.seed = seed;
    plan.stream = stream;
    const PlannedMotion motion = PlanMotion(*arm.kinematics, collisions, configuration(from),
                                            configuration(to), speeds, plan);
    if (motion.stopped_by_time)
      spdlog::warn("planning the move between {} and {} {} stopped at --plan-time {} s: the "
                   "answer may differ on a faster machine — raise --plan-time",
                   name(from), name(to), where, options.plan_seconds);
    verdict.seconds = motion.seconds;  // +inf when not found
    verdict.planned = motion.found;
    if (motion.found) verdict.via.assign(motion.waypoints.begin() + 1, motion.waypoints.end() - 1);
    return verdict;
  };
  // Solve on the straight moves' times, check the moves the answer uses in the cells they cross
  // (planning around a collision), and solve again until every move it uses has its checked
  // time: exact, as a checked move is never faster than its straight time (a norm).
  std::map<std::tuple<size_t, size_t, size_t>, MoveVerdict> verdicts;  // (state, lower, upper)
  Track track;
  size_t solves = 0;
  for (;;) {
    ++solves;
    track = SolveTrack(problem);
    if (!track.feasible) break;
    bool changed = false;
    for (size_t s = 0; s < states; ++s) {
      const size_t from = s == 0 ? n : track.views[s - 1], to = track.views[s];
      if (from == to) continue;  // the arm stays
      const auto [low, high] = std::minmax(from, to);
      if (verdicts.count({s, low, high})) continue;
      MoveVerdict verdict =
          check(low, high, *arm.move_collisions[s],
                (id(low) << 32) ^ id(high) ^ (static_cast<uint64_t>(s) << 48),
                fmt::format("into state '{}'", observed.states[s].name));
      if (verdict.seconds != times.motion[low][high]) {
        const auto a = static_cast<uint32_t>(low), b = static_cast<uint32_t>(high);
        problem.state_moves[s][{a, b}] = problem.state_moves[s][{b, a}] = verdict.seconds;
        changed = true;
      }
      verdicts.emplace(std::make_tuple(s, low, high), std::move(verdict));
    }
    if (!changed) break;
  }
  if (!track.feasible)
    throw InputError(AtPlace(options.state_interval ? "--state-interval" : "--track", 0,
                             fmt::format("no sequence of the arm's {} views, one per state, is "
                                         "connected{}: the moves it needs collide and the "
                                         "planner found no way around — {}",
                                         n,
                                         options.state_interval
                                             ? fmt::format(" within {} s", *options.state_interval)
                                             : std::string(),
                                         options.state_interval ? "lengthen --state-interval"
                                                                : "move the cell's objects")));
  // The answer: a result of its distinct views, its path as the arm's tour, each state's view.
  TrackInfo info;
  info.move_penalty = problem.seconds_weight;
  info.state_interval = options.state_interval;
  info.value = track.value;
  info.coverage_sum = track.coverage;
  info.views = n;
  info.checked_moves = verdicts.size();
  info.solves = solves;
  Selection selection;
  selection.method = "track";
  selection.objective = "track";
  ArmTour tour;
  tour.robot = arm.robot;
  tour.population = arm.population;
  tour.joint_names = arm.kinematics->joint_names();
  tour.home = arm.home;
  tour.resolution = options.resolution;
  tour.state_interval = options.state_interval;
  tour.tour.method = "track";
  tour.tour.exact = true;
  double paper = 0;
  for (size_t s = 0; s < states; ++s) {
    const size_t k = track.views[s];
    const uint32_t candidate = views[k];
    const size_t from = s == 0 ? n : track.views[s - 1];
    const auto found = verdicts.find({s, std::min(from, k), std::max(from, k)});
    const bool planned = found != verdicts.end() && found->second.planned;
    info.states.push_back({observed.states[s].name, candidate, problem.coverage[s][k],
                           track.move_seconds[s], planned, free_count[s]});
    info.move_seconds += track.move_seconds[s];
    if (std::find(selection.chosen.begin(), selection.chosen.end(), candidate) ==
        selection.chosen.end())
      selection.chosen.push_back(candidate);
    selection.state_coverage.push_back(problem.coverage[s][k]);
    const ObservedState& state = observed.states[s];
    const uint32_t one[] = {candidate};
    paper += CoverageEvaluator(state.observations, state.reference.size()).PaperCoverage(one);
    tour.views.push_back(candidate);
    tour.states.push_back(state.name);
    tour.configurations.push_back(configuration(k));
    tour.move_seconds.push_back(track.move_seconds[s]);
    std::vector<std::vector<double>> inner;
    if (planned) {
      inner = found->second.via;
      if (from > k) std::reverse(inner.begin(), inner.end());
    }
    tour.move_via.push_back(ViaOf(inner, configuration(from), speeds));
    tour.acquisition_seconds.push_back(times.acquisition[k]);
    tour.planned_pairs += planned ? 1 : 0;
  }
  // Back home after the last state, in its cell.
  const size_t last = track.views.back();
  const MoveVerdict back = check(last, n, *arm.state_collisions.back(),
                                 (id(last) << 32) ^ id(n) ^ (static_cast<uint64_t>(states) << 48),
                                 "back home");
  if (!std::isfinite(back.seconds))
    RefuseUnconnected(arm, "--track", fmt::format("'{}'", name(last)), "home", back.collision);
  tour.return_seconds = back.seconds;
  tour.return_via = ViaOf(back.via, configuration(last), speeds);
  tour.planned_pairs += back.planned ? 1 : 0;
  tour.unconnected_pairs += std::isfinite(back.seconds) ? 0 : 1;
  selection.n = static_cast<int>(selection.chosen.size());
  selection.coverage = track.coverage / static_cast<double>(states);
  selection.paper_coverage = paper / static_cast<double>(states);
  selection.seconds = SecondsSince(start);
  tour.tour.order = tour.views;
  tour.tour.motion_seconds = info.move_seconds + tour.return_seconds;
  double acquiring = 0;
  for (double a : tour.acquisition_seconds) acquiring += a;
  tour.tour.acquisition_seconds = acquiring;
  // From home to home: with --state-interval the states are that far apart (the arm waits).
  tour.tour.total_seconds =
      options.state_interval
          ? track.move_seconds.front() +
                static_cast<double>(states - 1) * *options.state_interval +
                tour.acquisition_seconds.back() + tour.return_seconds
          : tour.tour.motion_seconds + acquiring;
  spdlog::info("--track: {} states, {} distinct views, summed coverage {:.4f}, {:.2f} s moving, "
               "value {:.4f} (exact; {} moves checked, {} solves)",
               states, selection.n, track.coverage, info.move_seconds, track.value,
               info.checked_moves, solves);
  report->results = {selection};
  report->tours = {tour};
  report->track = std::move(info);
  StatesInfo states_info;
  states_info.over = "track";
  for (const ObservedState& state : observed.states)
    states_info.states.push_back({state.name, state.reference.size(), state.same_as});
  report->states = std::move(states_info);
}

}  // namespace detail
}  // namespace vantage

namespace vantage::detail {

ArmAtViews::ArmAtViews(ArmViewsFile views, std::string path, std::optional<int> view)
    : views_(std::move(views)), path_(std::move(path)) {
  if (views_.views.empty())
    throw InputError(AtPlace(path_, 0, "no views — give the views.yaml a vantage run wrote"));
  const int chosen = view.value_or(1);
  if (chosen < 1 || static_cast<size_t>(chosen) > views_.views.size())
    throw InputError(AtPlace("--arm-view", 0,
                             fmt::format("{} is not a view of {} — give 1 to {}", chosen, path_,
                                         views_.views.size())));
  view_ = static_cast<size_t>(chosen - 1);
}

void ArmAtViews::Apply(Problem* problem, std::vector<Candidate>* sensors) {
  const auto robot = std::find_if(problem->robots.begin(), problem->robots.end(),
                                  [&](const PlacedRobot& r) { return r.name == views_.robot; });
  if (robot == problem->robots.end())
    throw InputError(AtPlace(path_, 0,
                             fmt::format("robot '{}' is not in the scene {} — render the run with "
                                         "its own scene",
                                         views_.robot, problem->source)));
  // The kinematics of the whole robot: any moving link's chain gives every link's pose.
  std::string tip;
  for (const RobotJoint& joint : robot->model.joints)
    if (joint.type != RobotJoint::Type::kFixed) tip = joint.child_link;
  if (tip.empty())
    throw InputError(AtPlace(path_, 0, fmt::format("robot '{}' has no joint that moves",
                                                   views_.robot)));
  auto kinematics = std::make_shared<ArmKinematics>(*robot, tip, std::vector<std::string>{});
  if (kinematics->joint_names() != views_.joint_names)
    throw InputError(AtPlace(path_, 0,
                             fmt::format("its joint_names are not robot '{}''s ({}) — render the "
                                         "run with its own scene",
                                         views_.robot, fmt::join(kinematics->joint_names(), ", "))));
  // Each view within its joints' limits, as every view a run writes is: a hand-edited 1e300 m on
  // a prismatic joint put the links beyond what Embree traces (an abort in its ray assertion).
  // The margin covers views.yaml's 9 significant digits.
  const std::vector<std::pair<double, double>>& limits = kinematics->limits();
  for (size_t v = 0; v < views_.views.size(); ++v) {
    for (size_t j = 0; j < limits.size(); ++j) {
      const double low = std::max(limits[j].first, -kMaxJointTravel);
      const double high = std::min(limits[j].second, kMaxJointTravel);
      const double q = views_.positions[v][j];
      if (q >= low - 1e-6 && q <= high + 1e-6) continue;
      throw InputError(AtPlace(path_, views_.lines[v],
                               fmt::format("view '{}': joint '{}' at {} is outside its limits "
                                           "[{:g}, {:g}] on robot '{}' — give the views.yaml a "
                                           "vantage run wrote",
                                           views_.views[v], views_.joint_names[j], q, low, high,
                                           views_.robot)));
    }
  }
  auto body = std::make_shared<ArmBody>();
  body->robot = robot->name;
  for (const auto& [link, mesh] : robot->visual_meshes) {
    body->links.push_back(link);
    body->link_meshes.push_back(mesh);
  }
  body->joint_names = kinematics->joint_names();
  // As optimize observed: the carried robot leaves the scene, each view carries its links.
  const std::string own = robot->name + "::";
  std::vector<SceneObject> kept;
  for (SceneObject& object : problem->scene.objects)
    if (object.name.rfind(own, 0) != 0) kept.push_back(std::move(object));
  problem->scene.objects = std::move(kept);
  for (Candidate& sensor : *sensors) {
    const auto at = std::find(views_.views.begin(), views_.views.end(), sensor.name);
    if (at == views_.views.end()) continue;
    const std::vector<double>& q = views_.positions[static_cast<size_t>(at - views_.views.begin())];
    const std::map<std::string, Pose> links = kinematics->LinkPosesAt(q);
    auto pose = std::make_shared<ArmPose>();
    pose->body = body;
    pose->joints = q;
    for (const std::string& link : body->links) pose->world_from_link.push_back(links.at(link));
    sensor.arm = std::move(pose);
  }
  body_ = std::move(body);
  kinematics_ = std::move(kinematics);
}

Scene ArmAtViews::SceneAtView(const Scene& scene, std::vector<Vec3>* frame) const {
  VANTAGE_CHECK(kinematics_ && body_);
  Scene shown = scene;
  const std::map<std::string, Pose> links = kinematics_->LinkPosesAt(views_.positions[view_]);
  for (size_t l = 0; l < body_->links.size(); ++l) {
    SceneObject object;
    object.name = body_->robot + "::" + body_->links[l];
    object.role = Role::kOccluder;
    object.mesh = body_->link_meshes[l];
    object.mesh.Transform(links.at(body_->links[l]));
    for (const Vec3& v : object.mesh.vertices) frame->push_back(v);
    shown.objects.push_back(std::move(object));
  }
  spdlog::info("render: robot '{}' drawn at view {} ({}) of {}", body_->robot, view_ + 1,
               views_.views[view_], path_);
  return shown;
}

}  // namespace vantage::detail
