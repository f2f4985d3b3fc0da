// Refined poses (issue 9) against answers derived here: a cube whose one visible face bounds what
// any pose of the region can see, regions checked by hand-computed bounds, and determinism.
#include "vantage/refine.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "vantage/constraints.hpp"
#include "vantage/error.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;

// observe_test.cpp's cube: faces at ±2.5 F (mid-cell), R = the shell of the 6x6x6 block of cells,
// 6³ - 4³ = 152 cells; one face is 6 x 6 = 36 of them.
constexpr double kCell = 0.01;
constexpr double kHalf = 2.5 * kCell;
constexpr double kShell = 6 * 6 * 6 - 4 * 4 * 4;
constexpr double kFace = 6 * 6;

Scene CubeScene() {
  Scene scene;
  TriangleMesh mesh = MakeBox(Vec3::Constant(2 * kHalf));
  scene.objects.push_back({"cube", Role::kTarget, std::move(mesh), {}});
  return scene;
}

// 800 px over 0.2 rad at about 1 m: 0.25 mm pixels, far below a cell, so every cell of a face in
// view receives rays.
SensorType FineCamera() {
  return SensorType::FromFov("fine", 800, 800, 0.2, std::nullopt, 0.2, 3.0);
}

// One clone (linear-x, count 1) at offset (0, sy/2, sz/2) of the box shifted by size/2: at
// (1, 0, 0). The region is x in [1, 1.2], y and z in [-0.02, 0.02]: every position in it lies in
// front of the face x = +2.5 F and inside the prism of the other faces' planes (|y|, |z| < 2.5 F),
// so it can see that face and no other — at most 36 cells, exactly 36 once the face is in view.
Population FacePopulation() {
  Population p;
  p.name = "pop";
  p.sensor_type = "fine";
  p.pose = Pose{Vec3(1.1, 0, 0), Quat::Identity()};
  p.region = RegionShape::kBox;
  p.box_size = Vec3(0.2, 0.04, 0.04);
  p.count = 1;
  p.distribution = Distribution::kLinearX;
  return p;
}

bool InFaceRegion(const Vec3& p) {
  constexpr double kTol = 1e-9;
  return p.x() >= 1.0 - kTol && p.x() <= 1.2 + kTol && std::abs(p.y()) <= 0.02 + kTol &&
         std::abs(p.z()) <= 0.02 + kTol;
}

struct Fixture {
  Scene scene = CubeScene();
  Reference reference;
  std::vector<Population> populations;
  std::vector<Candidate> candidates;
  std::vector<Observation> observations;
  Vec3 observation_point;
  Selection start;
  SelectOptions select;
};

// The observation point (0, 0.1159, 0) makes the look-at camera at (1, 0, 0) look past the cube:
// its axis is atan(0.1159) = 0.1154 rad off the cube centre, its half view 0.1 rad, and its up
// axis +z, so it sees the face x = 2.5 F (at distance 0.975) where y >= 0.975 tan(0.0154) = 0.015:
// the middle of cell column 1, so columns 1 and 2 of 6, 12 cells.
constexpr double kStripCells = 2 * 6;
const Vec3 kPastTheCube(0, 0.1159, 0);

Fixture FaceSetup(const Vec3& observation_point = kPastTheCube,
                  const Pose& model_from_camera = Pose{}) {
  Fixture s;
  s.reference = BuildReference(s.scene, {kCell});
  s.populations = {FacePopulation()};
  s.populations[0].model_from_camera = model_from_camera;
  s.observation_point = observation_point;
  DeployOptions deploy;
  deploy.observation_point = observation_point;
  s.candidates = DeployCandidates(s.populations, {}, {FineCamera()}, deploy);
  s.observations = Observe(s.scene, s.reference, s.candidates);
  s.select.n = 1;
  s.select.method = Method::kLocal;
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  return s;
}

