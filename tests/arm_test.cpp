// A camera on a robot arm (issue 45), against independent truths: the annulus a planar 2-link
// arm reaches, FCL's verdicts on primitives whose overlap is known analytically, the tour
// against every order, the pixels a link in front of the lens hides (a slab test per pixel ray),
// and the bad inputs the scene must refuse before any ray.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <map>
#include <set>
#include <tuple>

#include "test_util.hpp"
#include "vantage/arm.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/reference.hpp"
#include "vantage/tour.hpp"
#include "vantage/track.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {
namespace {

using test::TempDir;
using test::WriteText;

constexpr double kPi = std::numbers::pi;

/// Planar 2-link arm in the z = 0 plane: joints about z, links 0.5 and 0.3 m, no geometry.
/// With both joints over [-π, π] the tip reaches the annulus 0.2 <= r <= 0.8.
const char* kPlanarUrdf = R"(<robot name="planar">
  <link name="base"/>
  <link name="upper"/>
  <link name="fore"/>
  <link name="tip"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3.14159265358979" upper="3.14159265358979" velocity="2" effort="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3.14159265358979" upper="3.14159265358979" velocity="1" effort="1"/>
  </joint>
  <joint name="flange" type="fixed">
    <parent link="fore"/><child link="tip"/><origin xyz="0.3 0 0"/>
  </joint>
</robot>
)";

Problem LoadArmScene(const TempDir& dir, const std::string& urdf, const std::string& body) {
  WriteText(dir.File("arm.urdf"), urdf);
  WriteText(dir.File("scene.yaml"), body);
  return LoadYamlScene(dir.File("scene.yaml"));
}

std::vector<Candidate> Deploy(const Problem& problem) {
  DeployOptions options;
  options.observation_point = problem.observation_point;
  options.seed = problem.seed;
  return DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, options);
}

const char* kPlanarObjects = R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -2]}, box: {size: [0.1, 0.1, 0.1]}}
robots:
  - {name: arm, urdf: arm.urdf}
)";

TEST(ArmViewsTest, JointSpaceViewsOfAPlanarArmLieOnTheAnnulus) {
  TempDir dir;
  for (const char* sampling : {"random", "halton", "grid"}) {
    const Problem problem = LoadArmScene(
        dir, kPlanarUrdf,
        std::string(kPlanarObjects) + fmt::format(R"(populations:
  - name: wrist
    type: intel_realsense_d415
    count: 400
    arm: {{robot: arm, link: tip, sampling: {}}}
)",
                                                  sampling));
    const ArmViews views = ApplyArms(problem, Deploy(problem), problem.seed);
    ASSERT_EQ(views.candidates.size(), 400u) << sampling;  // nothing to collide with
    double nearest = 1, farthest = 0;
    for (const Candidate& c : views.candidates) {
      const Vec3& p = c.world_from_body.position;
      const double r = std::hypot(p.x(), p.y());
      EXPECT_NEAR(p.z(), 0.0, 1e-12);
      EXPECT_GE(r, 0.2 - 1e-9) << sampling;
      EXPECT_LE(r, 0.8 + 1e-9) << sampling;
      // The independent law of cosines: r² = L1² + L2² + 2 L1 L2 cos(elbow).
      ASSERT_TRUE(c.arm);
      const double elbow = c.arm->joints[1];
      EXPECT_NEAR(r * r, 0.25 + 0.09 + 0.3 * std::cos(elbow), 1e-9);
      nearest = std::min(nearest, r);
      farthest = std::max(farthest, r);
    }
    // Spread over the annulus, not a part of it.
    EXPECT_LT(nearest, 0.25) << sampling;
    EXPECT_GT(farthest, 0.78) << sampling;
  }
}

TEST(ArmViewsTest, IkKeepsExactlyTheRegionPosesInsideTheAnnulus) {
  TempDir dir;
  const Problem problem = LoadArmScene(dir, kPlanarUrdf, std::string(kPlanarObjects) + R"(populations:
  - name: reach
    type: intel_realsense_d415
    box: {size: [2, 2, 0.000001]}
    count: 300
    reach: {robot: arm, link: tip, match: position, position_tolerance: 0.0001}
)");
  const std::vector<Candidate> deployed = Deploy(problem);
  ASSERT_EQ(deployed.size(), 300u);
  const ArmViews views = ApplyArms(problem, deployed, problem.seed);
  size_t inside = 0;
  std::vector<std::string> kept;
  for (const Candidate& c : views.candidates) kept.push_back(c.name);
  for (const Candidate& c : deployed) {
    const Vec3& p = c.world_from_body.position;
    const double r = std::hypot(p.x(), p.y());
    const bool is_kept = std::find(kept.begin(), kept.end(), c.name) != kept.end();
    // Outside the annulus (by more than the tolerance): never kept.
    if (r < 0.2 - 2e-4 || r > 0.8 + 2e-4) {
      EXPECT_FALSE(is_kept) << c.name << " r=" << r;
    }
    // Well inside: inverse kinematics must find it.
    if (r > 0.21 && r < 0.79) {
      ++inside;
      EXPECT_TRUE(is_kept) << c.name << " r=" << r;
    }
  }
  EXPECT_GT(inside, 100u);
  EXPECT_EQ(views.unreachable + views.candidates.size(), deployed.size());
  // On one thread the same views, to the bit (KDL's joints cache their pose: one chain shared
  // by threads once raced).
  tbb::task_arena one_thread(1);
  const ArmViews serial = one_thread.execute([&] { return ApplyArms(problem, deployed, problem.seed); });
  ASSERT_EQ(serial.candidates.size(), views.candidates.size());
  for (size_t i = 0; i < serial.candidates.size(); ++i) {
    EXPECT_EQ(serial.candidates[i].name, views.candidates[i].name);
    EXPECT_EQ(serial.candidates[i].arm->joints, views.candidates[i].arm->joints);
  }
  for (const Candidate& c : views.candidates) {
    // The reached camera is where the region put it, within the tolerance.
    const auto original = std::find_if(deployed.begin(), deployed.end(),
                                       [&](const Candidate& d) { return d.name == c.name; });
    EXPECT_LE((c.world_from_body.position - original->world_from_body.position).norm(), 1e-4);
  }
}

TEST(ArmViewsTest, IkReachesTheOpticalAxisOfASixAxisArm) {
  // A UR-like chain: the camera 10 cm beyond the flange; targets drawn as configurations' own
  // camera poses, so each is reachable, and IK must find one (position and optical axis).
  TempDir dir;
  const std::string urdf = R"(<robot name="six">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <link name="l5"/><link name="l6"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.16"/><axis xyz="0 0 1"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.14 0"/><axis xyz="0 1 0"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 -0.12 0.42"/><axis xyz="0 1 0"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.39"/><axis xyz="0 1 0"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
  <joint name="j5" type="revolute"><parent link="l4"/><child link="l5"/>
    <origin xyz="0 0.11 0"/><axis xyz="0 0 1"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
  <joint name="j6" type="revolute"><parent link="l5"/><child link="l6"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-3.1" upper="3.1" velocity="3.1" effort="1"/></joint>
</robot>
)";
  const Problem problem = LoadArmScene(dir, urdf, R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -2]}, box: {size: [0.1, 0.1, 0.1]}}
robots:
  - {name: arm, urdf: arm.urdf}
populations:
  - name: wrist
    type: intel_realsense_d415
    count: 20
    arm: {link: l6, sampling: random, mount: {xyz: [0, 0.1, 0], rpy: [0, 0, 1.5708]}}
)");
  const ArmViews views = ApplyArms(problem, Deploy(problem), problem.seed);
  ASSERT_EQ(views.candidates.size(), 20u);
  const ArmSetup& arm = views.arms.front();
  Pose link_from_camera = problem.populations.front().arm->link_from_camera;
  size_t found = 0;
  for (size_t i = 0; i < views.candidates.size(); ++i) {
    const Pose target = views.candidates[i].world_from_body;
    // KDL's chain agrees with vantage's own forward kinematics.
    const Pose tip = arm.kinematics->TipPose(views.candidates[i].arm->joints);
    EXPECT_LE(((tip * link_from_camera).position - target.position).norm(), 1e-9);
    for (const auto match : {ArmKinematics::Match::kDirection, ArmKinematics::Match::kPose}) {
      const auto q = arm.kinematics->SolveIk(target, link_from_camera, match, 1e-4, 1e-3,
                                             arm.home, 16, 7, i);
      if (!q) continue;  // IK is local (restarts): counted below, not required of every view
      ++found;
      const Pose reached = arm.kinematics->LinkPosesAt(*q).at("l6") * link_from_camera;
      EXPECT_LE((reached.position - target.position).norm(), 1e-4);
      const Vec3 axis = reached.rotation * Vec3::UnitX();
      EXPECT_GE(axis.dot(target.rotation * Vec3::UnitX()), std::cos(1e-3));
      for (size_t j = 0; j < q->size(); ++j) {
        EXPECT_GE((*q)[j], -3.1);
        EXPECT_LE((*q)[j], 3.1);
      }
    }
  }
  // Every target is reachable; damped least squares with 16 restarts finds nearly all of them.
  EXPECT_GE(found, 36u);
}

