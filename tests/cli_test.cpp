// The `vantage` binary as users run it: exit codes 0/2/1, the file:line prefix of input errors,
// the two halves of the pipeline agreeing with the whole, determinism across thread counts, and
// outputs left untouched by a failed run.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "test_util.hpp"

namespace vantage {
namespace {

using nlohmann::json;
using test::RunVantage;

std::string Scene() { return test::DataPath("cli/cube_cell.yaml"); }

// report.json without the wall-clock fields, which legitimately differ between runs.
json WithoutTimings(json report) {
  report.erase("timings");
  for (json& r : report["results"]) r.erase("seconds");
  for (json& r : report["curve"]) r.erase("seconds");  // the curve's answers are timed too
  return report;
}

TEST(Cli, SensorsListsTheCatalog) {
  const auto table = RunVantage("sensors");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  for (const char* id : {"kinect_xbox_360", "photoneo_phoxi_s", "azure_kinect_wfov", "zed",
                         "femto_bolt_wfov_unbinned"})
    EXPECT_NE(table.out.find(id), std::string::npos) << id;
  const auto listed = RunVantage("sensors --json");
  ASSERT_EQ(listed.exit_code, 0);
  const json catalog = json::parse(listed.out);
  // SENSORS.md's 14, the modes of docs/sensor-models.md and the Femto Bolt's four (issue 43).
  ASSERT_EQ(catalog.size(), 23u);
  // SR300 (SENSORS.md): 640 px over 1.24791 rad -> fx = 320 / tan(0.623955).
  for (const json& t : catalog) {
    if (t["id"] == "intel_realsense_sr300") {
      EXPECT_NEAR(t["fx"].get<double>(), 320 / std::tan(0.623955), 1e-9);
    }
    // A vendor that publishes no price has none (issue 43), every other entry its number.
    EXPECT_EQ(t["cost"].is_null(), t["id"].get<std::string>().starts_with("femto_bolt")) << t["id"];
  }
}

TEST(Cli, HelpAndUsageErrors) {
  EXPECT_EQ(RunVantage("help optimize").exit_code, 0);
  EXPECT_NE(RunVantage("help optimize").out.find("--method"), std::string::npos);
  EXPECT_EQ(RunVantage("").exit_code, 2);
  EXPECT_EQ(RunVantage("optimize").exit_code, 2);
  EXPECT_EQ(RunVantage("frobnicate").exit_code, 2);
  EXPECT_EQ(RunVantage("optimize " + Scene() + " --no-such-option").exit_code, 2);
}

TEST(Cli, OptimizeWritesEveryOutput) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + Scene() + " --out " + dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* name : {"report.json", "candidates.csv", "reference.ply", "observed.ply"})
    EXPECT_TRUE(std::filesystem::exists(dir.File("out/") + name)) << name;
  const json report = json::parse(test::ReadText(dir.File("out/report.json")));
  // The 10 cm cube's faces lie on 1 cm grid planes: cells -5..5, 11³ - 9³ = 602.
  EXPECT_EQ(report["reference_voxels"], 602);
  EXPECT_EQ(report["candidates"].size(), 16u);  // 10 random + 2 x 3 grid
  EXPECT_EQ(report["seed"], 3);
  std::set<std::string> methods;
  for (const json& r : report["results"]) {
    methods.insert(r["method"].get<std::string>());
    EXPECT_LE(r["coverage"].get<double>(), 1.0);
    EXPECT_LE(r["coverage"].get<double>(), r["paper_coverage"].get<double>() + 1e-12);
  }
  for (const char* m : {"best", "ransac", "greedy"}) EXPECT_TRUE(methods.count(m)) << m;
  // The summary names the per-method results.
  EXPECT_NE(run.out.find("greedy"), std::string::npos);
  EXPECT_NE(run.out.find("reference        602 voxels"), std::string::npos);
}

