// Refined poses (issue 9): local pose search around the chosen sensors, tracing only the new
// candidates, then re-selection over old and new. The candidates' 4-DoF reduction (position in a
// population region, look-at orientation; GAZEBO.md) samples poses sparsely; a few small moves and
// re-aims around the chosen ones recover coverage that the sampling missed.
#include "vantage/refine.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/error.hpp"
#include "vantage/rng.hpp"
#include "vantage/interrupt.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;

/// Region boundaries count as inside: clones are placed on them (offset 0, linear distributions).
constexpr double kRegionTolerance = 1e-9;
/// Poses closer than this (position [m], rotation [rad]) are the same pose: not traced twice.
constexpr double kSamePosition = 1e-9;
constexpr double kSameAngle = 1e-9;

bool InRange(double value, double lo, double hi) {
  return value >= lo - kRegionTolerance && value <= hi + kRegionTolerance;
}

/// LookAt that yields nothing instead of throwing when the eye sits on the target.
std::optional<Quat> TryLookAt(const Vec3& eye, const Vec3& target) {
  if (!(target - eye).allFinite() || (target - eye).norm() < 1e-9) return std::nullopt;
  return LookAt(eye, target);
}

/// Roll of a model rotation about its own viewing direction, relative to the look-at along that
/// direction (0 for a plain look-at; the plugin's random roll otherwise). Kept when re-aiming so a
/// refined pose differs from its sensor only by the move and the turn.
double RollOf(const Quat& world_from_model) {
  const Mat3 r = world_from_model.toRotationMatrix();
  const Quat level = LookAt(Vec3::Zero(), r.col(0));
  const Mat3 relative = level.toRotationMatrix().transpose() * r;  // a rotation about x
  return std::atan2(relative(2, 1), relative(1, 1));
}

/// What a candidate may become: its population (nullptr for an explicit sensor) and the mount
/// between the model frame (which moves and is aimed) and the camera body.
struct Mount {
  const Population* population = nullptr;
  Pose model_from_camera;
};

/// One pose of the pool: a model pose, not yet composed with the mount.
struct PoolPose {
  Vec3 position;
  Quat rotation;
};

bool SamePose(const Pose& a, const Pose& b) {
  return (a.position - b.position).norm() < kSamePosition &&
         a.rotation.angularDistance(b.rotation) < kSameAngle;
}

/// Centroid of the reference cells in `cells` (indices into R); nullopt when empty.
std::optional<Vec3> Centroid(const Reference& reference, const std::vector<uint32_t>& cells) {
  if (cells.empty()) return std::nullopt;
  Vec3 sum = Vec3::Zero();
  for (const uint32_t c : cells) sum += VoxelCenter(reference.keys[c], reference.cell_size);
  return Vec3(sum / static_cast<double>(cells.size()));
}

/// Cells that `chosen` leave short of the objective, ascending: seen by fewer than k of them
/// (k = 1: not seen at all), or with `min_points`, holding fewer of their pixels' hits.
std::vector<uint32_t> Unobserved(const std::vector<Observation>& observations,
                                 const std::vector<uint32_t>& chosen,
                                 size_t reference_size,
                                 int k,
                                 std::optional<uint32_t> min_points) {
  std::vector<uint64_t> seen(reference_size, 0);
  for (const uint32_t c : chosen) {
    const Observation& o = observations[c];
    for (size_t j = 0; j < o.reference_indices.size(); ++j)
      seen[o.reference_indices[j]] += min_points ? o.reference_hits[j] : 1;
  }
  const uint64_t needed = min_points ? *min_points : static_cast<uint64_t>(k);
  std::vector<uint32_t> cells;
  for (uint32_t i = 0; i < reference_size; ++i) {
    if (seen[i] < needed) cells.push_back(i);
  }
  return cells;
}