/// A prismatic slider along x carrying `link_shape` on link "slider" (through an empty link, so
/// that the slider and the base are not adjacent), the base a 0.2 m box at the origin.
std::string SliderUrdf(const std::string& link_shape) {
  return fmt::format(R"(<robot name="slider">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="carriage"/>
  <link name="slider"><collision><geometry>{}</geometry></collision></link>
  <joint name="x" type="prismatic"><parent link="base"/><child link="carriage"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" velocity="0.5" effort="1"/></joint>
  <joint name="bolt" type="fixed"><parent link="carriage"/><child link="slider"/></joint>
</robot>
)",
                     link_shape);
}

TEST(ArmCollisionTest, FclVerdictsMatchTheAnalyticOverlapOfPrimitives) {
  TempDir dir;
  struct Case {
    std::string link_shape;   // on the slider, centred at x = q
    std::string obstacle;     // a scene object
    double touch;             // |q - 1| below which they overlap (analytic)
  };
  const std::vector<Case> cases = {
      // Boxes of 0.2 and 0.3 m: overlap while the centres are nearer than 0.25 m.
      {R"(<box size="0.2 0.2 0.2"/>)", "box: {size: [0.3, 0.3, 0.3]}", 0.25},
      // Spheres of 0.1 and 0.15 m: 0.25 m.
      {R"(<sphere radius="0.1"/>)", "sphere: {radius: 0.15}", 0.25},
      // A sphere of 0.1 m against a cylinder of radius 0.2 along z: 0.3 m sideways.
      {R"(<sphere radius="0.1"/>)", "cylinder: {radius: 0.2, length: 1}", 0.3},
  };
  for (const Case& c : cases) {
    const Problem problem = LoadArmScene(dir, SliderUrdf(c.link_shape), fmt::format(R"(objects:
  - {{name: part, role: target, pose: {{xyz: [0, 0, -3]}}, box: {{size: [0.1, 0.1, 0.1]}}}}
  - {{name: obstacle, role: occluder, pose: {{xyz: [1, 0, 0]}}, {}}}
robots:
  - {{name: arm, urdf: arm.urdf}}
)",
                                                                                     c.obstacle));
    const PlacedRobot& robot = problem.robots.front();
    const ArmKinematics kinematics(robot, "slider", {"x"});
    const ArmCollisions collisions(robot, problem.scene, {}, {"x"}, {});
    for (const double gap : {-0.05, -0.002, 0.002, 0.05}) {
      for (const double side : {-1.0, 1.0}) {
        const double q = 1 + side * (c.touch + gap);
        std::string what;
        const ArmCollision verdict = collisions.Check(kinematics.LinkPosesAt({q}), &what);
        const bool overlap = gap < 0;
        // Near the base (q < 0.2 + 0.1) the slider would hit the base too: not in these q.
        EXPECT_EQ(verdict, overlap ? ArmCollision::kScene : ArmCollision::kNone)
            << c.obstacle << " q=" << q << " " << what;
        if (overlap) {
          EXPECT_NE(what.find("object 'obstacle'"), std::string::npos) << what;
        }
      }
    }
  }
}

TEST(ArmCollisionTest, SelfKeepOutAndAllowedPairs) {
  TempDir dir;
  const Problem problem = LoadArmScene(dir, SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"), R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -3]}, box: {size: [0.1, 0.1, 0.1]}}
robots:
  - {name: arm, urdf: arm.urdf}
keep_out:
  - {name: cabinet, min: [2, -1, -1], max: [3, 1, 1]}
)");
  const PlacedRobot& robot = problem.robots.front();
  const ArmKinematics kinematics(robot, "slider", {"x"});
  const ArmCollisions collisions(robot, problem.scene, problem.mounting.keep_out, {"x"}, {});
  // Base and slider boxes of 0.2 m: they meet while |q| < 0.2.
  EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt({0.19})), ArmCollision::kSelf);
  EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt({-0.19})), ArmCollision::kSelf);
  EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt({0.21})), ArmCollision::kNone);
  // The keep-out box starts at x = 2: the slider's face reaches it at q = 1.9.
  EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt({1.89})), ArmCollision::kNone);
  EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt({1.91})), ArmCollision::kKeepOut);
  // Allowed, the pair is exempt.
  const ArmCollisions allowed(robot, problem.scene, {}, {"x"}, {{"base", "slider"}});
  EXPECT_EQ(allowed.Check(kinematics.LinkPosesAt({0.1})), ArmCollision::kNone);
}

TEST(ArmCollisionTest, ViewsRemovedByEachTestAreCounted) {
  TempDir dir;
  const Problem problem = LoadArmScene(dir, SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"), R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -3]}, box: {size: [0.1, 0.1, 0.1]}}
  - {name: post, role: occluder, pose: {xyz: [-1, 0, 0]}, box: {size: [0.2, 0.2, 0.2]}}
robots:
  - {name: arm, urdf: arm.urdf}
keep_out:
  - {name: cabinet, min: [2, -1, -1], max: [3, 1, 1]}
populations:
  - name: wrist
    type: intel_realsense_d415
    arm:
      link: slider
      mount: {xyz: [0, 0, 0.5]}
      configurations: [{x: 0.1}, {x: 0.5}, {x: -1.05}, {x: 1.95}, {x: 1.2}, {x: 2.5}]
)");
  const ArmViews views = ApplyArms(problem, Deploy(problem), problem.seed);
  EXPECT_EQ(views.drawn, 6u);
  EXPECT_EQ(views.self_collisions, 1u);   // 0.1
  EXPECT_EQ(views.scene_collisions, 1u);  // -1.05 (the post)
  EXPECT_EQ(views.arm_kept_out, 1u);      // 1.95 (the slider's face in the cabinet)
  EXPECT_EQ(views.camera_kept_out, 1u);   // 2.5 (the camera itself inside)
  ASSERT_EQ(views.candidates.size(), 2u);
  EXPECT_EQ(views.candidates[0].name, "wrist_1");
  EXPECT_EQ(views.candidates[1].name, "wrist_4");
}

// ----- planning around a colliding move -------------------------------------------------------

/// A planar 2-link arm with geometry: links of 0.5 and 0.3 m as thin boxes along x, joints about
/// z within ±3 rad; no geometry on the base.
const char* kPlanarBoxesUrdf = R"(<robot name="planar">
  <link name="base"/>
  <link name="upper"><collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.04 0.04"/></geometry></collision></link>
  <link name="fore"><collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.04 0.04"/></geometry></collision></link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1" effort="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="2" effort="1"/>
  </joint>
</robot>
)";

TEST(ArmPlanTest, APairWhoseStraightMoveCrossesABoxGetsAFreePathNoFaster) {
  // A box at x = 0.7 on the x axis: the stretched arm (elbow 0) sweeping the shoulder from -1 to
  // +1 rad passes through it; folding the elbow clears it (the upper link ends at r = 0.5).
  TempDir dir;
  const Problem problem = LoadArmScene(dir, kPlanarBoxesUrdf, R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -2]}, box: {size: [0.1, 0.1, 0.1]}}
  - {name: post, role: occluder, pose: {xyz: [0.7, 0, 0]}, box: {size: [0.1, 0.1, 0.5]}}
