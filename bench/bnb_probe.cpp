// Branch and bound probe (issue 14): loads a visibility matrix (`vantage observe`'s .vis, or
// "generated" for selection_table's 1,000 x 100,000 instance), starts from greedy + local search
// as exact does, runs BranchAndBound for each N given with a time limit, and prints its nodes,
// bounds and where its time went (BranchAndBoundResult's profile).
//
// Env: BNB_THREADS (TBB threads), BNB_NODES (max_nodes), BNB_ROOT_STEPS, BNB_ROOT_SHARE (limits).
// Usage: bnb_probe FILE.vis|generated SECONDS N [N ...]
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/scorer.hpp"
#include "vantage/rng.hpp"
#include "vantage/visibility_file.hpp"

namespace {

using namespace vantage;

std::vector<Observation> Generated(size_t* reference_size) {
  constexpr size_t kCandidates = 1000;
  constexpr size_t kCells = 100000;
  std::vector<Observation> observations(kCandidates);
  for (size_t i = 0; i < kCandidates; ++i) {
    Rng rng(1, Stream::kTest, i);
    const auto length = static_cast<size_t>(rng.Uniform(0.02, 0.10) * kCells);
    const size_t first = rng.Below(kCells - length);
    for (size_t c = first; c < first + length; ++c) {
      if (rng.Uniform01() >= 0.05)
        observations[i].reference_indices.push_back(static_cast<uint32_t>(c));
    }
  }
  *reference_size = kCells;
  return observations;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    fmt::print(stderr, "usage: bnb_probe FILE.vis|generated SECONDS N [N ...]\n");
    return 2;
  }
  // BNB_THREADS: TBB's thread count (default: TBB's own).
  std::unique_ptr<tbb::global_control> threads;
  if (const char* env = std::getenv("BNB_THREADS")) {
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    std::stoul(env));
  }
  const std::string file = argv[1];
  std::vector<Observation> observations;
  size_t reference_size = 0;
  if (file == "generated") {
    observations = Generated(&reference_size);
  } else {
    VisibilityFile data = LoadVisibilityFile(file);
    observations = std::move(data.observations);
    reference_size = data.reference.size();
  }
  const double seconds = std::stod(argv[2]);
  const detail::CoverageMatrix matrix(observations, reference_size);
  const double r = static_cast<double>(reference_size) / 100;
  {
    size_t nonzeros = 0;
    size_t runs = 0;
    for (const std::vector<uint32_t>& row : matrix.rows()) {
      nonzeros += row.size();
      for (size_t j = 0; j < row.size(); ++j) runs += j == 0 || row[j] != row[j - 1] + 1;
    }
    fmt::print("{} candidates, {} elements, {} nonzeros in {} runs of consecutive elements\n",
               matrix.candidate_count(), matrix.element_count(), nonzeros, runs);
  }
  for (int a = 3; a < argc; ++a) {
    const size_t n = std::stoul(argv[a]);
    const detail::CellScorer scorer(matrix);
    std::vector<uint32_t> start =
        detail::LocalSearch(scorer, detail::GreedyComplete(scorer, {}, n));
    const uint64_t upper = detail::GreedyUpperBound(matrix, start, n);
    detail::BranchAndBoundLimits limits;
    limits.seconds = seconds;
    if (const char* env = std::getenv("BNB_NODES")) limits.max_nodes = std::stol(env);
    if (const char* env = std::getenv("BNB_ROOT_STEPS")) limits.root_steps = std::stoi(env);
    if (const char* env = std::getenv("BNB_ROOT_SHARE")) limits.root_share = std::stod(env);
    rusage before{};
    getrusage(RUSAGE_SELF, &before);
    const auto t0 = std::chrono::steady_clock::now();
    const detail::BranchAndBoundResult res =
        detail::BranchAndBound(matrix, n, start, upper, limits);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    const auto seconds_of = [](const timeval& t) { return t.tv_sec + t.tv_usec * 1e-6; };
    const double cpu = seconds_of(after.ru_utime) - seconds_of(before.ru_utime);
    const auto& p = res.profile;
    fmt::print(
        "N={} cells {} ({:.2f}%) bound {} ({:.2f}%) gap {:.2f} pp{} | nodes {} ({:.0f}/s, "
        "{:.0f}/cpu s) root {} "
        "fixed {}+{} steps {} sg {} lp {} ({:.2f} s) | wall {:.2f} cpu {:.2f}: root {:.2f} rebuild "
        "{:.2f} rows {:.2f} eval {:.2f} "
        "descent {:.2f} offer {:.2f} fixing {:.2f} | evals {}\n",
        n, res.cells, res.cells / r, res.upper_bound, res.upper_bound / r,
        (double(res.upper_bound) - double(res.cells)) / r, res.proven_optimal ? " *" : "",
        res.nodes, res.nodes / wall, res.nodes / cpu, res.root_bound, res.root_fixed_in,
        res.root_removed, res.root_steps, res.root_subgradient_bound, res.root_lp_bound,
        res.root_lp_seconds, wall, cpu, p.root_seconds, p.rebuild_seconds, p.rows_seconds,
        p.eval_seconds, p.descent_seconds, p.offer_seconds, p.fixing_seconds, p.evaluations);
    std::fflush(stdout);
  }
  return 0;
}
