#include <spdlog/spdlog.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct ObserveCommandOptions {
  SceneOptions scene;
  std::optional<int> n;
  std::string out;
};

void RunObserve(const ObserveCommandOptions& options) {
  SelectionOptions selection;
  selection.n = options.n;
  ObservedScene observed = ObserveScene(options.scene, &selection);
  if (!observed.states.empty())
    spdlog::warn("{}: the visibility file holds the first state '{}' only; `vantage optimize` selects over "
                 "all {} states", observed.data.scene, observed.states.front().name, observed.states.size());
  SaveVisibilityFile(options.out, observed.data);
  fmt::print("reference        {} voxels of {} m\n", observed.data.reference.size(),
             observed.data.reference.cell_size);
  fmt::print("candidates       {}\n", observed.data.candidates.size());
  fmt::print("observe          {:.3f} s\n", observed.timings.observe);
  fmt::print("visibility       {}\n", options.out);
}

}  // namespace

void SetupObserve(CLI::App* parent) {
  auto options = std::make_shared<ObserveCommandOptions>();
  CLI::App* app = parent->add_subcommand(
      "observe", "ray cast every candidate and save the visibility matrix for `vantage select`");
  AddSceneOptions(app, &options->scene);
  app->add_option("-n,--sensors", options->n, "default number of sensors stored with the matrix");
  app->add_option("-o,--out", options->out, "visibility matrix file to write (e.g. scene.vis)")->required();
  app->callback([options] { RunObserve(*options); });
}

}  // namespace vantage::cli
