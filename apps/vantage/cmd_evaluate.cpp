#include <spdlog/spdlog.h>

#include <memory>
#include <numeric>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct EvaluateOptions {
  SceneOptions scene;
  std::string constellation;
  std::string out;
};

void RunEvaluate(const EvaluateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Problem problem = LoadScene(options.scene);
  if (!problem.states.empty())
    spdlog::warn("{}: evaluated on the objects as listed; its {} states are scored by `vantage optimize` "
                 "only", problem.source, problem.states.size());
  const Constellation constellation = LoadConstellation(options.constellation);
  Timings timings;
  timings.load = SecondsSince(start);
  ReferenceOptions reference_options;
  reference_options.cell_size = problem.cell_size;
  auto stage = std::chrono::steady_clock::now();
  VisibilityFile data;
  data.scene = problem.source;
  data.seed = problem.seed;
  data.n = static_cast<int>(constellation.sensors.size());
  data.reference = BuildReference(problem.scene, reference_options);
  timings.reference = SecondsSince(stage);
  stage = std::chrono::steady_clock::now();
  data.candidates = constellation.sensors;
  ObserveOptions observe_options;
  observe_options.cull = !options.scene.no_cull;
  data.observations = Observe(problem.scene, data.reference, data.candidates, observe_options);
  timings.observe = SecondsSince(stage);

  stage = std::chrono::steady_clock::now();
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  Selection given = WholeConstellation(evaluator);
  timings.select = given.seconds = SecondsSince(stage);
  timings.total = SecondsSince(start);

  for (size_t i = 0; i < data.candidates.size(); ++i) {
    const std::vector<uint32_t> one{static_cast<uint32_t>(i)};
    fmt::print("sensor  {:<24} {:6.2f} %\n", data.candidates[i].name, 100.0 * evaluator.Coverage(one));
  }
  fmt::print("union   {} sensors            {:6.2f} %  (paper metric {:.2f} %)\n", given.chosen.size(),
             100.0 * given.coverage, 100.0 * given.paper_coverage);
  if (!options.out.empty()) {
    Report report;
    report.scene = data.scene;
    report.seed = data.seed;
    report.data = &data;
    report.results = {given};
    report.timings = timings;
    WriteOutputs(options.out, report,
                 {{"report.html", HtmlReport(report, problem.scene)},
                  {"static_transforms.yaml", StaticTransformsYaml(report)}});
    fmt::print("outputs {}/\n", options.out);
  }
}

}  // namespace

void SetupEvaluate(CLI::App* parent) {
  auto options = std::make_shared<EvaluateOptions>();
  CLI::App* app = parent->add_subcommand("evaluate", "coverage of given sensor poses");
  AddSceneOptions(app, &options->scene);
  app->add_option("-c,--constellation", options->constellation,
                  "report.json (its primary result's sensors, or all its candidates)")
      ->required();
  app->add_option("-o,--out", options->out, "also write a report folder here");
  app->callback([options] { RunEvaluate(*options); });
}

}  // namespace vantage::cli
