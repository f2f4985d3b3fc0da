// Selection on a synthetic visibility matrix: 1,000 candidates × 100,000 reference cells, each
// candidate seeing one contiguous-ish patch of 2–10 % of the cells (STYLE.md, benchmarks).
// Arguments: n, and the share of cells (in percent) missing inside each patch: 0 gives clean
// patches (cells merge into few elements), 10 gives ragged ones (little merging: the hard case).
#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "vantage/observe.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

constexpr size_t kCandidates = 1000;
constexpr size_t kCells = 100000;

std::vector<Observation> SyntheticInstance(int hole_percent) {
  std::vector<Observation> obs(kCandidates);
  for (size_t i = 0; i < kCandidates; ++i) {
    Rng rng(1, Stream::kTest, i);
    const auto length = static_cast<size_t>(rng.Uniform(0.02, 0.10) * kCells);
    const size_t first = rng.Below(kCells - length);
    for (size_t c = first; c < first + length; ++c) {
      if (rng.Uniform01() * 100 >= hole_percent) {
        obs[i].reference_indices.push_back(static_cast<uint32_t>(c));
      }
    }
  }
  return obs;
}

const std::vector<Observation>& Instance(int hole_percent) {
  static std::map<int, std::vector<Observation>> cache;
  auto it = cache.find(hole_percent);
  if (it == cache.end()) it = cache.emplace(hole_percent, SyntheticInstance(hole_percent)).first;
  return it->second;
}

void RunMethod(benchmark::State& state, Method method) {
  const std::vector<Observation>& obs = Instance(static_cast<int>(state.range(1)));
  SelectOptions options;
  options.method = method;
  options.n = static_cast<int>(state.range(0));
  std::vector<Selection> result;
  for (auto _ : state) {
    result = Select(obs, kCells, options);
    // On the vector, not on a double: benchmark 1.7's DoNotOptimize corrupts doubles under GCC.
    benchmark::DoNotOptimize(result);
  }
  const double coverage = result.front().coverage;
  state.SetLabel("coverage " + std::to_string(coverage));
}

void BM_SelectGreedy(benchmark::State& state) { RunMethod(state, Method::kGreedy); }
void BM_SelectLocal(benchmark::State& state) { RunMethod(state, Method::kLocal); }

BENCHMARK(BM_SelectGreedy)
    ->ArgsProduct({{5, 10}, {0, 10}})
    ->ArgNames({"n", "holes%"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelectLocal)
    ->ArgsProduct({{5, 10}, {0, 10}})
    ->ArgNames({"n", "holes%"})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vantage
