// `vantage merge part_*.vis --out all.vis`: the shards of `vantage observe --shard i/K` as one
// visibility file, the same bytes as one process's.
#include <fmt/format.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct MergeFlags {
  std::vector<std::string> parts;
  std::string out;
};

void RunMerge(const MergeFlags& flags) {
  const OutputGuard guard = RefuseOutputOverInput(flags.out, flags.parts);
  const VisibilityFile merged = MergeShards(flags.parts);
  SaveVisibilityFile(flags.out, merged);
  fmt::print("merged           {} parts, {} candidates\n", flags.parts.size(),
             merged.candidates.size());
  fmt::print("visibility       {}\n", ShownOnOneLine(flags.out));
}

}  // namespace

void SetupMerge(CLI::App* parent) {
  auto flags = std::make_shared<MergeFlags>();
  CLI::App* app = parent->add_subcommand(
      "merge", "join the parts of `vantage observe --shard i/K` into one visibility file");
  app->add_option("parts", flags->parts, "the part files, one per shard, in any order")
      ->required();
  app->add_option("-o,--out", flags->out, "visibility matrix file to write (e.g. all.vis)")
      ->check(OutPathValidator())
      ->required();
  app->callback([flags] { RunMerge(*flags); });
}

}  // namespace vantage::cli
