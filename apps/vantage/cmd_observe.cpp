// `vantage observe SCENE --out FILE`: the visibility matrix, saved for `vantage select`.
#include <fmt/format.h>

#include <memory>
#include <optional>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct ObserveFlags {
  ObserveRunOptions options;
  std::string out;
  std::string shard;  ///< --shard i/K or env/K
};

void PrintObserved(const VisibilityFile& data) {
  fmt::print("reference        {} voxels of {} m\n", data.reference.size(),
             data.reference.cell_size);
  fmt::print("candidates       {}\n", data.candidates.size());
}

void RunObserve(ObserveFlags flags, const RunSettings& settings) {
  const OutputGuard guard = RefuseOutputOverInput(flags.out, {flags.options.scene.path});
  flags.options.observe.progress = ProgressBar("observe");
  if (!flags.shard.empty()) {
    const ShardSpec spec = ParseShard(flags.shard);
    // A launcher's job of one rank (srun under Slurm's PMIx default) is one process: a shard.
    if (const MpiJob* job = MpiJob::Current(); job && job->size() > 1)
      throw InputError(AtPlace("--shard", 0,
                               "shards are for job arrays, not mpirun — drop --shard or mpirun"));
    const VisibilityShard shard = ObserveShard(flags.options, spec, settings);
    SaveVisibilityShard(flags.out, shard);
    PrintObserved(shard.file);
    fmt::print("shard            {}/{}: {} candidates observed\n", shard.index, shard.count,
               shard.candidates.size());
    fmt::print("part             {}\n", ShownOnOneLine(flags.out));
    return;
  }
  // Under mpirun every rank traces its share; rank 0 alone writes and prints.
  const std::optional<ObserveRunResult> result = ObserveInJob(flags.options, settings);
  if (!result) return;
  SaveVisibilityFile(flags.out, result->data);
  PrintObserved(result->data);
  fmt::print("observe          {:.3f} s\n", result->timings.observe);
  fmt::print("visibility       {}\n", ShownOnOneLine(flags.out));
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
  app->add_option("--shard", flags->shard,
                  "observe only shard i of K (i/K, or env/K: i from SLURM_ARRAY_TASK_ID or "
                  "JOB_COMPLETION_INDEX) into a part for `vantage merge` (docs/distributed.md)")
      ->type_name("i/K");
  app->callback([flags, app] { RunObserve(*flags, GivenSettings(*app)); });
}

}  // namespace vantage::cli