robots:
  - {name: arm, urdf: arm.urdf}
)");
  const PlacedRobot& robot = problem.robots.front();
  const ArmKinematics kinematics(robot, "fore", {"shoulder", "elbow"});
  const ArmCollisions collisions(robot, problem.scene, {}, {"shoulder", "elbow"}, {});
  const std::vector<double> from = {-1, 0}, to = {1, 0}, speeds = {1, 2};
  const double resolution = 0.01;
  // The straight move collides: at shoulder 0 the forearm (x from 0.5 to 0.8) is in the post.
  ASSERT_EQ(collisions.Check(kinematics.LinkPosesAt({0, 0})), ArmCollision::kScene);
  ASSERT_FALSE(StraightMotionIsFree(kinematics, collisions, from, to, resolution));

  MotionPlanOptions options;
  options.resolution = resolution;
  options.seed = 3;
  options.stream = 7;
  const PlannedMotion motion = PlanMotion(kinematics, collisions, from, to, speeds, options);
  ASSERT_TRUE(motion.found);
  ASSERT_GE(motion.waypoints.size(), 3u);  // it cannot be the straight move
  EXPECT_EQ(motion.waypoints.front(), from);
  EXPECT_EQ(motion.waypoints.back(), to);
  // Every waypoint within the URDF limits and free; every segment free, re-checked here at half
  // the stated step by interpolating each segment ourselves.
  double seconds = 0;
  for (size_t k = 0; k < motion.waypoints.size(); ++k) {
    const std::vector<double>& q = motion.waypoints[k];
    for (double x : q) {
      EXPECT_GE(x, -3.0);
      EXPECT_LE(x, 3.0);
    }
    EXPECT_EQ(collisions.Check(kinematics.LinkPosesAt(q)), ArmCollision::kNone) << k;
    if (k == 0) continue;
    const std::vector<double>& p = motion.waypoints[k - 1];
    const double largest = std::max(std::abs(q[0] - p[0]), std::abs(q[1] - p[1]));
    const int steps = static_cast<int>(std::ceil(largest / (resolution / 2)));
    for (int s = 0; s <= steps; ++s) {
      const double f = steps == 0 ? 0.0 : static_cast<double>(s) / steps;
      const std::vector<double> at = {p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])};
      ASSERT_EQ(collisions.Check(kinematics.LinkPosesAt(at)), ArmCollision::kNone)
          << "segment " << k << " at " << at[0] << ", " << at[1];
    }
    // The slowest joint at its speed, segment by segment.
    seconds += std::max(std::abs(q[0] - p[0]) / speeds[0], std::abs(q[1] - p[1]) / speeds[1]);
  }
  EXPECT_NEAR(motion.seconds, seconds, 1e-12);
  // No faster than the straight move: the shoulder turns 2 rad at 1 rad/s whatever the path.
  EXPECT_GE(motion.seconds, 2.0 - 1e-12);
  // The path folds the elbow where the shoulder passes the post (shoulder 0 needs a folded
  // forearm): some waypoint has a bent elbow.
  double bent = 0;
  for (const auto& q : motion.waypoints) bent = std::max(bent, std::abs(q[1]));
  EXPECT_GT(bent, 0.1);
  // The same call, the same path.
  const PlannedMotion again = PlanMotion(kinematics, collisions, from, to, speeds, options);
  EXPECT_EQ(again.waypoints, motion.waypoints);
  // An end in collision: not found.
  EXPECT_FALSE(PlanMotion(kinematics, collisions, from, {0, 0}, speeds, options).found);
}

// ----- the tour ----------------------------------------------------------------------------

/// Motion times between random points (and home) in a 3-D joint space at unit speeds: the
/// largest coordinate difference, as MotionSeconds times a move.
TourTimes RandomTimes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-2, 2);
  std::vector<std::vector<double>> points(n + 1, std::vector<double>(3));
  for (auto& p : points)
    for (double& x : p) x = unit(rng);
  TourTimes times;
  times.motion.assign(n + 1, std::vector<double>(n + 1, 0));
  for (size_t a = 0; a <= n; ++a)
    for (size_t b = 0; b <= n; ++b)
      times.motion[a][b] = MotionSeconds(points[a], points[b], {1.0, 0.5, 2.0});
  for (size_t i = 0; i < n; ++i) times.acquisition.push_back(0.1 * static_cast<double>(i % 3));
  return times;
}

double BruteForce(const TourTimes& times, std::vector<uint32_t> subset) {
  std::sort(subset.begin(), subset.end());
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, TourSeconds(times, subset));
  } while (std::next_permutation(subset.begin(), subset.end()));
  return best;
}

TEST(TourTest, HeldKarpEqualsEveryOrderUpToEightViews) {
  for (uint32_t seed = 1; seed <= 12; ++seed) {
    for (size_t n = 1; n <= 8; ++n) {
      const TourTimes times = RandomTimes(n + 2, seed * 31 + static_cast<uint32_t>(n));
      std::vector<uint32_t> subset;
      for (uint32_t i = 0; i < n; ++i) subset.push_back(i + 1);  // leave view 0 out
      const Tour tour = SolveTour(times, subset);
      EXPECT_TRUE(tour.exact);
      EXPECT_EQ(tour.method, "held-karp");
      EXPECT_NEAR(tour.total_seconds, BruteForce(times, subset), 1e-9) << seed << " " << n;
      std::vector<uint32_t> visited = tour.order;
      std::sort(visited.begin(), visited.end());
      EXPECT_EQ(visited, subset);
      EXPECT_NEAR(tour.total_seconds, tour.motion_seconds + tour.acquisition_seconds, 1e-12);
      // The heuristic never beats the exact order, and says it is not exact.
      const Tour heuristic = SolveTour(times, subset, 0);
      EXPECT_FALSE(heuristic.exact);
      EXPECT_EQ(heuristic.method, "2-opt+or-opt");
      EXPECT_GE(heuristic.total_seconds, tour.total_seconds - 1e-9);
    }
  }
}

TEST(TourTest, UnconnectedMovesAreAvoidedOrReported) {
  TourTimes times = RandomTimes(4, 5);
  const double inf = std::numeric_limits<double>::infinity();
  times.motion[0][1] = times.motion[1][0] = inf;
  const std::vector<uint32_t> subset = {0, 1, 2, 3};
  const Tour tour = SolveTour(times, subset);
  EXPECT_TRUE(tour.connected());
  EXPECT_NEAR(tour.total_seconds, BruteForce(times, subset), 1e-9);
  // Cut from home: no tour.
  for (uint32_t v = 0; v < 4; ++v) times.motion[4][v] = times.motion[v][4] = inf;
  EXPECT_FALSE(SolveTour(times, subset).connected());
}

TEST(TourTest, CycleTimeKeepsTheTourWithinIt) {
  const TourTimes times = RandomTimes(9, 3);
  // Each view sees cells {i, i + 1, ..., i + 3} of 12.
  std::vector<Observation> observations(9);
  for (uint32_t i = 0; i < 9; ++i)
    for (uint32_t c = i; c < i + 4; ++c) observations[i].reference_indices.push_back(c);
  for (const double limit : {0.0, 2.0, 4.0, 8.0, 100.0}) {
    const CycleTimeResult result = MostCoverageWithinCycleTime(times, observations, 12, limit);
    EXPECT_LE(result.tour.total_seconds, limit + 1e-12);
    std::vector<bool> seen(12, false);
    for (uint32_t v : result.chosen)
      for (uint32_t c : observations[v].reference_indices) seen[c] = true;
    EXPECT_DOUBLE_EQ(result.coverage,
                     static_cast<double>(std::count(seen.begin(), seen.end(), true)) / 12.0);
    if (limit == 100.0) {
      EXPECT_DOUBLE_EQ(result.coverage, 1.0);
    }
    if (limit == 0.0) {
      EXPECT_TRUE(result.chosen.empty());
    }
  }
}

// ----- following a changing scene ---------------------------------------------------------------

/// The time of the move into state s (the problem's own override, else `motion`), read here
/// from the raw tables.
double EnumeratedMove(const TrackProblem& p, size_t s, uint32_t from, uint32_t to) {
  if (s < p.state_moves.size()) {
    for (const auto& [pair, seconds] : p.state_moves[s])
      if (pair.first == from && pair.second == to) return seconds;
  }
  return p.motion[from][to];
}

/// Every sequence of one view per state and its value; the best value kept.
Track EnumerateTrack(const TrackProblem& p) {
  const size_t states = p.coverage.size(), n = p.motion.size() - 1;
  Track best;
  std::vector<uint32_t> views(states, 0);
  for (;;) {
    bool ok = true;
    double coverage = 0, seconds = 0;
    for (size_t s = 0; s < states && ok; ++s) {
      const double c = p.coverage[s][views[s]];
      const double m = s > 0 ? EnumeratedMove(p, s, views[s - 1], views[s])
                             : (p.start_at_home ? EnumeratedMove(p, 0, static_cast<uint32_t>(n),
                                                                 views[s])
                                                : 0.0);
      const double before = s > 0 && !p.acquisition.empty() ? p.acquisition[views[s - 1]] : 0.0;
      ok = std::isfinite(c) && std::isfinite(m) &&
           (s == 0 || !p.state_interval || before + m <= *p.state_interval);
      coverage += c;
      seconds += m;
    }
    const double value = coverage - p.seconds_weight * seconds;
    if (ok && (!best.feasible || value > best.value + 1e-12)) {
      best.feasible = true;
      best.value = value;
      best.coverage = coverage;
      best.views = views;
    }
    size_t s = 0;
    while (s < states && ++views[s] == n) views[s++] = 0;
    if (s == states) break;
  }
  return best;
}

