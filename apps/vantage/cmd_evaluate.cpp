// `vantage evaluate [SCENE] [--constellation report.json]`: the coverage of given sensor poses
// (without --constellation: of the sensors the scene declares).
#include <fmt/format.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct EvaluateFlags {
  EvaluateOptions options;
  std::string out;
};

void RunEvaluate(EvaluateFlags flags) {
  if (!flags.out.empty()) CheckRunFolder(flags.out);
  flags.options.observe.progress = ProgressBar("observe");
  const EvaluateResult result = Evaluate(flags.options);
  const VisibilityFile& data = *result.run.data;
  for (size_t i = 0; i < data.candidates.size(); ++i)
    fmt::print("sensor  {:<24} {:6.2f} %\n", data.candidates[i].name,
               100.0 * result.sensor_coverage[i]);
  const Selection& given = result.run.report.results.front();
  fmt::print("union   {} sensors            {:6.2f} %  (paper metric {:.2f} %)\n",
             given.chosen.size(), 100.0 * given.coverage, 100.0 * given.paper_coverage);
  const Report& report = result.run.report;
  if (report.ceiling && !report.parts.empty()) {
    // What the scene lets any layout reach: the surface resting on or enclosed by other geometry.
    if (report.exposure_known && !data.reference.exposed_only && data.reference.size() > 0)
      fmt::print("unexposed       {:.2f} % of R: no layout sees it (resting on or enclosed by "
                 "other geometry)\n",
                 100.0 * report.unexposed / data.reference.size());
    PrintParts(report, {0});
  }
  PrintPoseTolerance(report);
  if (report.constraints) PrintConstraints(report);
  if (flags.out.empty()) return;
  WriteRun(flags.out, result.run);
  fmt::print("outputs {}/\n", ShownOnOneLine(flags.out));
}

}  // namespace

void SetupEvaluate(CLI::App* parent) {
  auto flags = std::make_shared<EvaluateFlags>();
  CLI::App* app = parent->add_subcommand("evaluate", "coverage of given sensor poses");
  app->add_option("scene", flags->options.scene.path,
                  "scene: .yaml or Gazebo .world/.sdf (default: the one the constellation's run "
                  "used)");
  AddSceneFlags(app, &flags->options.scene, /*scene_positional=*/false);
  AddObserveFlags(app, &flags->options.observe, &flags->options.limits);
  app->add_option("-c,--constellation", flags->options.constellation,
                  "report.json (its primary result's sensors, or all its candidates); options "
                  "not given are the run's (its `inputs`). Without it: the sensors the scene "
                  "declares (a gz-sim world's cameras, a YAML scene's `sensors:`)");
  AddConstraintFlags(app, &flags->options.constraints);
  AddPointDensityFlags(app, &flags->options.min_points, &flags->options.min_density);
  AddPoseToleranceFlags(app, &flags->options.pose_tolerance);
  app->add_option("-o,--out", flags->out, "also write a report folder here")
      ->check(OutPathValidator());
  app->callback([flags] { RunEvaluate(*flags); });
}

}  // namespace vantage::cli