/// Every pose tried around one sensor, in a fixed order: positions (where it is, ± step along the
/// model's axes and the world's, one step toward the unobserved cells; only those in the region),
/// each aimed at the observation point and at the unobserved centroids, with ± turn in yaw and
/// pitch about the aim; and, where it is, its own orientation turned.
std::vector<PoolPose> Pool(const Pose& world_from_model,
                           const Population* population,
                           const Vec3& observation_point,
                           const std::vector<Vec3>& unobserved_targets,
                           double move,
                           double turn) {
  const Vec3& here = world_from_model.position;
  const Mat3 axes = world_from_model.rotation.toRotationMatrix();
  std::vector<Vec3> positions{here};
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) positions.push_back(here + sign * move * axes.col(axis));
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0})
      positions.push_back(here + sign * move * Vec3::Unit(axis));
  }
  for (const Vec3& target : unobserved_targets) {
    const Vec3 toward = target - here;
    if (toward.norm() > move) positions.push_back(here + move * toward.normalized());
  }
  std::erase_if(positions, [&](const Vec3& p) {
    return population != nullptr && !RegionContains(*population, p);
  });
  // The start position is kept even when the region test rejects it (a sensor given outside its
  // region still turns in place).
  if (positions.empty() || (positions.front() - here).norm() > 0)
    positions.insert(positions.begin(), here);

  const double roll = RollOf(world_from_model.rotation);
  const Quat roll_rotation(Eigen::AngleAxisd(roll, Vec3::UnitX()));
  const auto turns = [&](const Quat& aim, std::vector<PoolPose>* out, const Vec3& position) {
    for (const double sign : {1.0, -1.0}) {
      out->push_back(
          {position, (aim * Quat(Eigen::AngleAxisd(sign * turn, Vec3::UnitZ())) * roll_rotation)
                         .normalized()});
      out->push_back(
          {position, (aim * Quat(Eigen::AngleAxisd(sign * turn, Vec3::UnitY())) * roll_rotation)
                         .normalized()});
    }
  };
  std::vector<Vec3> targets{observation_point};
  targets.insert(targets.end(), unobserved_targets.begin(), unobserved_targets.end());
  std::vector<PoolPose> pool;
  for (const Vec3& position : positions) {
    for (const Vec3& target : targets) {
      const std::optional<Quat> aim = TryLookAt(position, target);
      if (!aim) continue;
      pool.push_back({position, (*aim * roll_rotation).normalized()});
      turns(*aim, &pool, position);
    }
  }
  // Its own orientation turned in place: lets a pose aimed elsewhere keep turning.
  const Quat level = LookAt(Vec3::Zero(), axes.col(0));
  turns(level, &pool, here);
  return pool;
}

/// Whether `a` is a better answer than `b` under the objective: fewer sensors for set cover (then
/// more coverage), else more coverage.
bool IsBetter(const Selection& a, const Selection& b, Objective objective) {
  if (objective == Objective::kSetCover) {
    if (a.n != b.n) return a.n < b.n;
  }
  return a.coverage > b.coverage;
}

}  // namespace

void RefineOptions::Validate() const {
  if (max_rounds < 0)
    throw InputError(fmt::format("refine max_rounds {} must be >= 0", max_rounds));
  if (!std::isfinite(move) || move <= 0)
    throw InputError(fmt::format("refine move {} must be a positive length [m]", move));
  if (!std::isfinite(turn_deg) || turn_deg <= 0 || turn_deg >= 180)
    throw InputError(fmt::format("refine turn_deg {} must be in (0, 180) degrees", turn_deg));
  if (per_sensor < 1)
    throw InputError(fmt::format("refine per_sensor {} must be >= 1", per_sensor));
  if (max_halvings < 0)
    throw InputError(fmt::format("refine max_halvings {} must be >= 0", max_halvings));
  observe.Validate();
}