TEST(TrackTest, DynamicProgrammeEqualsEveryViewSequence) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  size_t feasible = 0, with_limit = 0;
  for (int instance = 0; instance < 120; ++instance) {
    const size_t n = 2 + static_cast<size_t>(instance % 4);       // 2..5 views
    const size_t states = 1 + static_cast<size_t>(instance % 5);  // 1..5 states
    TrackProblem p;
    const TourTimes times = RandomTimes(n, static_cast<uint32_t>(instance + 1));
    p.motion = times.motion;
    p.coverage.assign(states, std::vector<double>(n));
    for (auto& row : p.coverage)
      for (double& c : row) c = std::round(unit(rng) * 8) / 8;  // ties happen
    if (instance % 7 == 3) p.coverage[0][0] = -std::numeric_limits<double>::infinity();
    if (instance % 5 == 2) p.motion[0][1] = p.motion[1][0] = std::numeric_limits<double>::infinity();
    p.seconds_weight = (instance % 3) * 0.2;
    p.start_at_home = instance % 2 == 0;
    if (instance % 4 == 1) {
      p.state_interval = 1.5;
      if (instance % 8 == 1) p.acquisition = times.acquisition;
      ++with_limit;
    }
    if (instance % 3 == 1) {
      // A move into some state checked and slower there (planned), or unconnected.
      p.state_moves.resize(states);
      p.state_moves[states - 1][{0, static_cast<uint32_t>(n - 1)}] = 2.5;
      p.state_moves[0][{static_cast<uint32_t>(n), 1}] = std::numeric_limits<double>::infinity();
    }
    const Track dp = SolveTrack(p);
    const Track all = EnumerateTrack(p);
    ASSERT_EQ(dp.feasible, all.feasible) << instance;
    if (!all.feasible) continue;
    ++feasible;
    EXPECT_NEAR(dp.value, all.value, 1e-9) << instance;
    // The DP's own sequence has the value it claims.
    double coverage = 0, seconds = 0;
    for (size_t s = 0; s < states; ++s) {
      coverage += p.coverage[s][dp.views[s]];
      seconds += dp.move_seconds[s];
      const double m =
          s > 0 ? EnumeratedMove(p, s, dp.views[s - 1], dp.views[s])
                : (p.start_at_home ? EnumeratedMove(p, 0, static_cast<uint32_t>(n), dp.views[s])
                                   : 0.0);
      EXPECT_DOUBLE_EQ(dp.move_seconds[s], m);
      if (p.state_interval && s > 0) {
        EXPECT_LE(m + (p.acquisition.empty() ? 0.0 : p.acquisition[dp.views[s - 1]]),
                  *p.state_interval);
      }
    }
    EXPECT_NEAR(dp.coverage, coverage, 1e-12);
    EXPECT_NEAR(dp.value, coverage - p.seconds_weight * seconds, 1e-12);
  }
  EXPECT_GT(feasible, 100u);
  EXPECT_GT(with_limit, 20u);
}

/// The example of a hand closing on a part (examples/scenes/arm_track_hand.yaml).
std::string TrackExample() {
  return std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/arm_track_hand.yaml";
}

TEST(TrackPipelineTest, OptimizeTrackEqualsEveryViewSequenceOfTheExample) {
  // Through the pipeline's wiring (Optimize's halves): the answer against every sequence of one
  // view per state, valued here from the observations (|O ∩ R_s| / |R_s|) and the joints
  // (max_i |Δq_i| / v_i at the URDF speeds), none of the pipeline's tables reused.
  struct Case {
    double penalty;
    std::optional<double> interval;
  };
  std::set<std::vector<std::string>> answers;
  size_t unconstrained = 0;  // cases where no sequence beats the answer even ignoring collisions
  for (const Case& c : {Case{0.0, {}}, Case{0.01, {}}, Case{0.2, {}}, Case{0.0, 2.5}}) {
    OptimizeOptions options;
    options.scene.path = TrackExample();
    options.arm.track = true;
    options.arm.move_penalty = c.penalty;
    options.arm.state_interval = c.interval;
    OptimizeObserved observed = ObserveForOptimize(options);
    const ObservedScene& scene = observed.observed;
    const std::vector<Candidate> candidates = scene.data.candidates;  // observed moves on
    const size_t n = candidates.size(), states = scene.states.size();
    ASSERT_EQ(states, 3u);
    ASSERT_GT(n, 10u);
    std::vector<std::vector<double>> coverage(states, std::vector<double>(n));
    for (size_t s = 0; s < states; ++s)
      for (size_t k = 0; k < n; ++k)
        coverage[s][k] = static_cast<double>(scene.states[s].observations[k].reference_indices.size()) /
                         static_cast<double>(scene.states[s].reference.size());
    const ArmSetup arm = scene.arms.front();
    const auto seconds = [&](const std::vector<double>& a, const std::vector<double>& b) {
      double slowest = 0;
      for (size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) slowest = std::max(slowest, std::abs(a[i] - b[i]) / arm.speeds[i]);
      return slowest;
    };
    const auto joints = [&](size_t k) -> const std::vector<double>& {
      return k == n ? arm.home : candidates[k].arm->joints;
    };
    std::vector<double> acquisition;
    for (const Candidate& candidate : candidates) acquisition.push_back(1.0 / candidate.sensor.fps);
    const RunResult run = FinishOptimize(options, std::move(observed));
    ASSERT_TRUE(run.report.track);
    const TrackInfo& track = *run.report.track;
    ASSERT_EQ(track.states.size(), states);
    // A straight move into state s collides there (or in the state before): the test's own
    // check at the resolution, cached by pair.
    std::map<std::tuple<size_t, size_t, size_t>, bool> collides;
    const auto blocked = [&](size_t s, size_t a, size_t b) {
      const auto key = std::make_tuple(s, std::min(a, b), std::max(a, b));
      if (!collides.count(key))
        collides[key] = !StraightMotionIsFree(*arm.kinematics, *arm.move_collisions[s], joints(a),
                                              joints(b), options.arm.resolution);
      return collides[key];
    };
    std::vector<std::string> answer;
    std::vector<size_t> chosen;
    for (size_t s = 0; s < states; ++s) {
      EXPECT_FALSE(track.states[s].planned);
      EXPECT_EQ(track.states[s].views_free, n);  // every view is free in every state
      EXPECT_DOUBLE_EQ(track.states[s].coverage, coverage[s][track.states[s].view]);
      answer.push_back(candidates[track.states[s].view].name);
      chosen.push_back(track.states[s].view);
    }
    // Every sequence valued above the answer at the straight moves' times (an upper bound on
    // its true value: a planned move is slower) needs a move that collides; the answer's own
    // value is its straight one, its moves free.
    size_t above = 0;
    double answer_value = 0;
    std::vector<size_t> views(states, 0);
    for (;;) {
      double value = 0;
      bool fits = true;
      for (size_t s = 0; s < states; ++s) {
        const size_t from = s == 0 ? n : views[s - 1];
        const double move = seconds(joints(from), joints(views[s]));
        if (s > 0 && c.interval && acquisition[from] + move > *c.interval) fits = false;
        value += coverage[s][views[s]] - c.penalty * move;
      }
      if (views == chosen) answer_value = value;
      if (fits && value > track.value + 1e-9) {
        ++above;
        bool any = false;
        for (size_t s = 0; s < states && !any; ++s)
          any = (s == 0 ? n : views[s - 1]) != views[s] &&
                blocked(s, s == 0 ? n : views[s - 1], views[s]);
        EXPECT_TRUE(any) << "a free sequence beats the answer, penalty " << c.penalty;
      }
      size_t s = 0;
      while (s < states && ++views[s] == n) views[s++] = 0;
      if (s == states) break;
    }
    EXPECT_NEAR(track.value, answer_value, 1e-9) << c.penalty;
    for (size_t s = 0; s < states; ++s) {
      const size_t from = s == 0 ? n : chosen[s - 1];
      if (from != chosen[s]) {
        EXPECT_FALSE(blocked(s, from, chosen[s]));
      }
    }
    if (above == 0) ++unconstrained;
    answers.insert(answer);
  }
  EXPECT_GE(answers.size(), 2u) << "the penalty and the interval never changed the answer";
  EXPECT_GE(unconstrained, 2u);
}