RefineResult RunRefine(const Fixture& s, const RefineOptions& options = {}) {
  return Refine(RayScene(s.scene), s.reference, s.candidates, s.observations, s.populations,
                s.observation_point, s.start, s.select, options);
}

// |∪ reference_indices of chosen| / |R|, counted here rather than by CoverageEvaluator.
double UnionCoverage(const RefineResult& r, size_t reference_size) {
  std::set<uint32_t> cells;
  for (const uint32_t c : r.selection.chosen) {
    cells.insert(r.observations[c].reference_indices.begin(),
                 r.observations[c].reference_indices.end());
  }
  return static_cast<double>(cells.size()) / static_cast<double>(reference_size);
}

TEST(Refine, FindsThePoseThatSeesTheWholeFace) {
  const Fixture s = FaceSetup();
  ASSERT_EQ(s.reference.size(), kShell);
  ASSERT_EQ(s.candidates.size(), 1u);
  ASSERT_TRUE(s.candidates[0].world_from_body.position.isApprox(Vec3(1, 0, 0)));
  // Before: a strip of the face only.
  EXPECT_DOUBLE_EQ(s.start.coverage, kStripCells / kShell);

  const RefineResult r = RunRefine(s);
  EXPECT_DOUBLE_EQ(r.coverage_before, s.start.coverage);
  // After: the whole face, the most any pose of the region can see.
  EXPECT_DOUBLE_EQ(r.selection.coverage, kFace / kShell);
  EXPECT_DOUBLE_EQ(UnionCoverage(r, s.reference.size()), kFace / kShell);
  EXPECT_GT(r.selection.coverage, r.coverage_before);
  ASSERT_EQ(r.selection.chosen.size(), 1u);
  EXPECT_GE(r.selection.chosen[0], 1u);  // a new candidate
  EXPECT_GE(r.rounds, 1);
  EXPECT_EQ(r.new_candidates, r.candidates.size() - 1);
  EXPECT_EQ(r.observations.size(), r.candidates.size());
  uint64_t rays = 0;
  for (size_t i = 1; i < r.observations.size(); ++i) rays += r.observations[i].rays_traced;
  EXPECT_EQ(r.extra_rays, rays);
  EXPECT_GT(r.extra_rays, 0u);
  // No more than per_sensor poses per chosen sensor per round (one sensor here).
  EXPECT_LE(r.new_candidates, static_cast<size_t>(r.rounds * RefineOptions{}.per_sensor));
}

TEST(Refine, NewPosesStayInTheRegionAndKeepTheSensor) {
  const Fixture s = FaceSetup();
  RefineOptions options;
  options.per_sensor = 1000;  // the whole pool each round
  const RefineResult r = RunRefine(s, options);
  ASSERT_GT(r.new_candidates, 0u);
  std::set<std::string> names;
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const Candidate& c = r.candidates[i];
    EXPECT_TRUE(InFaceRegion(c.world_from_body.position)) << c.name;
    EXPECT_TRUE(RegionContains(s.populations[0], c.world_from_body.position)) << c.name;
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate name " << c.name;
    if (i == 0) continue;
    EXPECT_EQ(c.name.rfind("pop_0_r", 0), 0u) << c.name;
    EXPECT_EQ(c.population, "pop");
    EXPECT_EQ(c.type_id, "fine");
    EXPECT_EQ(c.sensor.width, 800);
  }
}

TEST(Refine, ReAimsTheModelAndComposesTheMount) {
  // A camera mounted 5 cm above the model origin: the model, not the camera, moves in the region
  // and is aimed (DeployCandidates' composition), so model = body · mount⁻¹ must be in the region,
  // and some new pose must be the look-at of its model position at the observation point.
  const Pose mount{Vec3(0, 0, 0.05), Quat::Identity()};
  const Fixture s = FaceSetup(kPastTheCube, mount);
  RefineOptions options;
  options.per_sensor = 1000;
  options.max_rounds = 1;
  const RefineResult r = RunRefine(s, options);
  ASSERT_GT(r.new_candidates, 0u);
  bool has_moved_look_at = false;
  for (size_t i = 1; i < r.candidates.size(); ++i) {
    const Pose model = r.candidates[i].world_from_body * mount.Inverse();
    EXPECT_TRUE(InFaceRegion(model.position)) << r.candidates[i].name;
    const Quat aim = LookAt(model.position, s.observation_point);
    if ((model.position - Vec3(1, 0, 0)).norm() > 1e-6 &&
        model.rotation.angularDistance(aim) < 1e-9)
      has_moved_look_at = true;
  }
  EXPECT_TRUE(has_moved_look_at);
}