bool RegionContains(const Population& population, const Vec3& world_position) {
  const Quat inverse = population.pose.rotation.normalized().conjugate();
  if (population.distribution == Distribution::kGrid) {
    // Gazebo's grid shift, then offsets (j dx, i dy, 0) in the population frame (GAZEBO.md).
    Vec3 origin = population.pose.position;
    origin.x() -= population.step.x() * (population.cols - 1) / 2.0;
    origin.y() -= population.step.y() * (population.rows - 1) / 2.0;
    const Vec3 offset = inverse * (world_position - origin);
    const Vec3 span(population.step.x() * (population.cols - 1),
                    population.step.y() * (population.rows - 1), 0.0);
    for (int a = 0; a < 3; ++a) {
      const double half = std::abs(population.step[a]) / 2;
      if (!InRange(offset[a], std::min(0.0, span[a]) - half, std::max(0.0, span[a]) + half))
        return false;
    }
    return true;
  }
  switch (population.region) {
    case RegionShape::kBox: {
      // The box is shifted by size/2 in world axes before the rotation (GAZEBO.md).
      const Vec3 offset =
          inverse * (world_position - (population.pose.position - population.box_size / 2));
      for (int a = 0; a < 3; ++a) {
        if (!InRange(offset[a], 0.0, population.box_size[a])) return false;
      }
      return true;
    }
    case RegionShape::kCylinder: {
      const Vec3 offset = inverse * (world_position - population.pose.position);
      return std::hypot(offset.x(), offset.y()) <= population.radius + kRegionTolerance &&
             InRange(offset.z(), 0.0, population.length);
    }
    case RegionShape::kNone:
      break;
  }
  return false;
}