TEST(TrackPipelineTest, TheCliReportsEachStatesViewAndRefusesBadInput) {
  TempDir dir;
  const auto run = test::RunVantage("optimize " + TrackExample() +
                                    " --track --move-penalty 0.01 --out " + dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("closing"), std::string::npos) << run.out;
  const auto report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  ASSERT_TRUE(report.contains("track"));
  ASSERT_EQ(report["track"]["states"].size(), 3u);
  EXPECT_EQ(report["track"]["states"][2]["state"], "closed");
  EXPECT_EQ(report["results"][0]["method"], "track");
  EXPECT_EQ(report["results"][0]["tour"]["states"].size(), 3u);
  double sum = 0;
  for (const auto& state : report["track"]["states"]) sum += state["coverage"].get<double>();
  EXPECT_NEAR(report["track"]["coverage_sum"].get<double>(), sum, 1e-12);
  const std::string views = test::ReadText(dir.File("out/views.yaml"));
  EXPECT_NE(views.find("state: closed"), std::string::npos) << views;

  // Bad input: exit 2 naming the option (or the place), before any ray.
  const auto refused = [&](const std::string& scene, const std::string& flags,
                           const std::string& words) {
    WriteText(dir.File("scene.yaml"), scene);
    const auto r = test::RunVantage("optimize " + dir.File("scene.yaml") + " " + flags +
                                    " --out " + dir.File("bad"));
    EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("rays"), std::string::npos) << "refused after casting rays: " << r.err;
  };
  WriteText(dir.File("arm.urdf"), kPlanarUrdf);
  const std::string arm = std::string(kPlanarObjects) + R"(populations:
  - name: wrist
    type: intel_realsense_d415
    count: 6
    arm: {robot: arm, link: tip}
)";
  const std::string states = "states:\n  - name: a\n  - name: b\n    remove: [box]\n";
  refused(arm, "--track", "--track: the scene has no `states:`");
  refused(R"(objects:
  - {name: part, role: target, box: {size: [0.1, 0.1, 0.1]}}
  - {name: box, box: {size: [0.1, 0.1, 0.1]}, pose: {xyz: [0.3, 0, 0]}}
populations:
  - {name: ring, type: intel_realsense_d415, count: 4, cylinder: {radius: 1, length: 0.1}}
)" + states,
          "--track", "--track: no candidate is on an arm");
  refused(arm, "--move-penalty 0.1", "--move-penalty: only --track");
  refused(arm, "--track --state-interval -1",
          "--state-interval: -1 is not a number of seconds in (0, 1e6]");
  // 1e300 was refused as "not a positive number of seconds".
  refused(arm, "--track --state-interval 1e300",
          "--state-interval: 1e+300 is not a number of seconds in (0, 1e6]");
  const std::string with_states = std::string(R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -2]}, box: {size: [0.1, 0.1, 0.1]}}
  - {name: box, box: {size: [0.1, 0.1, 0.1]}, pose: {xyz: [3, 0, 0]}}
robots:
  - {name: arm, urdf: arm.urdf}
populations:
  - name: wrist
    type: intel_realsense_d415
    count: 6
    arm: {robot: arm, link: tip}
)") + states;
  refused(with_states, "", "follows them only with --track");
  refused(with_states, "--track --state-interval 0.001", "--state-interval: no sequence");
}

