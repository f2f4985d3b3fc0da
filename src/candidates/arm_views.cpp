// The views of a camera on an arm (issue 45): configurations drawn in joint space or reached by
// inverse kinematics from a region's poses, each kept only when the arm, standing there, is
// clear of the keep-out boxes, the cell and itself.
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "vantage/arm.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

const PlacedRobot& RobotOf(const Problem& problem, const ArmMount& arm) {
  for (const PlacedRobot& robot : problem.robots)
    if (robot.name == arm.robot) return robot;
  throw InternalError(fmt::format("arm on robot '{}' that the scene does not hold", arm.robot));
}

/// The views' shared body: the robot's visual meshes, which occlude its camera.
std::shared_ptr<const ArmBody> BodyOf(const PlacedRobot& robot, const ArmKinematics& kinematics) {
  auto body = std::make_shared<ArmBody>();
  body->robot = robot.name;
  for (const auto& [link, mesh] : robot.visual_meshes) {
    body->links.push_back(link);
    body->link_meshes.push_back(mesh);
  }
  body->joint_names = kinematics.joint_names();
  return body;
}

std::shared_ptr<const ArmPose> PoseOfArm(const std::shared_ptr<const ArmBody>& body,
                                         const std::vector<double>& q,
                                         const std::map<std::string, Pose>& world_from_link) {
  auto pose = std::make_shared<ArmPose>();
  pose->body = body;
  pose->joints = q;
  for (const std::string& link : body->links) pose->world_from_link.push_back(world_from_link.at(link));
  return pose;
}

/// What one view came to, filled in parallel and tallied in order.
struct Verdict {
  bool reached = true;
  bool camera_kept_out = false;
  ArmCollision collision = ArmCollision::kNone;
  std::string pair;  ///< what collided
  std::vector<double> q;
  std::map<std::string, Pose> links;
  Pose camera;
};

struct Tally {
  size_t drawn = 0, unreachable = 0, camera_kept_out = 0, arm_kept_out = 0, scene = 0, self = 0;
  std::map<std::string, size_t> pairs;  ///< collisions by pair, for the message when none is left
  size_t kept = 0;
  void Add(const Verdict& v) {
    ++drawn;
    if (!v.reached) {
      ++unreachable;
    } else if (v.camera_kept_out) {
      ++camera_kept_out;
    } else if (v.collision == ArmCollision::kKeepOut) {
      ++arm_kept_out;
      ++pairs[v.pair];
    } else if (v.collision == ArmCollision::kScene) {
      ++scene;
      ++pairs[v.pair];
    } else if (v.collision == ArmCollision::kSelf) {
      ++self;
      ++pairs[v.pair];
    } else {
      ++kept;
    }
  }
  std::string Removed() const {
    std::string text = fmt::format("{} drawn", drawn);
    if (unreachable) text += fmt::format(", {} out of reach (inverse kinematics)", unreachable);
    text += fmt::format(", {} with the camera in a keep-out box, {} with the arm in one, {} hitting "
                        "the cell, {} hitting itself",
                        camera_kept_out, arm_kept_out, scene, self);
    return text;
  }
  std::string MostOften() const {
    const auto most = std::max_element(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
      return a.second < b.second;
    });
    return most == pairs.end() ? std::string()
                               : fmt::format(" (most often {}: {} views)", most->first, most->second);
  }
};

const SensorType& TypeOf(const Problem& problem, const Population& population) {
  if (const SensorType* type = problem.FindType(population.sensor_type)) return *type;
  if (const SensorType* type = FindCatalogType(population.sensor_type)) return *type;
  throw InputError(AtPlace(population.file, population.line,
                           fmt::format("population '{}': unknown sensor type '{}'",
                                       population.name, population.sensor_type)));
}

}  // namespace

