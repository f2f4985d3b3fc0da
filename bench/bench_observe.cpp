// Micro-benchmarks of the hot stages: reference building, ray casting one camera, voxel dedup.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <numbers>

#include "vantage/observe.hpp"
#include "vantage/reference.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

Scene BenchScene() {
  Scene scene;
  TriangleMesh ball = MakeSphere(0.1, 0.0005);
  scene.objects.push_back({"ball", Role::kTarget, ball, {}});
  TriangleMesh floor = MakeBox(Vec3(2, 2, 0.02));
  floor.Transform(Pose{Vec3(0, 0, -0.12), Quat::Identity()});
  scene.objects.push_back({"floor", Role::kOccluder, floor, {}});
  return scene;
}

Candidate Camera(const std::string& id, double distance) {
  Candidate c;
  c.name = id;
  c.sensor = *FindCatalogType(id);
  c.type_id = id;
  // Looking along -x at the ball from +x.
  c.world_from_body = Pose{Vec3(distance, 0, 0), Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitZ()))};
  return c;
}

void BM_BuildReference(benchmark::State& state) {
  const Scene scene = BenchScene();
  const double cell = 0.005 / static_cast<double>(state.range(0));
  size_t cells = 0;
  for (auto _ : state) cells = BuildReference(scene, {cell}).size();
  state.counters["cells"] = static_cast<double>(cells);
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BuildReference)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_ObserveOneCamera(benchmark::State& state, const char* id, bool cull) {
  const Scene scene = BenchScene();
  const Reference reference = BuildReference(scene, {0.005});
  const std::vector<Candidate> cams(8, Camera(id, 0.6));
  ObserveOptions options;
  options.cull = cull;
  uint64_t rays = 0;
  for (auto _ : state) {
    const auto obs = Observe(scene, reference, cams, options);
    rays = 0;
    for (const auto& o : obs) rays += o.rays_traced;
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK_CAPTURE(BM_ObserveOneCamera, sr300_all_pixels, "intel_realsense_sr300", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ObserveOneCamera, sr300_culled, "intel_realsense_sr300", true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ObserveOneCamera, multisense_culled, "multisense_s7", true)->Unit(benchmark::kMillisecond);

// The physical sensor model's cost (issue 43): the same culled SR300 images with a projector
// 75 mm beside the camera (its field the camera's), ideal against physical. The extra work is one
// occlusion ray per pixel that hits a target, sent as 16-wide packets.
void BM_ObserveSecondAperture(benchmark::State& state, bool physical) {
  const Scene scene = BenchScene();
  const Reference reference = BuildReference(scene, {0.005});
  Candidate cam = Camera("intel_realsense_sr300", 0.6);
  SecondAperture projector;
  projector.kind = SecondAperture::Kind::kProjector;
  projector.baseline = 0.075;
  cam.sensor.second_aperture = projector;
  const std::vector<Candidate> cams(8, cam);
  ObserveOptions options;
  options.physical = physical;
  uint64_t rays = 0, hits = 0;
  for (auto _ : state) {
    const auto obs = Observe(scene, reference, cams, options);
    rays = hits = 0;
    for (const auto& o : obs) rays += o.rays_traced, hits += o.target_pixels;
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["measured_px"] = static_cast<double>(hits);
}
BENCHMARK_CAPTURE(BM_ObserveSecondAperture, ideal, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ObserveSecondAperture, physical, true)->Unit(benchmark::kMillisecond);

void BM_VoxelDedup(benchmark::State& state) {
  Rng rng(1, Stream::kTest, 0);
  std::vector<uint64_t> keys(static_cast<size_t>(state.range(0)));
  for (auto& k : keys) k = PackVoxel({static_cast<int64_t>(rng.Below(200)), static_cast<int64_t>(rng.Below(200)), 7});
  for (auto _ : state) {
    std::vector<uint64_t> copy = keys;
    std::sort(copy.begin(), copy.end());
    copy.erase(std::unique(copy.begin(), copy.end()), copy.end());
    benchmark::DoNotOptimize(copy.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_VoxelDedup)->Arg(1 << 16)->Arg(1 << 20);

}  // namespace
}  // namespace vantage