TEST(ArmRenderTest, RenderDrawsTheArmAtAViewAndReobservesAsTheRunDid) {
  TempDir dir;
  // The example's arm and part without its states: a tour of two views.
  std::string scene = test::ReadText(TrackExample());
  scene = scene.substr(0, scene.find("\nstates:"));
  const std::string urdf = "../robots/ur5e_class_arm.urdf";
  scene.replace(scene.find(urdf), urdf.size(),
                std::string(VANTAGE_SOURCE_DIR) + "/examples/robots/ur5e_class_arm.urdf");
  WriteText(dir.File("arm.yaml"), scene);
  const auto run = test::RunVantage("optimize " + dir.File("arm.yaml") + " -n 2 --method greedy --out " +
                                    dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Every result's tour time: in report.json, on its summary line and in the page's data (the
  // coverage-versus-seconds chart), the same number.
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  const std::string html = test::ReadText(dir.File("out/report.html"));
  ASSERT_FALSE(report["results"].empty());
  for (const auto& result : report["results"]) {
    ASSERT_TRUE(result.contains("tour")) << result.dump();
    const double seconds = result["tour"]["seconds"].get<double>();
    EXPECT_GT(seconds, 0);
    EXPECT_NE(run.out.find(fmt::format("tour {:.2f} s", seconds)), std::string::npos) << run.out;
    EXPECT_NE(html.find(fmt::format("\"tour_seconds\":{}", nlohmann::json(seconds).dump())),
              std::string::npos);
  }
  for (const auto& answer : report["curve"]) EXPECT_TRUE(answer.contains("tour")) << answer.dump();
  // The re-observed coverage equals the report's only when each chosen view carries the arm as
  // it stood in it (the robot's static copy at home would hide other pixels).
  const auto render = test::RunVantage("render " + dir.File("out") + " --arm-view 2 --width 160 " +
                                       "--height 120 --png " + dir.File("arm.png"));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_NE(render.err.find("drawn at view 2"), std::string::npos) << render.err;
  EXPECT_EQ(render.err.find("has the scene changed"), std::string::npos) << render.err;
  const auto beyond = test::RunVantage("render " + dir.File("out") + " --arm-view 9 --png " +
                                       dir.File("bad.png"));
  EXPECT_EQ(beyond.exit_code, 2) << beyond.err;
  EXPECT_NE(beyond.err.find("--arm-view: 9 is not a view"), std::string::npos) << beyond.err;
  // A run without an arm has no views.yaml.
  WriteText(dir.File("plain.yaml"), R"(objects:
  - {name: part, role: target, box: {size: [0.1, 0.1, 0.1]}}
sensors:
  - {name: cam, type: intel_realsense_d415, position: [-1, 0, 0]}
)");
  ASSERT_EQ(test::RunVantage("optimize " + dir.File("plain.yaml") + " --out " + dir.File("plain"))
                .exit_code,
            0);
  const auto no_arm = test::RunVantage("render " + dir.File("plain") + " --arm-view 1 --png " +
                                       dir.File("bad.png"));
  EXPECT_EQ(no_arm.exit_code, 2) << no_arm.err;
  EXPECT_NE(no_arm.err.find("--arm-view: the run has no views.yaml"), std::string::npos)
      << no_arm.err;
}

// ----- select FILE of a camera on an arm --------------------------------------------------------

/// The arm example (examples/scenes/arm_wrist_camera.yaml) copied into `dir` with its URDF named
/// absolutely, so that the copy can be edited after observe.
std::string WristExampleIn(const TempDir& dir) {
  std::string scene =
      test::ReadText(std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/arm_wrist_camera.yaml");
  const std::string urdf = "urdf: ../robots/ur5e_class_arm.urdf";
  scene.replace(scene.find(urdf), urdf.size(),
                "urdf: " + std::string(VANTAGE_SOURCE_DIR) + "/examples/robots/ur5e_class_arm.urdf");
  WriteText(dir.File("arm.yaml"), scene);
  return dir.File("arm.yaml");
}

TEST(ArmSelectTest, SelectOfTheObservedFileGivesTheToursOfOptimize) {
  // optimize is the independent path: it draws, reaches and times the views from the scene
  // itself; select has only the file's stored joints and the reloaded robot.
  TempDir dir;
  const std::string scene = WristExampleIn(dir);
  const auto observe = test::RunVantage("observe " + scene + " --out " + dir.File("arm.vis"));
  ASSERT_EQ(observe.exit_code, 0) << observe.err;
  for (const std::string flags : {"-n 3 --method greedy",
                                  "--goal 0.5 --method greedy --joint-speed 2 --frames 3",
                                  "--cycle-time 6 --joint-speed 2 --frames 2 "
                                  "--motion-resolution 0.02 --plan-time 1"}) {
    SCOPED_TRACE(flags);
    const std::string o = dir.File("o"), s = dir.File("s");
    std::filesystem::remove_all(o);
    std::filesystem::remove_all(s);
    const auto optimize = test::RunVantage("optimize " + scene + " " + flags + " --out " + o);
    ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
    const auto select =
        test::RunVantage("select " + dir.File("arm.vis") + " " + flags + " --out " + s);
    ASSERT_EQ(select.exit_code, 0) << select.err;
    const auto by_optimize = nlohmann::json::parse(test::ReadText(o + "/report.json"));
    const auto by_select = nlohmann::json::parse(test::ReadText(s + "/report.json"));
    ASSERT_FALSE(by_optimize["results"].empty());
    ASSERT_EQ(by_select["results"].size(), by_optimize["results"].size());
    for (size_t r = 0; r < by_optimize["results"].size(); ++r) {
      const auto& want = by_optimize["results"][r];
      const auto& got = by_select["results"][r];
      EXPECT_EQ(got["method"], want["method"]);
      EXPECT_EQ(got["sensors"], want["sensors"]);
      ASSERT_TRUE(want.contains("tour")) << want.dump();
      EXPECT_EQ(got["tour"], want["tour"]);  // order, seconds, method, moves
      const double seconds = got["tour"]["seconds"].get<double>();
      EXPECT_NE(select.out.find(fmt::format("tour {:.2f} s", seconds)), std::string::npos)
          << select.out;
    }
    ASSERT_EQ(by_select["curve"].size(), by_optimize["curve"].size());
    for (size_t r = 0; r < by_optimize["curve"].size(); ++r)
      EXPECT_EQ(by_select["curve"][r].value("tour", nlohmann::json()),
                by_optimize["curve"][r].value("tour", nlohmann::json()));
    EXPECT_EQ(by_select.value("cycle_time", nlohmann::json()),
              by_optimize.value("cycle_time", nlohmann::json()));
    for (const char* file : {"/views.yaml", "/trajectory.json"})
      EXPECT_EQ(test::ReadText(s + file), test::ReadText(o + file)) << file;
  }
}

TEST(ArmSelectTest, AFileThatNoLongerFitsItsSceneIsRefusedAndAnOldOneSelectsWithoutTours) {
  TempDir dir;
  const std::string scene = WristExampleIn(dir);
  ASSERT_EQ(test::RunVantage("observe " + scene + " --out " + dir.File("arm.vis")).exit_code, 0);
  const VisibilityFile observed = LoadVisibilityFile(dir.File("arm.vis"));
  ASSERT_EQ(observed.arm_views.size(), observed.candidates.size());
  // Exit 2 naming the file and the candidate, before any selection, nothing written.
  const auto refused = [&](const std::string& file, const std::string& words) {
    const auto run =
        test::RunVantage("select " + file + " -n 2 --method greedy --out " + dir.File("bad"));
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find(file + ": candidate '"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("bad")));
  };
  // A joint too few for the robot (a tampered or foreign file).
  VisibilityFile tampered = observed;
  for (auto& view : tampered.arm_views) {
    ASSERT_TRUE(view.has_value());  // every candidate of the example is on the arm
    ASSERT_EQ(view->joint_names.size(), 6u);
    view->joint_names.pop_back();
    view->joints.pop_back();
  }
  SaveVisibilityFile(dir.File("tampered.vis"), tampered);
  refused(dir.File("tampered.vis"), "robot 'arm' had 5 joints");
  // Another robot name.
  VisibilityFile renamed = observed;
  for (auto& view : renamed.arm_views) view->robot = "other_arm";
  SaveVisibilityFile(dir.File("renamed.vis"), renamed);
  refused(dir.File("renamed.vis"), "its robot was 'other_arm'");
  // The scene edited since observe: the arm's base 5 cm along x puts every camera elsewhere.
  const std::string original = test::ReadText(scene);
  std::string moved = original;
  const std::string robot = "  - name: arm\n";
  moved.insert(moved.find(robot) + robot.size(), "    pose: {xyz: [0.05, 0, 0]}\n");
  WriteText(scene, moved);
  refused(dir.File("arm.vis"), "put the camera 0.05 m");
  // The scene gone: the selection as before, without tours, and a warning; --cycle-time refused.
  std::filesystem::remove(scene);
  const auto away = test::RunVantage("select " + dir.File("arm.vis") +
                                     " -n 2 --method greedy --out " + dir.File("away"));
  ASSERT_EQ(away.exit_code, 0) << away.err;
  EXPECT_NE(away.err.find("its cameras on an arm get no tours"), std::string::npos) << away.err;
  for (const auto& result :
       nlohmann::json::parse(test::ReadText(dir.File("away/report.json")))["results"])
    EXPECT_FALSE(result.contains("tour"));
  const auto timed = test::RunVantage("select " + dir.File("arm.vis") + " --cycle-time 5 --out " +
                                      dir.File("bad"));
  EXPECT_EQ(timed.exit_code, 2) << timed.err;
  EXPECT_NE(timed.err.find("--cycle-time: the scene of"), std::string::npos) << timed.err;
  WriteText(scene, original);

  // A file as vantage before format 11 wrote it (no arm views: version 10) still selects, as it
  // did, without tours, and says why.
  VisibilityFile old = observed;
  old.arm_views.clear();
  SaveVisibilityFile(dir.File("old.vis"), old);
  EXPECT_EQ(test::ReadText(dir.File("old.vis"))[8], 10);
  const auto selected = test::RunVantage("select " + dir.File("old.vis") +
                                         " -n 2 --method greedy --out " + dir.File("old"));
  ASSERT_EQ(selected.exit_code, 0) << selected.err;
  EXPECT_NE(selected.err.find("written before format 11"), std::string::npos) << selected.err;
  const auto report = nlohmann::json::parse(test::ReadText(dir.File("old/report.json")));
  ASSERT_FALSE(report["results"].empty());
  for (const auto& result : report["results"]) EXPECT_FALSE(result.contains("tour"));
  EXPECT_FALSE(std::filesystem::exists(dir.File("old/views.yaml")));
  const auto cycle = test::RunVantage("select " + dir.File("old.vis") + " --cycle-time 5 --out " +
                                      dir.File("bad"));
  EXPECT_EQ(cycle.exit_code, 2) << cycle.err;
  EXPECT_NE(cycle.err.find("--cycle-time: "), std::string::npos) << cycle.err;
  // One state per file: --track is optimize's.
  SelectFileOptions track;
  track.visibility_file = dir.File("arm.vis");
  track.arm.track = true;
  try {
    SelectFromFile(track);
    ADD_FAILURE() << "--track accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--track: ", 0), 0u) << e.what();
  }
}

// ----- the arm occludes its own camera -------------------------------------------------------

// A target wall 2 m ahead of a camera at the origin looking along +x.
Scene TargetWallScene() {
  Scene scene;
  SceneObject wall;
  wall.name = "wall";
  wall.role = Role::kTarget;
  wall.mesh = MakeBox(Vec3(0.01, 4, 4));
  wall.mesh.Transform(Pose{Vec3(2, 0, 0), Quat::Identity()});
  scene.objects.push_back(wall);
  return scene;
}

TEST(ArmOcclusionTest, ALinkInFrontOfTheLensHidesExactlyItsSilhouette) {
  // A target wall 2 m ahead of the camera; a 0.1 m cube link 0.5 m ahead, off-centre.
  const Scene scene = TargetWallScene();
  ReferenceOptions reference_options;
  reference_options.cell_size = 0.02;
  const Reference reference = BuildReference(scene, reference_options);

  Candidate camera;
  camera.name = "wrist";
  camera.sensor = SensorType::FromFov("test", 64, 48, 1.0, std::nullopt, 0.1, 5.0);
  camera.type_id = "test";
  camera.world_from_body = Pose{};
  const Vec3 cube_centre(0.5, 0.031, -0.017);
  const double half = 0.05;
  auto body = std::make_shared<ArmBody>();
  body->robot = "arm";
  body->links = {"wrist_link"};
  body->link_meshes = {MakeBox(Vec3::Constant(2 * half))};
  auto arm = std::make_shared<ArmPose>();
  arm->body = body;
  arm->world_from_link = {Pose{cube_centre, Quat::Identity()}};
  Candidate carried = camera;
  carried.arm = arm;

  ObserveOptions options;
  options.cull = false;
  const std::vector<Candidate> both = {camera, carried};
  const std::vector<Observation> seen = Observe(scene, reference, both, options);
  // The silhouette, by a slab test of every pixel's ray against the cube (double precision).
  int64_t hidden = 0;
  for (int v = 0; v < camera.sensor.height; ++v) {
    for (int u = 0; u < camera.sensor.width; ++u) {
      const Vec3 d = PixelRayInBody(camera.sensor, u, v);
      double enter = 0, leave = 1e9;
      for (int a = 0; a < 3; ++a) {
        double t0 = (cube_centre[a] - half) / d[a], t1 = (cube_centre[a] + half) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0);
        leave = std::min(leave, t1);
      }
      hidden += enter <= leave ? 1 : 0;
    }
  }
  ASSERT_GT(hidden, 20);
  EXPECT_EQ(seen[0].target_pixels, static_cast<uint64_t>(camera.sensor.PixelCount()));
  EXPECT_EQ(seen[0].target_pixels - seen[1].target_pixels, static_cast<uint64_t>(hidden));
}

