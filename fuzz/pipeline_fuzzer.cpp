// libFuzzer target: the pipeline on a tiny scene from the fuzzer's bytes (issue 15: the reader
// targets stopped at the readers and missed every value that crashed Embree). A YAML scene is
// prepared (load, deploy, checks), observed (R, memory and time estimates, ray casting) and
// selected (greedy, RANSAC, local search) with small limits so that one input takes milliseconds.
// An InputError is the expected outcome for bad input; anything else (another exception, a
// sanitizer report, an Embree assertion, a timeout, an out-of-memory) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <tbb/global_control.h>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/select.hpp"

namespace {

// Small images and few candidates: the limits of one fuzzed run.
constexpr size_t kMaxCandidates = 32;
constexpr int64_t kMaxPixels = 200'000;
constexpr size_t kMaxReference = 50'000;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  // One thread: with TBB's workers, how a parallel loop is split (work stealing) changes the
  // hit counts of its body from run to run, and libFuzzer counted those as new features of the
  // same input, so the pipeline's coverage never settled. The process lives as long as the
  // fuzzer, so the limit is never freed.
  static auto* const one_thread =  // NOLINT(cppcoreguidelines-owning-memory)
      new tbb::global_control(tbb::global_control::max_allowed_parallelism, 1);
  (void)one_thread;
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vantage;  // NOLINT(google-build-using-namespace): a fuzzer's one function
  const std::string path = fuzz::WriteInput("scenes/pipeline.yaml", data, size);
  try {
    SceneInput input;
    input.path = path;
    PreparedScene prepared = Prepare(input);
    int64_t pixels = 0;
    for (const Candidate& c : prepared.candidates) pixels += c.sensor.PixelCount();
    if (prepared.candidates.size() > kMaxCandidates || pixels > kMaxPixels) return 0;
    if (EstimateReferenceCells(prepared.problem.scene, prepared.problem.cell_size) > kMaxReference)
      return 0;
    const std::string source = prepared.problem.source;
    const uint64_t seed = prepared.problem.seed;
    RunLimits limits;
    limits.max_memory_mib = 512;
    limits.max_seconds = 10;
    SelectOptions select = ResolveSelection(prepared.problem.selection, {}, seed,
                                            prepared.candidates, source, Method::kGreedy);
    const ObservedScene observed =
        ObservePrepared(std::move(prepared), ObserveOptions{}, limits, {});
    const VisibilityFile& matrix = observed.data;
    VANTAGE_CHECK(matrix.observations.size() == matrix.candidates.size());
    for (const Observation& o : matrix.observations) {
      for (const uint32_t i : o.reference_indices) VANTAGE_CHECK(i < matrix.reference.size());
    }
    if (matrix.reference.size() == 0) return 0;
    select.ransac_iterations = std::min(select.ransac_iterations, 200);
    for (const Method method : {Method::kGreedy, Method::kRansac, Method::kLocal}) {
      select.method = method;
      for (const Selection& s : Select(matrix.observations, matrix.reference.size(), select)) {
        VANTAGE_CHECK(std::isfinite(s.coverage) && s.coverage >= 0 && s.coverage <= 1);
        for (const uint32_t i : s.chosen) VANTAGE_CHECK(i < matrix.candidates.size());
      }
    }
  } catch (const InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
