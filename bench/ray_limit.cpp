// The ray-casting limit for a scene: trace pixels of every candidate camera with Embree packets
// on all cores and do nothing else (no voxels, no sets). Loops, each timed alone:
//   all_pixels  every pixel of every image;
//   culled      exactly the pixels vantage's culling traces (the primary rays of `vantage
//               observe`), whose time scripts/bench_e2e.sh divides vantage's observe time by;
//   same_rays   the culled pixels' rays and, under the physical sensor model (issue 43), the
//               occlusion segments observe casts from each target hit its candidate's second
//               aperture sees to that aperture (16 to a packet): every ray observe casts. The
//               segments are found in an untimed pass (the conditions of observe.cpp's
//               PixelJudge::Take). Under the ideal model (a Gazebo world of the original system,
//               or --ideal) there are none and same_rays is culled again.
// The spans to trace are computed outside the timed loops (observe computes them per candidate;
// spans_seconds times that alone), as is the BVH (rays_build_seconds: RayScene's build, which
// vantage's observe time includes).
// With RAY_LIMIT_ROUNDS=R: R rounds of vantage's Observe, the culled loop and the same-rays loop,
// interleaved, each in CPU seconds (user + system, all threads), and the least of each: the
// ratios a loaded machine moves least (observe_rays: the rays Observe traced, the culled count
// but where a flying-pixel filter traces its spans' borders too).
// Usage: ray_limit SCENE [--model-path DIR] [--resource-path DIR] [--physical | --ideal]
//   -> one JSON line on stdout.
#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "limit_loops.hpp"
#include "observe/culling.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/vantage.hpp"

namespace {

// The process's CPU seconds (user + system, all threads).
double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// A Gazebo world by its extension, as the pipeline decides the default sensor model.
bool IsGazeboWorld(std::string path) {
  for (char& c : path) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto ends = [&](const std::string& tail) {
    return path.size() >= tail.size() && path.compare(path.size() - tail.size(), tail.size(), tail) == 0;
  };
  return ends(".world") || ends(".sdf");
}

}  // namespace