TEST(Refine, CoverageNeverDrops) {
  // Already optimal: the camera aimed at the cube centre sees the whole face; nothing better
  // exists in the region, so refinement keeps exactly that.
  {
    const Fixture s = FaceSetup(Vec3::Zero());
    ASSERT_DOUBLE_EQ(s.start.coverage, kFace / kShell);
    const RefineResult r = RunRefine(s);
    EXPECT_DOUBLE_EQ(r.selection.coverage, kFace / kShell);
    EXPECT_EQ(r.selection.chosen, s.start.chosen);
    for (const double c : r.history) EXPECT_DOUBLE_EQ(c, kFace / kShell);
  }
  // A richer case: two populations around the cube and an explicit sensor, N = 2.
  Fixture s;
  s.reference = BuildReference(s.scene, {kCell});
  Population side = FacePopulation();
  side.distribution = Distribution::kRandom;
  side.count = 3;
  Population top;
  top.name = "top";
  top.sensor_type = "fine";
  top.pose = Pose{Vec3(0.3, 0, 0.9), Quat::Identity()};
  top.region = RegionShape::kCylinder;
  top.radius = 0.2;
  top.length = 0.1;
  top.count = 3;
  s.populations = {side, top};
  ExplicitSensor other;
  other.name = "explicit";
  other.sensor_type = "fine";
  other.pose = Pose{Vec3(-0.8, 0.6, 0.2), Quat::Identity()};
  s.observation_point = Vec3(0.05, 0.05, 0.0);
  DeployOptions deploy;
  deploy.observation_point = s.observation_point;
  s.candidates = DeployCandidates(s.populations, {other}, {FineCamera()}, deploy);
  s.observations = Observe(s.scene, s.reference, s.candidates);
  s.select.n = 2;
  s.select.method = Method::kGreedy;
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  RefineOptions options;
  options.per_sensor = 6;
  const RefineResult r = RunRefine(s, options);
  ASSERT_EQ(r.history.size(), static_cast<size_t>(r.rounds) + 1);
  EXPECT_DOUBLE_EQ(r.history.front(), s.start.coverage);
  for (size_t i = 1; i < r.history.size(); ++i) EXPECT_GE(r.history[i], r.history[i - 1]);
  EXPECT_GE(r.selection.coverage, s.start.coverage);
  EXPECT_DOUBLE_EQ(r.selection.coverage, UnionCoverage(r, s.reference.size()));
  EXPECT_EQ(r.selection.chosen.size(), 2u);
  for (size_t i = s.candidates.size(); i < r.candidates.size(); ++i) {
    const Candidate& c = r.candidates[i];
    if (c.population == "pop") {
      EXPECT_TRUE(InFaceRegion(c.world_from_body.position)) << c.name;
    }
    if (c.population == "top") {
      // Cylinder about (0.3, 0, 0.9) with radius 0.2 and z in [0.9, 1.0].
      const Vec3 p = c.world_from_body.position;
      EXPECT_LE(std::hypot(p.x() - 0.3, p.y()), 0.2 + 1e-9) << c.name;
      EXPECT_GE(p.z(), 0.9 - 1e-9);
      EXPECT_LE(p.z(), 1.0 + 1e-9);
    }
  }
}