// The physical model's second aperture (issue 43) sees past the arm no more than the primary ray
// does: a link between the projector and the wall hides the points behind it from the projector.
// Truth: the same cube as a fixed occluder of the cell, traced by the tested static path.
TEST(ArmOcclusionTest, ALinkHidesTheWallFromTheSecondApertureAsAFixedOccluderDoes) {
  const Scene scene = TargetWallScene();
  ReferenceOptions reference_options;
  reference_options.cell_size = 0.02;
  const Reference reference = BuildReference(scene, reference_options);

  Candidate camera;
  camera.name = "wrist";
  camera.type_id = "structured";
  camera.sensor = SensorType::FromFov("structured", 64, 48, 1.0, std::nullopt, 0.1, 5.0);
  SecondAperture projector;
  projector.kind = SecondAperture::Kind::kProjector;
  projector.baseline = 0.3;
  projector.hfov = projector.vfov = 2.0;  // wide: the whole wall is in its field
  camera.sensor.second_aperture = projector;
  camera.world_from_body = Pose{};
  // Two cubes 0.3 m to either side of the optical axis, 0.4 m ahead: whichever side the
  // projector stands on, one lies across its segments to the wall's middle.
  const double half = 0.06;
  const std::vector<Vec3> centres = {Vec3(0.4, 0.22, 0.01), Vec3(0.4, -0.22, -0.01)};
  auto body = std::make_shared<ArmBody>();
  body->robot = "arm";
  auto arm = std::make_shared<ArmPose>();
  arm->body = body;
  Scene fixed = TargetWallScene();
  for (size_t i = 0; i < centres.size(); ++i) {
    body->links.push_back("link_" + std::to_string(i));
    body->link_meshes.push_back(MakeBox(Vec3::Constant(2 * half)));
    arm->world_from_link.push_back(Pose{centres[i], Quat::Identity()});
    SceneObject cube;
    cube.name = "cube_" + std::to_string(i);
    cube.role = Role::kOccluder;
    cube.mesh = MakeBox(Vec3::Constant(2 * half));
    cube.mesh.Transform(Pose{centres[i], Quat::Identity()});
    fixed.objects.push_back(cube);
  }
  Candidate carried = camera;
  carried.arm = arm;

  ObserveOptions options;
  options.cull = false;
  options.physical = true;
  const Observation by_arm = Observe(scene, reference, std::vector<Candidate>{carried}, options)[0];
  const Observation by_cell = Observe(fixed, reference, std::vector<Candidate>{camera}, options)[0];
  ObserveOptions ideal = options;
  ideal.physical = false;
  const Observation pinhole = Observe(fixed, reference, std::vector<Candidate>{camera}, ideal)[0];
  // The projector's shadows of the cubes drop cells the pinhole keeps: the case is not vacuous.
  ASSERT_LT(by_cell.reference_indices.size() + 20, pinhole.reference_indices.size());
  EXPECT_EQ(by_arm.target_pixels, by_cell.target_pixels);
  EXPECT_EQ(by_arm.reference_indices, by_cell.reference_indices);
  EXPECT_EQ(by_arm.ideal_reference_indices, by_cell.ideal_reference_indices);
}

// ----- bad input: exit 2 naming the place, before any ray -------------------------------------

class ArmBadInputTest : public ::testing::Test {
 protected:
  TempDir dir_;
  void Expect(const std::string& urdf, const std::string& population, const std::string& place,
              const std::string& words) {
    WriteText(dir_.File("arm.urdf"), urdf);
    WriteText(dir_.File("scene.yaml"), std::string(kPlanarObjects) + "populations:\n" + population);
    const auto run = test::RunVantage("optimize " + dir_.File("scene.yaml") + " --out " +
                                      dir_.File("out"));
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find("scene.yaml:" + place), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("rays"), std::string::npos) << "refused after casting rays: " << run.err;
  }
};

TEST_F(ArmBadInputTest, EachIsRefusedAtItsPlace) {
  const std::string head = "  - name: wrist\n    type: intel_realsense_d415\n    count: 10\n";
  Expect(kPlanarUrdf, head + "    arm: {robot: crane, link: tip}\n", "9", "no robot 'crane'");
  Expect(kPlanarUrdf, head + "    arm: {robot: arm, link: tool0}\n", "9", "no link 'tool0'");
  Expect(kPlanarUrdf, head + "    arm: {robot: arm, link: base}\n", "9", "nothing to move");
  // Session 34: "joints must be a list of joint names, got a list".
  Expect(kPlanarUrdf, head + "    arm: {robot: arm, link: tip, joints: []}\n", "9",
         "population 'wrist'.arm.joints must be a list of joint names, got an empty list");
  // Session 34: [tip, tip] exempts nothing (a shape never collides with itself).
  Expect(kPlanarUrdf, head + "    arm: {robot: arm, link: tip, allowed_collisions: [[tip, tip]]}\n",
         "9", "population 'wrist'.arm.allowed_collisions[0] pairs 'tip' with itself");
  // Session 33: a mount at 1e300 m read as "120 out of reach (inverse kinematics)".
  Expect(kPlanarUrdf, head + "    arm: {robot: arm, link: tip, mount: {xyz: [0, 0, 1e300]}}\n",
         "9", "population 'wrist'.arm.mount: its offset (0, 0, 1e+300) m, beyond the ±1e+09 m");
  std::string continuous = kPlanarUrdf;
  continuous.replace(continuous.find("type=\"revolute\""), 15, "type=\"continuous\"");
  Expect(continuous, head + "    arm: {robot: arm, link: tip}\n", "9", "has no <limit");
  // Every view of a slider that cannot leave a wall around it.
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  WriteText(dir_.File("scene.yaml"), R"(objects:
  - {name: part, role: target, pose: {xyz: [0, 0, -3]}, box: {size: [0.1, 0.1, 0.1]}}
  - {name: sleeve, role: occluder, box: {size: [8, 0.25, 0.25]}}
robots:
  - {name: arm, urdf: arm.urdf}
populations:
  - name: wrist
    type: intel_realsense_d415
    count: 10
    arm: {link: slider}
)");
  const auto run =
      test::RunVantage("optimize " + dir_.File("scene.yaml") + " --out " + dir_.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("scene.yaml:7: population 'wrist': no view"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("object 'sleeve'"), std::string::npos) << run.err;
}

/// A slider whose base box (0.2 m) it cannot pass: |x| < 0.2 is a self collision (the two boxes
/// overlap), so in one dimension nothing connects x < 0 with x > 0. Two targets, one below each
/// side's view (the camera 0.2 m under the slider, looking down), so that -n 2 takes both.
std::string SliderTourScene(const std::string& configurations, const std::string& home) {
  return R"(objects:
  - {name: left, role: target, pose: {xyz: [-1.5, 0, -1]}, box: {size: [0.2, 0.2, 0.2]}}
  - {name: right, role: target, pose: {xyz: [1.5, 0, -1]}, box: {size: [0.2, 0.2, 0.2]}}
robots:
  - {name: arm, urdf: arm.urdf}
populations:
  - name: wrist
    type: intel_realsense_d415
    arm:
      link: slider
      mount: {xyz: [0, 0, -0.2], rpy: [0, 1.5707963, 0]}
      configurations: )" + configurations + "\n" + home;
}