TEST(Cli, ObserveThenSelectEqualsOptimize) {
  test::TempDir dir;
  ASSERT_EQ(RunVantage("optimize " + Scene() + " --method greedy --out " + dir.File("whole")).exit_code, 0);
  const auto observe = RunVantage("observe " + Scene() + " --out " + dir.File("m.vis"));
  ASSERT_EQ(observe.exit_code, 0) << observe.err;
  const auto select = RunVantage("select " + dir.File("m.vis") + " --method greedy --out " + dir.File("halves"));
  ASSERT_EQ(select.exit_code, 0) << select.err;
  const json whole = json::parse(test::ReadText(dir.File("whole/report.json")));
  const json halves = json::parse(test::ReadText(dir.File("halves/report.json")));
  EXPECT_EQ(whole["results"][0]["sensors"], halves["results"][0]["sensors"]);
  EXPECT_EQ(whole["results"][0]["coverage"], halves["results"][0]["coverage"]);
  EXPECT_EQ(whole["candidates"], halves["candidates"]);
}

// The current folder, changed for one scope: a command run from another folder than observe's.
class InFolder {
 public:
  explicit InFolder(const std::filesystem::path& folder) : before_(std::filesystem::current_path()) {
    std::filesystem::current_path(folder);
  }
  ~InFolder() { std::filesystem::current_path(before_); }
  InFolder(const InFolder&) = delete;
  InFolder& operator=(const InFolder&) = delete;

 private:
  std::filesystem::path before_;
};

// The .vis names the scene as observe read it (format 10): `select` run from another folder, and
// of a Gazebo world that needs --model-path, reloads the same scene, so robustness's shrunk fields
// of view (re-traced on its geometry) equal optimize's on the scene itself; report.json's inputs
// name it absolutely, so `render` of select's folder finds it too. Before, the path as typed was
// looked up from select's folder and the world's models in no folder: both re-traces were skipped.
TEST(Cli, SelectReloadsTheSceneObserveRead) {
  test::TempDir dir;
  const std::filesystem::path data = std::filesystem::path(test::DataPath("cli")).parent_path();
  const std::string models = (data / "worlds" / "models").string();
  const std::string world = dir.File("world/cell.world");  // away from its models
  std::filesystem::create_directories(dir.File("world"));
  std::filesystem::copy_file(data / "worlds" / "export.world", world);
  std::filesystem::create_directories(dir.File("elsewhere"));
  struct Case {
    std::string name, scene, relative_scene, load;
  };
  for (const Case& c : {Case{"yaml", Scene(), "cli/cube_cell.yaml", ""},
                        Case{"world", world, "world/cell.world", " --model-path " + models}}) {
    SCOPED_TRACE(c.name);
    const std::string whole = dir.File(c.name + "_whole");
    ASSERT_EQ(RunVantage("optimize " + c.scene + c.load + " -n 2 --method greedy --out " + whole)
                  .exit_code,
              0);
    const std::string vis = dir.File(c.name + ".vis");
    {
      InFolder observe_folder(c.name == "yaml" ? data : std::filesystem::path(dir.path()));
      const auto observe = RunVantage("observe " + c.relative_scene + c.load + " --out " + vis);
      ASSERT_EQ(observe.exit_code, 0) << observe.err;
    }
    const std::string halves = dir.File(c.name + "_halves");
    {
      InFolder select_folder(dir.File("elsewhere"));
      const auto select = RunVantage("select " + vis + " -n 2 --method greedy --out " + halves);
      ASSERT_EQ(select.exit_code, 0) << select.err;
      EXPECT_EQ(select.err.find("without meshes"), std::string::npos) << select.err;
    }
    const json expected = json::parse(test::ReadText(whole + "/report.json"));
    const json got = json::parse(test::ReadText(halves + "/report.json"));
    ASSERT_TRUE(expected["robustness"].contains("fov_shrunk_coverage")) << expected["robustness"];
    EXPECT_EQ(got["robustness"].value("fov_shrunk_coverage", -1.0),
              expected["robustness"]["fov_shrunk_coverage"].get<double>());
    EXPECT_EQ(got["inputs"]["scene"], expected["inputs"]["scene"]);
    EXPECT_EQ(got["inputs"].value("model_paths", json::array()),
              expected["inputs"].value("model_paths", json::array()));
    EXPECT_EQ(got["scene"], c.relative_scene);  // the report names it as observe was given it
  }
}