// Installation constraints (issue 20): a pose that may not be mounted is never traced, and the
// refined constellation obeys the constraints recomputed over old and new poses.
TEST(Refine, NewPosesAvoidWhereTheyMayNotBeMounted) {
  const Fixture s = FaceSetup();
  RefineOptions options;
  options.per_sensor = 1000;  // the whole pool each round
  // Without the rule the pool moves the camera to y = +5 cm (toward the unobserved column too).
  const RefineResult free = RunRefine(s, options);
  const auto above = [](const Candidate& c) { return c.world_from_body.position.y() > 1e-6; };
  EXPECT_TRUE(std::any_of(free.candidates.begin(), free.candidates.end(), above));
  options.may_mount = [](const Pose& body) { return body.position.y() <= 1e-6; };
  const RefineResult r = RunRefine(s, options);
  ASSERT_GT(r.new_candidates, 0u);
  EXPECT_FALSE(std::any_of(r.candidates.begin(), r.candidates.end(), above));
  EXPECT_GE(r.selection.coverage, s.start.coverage);
}

TEST(Refine, ObeysTheConstraintsOverOldAndNewPoses) {
  // Two faces, +x and -x, one population each, N = 2: unconstrained, refinement finds a pose
  // that sees the whole of each face (72 cells). The rule: two sensors that each see a whole face
  // conflict — so at most one of the two faces can be seen whole.
  Fixture s;
  s.reference = BuildReference(s.scene, {kCell});
  Population plus = FacePopulation();
  Population minus = FacePopulation();
  minus.name = "minus";
  minus.pose = Pose{Vec3(-1.1, 0, 0), Quat::Identity()};  // region x in [-1.2, -1.0]
  s.populations = {plus, minus};
  s.observation_point = kPastTheCube;
  DeployOptions deploy;
  deploy.observation_point = s.observation_point;
  s.candidates = DeployCandidates(s.populations, {}, {FineCamera()}, deploy);
  ASSERT_EQ(s.candidates.size(), 2u);
  s.observations = Observe(s.scene, s.reference, s.candidates);
  s.select.n = 2;
  s.select.method = Method::kLocal;
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  ASSERT_LT(s.start.coverage, 2 * kFace / kShell);
  const auto whole_faces = [](std::span<const Candidate> candidates,
                              std::span<const Observation> observations) {
    InstallConstraints constraints;
    for (uint32_t a = 0; a < candidates.size(); ++a) {
      for (uint32_t b = a + 1; b < candidates.size(); ++b) {
        if (observations[a].reference_indices.size() == kFace &&
            observations[b].reference_indices.size() == kFace)
          constraints.conflicts.push_back({a, b, ConflictKind::kSeparation, 0});
      }
    }
    return constraints;
  };
  RefineOptions options;
  options.per_sensor = 1000;
  const RefineResult free = RunRefine(s, options);
  EXPECT_DOUBLE_EQ(free.selection.coverage, 2 * kFace / kShell);
  options.constraints = whole_faces;
  const RefineResult r = RunRefine(s, options);
  EXPECT_GE(r.selection.coverage, s.start.coverage);
  EXPECT_LT(r.selection.coverage, 2 * kFace / kShell);
  ASSERT_EQ(r.selection.chosen.size(), 2u);
  size_t whole = 0;
  for (const uint32_t c : r.selection.chosen)
    whole += r.observations[c].reference_indices.size() == kFace ? 1 : 0;
  EXPECT_LE(whole, 1u);
  // One whole face is still reachable: the other sensor keeps its part.
  EXPECT_GT(r.selection.coverage, kFace / kShell);
  EXPECT_DOUBLE_EQ(r.selection.coverage, UnionCoverage(r, s.reference.size()));
}

