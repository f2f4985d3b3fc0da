// The refined-poses table of issue 9: for one world, observe every candidate once, then for each
// N = 1..N_max select with `local`, refine (vantage/refine.hpp) and print a markdown row: the
// unrefined and refined coverage, the gain in points, the new candidates and the extra rays traced
// for them, and the seconds of the refinement. Exits 1 when a refined coverage is below the
// unrefined one (the target: refined >= unrefined at every N).
//
// Usage: refine_table WORLD [--model-path DIR] [--resource-path DIR] [--n-max 5] [--rounds 4]
//                     [--per-sensor 12] [--move 0.05] [--turn 5] [--seed S] [--header]
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/problem.hpp"
#include "vantage/refine.hpp"
#include "vantage/select.hpp"

int main(int argc, char** argv) {
  using namespace vantage;
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: refine_table WORLD [--model-path DIR] [--resource-path DIR] [--n-max 5] "
                 "[--rounds 4] [--per-sensor 12] [--move 0.05] [--turn 5] [--seed S] [--header]\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);
  LoadOptions load;
  RefineOptions refine;
  int n_max = 5;
  bool header = false;
  std::optional<uint64_t> seed;
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--header") {
      header = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "refine_table: %s needs a value\n", flag.c_str());
      return 2;
    }
    const std::string value = argv[++i];
    if (flag == "--model-path") {
      load.model_paths.push_back(value);
    } else if (flag == "--resource-path") {
      load.resource_paths.push_back(value);
    } else if (flag == "--n-max") {
      n_max = std::stoi(value);
    } else if (flag == "--rounds") {
      refine.max_rounds = std::stoi(value);
    } else if (flag == "--per-sensor") {
      refine.per_sensor = std::stoi(value);
    } else if (flag == "--move") {
      refine.move = std::stod(value);
    } else if (flag == "--turn") {
      refine.turn_deg = std::stod(value);
    } else if (flag == "--seed") {
      seed = std::stoull(value);
    } else {
      std::fprintf(stderr, "refine_table: unknown option %s\n", flag.c_str());
      return 2;
    }
  }
  try {
    const Problem problem = LoadProblem(argv[1], load);
    const uint64_t run_seed = seed.value_or(problem.seed);
    refine.seed = run_seed;
    DeployOptions deploy{problem.observation_point, problem.random_roll, run_seed};
    const std::vector<Candidate> candidates =
        DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
    const Reference reference = BuildReference(problem.scene, {problem.cell_size});
    auto start = std::chrono::steady_clock::now();
    const RayScene ray_scene(problem.scene);
    const std::vector<Observation> observations = Observe(ray_scene, reference, candidates);
    const double observe_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    uint64_t rays = 0;
    for (const Observation& o : observations) rays += o.rays_traced;
    const std::string world = std::filesystem::path(argv[1]).stem().string();
    std::fprintf(stderr, "%s: %zu candidates, %zu reference cells, %llu rays in %.2f s\n",
                 world.c_str(), candidates.size(), reference.size(),
                 static_cast<unsigned long long>(rays), observe_seconds);
    if (header) {
      std::printf(
          "| world | N | unrefined (local) | refined | gain (points) | rounds | "
          "new candidates | extra rays | seconds |\n");
      std::printf("|---|---|---|---|---|---|---|---|---|\n");
    }
    bool is_ok = true;
    for (int n = 1; n <= n_max && n <= static_cast<int>(candidates.size()); ++n) {
      SelectOptions select;
      select.n = n;
      select.method = Method::kLocal;
      select.seed = run_seed;
      select.ransac_iterations = problem.selection.ransac_iterations;
      const Selection unrefined = Select(observations, reference.size(), select).at(0);
      const RefineResult r =
          Refine(ray_scene, reference, candidates, observations, problem.populations,
                 problem.observation_point, unrefined, select, refine);
      const double gain = 100 * (r.selection.coverage - unrefined.coverage);
      is_ok = is_ok && r.selection.coverage >= unrefined.coverage;
      std::printf("| %s | %d | %.2f %% | %.2f %% | %+.2f | %d | %zu | %llu (%.2fx) | %.2f |\n",
                  world.c_str(), n, 100 * unrefined.coverage, 100 * r.selection.coverage, gain,
                  r.rounds, r.new_candidates, static_cast<unsigned long long>(r.extra_rays),
                  rays ? static_cast<double>(r.extra_rays) / static_cast<double>(rays) : 0.0,
                  r.seconds);
      std::fflush(stdout);
    }
    if (!is_ok) {
      std::fprintf(stderr, "refine_table: a refined coverage is below the unrefined one\n");
      return 1;
    }
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "refine_table: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "refine_table: internal: %s\n", e.what());
    return 1;
  }
}
