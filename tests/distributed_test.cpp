// Beyond one process (issue 18): the cost split, --shard and `vantage merge`. The MPI runs are
// CTest cases of tests/mpi_test.sh (they need mpirun).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numeric>
#include <sstream>

#include "test_util.hpp"
#include "vantage/distribute.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"

namespace vantage {
namespace {

using test::RunVantage;

std::string Example() {
  return std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
}

// Sets an environment variable for one test and restores its absence afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedEnv() { ::unsetenv(name_); }

 private:
  const char* name_;
};

TEST(SplitByCost, BoundariesByEnumeratedPrefixCosts) {
  const std::vector<uint64_t> even = {1, 1, 1, 1};
  EXPECT_EQ(SplitByCost(even, 2), (std::vector<size_t>{0, 2, 4}));
  EXPECT_EQ(SplitByCost(even, 1), (std::vector<size_t>{0, 4}));
  // One heavy candidate of half the total: it alone is the first part, not the first half by count.
  const std::vector<uint64_t> heavy = {10, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(SplitByCost(heavy, 2), (std::vector<size_t>{0, 1, 11}));
  // More parts than candidates: some parts are empty, every candidate in exactly one.
  const std::vector<uint64_t> two = {5, 5};
  EXPECT_EQ(SplitByCost(two, 4), (std::vector<size_t>{0, 0, 1, 1, 2}));
  EXPECT_EQ(SplitByCost(std::vector<uint64_t>{}, 3), (std::vector<size_t>{0, 0, 0, 0}));
}

TEST(SplitByCost, EachPartWithinOneCandidateOfItsShare) {
  std::vector<uint64_t> costs;
  for (uint64_t i = 0; i < 1000; ++i) costs.push_back(1 + (i * 7919) % 1000);  // 1..1000
  const uint64_t total = std::accumulate(costs.begin(), costs.end(), uint64_t{0});
  for (size_t parts : {2, 3, 7, 64}) {
    const std::vector<size_t> b = SplitByCost(costs, parts);
    ASSERT_EQ(b.size(), parts + 1);
    for (size_t p = 0; p < parts; ++p) {
      const uint64_t part = std::accumulate(costs.begin() + static_cast<long>(b[p]),
                                            costs.begin() + static_cast<long>(b[p + 1]),
                                            uint64_t{0});
      EXPECT_NEAR(static_cast<double>(part), static_cast<double>(total) / parts, 1000.0)
          << parts << " parts, part " << p;
    }
  }
}

TEST(TraceCosts, CountsTheRaysObserveTraces) {
  SceneInput input;
  input.path = Example();
  PreparedScene prepared = Prepare(input);
  const Reference reference =
      BuildReference(prepared.problem.scene, ReferenceOptions{prepared.problem.cell_size});
  ObserveOptions observe;
  const std::vector<Observation> traced =
      Observe(prepared.problem.scene, reference, prepared.candidates, observe);
  const std::vector<uint64_t> rays = CountRaysToTrace(reference, prepared.candidates, observe);
  ASSERT_EQ(rays.size(), prepared.candidates.size());
  for (size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(rays[i], traced[i].rays_traced) << i;
  // Without culling every pixel is a ray: width × height.
  observe.cull = false;
  const std::vector<uint64_t> all = CountRaysToTrace(reference, prepared.candidates, observe);
  for (size_t i = 0; i < all.size(); ++i) {
    const SensorType& s = prepared.candidates[i].sensor;
    EXPECT_EQ(all[i], static_cast<uint64_t>(s.width) * static_cast<uint64_t>(s.height)) << i;
  }
}

// The pipeline traces through the TraceFunction once per geometry: the example's three states
// (idle, a gripper added, the motor moved) are three geometries, each traced over all 73
// candidates, and what the function returns is what the run keeps.
TEST(TraceFunction, CalledOncePerStateGeometryWithEveryCandidate) {
  SceneInput input;
  input.path = std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_states.yaml";
  std::vector<size_t> calls;
  const TraceFunction trace = [&](const RayScene& rays, const Reference& reference,
                                  std::span<const Candidate> candidates,
                                  const ObserveOptions& options) {
    calls.push_back(candidates.size());
    std::vector<Observation> observations = Observe(rays, reference, candidates, options);
    observations[0].rays_traced = 12345;  // marks what the run kept
    return observations;
  };
  const ObservedScene observed = ObservePrepared(Prepare(input), ObserveOptions{}, RunLimits{},
                                                 trace);
  EXPECT_EQ(calls, (std::vector<size_t>{73, 73, 73}));
  ASSERT_EQ(observed.states.size(), 3u);
  for (const ObservedState& state : observed.states)
    EXPECT_EQ(state.observations[0].rays_traced, 12345u) << state.name;
  EXPECT_EQ(observed.data.observations[0].rays_traced, 12345u);
}

TEST(ParseShard, IndexFromTheFlagOrTheJobArray) {
  const ShardSpec s = ParseShard("1/4");
  EXPECT_EQ(s.index, 1u);
  EXPECT_EQ(s.count, 4u);
  // Leading zeros are refused as every other whole number of the command line refuses them
  // (issue 44: "01/2" was accepted).
  for (const char* bad : {"4/4", "1", "-1/4", "1/0", "a/4", "1/4x", "env/4", "01/2", "1/02",
                          "00/2", "+1/2", "0/+2", "env/02"}) {
    try {
      ParseShard(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--shard", 0), 0u) << e.what();
    }
  }
  {
    ScopedEnv slurm("SLURM_ARRAY_TASK_ID", "2");
    EXPECT_EQ(ParseShard("env/4").index, 2u);
    EXPECT_THROW(ParseShard("env/2"), InputError);  // 2 is not below K = 2
  }
  ScopedEnv kubernetes("JOB_COMPLETION_INDEX", "3");
  EXPECT_EQ(ParseShard("env/4").index, 3u);
}

std::string Bytes(const std::string& path) { return test::ReadText(path); }

// Shards 0..K-1 merged are the single process's file byte for byte, whatever K and the order of
// the parts; each shard observes a contiguous range, together every candidate once.
TEST(Shards, MergedPartsAreTheOneProcessFile) {
  test::TempDir dir;
  const std::string flags = " --max-incidence 70 -n 2";
  auto run = RunVantage("-q observe " + Example() + flags + " --out " + dir.File("one.vis"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (int k : {1, 3, 5}) {
    std::string parts;
    for (int i = k - 1; i >= 0; --i) {  // reversed: merge sorts the parts by index
      const std::string part = dir.File(fmt::format("part_{}_{}.vis", k, i));
      run = RunVantage(fmt::format("-q observe {}{} --shard {}/{} --out {}", Example(), flags, i,
                                   k, part));
      ASSERT_EQ(run.exit_code, 0) << run.err;
      parts += " " + part;
    }
    const std::string merged = dir.File(fmt::format("all_{}.vis", k));
    run = RunVantage("merge" + parts + " --out " + merged);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(Bytes(merged), Bytes(dir.File("one.vis"))) << k << " shards";
  }
  // Each part observed only its own, and the ranges split by cost: within one candidate's cost.
  uint64_t total = 0, largest = 0, heaviest_part = 0;
  const VisibilityFile one = LoadVisibilityFile(dir.File("one.vis"));
  for (const Observation& o : one.observations) {
    total += o.rays_traced + 256;
    largest = std::max<uint64_t>(largest, o.rays_traced + 256);
  }
  for (int i = 0; i < 3; ++i) {
    const VisibilityShard part = LoadVisibilityShard(dir.File(fmt::format("part_3_{}.vis", i)));
    uint64_t cost = 0;
    for (size_t c = 0; c < part.file.observations.size(); ++c) {
      const bool own = std::binary_search(part.candidates.begin(), part.candidates.end(), c);
      if (own) {
        cost += one.observations[c].rays_traced + 256;
      } else {
        EXPECT_EQ(part.file.observations[c].rays_traced, 0u) << c;
      }
    }
    heaviest_part = std::max(heaviest_part, cost);
  }
  EXPECT_LE(heaviest_part, total / 3 + largest);
}

TEST(Shards, MergedPartsOfAnArmSceneKeepEachArmView) {
  // Format 11 (issue 45): the parts carry the arm views of every candidate, and the merged file
  // is the one-process file, arm section included, so that `select` of it gives the tours.
  test::TempDir dir;
  const std::string scene =
      std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/arm_wrist_camera.yaml";
  auto run = RunVantage("-q observe " + scene + " --out " + dir.File("one.vis"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (int i : {1, 0}) {
    run = RunVantage(fmt::format("-q observe {} --shard {}/2 --out {}", scene, i,
                                 dir.File(fmt::format("part_{}.vis", i))));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  run = RunVantage("merge " + dir.File("part_1.vis") + " " + dir.File("part_0.vis") + " --out " +
                   dir.File("all.vis"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Bytes(dir.File("all.vis")), Bytes(dir.File("one.vis")));
  const VisibilityFile all = LoadVisibilityFile(dir.File("all.vis"));
  ASSERT_EQ(all.arm_views.size(), all.candidates.size());
  for (const auto& view : all.arm_views) {
    ASSERT_TRUE(view.has_value());
    EXPECT_EQ(view->robot, "arm");
    EXPECT_EQ(view->joints.size(), 6u);
  }
}

TEST(Shards, MergeRefusesForeignMissingAndRepeatedParts) {
  test::TempDir dir;
  const auto observe = [&](const std::string& flags, const std::string& name) {
    const auto run = RunVantage("-q observe " + Example() + " " + flags + " --out " +
                                dir.File(name));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  };
  observe("--shard 0/3", "p0.vis");
  observe("--shard 1/3", "p1.vis");
  observe("--shard 2/3", "p2.vis");
  observe("--shard 2/3 --seed 7", "seed7.vis");          // another deployment
  observe("--shard 2/3 --max-incidence 60", "q60.vis");  // another quality filter
  observe("--shard 1/2", "half.vis");                    // another K
  const std::string out = dir.File("all.vis");
  test::WriteText(out, "earlier");
  const auto refused = [&](const std::string& parts, const std::string& needle) {
    const auto run = RunVantage("merge " + parts + " --out " + out);
    EXPECT_EQ(run.exit_code, 2) << parts << "\n" << run.err;
    EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    EXPECT_EQ(test::ReadText(out), "earlier");  // previous output untouched
  };
  const std::string p0 = dir.File("p0.vis"), p1 = dir.File("p1.vis");
  refused(p0 + " " + p1 + " " + dir.File("seed7.vis"),
          dir.File("seed7.vis") + ": was observed with other options than " + p0 + ": " +
              dir.File("seed7.vis") + " has '--seed 7', " + p0 + " has not");
  refused(p0 + " " + p1 + " " + dir.File("q60.vis"),
          dir.File("q60.vis") + ": was observed with other options than " + p0 + ": " +
              dir.File("q60.vis") + " has '--max-incidence 60', " + p0 + " has not");
  refused(p0 + " " + p1, "shard 2/3 is missing");
  refused(p0 + " " + p1 + " " + p1, dir.File("p1.vis") + ": repeats shard 1/3");
  refused(p0 + " " + dir.File("half.vis"), "half.vis: is shard 1/2, but");
  refused(dir.File("one_missing.vis"), "one_missing.vis");
  refused(Example(), "not a shard");
  // The three right parts merge.
  const auto run =
      RunVantage("merge " + p0 + " " + p1 + " " + dir.File("p2.vis") + " --out " + out);
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

// A copy of the example in `folder` (its mesh beside it), with `edit` applied to its text.
std::string ExampleCopy(const test::TempDir& dir, const std::string& folder,
                        const std::function<std::string(std::string)>& edit = {}) {
  std::filesystem::create_directories(dir.File(folder));
  std::string text = test::ReadText(Example());
  const std::string mesh = "../meshes/small_motor.obj";
  const size_t at = text.find(mesh);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, mesh.size(), "small_motor.obj");
  if (edit) text = edit(text);
  test::WriteText(dir.File(folder + "/scene.yaml"), text);
  std::filesystem::copy_file(std::string(VANTAGE_SOURCE_DIR) + "/examples/meshes/small_motor.obj",
                             dir.File(folder + "/small_motor.obj"));
  return dir.File(folder + "/scene.yaml");
}

// Issue 44: parts of a scene edited between the shards (the scene's text, or only a mesh it
// includes) were merged into a mixed matrix; the fingerprint covers the content, not the path, so
// the same content at another path merges into the one process's file.
TEST(Shards, MergeRefusesPartsOfAnEditedScene) {
  test::TempDir dir;
  const std::string scene = ExampleCopy(dir, "cell");
  const auto observe = [&](const std::string& path, const std::string& flags,
                           const std::string& name) {
    const auto run = RunVantage("-q observe " + path + " " + flags + " --out " + dir.File(name));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  };
  observe(scene, "--shard 0/2", "p0.vis");
  observe(scene, "--shard 1/2", "p1.vis");
  observe(scene, "", "one.vis");
  const std::string p0 = dir.File("p0.vis"), p1 = dir.File("p1.vis"), out = dir.File("all.vis");
  const auto refused = [&](const std::string& part, const std::string& needle) {
    test::WriteText(out, "earlier");
    const auto run = RunVantage("merge " + p0 + " " + part + " --out " + out);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    EXPECT_EQ(test::ReadText(out), "earlier");
  };
  // A bin wall moved 5 mm in the scene's text, then shard 1 observed.
  const std::string wall = "pose: {xyz: [0, 0.145, 0.805]}";
  test::WriteText(scene, [&] {
    std::string text = test::ReadText(scene);
    const size_t at = text.find(wall);
    EXPECT_NE(at, std::string::npos);
    return text.replace(at, wall.size(), "pose: {xyz: [0, 0.15, 0.805]}");
  }());
  observe(scene, "--shard 1/2", "moved.vis");
  refused(dir.File("moved.vis"), dir.File("moved.vis") + ": was observed in another scene "
                                     "geometry than " + p0);
  // The scene's text as it was, the mesh it includes changed (one vertex 2 mm off).
  ExampleCopy(dir, "edited_mesh");
  const std::string mesh = dir.File("edited_mesh/small_motor.obj");
  std::string obj = test::ReadText(mesh);
  const size_t begin = obj.find("\nv ") + 1;
  ASSERT_NE(begin, 0u);
  const size_t end = obj.find('\n', begin);
  std::istringstream fields(obj.substr(begin + 2, end - begin - 2));
  double x = 0, y = 0, z = 0;
  fields >> x >> y >> z;
  obj.replace(begin, end - begin, fmt::format("v {} {} {}", x + 0.002, y, z));
  test::WriteText(mesh, obj);
  observe(dir.File("edited_mesh/scene.yaml"), "--shard 1/2", "mesh.vis");
  refused(dir.File("mesh.vis"), dir.File("mesh.vis") + ": was observed in another scene "
                                    "geometry than " + p0);
  // The same content at another path: merged, shard 0's file byte for byte.
  const std::string elsewhere = ExampleCopy(dir, "elsewhere");
  observe(elsewhere, "--shard 1/2", "elsewhere.vis");
  const auto run = RunVantage("merge " + dir.File("elsewhere.vis") + " " + p0 + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Bytes(out), Bytes(dir.File("one.vis")));
}

// Issue 44: a part observed with --no-cull (which splits by other costs) was refused as "written
// by different vantage builds?", naming no file; another build is named as such.
TEST(Shards, MergeNamesTheOptionOrBuildThatDiffers) {
  test::TempDir dir;
  const auto observe = [&](const std::string& flags, const std::string& name) {
    const auto run = RunVantage("-q observe " + Example() + " " + flags + " --out " +
                                dir.File(name));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  };
  observe("--shard 0/2", "p0.vis");
  observe("--shard 1/2 --no-cull", "nocull.vis");
  {
    ScopedEnv build("VANTAGE_TEST_BUILD_ID", "another build");
    observe("--shard 1/2", "build.vis");
  }
  const std::string p0 = dir.File("p0.vis");
  auto run = RunVantage("merge " + p0 + " " + dir.File("nocull.vis") + " --out " +
                        dir.File("all.vis"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(dir.File("nocull.vis") + ": was observed with other options than " + p0 +
                         ": " + dir.File("nocull.vis") + " has '--no-cull', " + p0 + " has not"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(run.err.find("different vantage builds"), std::string::npos) << run.err;
  run = RunVantage("merge " + p0 + " " + dir.File("build.vis") + " --out " + dir.File("all.vis"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(dir.File("build.vis") + ": was observed by another vantage build "
                                                 "(another build) than " + p0),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("all.vis")));
}

TEST(Shards, IndexFromTheJobArrayEnvironment) {
  test::TempDir dir;
  ScopedEnv array("JOB_COMPLETION_INDEX", "1");
  auto run = RunVantage("-q observe " + Example() + " --shard env/2 --out " + dir.File("p.vis"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(LoadVisibilityShard(dir.File("p.vis")).index, 1u);
  run = RunVantage("-q observe " + Example() + " --shard env/1 --out " + dir.File("q.vis"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--shard"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("q.vis")));
}

}  // namespace
}  // namespace vantage