// Kept sensors (--keep-existing, issue 42): the kept camera stays where it is — no pose is
// searched around it and every answer holds it — while the other one is refined. Two faces, one
// population each: the kept +x camera sees its strip of 12 cells; the -x one can be turned to see
// its whole face (36), so the refined layout sees 12 + 36 cells (the faces are disjoint).
TEST(Refine, KeptSensorsStayWhereTheyAre) {
  Fixture s;
  s.reference = BuildReference(s.scene, {kCell});
  Population plus = FacePopulation();
  Population minus = FacePopulation();
  minus.name = "minus";
  minus.pose = Pose{Vec3(-1.1, 0, 0), Quat::Identity()};  // region x in [-1.2, -1.0]
  s.populations = {plus, minus};
  s.observation_point = kPastTheCube;
  DeployOptions deploy;
  deploy.observation_point = s.observation_point;
  s.candidates = DeployCandidates(s.populations, {}, {FineCamera()}, deploy);
  ASSERT_EQ(s.candidates.size(), 2u);
  ASSERT_EQ(s.candidates[0].population, "pop");
  s.observations = Observe(s.scene, s.reference, s.candidates);
  ASSERT_EQ(s.observations[0].reference_indices.size(), kStripCells);
  s.select.n = 2;
  s.select.method = Method::kLocal;
  s.select.fixed = {0};
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  RefineOptions options;
  options.per_sensor = 1000;
  const RefineResult r = RunRefine(s, options);
  ASSERT_EQ(r.selection.chosen.size(), 2u);
  EXPECT_EQ(r.selection.chosen[0], 0u);  // the kept camera, first, at its own pose
  EXPECT_TRUE(r.candidates[0].world_from_body.position.isApprox(
      s.candidates[0].world_from_body.position));
  for (size_t i = s.candidates.size(); i < r.candidates.size(); ++i)
    EXPECT_EQ(r.candidates[i].population, "minus") << r.candidates[i].name;  // none around +x
  EXPECT_DOUBLE_EQ(r.selection.coverage, (kStripCells + kFace) / kShell);
  EXPECT_DOUBLE_EQ(r.selection.coverage, UnionCoverage(r, s.reference.size()));
  // A start that lacks the kept camera is refused.
  Fixture lacking = s;
  lacking.start.chosen = {1};
  EXPECT_THROW(RunRefine(lacking, options), InputError);
}

// Point density (--min-points, issue 42): the new poses keep their pixel counts, and the refined
// layout is scored by the cells holding the points, recomputed here from the hits.
TEST(Refine, MinPointsScoresTheRefinedLayoutInPoints) {
  Fixture s = FaceSetup();
  s.select.min_points = 50;
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  const RefineResult r = RunRefine(s);
  EXPECT_EQ(r.selection.objective, "min-points");
  ASSERT_TRUE(r.selection.min_points.has_value());
  EXPECT_EQ(*r.selection.min_points, 50u);
  for (const Observation& o : r.observations) EXPECT_TRUE(o.has_point_counts());
  // The cells in which the chosen put at least 50 hits, counted here.
  std::map<uint32_t, uint64_t> hits;
  for (const uint32_t c : r.selection.chosen) {
    const Observation& o = r.observations[c];
    for (size_t j = 0; j < o.reference_indices.size(); ++j)
      hits[o.reference_indices[j]] += o.reference_hits[j];
  }
  size_t cells = 0;
  for (const auto& [cell, h] : hits) cells += h >= 50 ? 1 : 0;
  EXPECT_DOUBLE_EQ(r.selection.coverage, static_cast<double>(cells) / kShell);
  EXPECT_GE(r.selection.coverage, s.start.coverage);
  // A 0.25 mm pixel puts about 1600 rays in a 1 cm cell face on: the whole face holds 50.
  EXPECT_DOUBLE_EQ(r.selection.coverage, kFace / kShell);
}

