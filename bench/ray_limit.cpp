// The ray-casting limit for a scene: trace every pixel of every candidate camera with Embree
// packets on all cores and do nothing else (no culling, no voxels). scripts/bench_e2e.sh divides
// vantage's observe time by this loop's time for the same number of rays.
// Usage: ray_limit SCENE [--model-path DIR] [--resource-path DIR]  -> one JSON line on stdout.
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>

#include "observe/ray_scene.hpp"
#include "vantage/vantage.hpp"

int main(int argc, char** argv) {
  using namespace vantage;
  if (argc < 2) {
    std::fprintf(stderr, "usage: ray_limit SCENE [--model-path DIR] [--resource-path DIR]\n");
    return 2;
  }
  LoadOptions load;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--model-path") load.model_paths.push_back(argv[i + 1]);
    if (flag == "--resource-path") load.resource_paths.push_back(argv[i + 1]);
  }
  try {
    const Problem problem = LoadProblem(argv[1], load);
    DeployOptions deploy{problem.observation_point, problem.random_roll, problem.seed};
    const std::vector<Candidate> cams =
        DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
    const detail::RayScene rays(problem.scene);
    std::atomic<uint64_t> hits{0};
    uint64_t total = 0;
    for (const Candidate& c : cams) total += static_cast<uint64_t>(c.sensor.PixelCount());
    const auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(size_t{0}, cams.size(), [&](size_t i) {
      const Candidate& c = cams[i];
      const Mat3 rotation = c.world_from_body.rotation.toRotationMatrix();
      detail::RayBatch batch;
      for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(c.world_from_body.position[a]);
      batch.tfar = static_cast<float>(c.sensor.far);
      uint64_t local_hits = 0;
      for (int v = 0; v < c.sensor.height; ++v) {
        for (int u0 = 0; u0 < c.sensor.width; u0 += detail::RayBatch::kWidth) {
          batch.active = std::min(detail::RayBatch::kWidth, c.sensor.width - u0);
          for (int lane = 0; lane < batch.active; ++lane) {
            const Vec3 d = rotation * PixelRayInBody(c.sensor, u0 + lane, v);
            for (int a = 0; a < 3; ++a) batch.dir[a][lane] = static_cast<float>(d[a]);
          }
          rays.Intersect(&batch);
          for (int lane = 0; lane < batch.active; ++lane) local_hits += batch.is_target[lane] ? 1 : 0;
        }
      }
      hits += local_hits;
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("{\"candidates\": %zu, \"rays\": %llu, \"target_hits\": %llu, \"seconds\": %.4f, \"rays_per_second\": %.1f}\n",
                cams.size(), static_cast<unsigned long long>(total),
                static_cast<unsigned long long>(hits.load()), seconds, static_cast<double>(total) / seconds);
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
