#pragma once
/// The subcommands of the `vantage` binary: each maps its flags onto the pipeline's option
/// structs (vantage/pipeline.hpp), calls one pipeline function and prints. No stage is called
/// from here. Only main.cpp maps errors to exit codes.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "vantage/distribute.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/words.hpp"

namespace vantage::cli {

/// --model-path, --resource-path, --package-path, --target: where the scene's parts are found.
void AddSourceFlags(CLI::App* app, SceneInput* scene);
/// --model-path, --resource-path, --target, --cell-size, --seed, --observation-point,
/// --random-roll (and the positional scene when `scene_positional`), into `scene`.
/// Each flag writes its pipeline field directly (CLI11 validators and callbacks do the units).
void AddSceneFlags(CLI::App* app, SceneInput* scene, bool scene_positional = true);
/// --no-cull, --max-incidence, --max-depth-noise, --max-memory.
void AddObserveFlags(CLI::App* app, ObserveOptions* observe, RunLimits* limits);
/// -n, --method, --iterations, --stop, --time-limit, --goal, --k, --budget, --over-states.
void AddSelectionFlags(CLI::App* app, SelectionRequest* request);
/// --interference, --interference-overlap, --calibration-overlap(-frac) (docs/constraints.md).
void AddConstraintFlags(CLI::App* app, ConstraintOptions* constraints);
/// --min-points and --min-density (optimize, select, evaluate).
void AddPointDensityFlags(CLI::App* app, std::optional<int64_t>* min_points,
                          std::optional<double>* min_density);
/// --fov-tolerance, --alternatives-within (points, stored as a fraction).
void AddRobustnessFlags(CLI::App* app, RobustnessOptions* robustness);
/// A camera on an arm's tour (optimize, select): --cycle-time, --joint-speed, --frames,
/// --motion-resolution, --plan-time.
void AddArmTourFlags(CLI::App* app, ArmTourOptions* arm);
/// --pose-tolerance P,A and --pose-samples S (optimize, select, evaluate).
void AddPoseToleranceFlags(CLI::App* app, std::optional<PoseToleranceOptions>* tolerance);
/// The summary's per-part table (results[shown]) and pose-tolerance lines; evaluate prints them
/// too.
void PrintParts(const Report& report, const std::vector<size_t>& shown);
void PrintPoseTolerance(const Report& report);

/// The check of the unsigned options (--seed, --calibration-overlap): refuses a sign (CLI11
/// would wrap "-1" to 2^64 - 1) and values beyond 2^64 - 1 (CLI11 would clamp them).
CLI::Validator WholeNumberValidator();

/// --out's check (optimize, select, evaluate, observe, merge) and render's --png: refuses an
/// empty path, which names no file or folder to write.
CLI::Validator OutPathValidator();

/// Every option value and argument: not empty (CLI11 read `-n ""` as not given and
/// `--observation-point "" "" ""` as the origin), and for a whole number, decimal (CLI11 read
/// `-n 010` as octal 8 and `-n 0x3` as hex). A number's spaces around it are dropped (CLI11 took
/// `-n ' 2'` and refused `-n '2 '`).
enum class ValueKind { kText, kNumber, kWholeNumber };
CLI::Validator PlainValueValidator(ValueKind kind);

/// A number from `low` to `high` (whole where `kind` says so). CLI::Range said "Value x not in
/// range 0.000000 to 45.000000" also of a word that is no number, and of 1.5 for a whole number.
CLI::Validator NumberFrom(double low, double high, ValueKind kind);

/// InputError "--out: PATH is FILE, an input of this run ..." when the output file `out` is one of
/// `inputs` (issue 15: `observe scene.yaml --out scene.yaml` replaced the scene with the matrix),
/// or when it is a device, a pipe or a folder (CheckOutputFile).
/// The guard it returns refuses, while it lives, every other input (a mesh, a URDF, a material
/// script) that names `out` (OutputGuard).
[[nodiscard]] OutputGuard RefuseOutputOverInput(const std::string& out,
                                                const std::vector<std::string>& inputs);

/// The settings of the command `command` parsed (RunSettings, vantage/distribute.hpp): its name,
/// then each option given, "--name value ...", in the command's order of options whatever the
/// order typed. Left out: the scene's path and the folders searched (the content read is
/// compared instead), --out, --shard, and the top level's --threads, -q and -v.
RunSettings GivenSettings(const CLI::App& command);

/// A progress bar with rate and ETA on stderr when it is a terminal; empty otherwise.
std::function<void(size_t, size_t)> ProgressBar(const std::string& label);

/// Prints the human summary of a run to stdout: its results, states, refinement, robustness.
void PrintSummary(const Report& report, const std::string& out_dir);
/// The installation constraints of a run and what its primary result avoided or breaks.
void PrintConstraints(const Report& report);

void SetupOptimize(CLI::App* parent);
void SetupObserve(CLI::App* parent);
void SetupSelect(CLI::App* parent);
void SetupEvaluate(CLI::App* parent);
void SetupSensors(CLI::App* parent);
void SetupRender(CLI::App* parent);
void SetupMerge(CLI::App* parent);

}  // namespace vantage::cli