TEST_F(ArmBadInputTest, HomeInCollisionOrCutOffIsRefusedBeforeAnyRay) {
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  // The default home is the robot's rest, x = 0: inside the base.
  WriteText(dir_.File("scene.yaml"), SliderTourScene("[{x: -1.5}, {x: 1.5}]", ""));
  auto run = test::RunVantage("optimize " + dir_.File("scene.yaml") + " --out " + dir_.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("scene.yaml:7: population 'wrist': the arm's home (x=0) on robot 'arm' "
                         "collides (links 'slider' and 'base')"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(run.err.find("rays"), std::string::npos) << "refused after casting rays: " << run.err;
  // Home on the left, every view on the right: no move leaves home, in any order.
  WriteText(dir_.File("scene.yaml"),
            SliderTourScene("[{x: 1.5}, {x: 1.2}]", "      home: {x: -1.5}\n"));
  run = test::RunVantage("optimize " + dir_.File("scene.yaml") + " --out " + dir_.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("scene.yaml:7: population 'wrist': the arm's home (x=-1.5) on robot "
                         "'arm' is cut off from all 2 views"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("links 'slider' and 'base'"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("rays"), std::string::npos) << "refused after casting rays: " << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out")));
}

// A cycle time shorter than every one-view tour holds no view: refused before any ray, naming the
// quickest. Truth: the slider at 0.5 m/s from home x = 1 to the view at x = 1.2 and back is
// 2 * 0.2 / 0.5 = 0.8 s of motion, plus one frame (the view at x = 1.5 takes 2 s). It ran to an
// empty answer ("cycle-time n=0 0.00 %").
TEST_F(ArmBadInputTest, ACycleTimeThatHoldsNoViewIsRefusedBeforeAnyRay) {
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  WriteText(dir_.File("scene.yaml"),
            SliderTourScene("[{x: 1.5}, {x: 1.2}]", "      home: {x: 1.0}\n"));
  auto run = test::RunVantage("optimize " + dir_.File("scene.yaml") +
                              " --cycle-time 0.79 --out " + dir_.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("--cycle-time: no view (on straight moves at the joints' speeds) fits "
                         "in 0.79 s: the quickest tour of one, home -> 'wrist_1' -> home on "
                         "robot 'arm' with its acquisition, takes at least 0.8"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(run.err.find("rays"), std::string::npos) << "refused after casting rays: " << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out")));
  // One second holds that view (and not the other: 2 s).
  run = test::RunVantage("optimize " + dir_.File("scene.yaml") + " --cycle-time 1 --out " +
                         dir_.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir_.File("out/report.json")));
  ASSERT_EQ(report["results"].size(), 1u);
  EXPECT_EQ(report["results"][0]["sensors"], nlohmann::json::array({"wrist_1"}));
  // After the rays: the view beside home (x = 2.9, 0.4 s) fits but sees neither target (its
  // field reaches x = 2.4 at the targets' depth); the one that sees the right target is
  // 2 * 1.3 / 0.5 = 5.2 s away. Refused naming that one, nothing written.
  WriteText(dir_.File("scene.yaml"),
            SliderTourScene("[{x: 1.5}, {x: 2.9}]", "      home: {x: 2.8}\n"));
  run = test::RunVantage("optimize " + dir_.File("scene.yaml") + " --cycle-time 1 --out " +
                         dir_.File("out2"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("--cycle-time: no view that sees the targets fits in 1 s: the quickest "
                         "tour of one, home -> 'wrist_0' -> home on robot 'arm' with its "
                         "acquisition, takes at least 5.2"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out2")));
}

// --cycle-time chooses by coverage within the tour's time only: a goal, a budget, k-coverage, a
// point density or an installation constraint beside it were dropped without a word (session 34:
// "--cycle-time 10 --k 2" gave the plain answer, "cycle-time n=7 78.68 %", as without --k).
// Refused before any ray, from the command line, the scene's settings and for select FILE.
TEST_F(ArmBadInputTest, ObjectivesBesideACycleTimeAreRefusedBeforeAnyRay) {
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  const std::string scene = SliderTourScene("[{x: 1.5}, {x: 1.2}]", "      home: {x: 1.0}\n");
  WriteText(dir_.File("scene.yaml"), scene);
  const auto refused = [&](const std::string& command, const std::string& conflict) {
    SCOPED_TRACE(command);
    const auto run = test::RunVantage(command + " --cycle-time 1 --out " + dir_.File("out"));
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find("--cycle-time: --cycle-time chooses the views of most coverage whose "
                           "tour fits it, which " + conflict + " does not"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(run.err.find("rays"), std::string::npos) << "refused after casting rays: " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("out")));
  };
  const std::string optimize = "optimize " + dir_.File("scene.yaml");
  refused(optimize + " --goal 0.5", "a coverage goal");
  refused(optimize + " --budget 1000", "a budget");
  refused(optimize + " --k 2 -n 2", "k-coverage");
  refused(optimize + " --min-points 2", "a point density");
  refused(optimize + " --calibration-overlap 1", "an installation constraint");
  const auto observe =
      test::RunVantage("observe " + dir_.File("scene.yaml") + " --out " + dir_.File("arm.vis"));
  ASSERT_EQ(observe.exit_code, 0) << observe.err;
  refused("select " + dir_.File("arm.vis") + " --k 2 -n 2", "k-coverage");
  refused("select " + dir_.File("arm.vis") + " --goal 0.5", "a coverage goal");
  // The scene's own goal counts as given.
  WriteText(dir_.File("scene.yaml"), "settings: {goal: 0.5}\n" + scene);
  refused(optimize, "a coverage goal");
}

TEST_F(ArmBadInputTest, ATourThatCannotBeConnectedWritesNothing) {
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  // Home on the right with one view; the other view on the left, where only the left target is
  // seen: two views chosen, one on each side of the base.
  WriteText(dir_.File("scene.yaml"),
            SliderTourScene("[{x: -1.5}, {x: 1.5}]", "      home: {x: 1.5}\n"));
  // A previous run's outputs in --out stay as they were.
  std::filesystem::create_directories(dir_.File("out"));
  WriteText(dir_.File("out/report.json"), "previous\n");
  const auto run = test::RunVantage("optimize " + dir_.File("scene.yaml") +
                                    " -n 2 --method greedy --out " + dir_.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("scene.yaml:7: population 'wrist': the tour of the result greedy n=2 on "
                         "robot 'arm' cannot be connected: the move between"),
            std::string::npos)
      << run.err;
  // The move that crosses the base, whichever direction the order takes it.
  const bool named = run.err.find("between 'wrist_0' and 'wrist_1'") != std::string::npos ||
                     run.err.find("between 'wrist_1' and 'wrist_0'") != std::string::npos ||
                     run.err.find("between home and 'wrist_0'") != std::string::npos ||
                     run.err.find("between 'wrist_0' and home") != std::string::npos;
  EXPECT_TRUE(named) << run.err;
  EXPECT_NE(run.err.find("(links 'slider' and 'base')"), std::string::npos) << run.err;
  EXPECT_EQ(test::ReadText(dir_.File("out/report.json")), "previous\n");
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir_.File("out")))
    files.push_back(entry.path().filename().string());
  EXPECT_EQ(files, std::vector<std::string>{"report.json"});
}

// render poses the links at views.yaml's positions: a hand-edited 1e300 m on the slider put its
// link where Embree cannot trace (session 34: render aborted in Embree's `ray.valid()` assertion,
// exit 134). A position outside the joint's limits [-3, 3] m is refused at the view's line; the
// run's own file draws.
TEST_F(ArmBadInputTest, RenderRefusesAViewOutsideItsJointsLimits) {
  WriteText(dir_.File("arm.urdf"), SliderUrdf(R"(<box size="0.2 0.2 0.2"/>)"));
  WriteText(dir_.File("scene.yaml"),
            SliderTourScene("[{x: 1.5}, {x: 1.2}]", "      home: {x: 1.0}\n"));
  const auto run = test::RunVantage("optimize " + dir_.File("scene.yaml") +
                                    " -n 1 --method greedy --out " + dir_.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string views = test::ReadText(dir_.File("out/views.yaml"));
  const std::string render = "render " + dir_.File("out") + " --width 64 --height 48 --png ";
  ASSERT_EQ(test::RunVantage(render + dir_.File("good.png")).exit_code, 0);
  const size_t at = views.find("positions: [");
  ASSERT_NE(at, std::string::npos) << views;
  const int line = 1 + static_cast<int>(std::count(views.begin(), views.begin() + at, '\n')) - 1;
  for (const std::string position : {"1e300", "-3.5", "1e7"}) {
    SCOPED_TRACE(position);
    std::string edited = views;
    edited.replace(at, views.find(']', at) + 1 - at, "positions: [" + position + "]");
    WriteText(dir_.File("out/views.yaml"), edited);
    const auto refused = test::RunVantage(render + dir_.File("bad.png"));
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find(fmt::format("views.yaml:{}: view 'wrist_", line)), std::string::npos)
        << refused.err;
    EXPECT_NE(refused.err.find("joint 'x' at " + fmt::format("{}", std::stod(position)) +
                               " is outside its limits [-3, 3] on robot 'arm'"),
              std::string::npos)
        << refused.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("bad.png")));
  }
  // `views` a mapping, or a view not one: yaml-cpp's "invalid node; this may result from using a
  // map iterator ..." had no line.
  for (const auto& [text, line_of_it] : std::vector<std::pair<std::string, int>>{
           {"robot: arm\njoint_names: [x]\nviews: {a: 1}\n", 3},
           {"robot: arm\njoint_names: [x]\nviews:\n  - 7\n", 4}}) {
    WriteText(dir_.File("out/views.yaml"), text);
    const auto refused = test::RunVantage(render + dir_.File("bad.png"));
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find(fmt::format("views.yaml:{}: ", line_of_it)), std::string::npos)
        << refused.err;
    EXPECT_EQ(refused.err.find("invalid node"), std::string::npos) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("bad.png")));
  }
}

}  // namespace
}  // namespace vantage