TEST(Cli, EvaluateReproducesTheChosenCoverage) {
  test::TempDir dir;
  ASSERT_EQ(RunVantage("optimize " + Scene() + " -n 3 --method greedy --out " + dir.File("o")).exit_code, 0);
  const json report = json::parse(test::ReadText(dir.File("o/report.json")));
  const auto eval = RunVantage("evaluate " + Scene() + " --constellation " + dir.File("o/report.json") +
                               " --out " + dir.File("e"));
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  const json evaluated = json::parse(test::ReadText(dir.File("e/report.json")));
  EXPECT_DOUBLE_EQ(evaluated["results"][0]["coverage"].get<double>(), report["results"][0]["coverage"].get<double>());
  EXPECT_EQ(evaluated["results"][0]["sensors"], report["results"][0]["sensors"]);
}

TEST(Cli, ExportedConstellationYamlReloadsToTheSameCoverage) {
  test::TempDir dir;
  ASSERT_EQ(RunVantage("optimize " + Scene() + " -n 3 --method greedy --out " + dir.File("o")).exit_code, 0);
  const json report = json::parse(test::ReadText(dir.File("o/report.json")));
  // The export holds exactly the 3 chosen sensors: optimizing it with n = 3 takes them all.
  const auto again = RunVantage("optimize " + dir.File("o/constellation.yaml") + " -n 3 --method greedy --out " +
                                dir.File("again"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json reloaded = json::parse(test::ReadText(dir.File("again/report.json")));
  EXPECT_EQ(reloaded["candidates"].size(), 3u);
  std::set<std::string> chosen, exported;
  for (const json& n : report["results"][0]["sensors"]) chosen.insert(n.get<std::string>());
  for (const json& c : reloaded["candidates"]) exported.insert(c["name"].get<std::string>());
  EXPECT_EQ(chosen, exported);
  // Poses travel as 17-digit decimals: at most a last-bit change of a ray, so allow one voxel.
  EXPECT_NEAR(reloaded["results"][0]["coverage"].get<double>(), report["results"][0]["coverage"].get<double>(),
              1.0 / report["reference_voxels"].get<double>());
}

TEST(Cli, SameSeedSameReportWhateverTheThreadCount) {
  test::TempDir dir;
  ASSERT_EQ(RunVantage("--threads 1 optimize " + Scene() + " --out " + dir.File("t1")).exit_code, 0);
  ASSERT_EQ(RunVantage("--threads 2 optimize " + Scene() + " --out " + dir.File("t2")).exit_code, 0);
  ASSERT_EQ(RunVantage("optimize " + Scene() + " --threads 2 --out " + dir.File("t2b")).exit_code, 0);
  const json t1 = WithoutTimings(json::parse(test::ReadText(dir.File("t1/report.json"))));
  EXPECT_EQ(t1, WithoutTimings(json::parse(test::ReadText(dir.File("t2/report.json")))));
  EXPECT_EQ(t1, WithoutTimings(json::parse(test::ReadText(dir.File("t2b/report.json")))));
  EXPECT_EQ(test::ReadText(dir.File("t1/observed.ply")), test::ReadText(dir.File("t2/observed.ply")));
  // Another seed moves the random population.
  ASSERT_EQ(RunVantage("optimize " + Scene() + " --seed 4 --out " + dir.File("s4")).exit_code, 0);
  const json s4 = json::parse(test::ReadText(dir.File("s4/report.json")));
  EXPECT_NE(t1["candidates"][0]["position"], s4["candidates"][0]["position"]);
}

TEST(Cli, CellSizeOptionGivesTheResultOfTheScenesCellSize) {
  // cube_cell.yaml with a sphere and a cylinder as targets: --cell-size must tessellate them as
  // the scene's own cell_size would (it used to keep the file's coarser chord).
  test::TempDir dir;
  std::string text = test::ReadText(Scene());
  const std::string cube =
      "  - name: cube\n    role: target\n    box: {size: [0.1, 0.1, 0.1]}\n"
      "    pose: {xyz: [0, 0, 0.05]}\n";
  ASSERT_NE(text.find(cube), std::string::npos);
  text.replace(text.find(cube), cube.size(),
               "  - name: ball\n    role: target\n    sphere: {radius: 0.04}\n"
               "    pose: {xyz: [0, 0, 0.05]}\n"
               "  - name: can\n    role: target\n    cylinder: {radius: 0.03, length: 0.08}\n"
               "    pose: {xyz: [-0.1, 0.05, 0.04]}\n");
  ASSERT_NE(text.find("cell_size: 0.01"), std::string::npos);
  test::WriteText(dir.File("coarse.yaml"), text);
  text.replace(text.find("cell_size: 0.01"), 15, "cell_size: 0.0025");
  test::WriteText(dir.File("fine.yaml"), text);
  const auto overridden = RunVantage("optimize " + dir.File("coarse.yaml") +
                                     " --method greedy --cell-size 0.0025 --out " + dir.File("o"));
  ASSERT_EQ(overridden.exit_code, 0) << overridden.err;
  const auto fine =
      RunVantage("optimize " + dir.File("fine.yaml") + " --method greedy --out " + dir.File("f"));
  ASSERT_EQ(fine.exit_code, 0) << fine.err;
  const json a = json::parse(test::ReadText(dir.File("o/report.json")));
  const json b = json::parse(test::ReadText(dir.File("f/report.json")));
  EXPECT_EQ(a["cell_size"], 0.0025);
  EXPECT_EQ(a["reference_voxels"], b["reference_voxels"]);
  ASSERT_EQ(a["results"].size(), b["results"].size());
  for (size_t i = 0; i < a["results"].size(); ++i) {
    EXPECT_EQ(a["results"][i]["coverage"], b["results"][i]["coverage"]) << i;
    EXPECT_EQ(a["results"][i]["sensors"], b["results"][i]["sensors"]) << i;
  }
  // render reloads the scene with the run's cell size: the same coverage again.
  const auto render = RunVantage("render " + dir.File("o") + " --png " + dir.File("v.png") +
                                 " --width 64 --height 48");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_EQ(render.err.find("has the scene changed"), std::string::npos) << render.err;
}

TEST(Cli, BadInputExitsTwoAndLeavesThePreviousOutputs) {
  test::TempDir dir;
  const std::string out = dir.File("out");
  ASSERT_EQ(RunVantage("optimize " + Scene() + " --out " + out).exit_code, 0);
  const std::string before = test::ReadText(out + "/report.json");

  test::WriteText(dir.File("broken.yaml"), "settings:\n  cell_size: 0.01\nobjects: [\n");
  test::WriteText(dir.File("negative.yaml"), test::ReadText(Scene()) + "\n");
  std::string negative = test::ReadText(Scene());
  negative.replace(negative.find("cell_size: 0.01"), 15, "cell_size: -0.01");
  test::WriteText(dir.File("negative.yaml"), negative);

  struct Case {
    std::string args;
    std::string place;  // expected prefix of the error, "" when no file applies
  };
  const std::vector<Case> cases = {
      {"optimize " + dir.File("missing.yaml"), dir.File("missing.yaml")},
      {"optimize " + dir.File("broken.yaml"), dir.File("broken.yaml") + ":"},
      {"optimize " + dir.File("negative.yaml"), dir.File("negative.yaml") + ":4:"},
      {"optimize " + Scene() + " -n 99", Scene()},
      {"optimize " + Scene() + " --method magic", ""},
      {"optimize " + Scene() + " --cell-size 0", ""},
  };
  for (const Case& c : cases) {
    const auto run = RunVantage(c.args + " --out " + out);
    EXPECT_EQ(run.exit_code, 2) << c.args << "\n" << run.err;
    EXPECT_EQ(run.err.find("internal"), std::string::npos) << run.err;
    if (!c.place.empty()) {
      EXPECT_NE(run.err.find(c.place), std::string::npos) << c.args << "\n" << run.err;
    }
    EXPECT_EQ(test::ReadText(out + "/report.json"), before) << c.args;
  }
}

}  // namespace
}  // namespace vantage