std::vector<std::vector<double>> DrawConfigurations(const Population& population,
                                                    const ArmKinematics& kinematics,
                                                    uint64_t seed, uint32_t population_index) {
  const ArmMount& arm = *population.arm;
  const std::vector<double> rest = kinematics.Rest();
  const auto& limits = kinematics.limits();
  std::vector<size_t> drawn;  // the sampled joints' indices, in the order the user listed them
  for (const std::string& name : arm.joints) {
    const auto& names = kinematics.joint_names();
    drawn.push_back(static_cast<size_t>(std::find(names.begin(), names.end(), name) - names.begin()));
  }
  std::vector<std::vector<double>> configurations;
  const auto at = [&](size_t k, double unit) {
    return limits[drawn[k]].first + unit * (limits[drawn[k]].second - limits[drawn[k]].first);
  };
  const auto count = static_cast<size_t>(population.count);
  switch (arm.sampling) {
    case JointSampling::kRandom:
      for (size_t i = 0; i < count; ++i) {
        Rng rng(seed, Stream::kArm, population_index, i);
        std::vector<double> q = rest;
        for (size_t k = 0; k < drawn.size(); ++k) q[drawn[k]] = at(k, rng.Uniform01());
        configurations.push_back(std::move(q));
      }
      break;
    case JointSampling::kHalton:
      for (size_t i = 0; i < count; ++i) {
        const std::vector<double> unit = HaltonPoint(i + 1, drawn.size());
        std::vector<double> q = rest;
        for (size_t k = 0; k < drawn.size(); ++k) q[drawn[k]] = at(k, unit[k]);
        configurations.push_back(std::move(q));
      }
      break;
    case JointSampling::kGrid: {
      // floor(count^(1/d)) values per joint, both limits included (one value: the middle).
      const auto d = static_cast<double>(drawn.size());
      auto per_joint = static_cast<size_t>(std::floor(std::pow(static_cast<double>(count), 1.0 / d) + 1e-9));
      per_joint = std::max<size_t>(1, per_joint);
      size_t total = 1;
      for (size_t k = 0; k < drawn.size(); ++k) total *= per_joint;
      for (size_t i = 0; i < total; ++i) {
        std::vector<double> q = rest;
        size_t rest_index = i;
        for (size_t k = 0; k < drawn.size(); ++k) {
          const size_t step = rest_index % per_joint;
          rest_index /= per_joint;
          const double unit = per_joint == 1 ? 0.5
                                             : static_cast<double>(step) /
                                                   static_cast<double>(per_joint - 1);
          q[drawn[k]] = at(k, unit);
        }
        configurations.push_back(std::move(q));
      }
      break;
    }
    case JointSampling::kList:
      for (const auto& listed : arm.configurations) {
        std::vector<double> q = rest;
        const auto& names = kinematics.joint_names();
        for (const auto& [name, value] : listed) {
          const auto it = std::find(names.begin(), names.end(), name);
          VANTAGE_CHECK(it != names.end());  // the reader checked the names and limits
          q[static_cast<size_t>(it - names.begin())] = value;
        }
        configurations.push_back(std::move(q));
      }
      break;
  }
  return configurations;
}

std::vector<ArmSetup> ArmSetupsOf(const Problem& problem) {
  std::vector<ArmSetup> arms;
  for (const Population& population : problem.populations) {
    if (!population.arm) continue;
    const ArmMount& arm = *population.arm;
    const PlacedRobot& robot = RobotOf(problem, arm);
    ArmSetup setup;
    setup.population = population.name;
    setup.robot = robot.name;
    setup.file = arm.file;
    setup.line = population.line;
    auto kinematics = std::make_shared<ArmKinematics>(robot, arm.link, arm.joints);
    std::vector<std::string> moving;
    for (size_t i : kinematics->moved()) moving.push_back(kinematics->joint_names()[i]);
    setup.collisions = std::make_shared<ArmCollisions>(robot, problem.scene,
                                                       problem.mounting.keep_out, moving,
                                                       arm.allowed_pairs);
    setup.home = kinematics->Rest();
    for (const auto& [name, q] : arm.home) {
      const auto& names = kinematics->joint_names();
      setup.home[static_cast<size_t>(std::find(names.begin(), names.end(), name) - names.begin())] = q;
    }
    for (const std::string& name : kinematics->joint_names())
      setup.speeds.push_back(robot.model.FindJoint(name)->velocity);
    setup.body = BodyOf(robot, *kinematics);
    setup.kinematics = std::move(kinematics);
    arms.push_back(std::move(setup));
  }
  return arms;
}