// A budget (issue 42): a new pose costs what the candidate it descends from costs, so the refined
// layout's cost is the root's price (3.5), within the budget, and its coverage is the union
// counted here. (Scoring once read prices past the given candidates' costs.)
TEST(Refine, BudgetPricesNewPosesLikeTheirCandidate) {
  Fixture s = FaceSetup();
  ASSERT_EQ(s.candidates.size(), 1u);
  s.select.budget = 4.0;
  s.select.costs = {3.5};
  s.start = Select(s.observations, s.reference.size(), s.select).at(0);
  ASSERT_EQ(s.start.chosen.size(), 1u);
  const RefineResult r = RunRefine(s);
  ASSERT_GT(r.candidates.size(), s.candidates.size());  // new poses were made
  ASSERT_EQ(r.selection.chosen.size(), 1u);
  ASSERT_TRUE(r.selection.cost.has_value());
  EXPECT_DOUBLE_EQ(*r.selection.cost, 3.5);
  EXPECT_DOUBLE_EQ(r.selection.coverage, UnionCoverage(r, s.reference.size()));
  EXPECT_GT(r.selection.coverage, s.start.coverage);
}

// Scene states (issue 42): a second state puts a hand between the region and the +y half of
// the face. Every new pose is traced in both states (in the hand state it sees a subset of what it
// sees without, and the hand hides something from some pose), and the refined layout is scored by
// the states' mean, recomputed here from the two matrices.
TEST(Refine, OverStatesTracesEveryStateAndScoresTheMean) {
  Fixture s = FaceSetup();
  Scene hand_scene = CubeScene();
  TriangleMesh hand = MakeBox(Vec3(0.01, 0.04, 0.08));
  hand.Transform(Pose{Vec3(0.5, 0.02, 0), Quat::Identity()});
  hand_scene.objects.push_back({"hand", Role::kOccluder, std::move(hand), {}});
  const Reference hand_reference = BuildReference(hand_scene, {kCell});
  ASSERT_EQ(hand_reference.size(), kShell);
  const std::vector<Observation> hand_observations =
      Observe(hand_scene, hand_reference, s.candidates);
  const std::vector<StateObservations> views{
      {"empty", s.reference.size(), s.observations},
      {"hand", hand_reference.size(), hand_observations}};
  s.start = SelectOverStates(views, OverStates::kMean, s.select).at(0).selection;
  const RayScene hand_rays(hand_scene);
  RefineOptions options;
  options.states = {{"hand", &hand_rays, &hand_reference, hand_observations}};
  options.over = OverStates::kMean;
  const RefineResult r = RunRefine(s, options);
  ASSERT_GT(r.new_candidates, 0u);
  ASSERT_EQ(r.state_observations.size(), 1u);
  const std::vector<Observation>& in_hand = r.state_observations[0];
  ASSERT_EQ(in_hand.size(), r.candidates.size());
  bool hidden = false;
  for (size_t i = s.candidates.size(); i < r.candidates.size(); ++i) {
    const std::set<uint32_t> free(r.observations[i].reference_indices.begin(),
                                  r.observations[i].reference_indices.end());
    for (const uint32_t cell : in_hand[i].reference_indices)
      EXPECT_TRUE(free.count(cell)) << r.candidates[i].name;
    hidden = hidden || in_hand[i].reference_indices.size() < free.size();
  }
  EXPECT_TRUE(hidden);
  // The mean of the two states' union coverages, counted here.
  const auto union_of = [&](const std::vector<Observation>& observations) {
    std::set<uint32_t> cells;
    for (const uint32_t c : r.selection.chosen)
      cells.insert(observations[c].reference_indices.begin(),
                   observations[c].reference_indices.end());
    return static_cast<double>(cells.size()) / kShell;
  };
  const double empty = union_of(r.observations), with_hand = union_of(in_hand);
  ASSERT_EQ(r.selection.state_coverage.size(), 2u);
  EXPECT_DOUBLE_EQ(r.selection.state_coverage[0], empty);
  EXPECT_DOUBLE_EQ(r.selection.state_coverage[1], with_hand);
  EXPECT_DOUBLE_EQ(r.selection.coverage, (empty + with_hand) / 2);
  EXPECT_DOUBLE_EQ(r.coverage_before, s.start.coverage);
  EXPECT_GT(r.selection.coverage, s.start.coverage);
  for (size_t i = 1; i < r.history.size(); ++i) EXPECT_GE(r.history[i], r.history[i - 1]);
  // A state without one observation per candidate is refused.
  options.states[0].observations.pop_back();
  EXPECT_THROW(RunRefine(s, options), InputError);
}