int main(int argc, char** argv) {
  using namespace vantage;
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: ray_limit SCENE [--model-path DIR] [--resource-path DIR] [--physical | --ideal]\n");
    return 2;
  }
  LoadOptions load;
  std::optional<bool> physical_flag;
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--physical") physical_flag = true;
    if (flag == "--ideal") physical_flag = false;
    if (i + 1 < argc && flag == "--model-path") load.model_paths.push_back(argv[++i]);
    if (i + 1 < argc && flag == "--resource-path") load.resource_paths.push_back(argv[++i]);
  }
  try {
    const Problem problem = LoadProblem(argv[1], load);
    DeployOptions deploy{problem.observation_point, problem.random_roll, problem.seed};
    const std::vector<Candidate> cams =
        DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
    // The sensor model as the pipeline picks it: physical unless a Gazebo world, and only where
    // some candidate's type has a second aperture.
    bool physical = physical_flag.value_or(!IsGazeboWorld(argv[1]));
    bool any_aperture = false;
    for (const Candidate& c : cams) any_aperture |= SecondApertureOf(c.sensor, c.type_id) != nullptr;
    physical = physical && any_aperture;
    auto start = std::chrono::steady_clock::now();
    const RayScene rays(problem.scene);
    const double rays_build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Reference reference = BuildReference(problem.scene, {problem.cell_size});
    const std::vector<Aabb> blocks = detail::ReferenceBlocks(reference);
    // Spans are computed outside the timed loop: the loop only traces.
    std::vector<std::vector<detail::RowSpan>> culled(cams.size()), full(cams.size());
    uint64_t culled_rays = 0, full_rays = 0;
    for (size_t i = 0; i < cams.size(); ++i) {
      full[i] = detail::SpansToTrace(cams[i], blocks, false);
      for (const auto& s : full[i]) full_rays += static_cast<uint64_t>(s.u1 - s.u0 + 1);
    }
    // The culled spans as observe computes them, on all cores, timed alone.
    start = std::chrono::steady_clock::now();
    tbb::parallel_for(size_t{0}, cams.size(),
                      [&](size_t i) { culled[i] = detail::SpansToTrace(cams[i], blocks, true); });
    const double spans_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (size_t i = 0; i < cams.size(); ++i)
      for (const auto& s : culled[i]) culled_rays += static_cast<uint64_t>(s.u1 - s.u0 + 1);

    // The primary rays of candidate i's spans, 16 at a time, into `intersect`.
    const auto trace_view = [&](size_t i, const std::vector<detail::RowSpan>& spans, const auto& intersect) {
      bench::TraceSpans(cams[i], spans, intersect);
    };

    // The occlusion segments observe casts under the physical model, found untimed.
    std::vector<bench::Segments> segments(cams.size());
    if (physical) {
      tbb::parallel_for(size_t{0}, cams.size(), [&](size_t i) {
        segments[i] = bench::FindSegments(cams[i], culled[i], [&](RayBatch* batch) { rays.Intersect(batch); });
      });
    }
    uint64_t segment_count = 0;
    for (const bench::Segments& s : segments) segment_count += s.dir.size();

    std::atomic<uint64_t> hits{0};  // rays of the last primary loop that hit a target
    // One candidate's primary rays of `spans[i]`, and its segments when `with_segments`.
    const auto cast_one = [&](size_t i, const std::vector<std::vector<detail::RowSpan>>& spans,
                              bool with_segments) {
      uint64_t local_hits = 0;
      trace_view(i, spans[i], [&](RayBatch* batch) {
        rays.Intersect(batch);
        for (int lane = 0; lane < batch->active; ++lane) local_hits += batch->is_target[lane] ? 1 : 0;
      });
      hits += local_hits;
      if (!with_segments) return;
      bench::CastSegments(segments[i], [&](OcclusionBatch* packet) { rays.Occluded(packet); });
    };
    const auto cast_all = [&](const std::vector<std::vector<detail::RowSpan>>& spans, bool with_segments) {
      hits = 0;
      tbb::parallel_for(size_t{0}, cams.size(), [&](size_t i) { cast_one(i, spans, with_segments); });
    };
    const auto wall = [&](const auto& work) {
      const auto begin = std::chrono::steady_clock::now();
      work();
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    };
    const double full_seconds = wall([&] { cast_all(full, false); });
    const double same_rays_seconds = wall([&] { cast_all(culled, true); });
    const double culled_seconds = wall([&] { cast_all(culled, false); });
    std::printf("{\"candidates\": %zu, \"all_pixels\": %llu, \"all_pixels_seconds\": %.4f, "
                "\"all_pixels_rays_per_second\": %.1f, \"culled_rays\": %llu, \"culled_seconds\": %.4f, "
                "\"culled_rays_per_second\": %.1f, \"target_hits\": %llu, \"physical\": %s, "
                "\"segments\": %llu, \"same_rays_seconds\": %.4f, \"spans_seconds\": %.4f, "
                "\"rays_build_seconds\": %.4f",
                cams.size(), static_cast<unsigned long long>(full_rays), full_seconds,
                static_cast<double>(full_rays) / full_seconds, static_cast<unsigned long long>(culled_rays),
                culled_seconds, static_cast<double>(culled_rays) / culled_seconds,
                static_cast<unsigned long long>(hits.load()), physical ? "true" : "false",
                static_cast<unsigned long long>(segment_count), same_rays_seconds, spans_seconds,
                rays_build_seconds);
    if (const char* env = std::getenv("RAY_LIMIT_ROUNDS")) {
      const int rounds = std::max(1, std::atoi(env));
      ObserveOptions options;
      options.physical = physical;
      double observe_cpu = 1e300, culled_cpu = 1e300, same_cpu = 1e300, spans_cpu = 1e300;
      uint64_t observed_rays = 0;
      const auto time = [&](double* least, const auto& work) {
        const double before = CpuSeconds();
        work();
        *least = std::min(*least, CpuSeconds() - before);
      };
      for (int r = 0; r < rounds; ++r) {
        time(&observe_cpu, [&] {
          observed_rays = 0;
          for (const Observation& o : Observe(rays, reference, cams, options)) observed_rays += o.rays_traced;
        });
        time(&culled_cpu, [&] { cast_all(culled, false); });
        time(&same_cpu, [&] { cast_all(culled, true); });
        time(&spans_cpu, [&] {
          tbb::parallel_for(size_t{0}, cams.size(),
                            [&](size_t i) { culled[i] = detail::SpansToTrace(cams[i], blocks, true); });
        });
      }
      std::printf(", \"rounds\": %d, \"cpu_observe\": %.4f, \"cpu_culled\": %.4f, \"cpu_same_rays\": %.4f, \"cpu_spans\": %.4f, "
                  "\"cpu_observe_over_culled\": %.3f, \"cpu_observe_over_same_rays\": %.3f, "
                  "\"observe_rays\": %llu",
                  rounds, observe_cpu, culled_cpu, same_cpu, spans_cpu, observe_cpu / culled_cpu, observe_cpu / same_cpu,
                  static_cast<unsigned long long>(observed_rays));
    }
    std::printf("}\n");
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