ArmViews ApplyArms(const Problem& problem, std::vector<Candidate> deployed, uint64_t seed) {
  ArmViews result;
  // Each population's arm, built once.
  result.arms = ArmSetupsOf(problem);
  std::map<std::string, size_t> arm_of_population;
  std::vector<std::shared_ptr<const ArmBody>> bodies;
  for (const ArmSetup& setup : result.arms) {
    arm_of_population[setup.population] = bodies.size();
    bodies.push_back(setup.body);
  }
  const auto judge = [&](const ArmSetup& setup, const ArmMount& arm, Verdict* v) {
    v->links = setup.kinematics->LinkPosesAt(v->q);
    v->camera = v->links.at(arm.link) * arm.link_from_camera;
    if (InKeepOut(problem.mounting.keep_out, v->camera.position)) {
      v->camera_kept_out = true;
      return;
    }
    v->collision = setup.collisions->Check(v->links, &v->pair);
  };
  const auto fail_if_empty = [&](const Population& population, const Tally& tally) {
    if (tally.kept > 0) return;
    throw InputError(AtPlace(population.arm->file, population.line,
                             fmt::format("population '{}': no view of the arm on robot '{}' is "
                                         "left: {}{} — widen the limits or the region, allow a "
                                         "pair (allowed_collisions), or move the cell",
                                         population.name, population.arm->robot, tally.Removed(),
                                         tally.MostOften())));
  };
  const auto add_note = [&](const Population& population, const Tally& tally) {
    result.notes.push_back(fmt::format("population '{}' (arm on robot '{}'): {} views kept of {}",
                                       population.name, population.arm->robot, tally.kept,
                                       tally.Removed()));
    result.drawn += tally.drawn;
    result.unreachable += tally.unreachable;
    result.camera_kept_out += tally.camera_kept_out;
    result.arm_kept_out += tally.arm_kept_out;
    result.scene_collisions += tally.scene;
    result.self_collisions += tally.self;
  };

  // Regions with `reach:`: IK from each deployed pose, in parallel, tallied in order.
  std::map<std::string, std::vector<size_t>> reach_members;
  for (size_t i = 0; i < deployed.size(); ++i) {
    const std::string& name = deployed[i].population;
    if (!name.empty() && arm_of_population.count(name)) reach_members[name].push_back(i);
  }
  std::vector<bool> keep(deployed.size(), true);
  for (const Population& population : problem.populations) {
    if (!population.arm || population.arm_views) continue;
    const ArmMount& arm = *population.arm;
    const size_t a = arm_of_population.at(population.name);
    const ArmSetup& setup = result.arms[a];
    const std::vector<size_t>& members = reach_members[population.name];
    std::vector<Verdict> verdicts(members.size());
    const auto match = arm.match == ArmMount::Match::kPose
                           ? ArmKinematics::Match::kPose
                           : arm.match == ArmMount::Match::kDirection
                                 ? ArmKinematics::Match::kDirection
                                 : ArmKinematics::Match::kPosition;
    tbb::parallel_for(size_t{0}, members.size(), [&](size_t k) {
      if (InterruptRequested()) return;
      Verdict& v = verdicts[k];
      const Candidate& c = deployed[members[k]];
      const auto q = setup.kinematics->SolveIk(
          c.world_from_body, arm.link_from_camera, match, arm.position_tolerance,
          arm.angle_tolerance, setup.home, arm.ik_restarts, seed, members[k]);
      if (!q) {
        v.reached = false;
        return;
      }
      v.q = *q;
      judge(setup, arm, &v);
    });
    ThrowIfInterrupted();
    Tally tally;
    for (size_t k = 0; k < members.size(); ++k) {
      const Verdict& v = verdicts[k];
      tally.Add(v);
      Candidate& c = deployed[members[k]];
      keep[members[k]] = v.reached && !v.camera_kept_out && v.collision == ArmCollision::kNone;
      if (!keep[members[k]]) continue;
      c.world_from_body = v.camera;  // the pose reached (its roll, within the tolerances)
      c.arm = PoseOfArm(bodies[a], v.q, v.links);
    }
    fail_if_empty(population, tally);
    add_note(population, tally);
  }
  for (size_t i = 0; i < deployed.size(); ++i)
    if (keep[i]) result.candidates.push_back(std::move(deployed[i]));

  // Kind `arm`: views drawn in joint space.
  for (size_t pi = 0; pi < problem.populations.size(); ++pi) {
    const Population& population = problem.populations[pi];
    if (!population.arm || !population.arm_views) continue;
    const ArmMount& arm = *population.arm;
    const size_t a = arm_of_population.at(population.name);
    const ArmSetup& setup = result.arms[a];
    const SensorType& type = TypeOf(problem, population);
    type.Validate(AtPlace(population.file, population.line, ""));
    const std::string catalog_id = MatchCatalogId(type);
    const std::vector<std::vector<double>> drawn =
        DrawConfigurations(population, *setup.kinematics, seed, static_cast<uint32_t>(pi));
    std::vector<Verdict> verdicts(drawn.size());
    tbb::parallel_for(size_t{0}, drawn.size(), [&](size_t k) {
      if (InterruptRequested()) return;
      verdicts[k].q = drawn[k];
      judge(setup, arm, &verdicts[k]);
    });
    ThrowIfInterrupted();
    Tally tally;
    for (size_t k = 0; k < drawn.size(); ++k) {
      const Verdict& v = verdicts[k];
      tally.Add(v);
      if (v.camera_kept_out || v.collision != ArmCollision::kNone) continue;
      Candidate c;
      c.name = fmt::format("{}_{}", population.name, k);
      c.type_id = catalog_id.empty() ? type.id : catalog_id;
      c.sensor = type;
      c.world_from_body = v.camera;
      c.population = population.name;
      c.arm = PoseOfArm(bodies[a], v.q, v.links);
      result.candidates.push_back(std::move(c));
    }
    fail_if_empty(population, tally);
    add_note(population, tally);
  }
  return result;
}