RefineResult Refine(const RayScene& rays,
                    const Reference& reference,
                    std::vector<Candidate> candidates,
                    std::vector<Observation> observations,
                    const std::vector<Population>& populations,
                    const Vec3& observation_point,
                    const Selection& start,
                    const SelectOptions& select,
                    const RefineOptions& options) {
  const Clock::time_point clock_start = Clock::now();
  options.Validate();
  if (observations.size() != candidates.size())
    throw InputError(fmt::format("refine: {} observations for {} candidates", observations.size(),
                                 candidates.size()));
  if (start.chosen.empty()) throw InputError("refine: the start selection chose no sensor");
  for (const uint32_t c : start.chosen) {
    if (c >= candidates.size())
      throw InputError(fmt::format("refine: the start selection names candidate {} of {}", c,
                                   candidates.size()));
  }
  if (!observation_point.allFinite()) throw InputError("refine: observation point is not finite");
  select.Validate(candidates.size());
  for (const RefineState& state : options.states) {
    if (state.rays == nullptr || state.reference == nullptr ||
        state.observations.size() != candidates.size())
      throw InputError(fmt::format("refine: state '{}' needs its geometry, its reference and one "
                                   "observation per candidate ({} given for {})",
                                   state.name, state.observations.size(), candidates.size()));
  }
  std::vector<RefineState> states = options.states;
  const bool over_states = !states.empty();
  if (select.min_points) {
    for (const Observation& o : observations) {
      if (!o.has_point_counts())
        throw InputError("refine: min_points needs the pixel counts per cell, which the given "
                         "observations do not carry");
    }
  }

  std::map<std::string, const Population*> by_name;
  for (const Population& p : populations) by_name[p.name] = &p;
  const size_t given = candidates.size();
  std::vector<Mount> mounts(given);
  for (size_t i = 0; i < given; ++i) {
    if (candidates[i].population.empty()) continue;  // explicit: the body moves, mount unknown
    const auto it = by_name.find(candidates[i].population);
    if (it == by_name.end())
      throw InputError(
          fmt::format("refine: candidate '{}' names population '{}', which is not "
                      "among the populations given",
                      candidates[i].name, candidates[i].population));
    mounts[i] = {it->second, it->second->model_from_camera};
  }
  // root[i]: the given candidate a refined one descends from (names, mount, cost).
  std::vector<uint32_t> root(given);
  for (uint32_t i = 0; i < given; ++i) root[i] = i;

  SelectOptions reselect = select;
  const Objective objective = select.objective();
  // One method re-selects: local search (set cover has none: greedy, as its `all` starts).
  if (reselect.method == Method::kAll || reselect.method == Method::kBest)
    reselect.method = objective == Objective::kSetCover ? Method::kGreedy : Method::kLocal;
  // The refined constellation has as many sensors as the one it refines.
  if (objective == Objective::kCoverage || objective == Objective::kKCoverage ||
      objective == Objective::kMinPoints)
    reselect.n = static_cast<int>(start.chosen.size());
  // Kept sensors (--keep-existing) stay where they are: no poses around them, and every
  // re-selection holds them (Select's and ImproveBySwaps' fixed variables).
  const std::vector<uint32_t>& kept = select.fixed;
  const auto is_kept = [&](uint32_t c) {
    return std::find(kept.begin(), kept.end(), c) != kept.end();
  };
  for (const uint32_t f : kept) {
    if (std::find(start.chosen.begin(), start.chosen.end(), f) == start.chosen.end())
      throw InputError(fmt::format("refine: the start selection lacks kept candidate {}", f));
  }
  // A cell counts once k sensors see it, whatever the objective (a goal or a budget counts k
  // times too), so the blind cells new poses aim at are those seen fewer than k times.
  const int k = select.k;

  // Every state's matrix as selection reads it (the first state's is `observations`).
  const auto views = [&] {
    std::vector<StateObservations> all{{"first", reference.size(), observations}};
    for (const RefineState& state : states)
      all.push_back({state.name, state.reference->size(), state.observations});
    return all;
  };
  // Scores a set of chosen candidates the way Select (over states: SelectOverStates) does, from
  // the observations themselves. Prices come from the re-selection's costs: a new pose costs what
  // its root does (select.costs covers only the given candidates).
  const auto score = [&](std::vector<uint32_t> chosen, const std::string& method) {
    SelectOptions scoring = select;
    scoring.costs = reselect.costs;
    if (over_states)
      return ScoreChosenOverStates(views(), options.over, std::move(chosen), method, scoring);
    return ScoreChosen(CoverageEvaluator(observations, reference.size()), std::move(chosen),
                       method, scoring);
  };

  // The constraints over the candidates so far: the start obeys them (selection did).
  const auto constrain = [&] {
    if (options.constraints) reselect.constraints = options.constraints(candidates, observations);
  };
  constrain();
  RefineResult result;
  Selection current = score(start.chosen, start.method);
  result.coverage_before = current.coverage;
  result.history.push_back(current.coverage);

  double move = options.move;
  double turn = options.turn_deg * std::numbers::pi / 180.0;
  int halvings = 0;
  for (int round = 1; round <= options.max_rounds; ++round) {
    ThrowIfInterrupted();
    // Where the constellation is still blind: all of it, and per sensor what lies within range.
    const std::vector<uint32_t> unobserved =
        Unobserved(observations, current.chosen, reference.size(), k, select.min_points);
    const std::optional<Vec3> blind_centroid = Centroid(reference, unobserved);

    std::vector<Candidate> fresh;
    std::vector<uint32_t> fresh_root;
    std::map<uint32_t, int> made;  // per root: poses made this round (name suffix)
    for (size_t p = 0; p < current.chosen.size(); ++p) {
      const uint32_t c = current.chosen[p];
      if (is_kept(c)) continue;
      const uint32_t r = root[c];
      const Mount& mount = mounts[r];
      const Pose world_from_model =
          candidates[c].world_from_body * mount.model_from_camera.Inverse();
      std::vector<Vec3> targets;
      if (blind_centroid) {
        targets.push_back(*blind_centroid);
        std::vector<uint32_t> near;
        for (const uint32_t cell : unobserved) {
          const Vec3 centre = VoxelCenter(reference.keys[cell], reference.cell_size);
          if ((centre - world_from_model.position).norm() <= candidates[c].sensor.far)
            near.push_back(cell);
        }
        if (near.size() != unobserved.size()) {
          if (const std::optional<Vec3> centroid = Centroid(reference, near))
            targets.push_back(*centroid);
        }
      }
      std::vector<PoolPose> pool =
          Pool(world_from_model, mount.population, observation_point, targets, move, turn);
      // Drop what is already a candidate of this root (or made this round): never trace twice;
      // and what may not be mounted there (a keep-out box).
      std::vector<Pose> bodies;
      for (const PoolPose& pose : pool) {
        const Pose body = Pose{pose.position, pose.rotation} * mount.model_from_camera;
        const auto same = [&](const Pose& other) { return SamePose(body, other); };
        bool is_known = std::any_of(bodies.begin(), bodies.end(), same) ||
                        std::any_of(fresh.begin(), fresh.end(),
                                    [&](const Candidate& f) { return same(f.world_from_body); });
        for (size_t i = 0; i < candidates.size() && !is_known; ++i) {
          is_known = root[i] == r && same(candidates[i].world_from_body);
        }
        if (!is_known && (!options.may_mount || options.may_mount(body))) bodies.push_back(body);
      }
      // A seeded partial Fisher–Yates draw of per_sensor poses (STYLE.md: no std::shuffle).
      Rng rng(options.seed, Stream::kRefine, static_cast<uint64_t>(round), p);
      const size_t draws = std::min(bodies.size(), static_cast<size_t>(options.per_sensor));
      for (size_t d = 0; d < draws; ++d) {
        const size_t pick = d + rng.Below(bodies.size() - d);
        std::swap(bodies[d], bodies[pick]);
        Candidate candidate = candidates[r];
        candidate.name = fmt::format("{}_r{}_{}", candidates[r].name, round, made[r]++);
        candidate.world_from_body = bodies[d];
        fresh.push_back(std::move(candidate));
        fresh_root.push_back(r);
      }
    }

    if (!fresh.empty()) {
      ++result.rounds;
      // The new poses are traced as the others were: the run's culling and quality filter.
      std::vector<Observation> seen = options.trace
                                          ? options.trace(rays, reference, fresh, options.observe)
                                          : Observe(rays, reference, fresh, options.observe);
      // And in every other state, once per geometry (states that share one share its poses).
      for (size_t st = 0; st < states.size(); ++st) {
        size_t same = st;
        for (size_t e = 0; e < st && same == st; ++e) {
          if (states[e].rays == states[st].rays && states[e].reference == states[st].reference)
            same = e;
        }
        if (same != st) {
          const std::vector<Observation>& earlier = states[same].observations;
          states[st].observations.insert(states[st].observations.end(),
                                         earlier.end() - static_cast<std::ptrdiff_t>(fresh.size()),
                                         earlier.end());
          continue;
        }
        // In this process: an MPI job's trace function traces its own ranks' scene (the first).
        std::vector<Observation> in_state =
            Observe(*states[st].rays, *states[st].reference, fresh, options.observe);
        for (Observation& o : in_state) {
          result.extra_rays += o.rays_traced;
          states[st].observations.push_back(std::move(o));
        }
      }
      for (size_t i = 0; i < fresh.size(); ++i) {
        result.extra_rays += seen[i].rays_traced;
        candidates.push_back(std::move(fresh[i]));
        observations.push_back(std::move(seen[i]));
        root.push_back(fresh_root[i]);
      }
      constrain();
      if (!reselect.costs.empty()) {
        reselect.costs.resize(given);
        for (size_t i = given; i < candidates.size(); ++i)
          reselect.costs.push_back(select.costs[root[i]]);
      }
      // Re-selection from scratch, and (but for set cover) swaps from the current answer, which
      // can only improve on it; the best of the current and both is kept.
      Selection best = current;
      const Selection selected =
          over_states
              ? SelectOverStates(views(), options.over, reselect).at(0).selection
              : Select(std::span<const Observation>(observations), reference.size(), reselect)
                    .at(0);
      Selection from_scratch = score(selected.chosen, selected.method);
      if (objective != Objective::kSetCover) {
        std::vector<uint32_t> improved =
            over_states
                ? ImproveOverStatesBySwaps(views(), options.over, current.chosen, reselect)
                : ImproveBySwaps(observations, reference.size(), current.chosen, reselect);
        Selection swapped = score(std::move(improved), MethodName(reselect.method));
        if (IsBetter(swapped, best, objective)) best = std::move(swapped);
      }
      if (IsBetter(from_scratch, best, objective)) best = std::move(from_scratch);
      const bool is_improved = IsBetter(best, current, objective);
      current = std::move(best);
      result.history.push_back(current.coverage);
      spdlog::debug("refine: round {}: {} new candidates, coverage {:.4f}, step {:.4f} m", round,
                      seen.size(), current.coverage, move);
      if (is_improved) {
        halvings = 0;
        continue;
      }
    }
    if (halvings >= options.max_halvings) break;
    ++halvings;
    move /= 2;
    turn /= 2;
  }

  result.new_candidates = candidates.size() - given;
  result.candidates = std::move(candidates);
  result.observations = std::move(observations);
  for (RefineState& state : states) result.state_observations.push_back(std::move(state.observations));
  result.selection = std::move(current);
  result.seconds = std::chrono::duration<double>(Clock::now() - clock_start).count();
  result.selection.seconds = result.seconds;
  return result;
}

}  // namespace vantage
