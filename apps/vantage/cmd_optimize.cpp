// `vantage optimize SCENE`: the whole pipeline, into an output folder.
#include <fmt/format.h>

#include <memory>
#include <optional>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct OptimizeFlags {
  OptimizeOptions options;
  std::string out = "vantage_out";
  bool refine = false;
  RefineOptions refine_options;
};

void RunOptimize(OptimizeFlags flags, const RunSettings& settings) {
  CheckRunFolder(flags.out);
  if (flags.refine) flags.options.refine = flags.refine_options;
  flags.options.observe.progress = ProgressBar("observe");
  // Under mpirun every rank traces its share; rank 0 alone writes and prints.
  const std::optional<RunResult> run = OptimizeInJob(flags.options, settings);
  if (!run) return;
  WriteRun(flags.out, *run);
  PrintSummary(run->report, flags.out);
}

}  // namespace

void SetupOptimize(CLI::App* parent) {
  auto flags = std::make_shared<OptimizeFlags>();
  CLI::App* app =
      parent->add_subcommand("optimize", "the whole pipeline: scene -> best constellation");
  AddSceneFlags(app, &flags->options.scene);
  AddObserveFlags(app, &flags->options.observe, &flags->options.limits);
  AddSelectionFlags(app, &flags->options.selection);
  AddRobustnessFlags(app, &flags->options.robustness);
  AddPoseToleranceFlags(app, &flags->options.pose_tolerance);
  app->add_option("-o,--out", flags->out, "output folder, default ./vantage_out (vantage's files in it are replaced "
                  "atomically; your own files there are kept)")
      ->check(OutPathValidator())
      ->capture_default_str();
  app->add_flag("--by-type", flags->options.by_type,
                "which sensor to buy: also choose the best constellation of each sensor type "
                "alone at every n, and show what mixing types gains (report.json by_type)");
  app->add_flag("--refine", flags->refine,
                "after selection, search new poses around the chosen sensors (inside their "
                "regions, outside keep-out boxes), trace only those and re-select while coverage "
                "improves, under the run's constraints over old and new poses; kept sensors "
                "(--keep-existing) stay where they are");
  CLI::Option* rounds =
      app->add_option("--refine-rounds", flags->refine_options.max_rounds, "rounds of --refine")
          ->check(NumberFrom(1, kMaxRefineRounds, ValueKind::kWholeNumber))
          ->capture_default_str();
  // A camera on an arm (docs/arm.md): how its tours are timed.
  ArmTourOptions& arm = flags->options.arm;
  AddArmTourFlags(app, &arm);
  app->add_flag("--track", arm.track,
                "a camera on an arm follows the scene's states (in time order): one view per "
                "state, the exact most summed coverage minus --move-penalty per second of motion");
  app->add_option("--move-penalty", arm.move_penalty,
                  "with --track: coverage (a fraction of R) given up per second of motion "
                  "(default 0)");
  app->add_option("--state-interval", arm.state_interval,
                  "with --track: the states are this many seconds apart; each view's acquisition "
                  "and the move to the next state's view must fit");
  app->callback([flags, rounds, app] {
    // Was accepted and ignored without --refine (issue 15).
    if (rounds->count() > 0 && !flags->refine)
      throw InputError("--refine-rounds: only --refine runs rounds — add --refine, or leave "
                       "--refine-rounds out");
    RunOptimize(*flags, GivenSettings(*app));
  });
}

}  // namespace vantage::cli