std::shared_ptr<const ArmCollisions> ArmCollisionsIn(const Problem& problem, const ArmSetup& arm,
                                                     const Scene& scene) {
  const auto population =
      std::find_if(problem.populations.begin(), problem.populations.end(),
                   [&](const Population& p) { return p.name == arm.population && p.arm; });
  VANTAGE_CHECK(population != problem.populations.end());
  std::vector<std::string> moving;
  for (size_t i : arm.kinematics->moved()) moving.push_back(arm.kinematics->joint_names()[i]);
  return std::make_shared<ArmCollisions>(RobotOf(problem, *population->arm), scene,
                                         problem.mounting.keep_out, moving,
                                         population->arm->allowed_pairs);
}

bool StraightMotionIsFree(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                          const std::vector<double>& from, const std::vector<double>& to,
                          double resolution, std::string* what) {
  VANTAGE_CHECK(resolution > 0 && from.size() == to.size());
  double largest = 0;
  for (size_t i = 0; i < from.size(); ++i) largest = std::max(largest, std::abs(to[i] - from[i]));
  // A count beyond 2^53 is no whole number and beyond 2^64 no size_t: the move would go
  // unchecked (ArmTourOptions::Validate keeps resolution >= 1e-4 and limits within ±1e6).
  VANTAGE_CHECK(largest / resolution < 0x1p53);
  const auto steps = static_cast<size_t>(std::ceil(largest / resolution));
  std::vector<double> q(from.size());
  for (size_t s = 0; s <= steps; ++s) {
    const double f = steps == 0 ? 0.0 : static_cast<double>(s) / static_cast<double>(steps);
    for (size_t i = 0; i < q.size(); ++i) q[i] = from[i] + f * (to[i] - from[i]);
    if (collisions.Check(kinematics.LinkPosesAt(q), what) != ArmCollision::kNone) return false;
  }
  return true;
}

// Neither needs KDL: here rather than in the arm module (module/arm_kinematics.cpp).
std::vector<double> HaltonPoint(uint64_t index, size_t dimensions) {
  static constexpr uint64_t kPrimes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31, 37,
                                         41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89};
  std::vector<double> point(dimensions, 0.0);
  for (size_t d = 0; d < dimensions; ++d) {
    const uint64_t base = kPrimes[d % std::size(kPrimes)];
    double fraction = 1.0, value = 0.0;
    for (uint64_t i = index; i > 0; i /= base) {
      fraction /= static_cast<double>(base);
      value += fraction * static_cast<double>(i % base);
    }
    point[d] = value;
  }
  return point;
}

double MotionSeconds(const std::vector<double>& from, const std::vector<double>& to,
                     const std::vector<double>& speeds) {
  VANTAGE_CHECK(from.size() == to.size() && to.size() == speeds.size());
  double seconds = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    const double delta = std::abs(to[i] - from[i]);
    if (delta == 0) continue;
    VANTAGE_CHECK(speeds[i] > 0);
    seconds = std::max(seconds, delta / speeds[i]);
  }
  return seconds;
}

}  // namespace vantage