// A set cover goal (the fewest sensors that reach it) re-selects with greedy: set cover has no
// local search (before, --refine --goal exited 2 naming `local`, which it had not been given).
TEST(Refine, SetCoverGoalReselectsWithGreedy) {
  for (const Method method : {Method::kAll, Method::kGreedy, Method::kExact}) {
    Fixture s = FaceSetup();
    s.select.goal = 10 / kShell;  // the strip's 12 cells reach it
    s.select.method = method;
    s.start = Select(s.observations, s.reference.size(), s.select).at(0);
    const RefineResult r = RunRefine(s);
    EXPECT_EQ(r.selection.chosen.size(), 1u) << MethodName(method);
    EXPECT_GE(r.selection.coverage, 10 / kShell) << MethodName(method);
    EXPECT_GE(r.selection.coverage, s.start.coverage) << MethodName(method);
  }
}

TEST(Refine, SameResultWithOneAndTwoThreads) {
  const Fixture s = FaceSetup();
  const auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return RunRefine(s);
  };
  const RefineResult a = run(1);
  const RefineResult b = run(2);
  ASSERT_EQ(a.candidates.size(), b.candidates.size());
  for (size_t i = 0; i < a.candidates.size(); ++i) {
    EXPECT_EQ(a.candidates[i].name, b.candidates[i].name);
    EXPECT_EQ(a.candidates[i].world_from_body.position, b.candidates[i].world_from_body.position);
    EXPECT_EQ(a.candidates[i].world_from_body.rotation.coeffs(),
              b.candidates[i].world_from_body.rotation.coeffs());
    EXPECT_EQ(a.observations[i].reference_indices, b.observations[i].reference_indices);
    EXPECT_EQ(a.observations[i].rays_traced, b.observations[i].rays_traced);
  }
  EXPECT_EQ(a.selection.chosen, b.selection.chosen);
  EXPECT_EQ(a.selection.coverage, b.selection.coverage);
  EXPECT_EQ(a.history, b.history);
  EXPECT_EQ(a.extra_rays, b.extra_rays);
}

TEST(Refine, ZeroRoundsChangesNothing) {
  const Fixture s = FaceSetup();
  RefineOptions options;
  options.max_rounds = 0;
  const RefineResult r = RunRefine(s, options);
  EXPECT_EQ(r.candidates.size(), 1u);
  EXPECT_EQ(r.selection.chosen, s.start.chosen);
  EXPECT_DOUBLE_EQ(r.selection.coverage, s.start.coverage);
  EXPECT_EQ(r.extra_rays, 0u);
}

TEST(Refine, RejectsBadInput) {
  const Fixture s = FaceSetup();
  RefineOptions bad;
  bad.move = 0;
  EXPECT_THROW(RunRefine(s, bad), InputError);
  bad = {};
  bad.per_sensor = 0;
  EXPECT_THROW(RunRefine(s, bad), InputError);
  // One observation short.
  EXPECT_THROW(Refine(RayScene(s.scene), s.reference, s.candidates, {}, s.populations, s.observation_point,
                      s.start, s.select, {}),
               InputError);
  // The candidate's population is not given.
  EXPECT_THROW(Refine(RayScene(s.scene), s.reference, s.candidates, s.observations, {}, s.observation_point,
                      s.start, s.select, {}),
               InputError);
  Selection out_of_range = s.start;
  out_of_range.chosen = {7};
  EXPECT_THROW(Refine(RayScene(s.scene), s.reference, s.candidates, s.observations, s.populations,
                      s.observation_point, out_of_range, s.select, {}),
               InputError);
}

