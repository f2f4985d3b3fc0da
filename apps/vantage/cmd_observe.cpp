// `vantage observe SCENE --out FILE`: the visibility matrix, saved for `vantage select`.
#include <fmt/format.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct ObserveFlags {
  ObserveRunOptions options;
  std::string out;
};

void RunObserve(ObserveFlags flags) {
  flags.options.observe.progress = ProgressBar("observe");
  const ObserveRunResult result = ObserveRun(flags.options);
  SaveVisibilityFile(flags.out, result.data);
  fmt::print("reference        {} voxels of {} m\n", result.data.reference.size(),
             result.data.reference.cell_size);
  fmt::print("candidates       {}\n", result.data.candidates.size());
  fmt::print("observe          {:.3f} s\n", result.timings.observe);
  fmt::print("visibility       {}\n", flags.out);
}

}  // namespace

void SetupObserve(CLI::App* parent) {
  auto flags = std::make_shared<ObserveFlags>();
  CLI::App* app = parent->add_subcommand(
      "observe", "ray cast every candidate and save the visibility matrix for `vantage select`");
  AddSceneFlags(app, &flags->options.scene);
  AddObserveFlags(app, &flags->options.observe, &flags->options.limits);
  app->add_option("-n,--sensors", flags->options.n,
                  "default number of sensors stored with the matrix");
  app->add_option("-o,--out", flags->out, "visibility matrix file to write (e.g. scene.vis)")
      ->check(OutPathValidator())
      ->required();
  app->callback([flags] { RunObserve(*flags); });
}

}  // namespace vantage::cli
