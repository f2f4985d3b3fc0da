// The ray-casting limit for a scene: trace pixels of every candidate camera with Embree packets
// on all cores and do nothing else (no voxels, no sets). Two loops: every pixel of every image,
// and exactly the pixels vantage's culling traces (the same rays as `vantage observe`), whose
// time scripts/bench_e2e.sh divides vantage's observe time by.
// Usage: ray_limit SCENE [--model-path DIR] [--resource-path DIR]  -> one JSON line on stdout.
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>

#include "observe/culling.hpp"
#include "vantage/ray_scene.hpp"
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
    const RayScene rays(problem.scene);
    const Reference reference = BuildReference(problem.scene, {problem.cell_size});
    const std::vector<Aabb> blocks = detail::ReferenceBlocks(reference);
    // Spans are computed outside the timed loop: the loop only traces.
    std::vector<std::vector<detail::RowSpan>> culled(cams.size()), full(cams.size());
    uint64_t culled_rays = 0, full_rays = 0;
    for (size_t i = 0; i < cams.size(); ++i) {
      culled[i] = detail::SpansToTrace(cams[i], blocks, true);
      full[i] = detail::SpansToTrace(cams[i], blocks, false);
      for (const auto& s : culled[i]) culled_rays += static_cast<uint64_t>(s.u1 - s.u0 + 1);
      for (const auto& s : full[i]) full_rays += static_cast<uint64_t>(s.u1 - s.u0 + 1);
    }
    std::atomic<uint64_t> hits{0};  // rays of the last loop that hit a target
    const auto trace = [&](const std::vector<std::vector<detail::RowSpan>>& spans) {
      hits = 0;
      const auto start = std::chrono::steady_clock::now();
      tbb::parallel_for(size_t{0}, cams.size(), [&](size_t i) {
        const Candidate& c = cams[i];
        const Mat3 rotation = c.world_from_body.rotation.toRotationMatrix();
        RayBatch batch;
        for (int a = 0; a < 3; ++a) batch.origin[a] = static_cast<float>(c.world_from_body.position[a]);
        batch.tfar = static_cast<float>(c.sensor.far);
        uint64_t local_hits = 0;
        for (const detail::RowSpan& span : spans[i]) {
          for (int u0 = span.u0; u0 <= span.u1; u0 += RayBatch::kWidth) {
            batch.active = std::min(RayBatch::kWidth, span.u1 - u0 + 1);
            for (int lane = 0; lane < batch.active; ++lane) {
              const Vec3 d = rotation * PixelRayInBody(c.sensor, u0 + lane, span.v);
              for (int a = 0; a < 3; ++a) batch.dir[a][lane] = static_cast<float>(d[a]);
            }
            rays.Intersect(&batch);
            for (int lane = 0; lane < batch.active; ++lane) local_hits += batch.is_target[lane] ? 1 : 0;
          }
        }
        hits += local_hits;
      });
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const double full_seconds = trace(full);
    const double culled_seconds = trace(culled);
    std::printf("{\"candidates\": %zu, \"all_pixels\": %llu, \"all_pixels_seconds\": %.4f, "
                "\"all_pixels_rays_per_second\": %.1f, \"culled_rays\": %llu, \"culled_seconds\": %.4f, "
                "\"culled_rays_per_second\": %.1f, \"target_hits\": %llu}\n",
                cams.size(), static_cast<unsigned long long>(full_rays), full_seconds,
                static_cast<double>(full_rays) / full_seconds, static_cast<unsigned long long>(culled_rays),
                culled_seconds, static_cast<double>(culled_rays) / culled_seconds,
                static_cast<unsigned long long>(hits.load()));
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