TEST(RegionContains, BoxIsShiftedBeforeTheRotation) {
  // P = (1, 2, 3) yawed 90°, size (0.4, 0.2, 0.1): origin P - size/2 = (0.8, 1.9, 2.95), offsets
  // o in [0, size] map to (-o_y, o_x, o_z): x in [0.6, 0.8], y in [1.9, 2.3], z in [2.95, 3.05].
  Population p;
  p.pose = Pose::FromXyzRpy(1, 2, 3, 0, 0, kPi / 2);
  p.region = RegionShape::kBox;
  p.box_size = Vec3(0.4, 0.2, 0.1);
  EXPECT_TRUE(RegionContains(p, Vec3(0.7, 2.1, 3.0)));
  EXPECT_TRUE(RegionContains(p, Vec3(0.6, 1.9, 2.95)));  // a corner
  EXPECT_FALSE(RegionContains(p, Vec3(1, 2, 3)));        // P itself: Gazebo's quirk
  EXPECT_FALSE(RegionContains(p, Vec3(0.85, 2.1, 3.0)));
  EXPECT_FALSE(RegionContains(p, Vec3(0.7, 2.35, 3.0)));
  EXPECT_FALSE(RegionContains(p, Vec3(0.7, 2.1, 3.06)));
  // Every clone that deployment places is inside.
  p.name = "box";
  p.count = 200;
  p.distribution = Distribution::kRandom;
  for (const Vec3& clone : PopulationPositions(p, 3, 0)) EXPECT_TRUE(RegionContains(p, clone));
}

TEST(RegionContains, Cylinder) {
  // Axis through (0, 0, 0.5), radius 0.3, z from 0.5 to 0.7 (P is the bottom centre, not shifted).
  Population p;
  p.name = "cyl";
  p.pose = Pose{Vec3(0, 0, 0.5), Quat::Identity()};
  p.region = RegionShape::kCylinder;
  p.radius = 0.3;
  p.length = 0.2;
  EXPECT_TRUE(RegionContains(p, Vec3(0.2, 0.1, 0.6)));
  EXPECT_TRUE(RegionContains(p, Vec3(0, 0, 0.5)));
  EXPECT_FALSE(RegionContains(p, Vec3(0.3, 0.1, 0.6)));  // ρ = 0.316
  EXPECT_FALSE(RegionContains(p, Vec3(0, 0, 0.45)));
  EXPECT_FALSE(RegionContains(p, Vec3(0, 0, 0.75)));
  p.count = 200;
  p.distribution = Distribution::kRandom;
  for (const Vec3& clone : PopulationPositions(p, 5, 1)) EXPECT_TRUE(RegionContains(p, clone));
}

TEST(RegionContains, GridIsItsLatticeWidenedByHalfAStep) {
  // Pose (0, 0, 1), 2 rows x 3 cols, step (0.1, 0.2, 0): lattice x in {-0.1, 0, 0.1}, y in
  // {-0.1, 0.1} at z = 1, so the region is x in [-0.15, 0.15], y in [-0.2, 0.2], z = 1.
  Population p;
  p.name = "grid";
  p.pose = Pose{Vec3(0, 0, 1), Quat::Identity()};
  p.region = RegionShape::kNone;
  p.distribution = Distribution::kGrid;
  p.rows = 2;
  p.cols = 3;
  p.step = Vec3(0.1, 0.2, 0);
  EXPECT_TRUE(RegionContains(p, Vec3(0.14, 0.19, 1)));
  EXPECT_TRUE(RegionContains(p, Vec3(-0.15, -0.2, 1)));
  EXPECT_FALSE(RegionContains(p, Vec3(0.16, 0, 1)));
  EXPECT_FALSE(RegionContains(p, Vec3(0, 0.21, 1)));
  EXPECT_FALSE(RegionContains(p, Vec3(0, 0, 1.001)));
  for (const Vec3& clone : PopulationPositions(p, 1, 0)) EXPECT_TRUE(RegionContains(p, clone));
}

}  // namespace
}  // namespace vantage
