#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <numeric>

#include "commands.hpp"

namespace vantage::cli {
namespace {

// A progress bar with rate and ETA on stderr when it is a terminal; nothing otherwise (the
// stage logs its own start and end lines).
std::function<void(size_t, size_t)> ProgressBar(const std::string& label) {
  if (!::isatty(STDERR_FILENO) || spdlog::get_level() > spdlog::level::info) return {};
  auto start = std::chrono::steady_clock::now();
  auto mutex = std::make_shared<std::mutex>();
  return [label, start, mutex](size_t done, size_t total) {
    std::lock_guard<std::mutex> lock(*mutex);
    const double elapsed = SecondsSince(start);
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
    const int width = 30;
    const int filled = total ? static_cast<int>(width * done / total) : width;
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu  %.1f/s  ETA %.1fs ", label.c_str(),
                 std::string(static_cast<size_t>(filled), '#').c_str(),
                 std::string(static_cast<size_t>(width - filled), '.').c_str(), done, total, rate, eta);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

// Refuses a run whose estimate exceeds the limit, before any ray is cast (issue #8).
void CheckMemory(const MemoryEstimate& estimate, double limit_mib, const std::string& source) {
  const double mib = 1024.0 * 1024.0;
  spdlog::info("memory estimate: {:.0f} MiB (scene {:.0f}, images {:.0f}, visibility {:.0f}, selection {:.0f})",
               estimate.Total() / mib, estimate.scene / mib, estimate.hit_buffers / mib,
               estimate.observations / mib, estimate.selection / mib);
  if (limit_mib <= 0) {
    const double ram = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
    limit_mib = 0.75 * ram / mib;
  }
  if (estimate.Total() / mib > limit_mib)
    throw InputError(AtPlace(source, 0, fmt::format(
        "this run needs about {:.0f} MiB, above the {:.0f} MiB limit — use fewer candidates, lower "
        "resolutions, a larger --cell-size, fewer --threads, or raise --max-memory",
        estimate.Total() / mib, limit_mib)));
}

// `--method all`: the coverage-versus-N curve, one row per n, one column per method, and the
// proven bound (exact's; "*" once proven optimal). Printed only when a method ran for several n
// (not for set cover, whose methods differ in n but each ran once).
void PrintCoverageByN(const std::vector<Selection>& results) {
  std::vector<int> ns;
  bool is_curve = false;
  for (const Selection& s : results) {
    if (std::find(ns.begin(), ns.end(), s.n) == ns.end()) ns.push_back(s.n);
    is_curve = is_curve || std::any_of(results.begin(), results.end(), [&](const Selection& o) {
                 return o.method == s.method && o.n != s.n;
               });
  }
  if (!is_curve) return;
  std::sort(ns.begin(), ns.end());
  std::vector<std::string> methods;
  for (const char* m : {"best", "ransac", "greedy", "local", "exact"}) {
    if (std::any_of(results.begin(), results.end(), [&](const Selection& s) { return s.method == m; }))
      methods.emplace_back(m);
  }
  const int k = results.front().k;
  fmt::print("coverage by n{}\n", k >= 2 ? fmt::format(" ({}-coverage, %)", k) : std::string(" (%)"));
  std::string header = fmt::format("{:>4}", "n");
  for (const std::string& m : methods) header += fmt::format(" {:>8}", m);
  fmt::print("{} {:>8}\n", header, "bound");
  for (const int n : ns) {
    std::string line = fmt::format("{:>4}", n);
    std::string bound = fmt::format("{:>8}", "-");
    for (const std::string& m : methods) {
      const auto it = std::find_if(results.begin(), results.end(),
                                   [&](const Selection& s) { return s.n == n && s.method == m; });
      line += it == results.end() ? fmt::format(" {:>8}", "-") : fmt::format(" {:8.2f}", 100.0 * it->coverage);
      if (it != results.end() && it->upper_bound)
        bound = fmt::format("{:8.2f}{}", 100.0 * *it->upper_bound, it->proven_optimal ? "*" : "");
    }
    fmt::print("{} {}\n", line, bound);
  }
  fmt::print("(* = proven optimal)\n");
}

}  // namespace

Selection WholeConstellation(const CoverageEvaluator& evaluator) {
  Selection given;
  given.method = "given";
  given.chosen.resize(evaluator.observations().size());
  std::iota(given.chosen.begin(), given.chosen.end(), 0u);
  given.n = static_cast<int>(given.chosen.size());
  given.coverage = evaluator.Coverage(given.chosen);
  given.paper_coverage = evaluator.PaperCoverage(given.chosen);
  return given;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void AddSceneOptions(CLI::App* app, SceneOptions* options, bool with_positional) {
  if (with_positional)
    app->add_option("scene", options->scene, "scene: .yaml (docs/scene-format.md) or Gazebo .world/.sdf")
        ->required();
  app->add_option("--model-path", options->model_paths, "folder of Gazebo models (repeatable)");
  app->add_option("--resource-path", options->resource_paths,
                  "folder of Gazebo resources, e.g. materials (repeatable)");
  app->add_option("--target", options->targets, "target object/model name, overrides the scene (repeatable)");
  app->add_option("--cell-size", options->cell_size, "voxel cell size F in metres (default: the scene's)");
  app->add_option("--seed", options->seed, "random seed (default: the scene's, else 1)");
  app->add_option("--observation-point", options->observation_point,
                  "x y z [m] every candidate looks at (default: the scene's)")
      ->expected(3);
  app->add_option("--random-roll", options->random_roll,
                  "true|false: random roll after the look-at (default: the scene's)");
  app->add_flag("--no-cull", options->no_cull, "trace every pixel (slower; same result)");
  app->add_option("--max-memory", options->max_memory_mib,
                  "refuse runs estimated above this many MiB (default: 75 % of RAM)");
}

void AddSelectionOptions(CLI::App* app, SelectionOptions* options) {
  app->add_option("-n,--sensors", options->n, "number of sensors wanted (default: the scene's)");
  app->add_option("--method", options->method, "best | ransac | greedy | local | exact | all");
  app->add_option("--iterations", options->iterations, "RANSAC iteration cap (default: the scene's)");
  app->add_option("--stop", options->stop_coverage,
                  "RANSAC stops at this coverage, fraction 0..1 (default: the scene's)");
  app->add_option("--time-limit", options->time_limit, "seconds for the exact solver")->capture_default_str();
  app->add_option("--goal", options->goal,
                  "objective: the fewest sensors whose coverage reaches this fraction 0..1 (set cover)");
  app->add_option("--k", options->k,
                  "objective: k-coverage, a cell counts once k chosen sensors see it (k >= 2)");
  app->add_option("--budget", options->budget,
                  "objective: the most coverage for a total sensor cost within this budget");
}

Problem LoadScene(const SceneOptions& options) {
  LoadOptions load;
  load.model_paths = options.model_paths;
  load.resource_paths = options.resource_paths;
  load.targets = options.targets;
  Problem problem = LoadProblem(options.scene, load);
  if (options.cell_size) problem.cell_size = *options.cell_size;
  if (options.seed) problem.seed = *options.seed;
  // Command-line options override the scene's (the Gazebo plugin's parameters, GAZEBO.md).
  if (options.observation_point.size() == 3) {
    problem.observation_point =
        Vec3(options.observation_point[0], options.observation_point[1], options.observation_point[2]);
  }
  if (options.random_roll) problem.random_roll = *options.random_roll;
  for (const std::string& note : problem.notes) spdlog::info("{}", note);
  return problem;
}

ObservedScene ObserveScene(const SceneOptions& options, const SelectionOptions* selection) {
  ObservedScene result;
  auto start = std::chrono::steady_clock::now();
  Problem problem = LoadScene(options);
  if (selection && selection->n) problem.n = *selection->n;
  ReferenceOptions reference_options;
  reference_options.cell_size = problem.cell_size;
  reference_options.Validate();
  spdlog::info("scene {}: {} objects, {} targets, {} triangles", problem.source,
               problem.scene.objects.size(), problem.scene.TargetCount(), problem.scene.TriangleCount());

  DeployOptions deploy;
  deploy.observation_point = problem.observation_point;
  deploy.random_roll = problem.random_roll;
  deploy.seed = problem.seed;
  std::vector<Candidate> candidates =
      DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
  if (candidates.empty())
    throw InputError(AtPlace(problem.source, 0, "no candidate sensors — add a population or a sensor"));
  if (problem.expected_candidates && *problem.expected_candidates != static_cast<int>(candidates.size())) {
    const std::string note = fmt::format(
        "{}: numberOfSamplingSensors is {} but the populations yield {} sensors", problem.source,
        *problem.expected_candidates, candidates.size());
    spdlog::warn("{}", note);
    result.notes.push_back(note);
  }
  result.timings.load = SecondsSince(start);

  start = std::chrono::steady_clock::now();
  Reference reference = BuildReference(problem.scene, reference_options);
  result.timings.reference = SecondsSince(start);
  spdlog::info("reference: {} voxels of {} m in {:.3f} s", reference.size(), problem.cell_size,
               result.timings.reference);

  int64_t pixels = 0;
  for (const Candidate& c : candidates) pixels += c.sensor.PixelCount();
  spdlog::info("observe: {} candidates, {:.1f} Mpx in all images", candidates.size(), pixels / 1e6);
  CheckMemory(EstimateMemory(problem.scene, reference.size(), candidates,
                             static_cast<size_t>(tbb::this_task_arena::max_concurrency())),
              options.max_memory_mib, problem.source);
  start = std::chrono::steady_clock::now();
  ObserveOptions observe_options;
  observe_options.cull = !options.no_cull;
  observe_options.progress = ProgressBar("observe");
  std::vector<Observation> observations = Observe(problem.scene, reference, candidates, observe_options);
  result.timings.observe = SecondsSince(start);
  uint64_t rays = 0;
  for (const Observation& o : observations) rays += o.rays_traced;
  spdlog::info("observe: {:.1f} M rays traced in {:.3f} s", rays / 1e6, result.timings.observe);

  VisibilityFile& data = result.data;
  data.scene = problem.source;
  data.seed = problem.seed;
  data.n = problem.n;
  data.ransac_iterations = problem.ransac_iterations;
  data.ransac_stop_coverage = problem.ransac_stop_coverage;
  data.method = problem.method;
  data.goal = problem.goal;
  data.k = problem.k;
  data.budget = problem.budget;
  data.reference = std::move(reference);
  data.candidates = std::move(candidates);
  data.observations = std::move(observations);
  result.notes.insert(result.notes.end(), problem.notes.begin(), problem.notes.end());
  result.scene = std::move(problem.scene);
  result.populations = std::move(problem.populations);
  result.sensors = std::move(problem.sensors);
  return result;
}

SelectOptions ResolveSelectOptions(const VisibilityFile& data, const SelectionOptions& cli,
                                   std::optional<uint64_t> seed, const std::string& method_default) {
  SelectOptions options;
  options.n = cli.n.value_or(data.n);
  options.method = ParseMethod(cli.method.value_or(data.method.empty() ? method_default : data.method));
  options.ransac_iterations = cli.iterations.value_or(data.ransac_iterations);
  options.ransac_stop_coverage = cli.stop_coverage.value_or(data.ransac_stop_coverage);
  options.seed = seed.value_or(data.seed);
  options.time_limit = cli.time_limit;
  // An objective on the command line replaces the scene's (so --k 2 over a scene's goal works).
  const bool cli_objective = cli.goal || cli.k || cli.budget;
  options.goal = cli_objective ? cli.goal : data.goal;
  options.k = cli_objective ? cli.k.value_or(1) : data.k;
  options.budget = cli_objective ? cli.budget : data.budget;
  if (options.budget) {
    options.costs.reserve(data.candidates.size());
    for (const Candidate& c : data.candidates) options.costs.push_back(c.sensor.cost);
  }
  try {
    options.Validate(data.candidates.size());
  } catch (const InputError& e) {
    throw InputError(AtPlace(data.scene, 0, e.what()));
  }
  return options;
}

void PrintSummary(const VisibilityFile& data, const std::vector<Selection>& results,
                  const Timings& timings, const std::string& out_dir) {
  const size_t r = data.reference.size();
  fmt::print("scene            {}\n", data.scene);
  fmt::print("reference        {} voxels of {} m\n", r, data.reference.cell_size);
  fmt::print("candidates       {}\n", data.candidates.size());
  size_t best = 0;
  for (size_t i = 1; i < data.observations.size(); ++i) {
    if (data.observations[i].reference_indices.size() > data.observations[best].reference_indices.size())
      best = i;
  }
  if (!data.candidates.empty()) {
    const Candidate& c = data.candidates[best];
    fmt::print("best single      {} ({}) {:.2f} %\n", c.name, c.type_id,
               r ? 100.0 * data.observations[best].reference_indices.size() / r : 0.0);
  }
  // The objective, when it is not plain coverage (all results share it).
  if (!results.empty()) {
    const Selection& first = results.front();
    if (first.goal) {
      fmt::print("objective        set cover: the fewest sensors reaching {:.2f} % coverage\n",
                 100.0 * *first.goal);
    } else if (first.budget) {
      fmt::print("objective        budget: the most coverage for a total sensor cost <= {:g}\n",
                 *first.budget);
    } else if (first.k >= 2) {
      fmt::print("objective        {0}-coverage: a cell counts once {0} chosen sensors see it "
                 "(coverages below are {0}-coverages)\n",
                 first.k);
    }
  }
  // One line per method at its largest n: the constellation it recommends.
  std::vector<const Selection*> shown;
  for (const Selection& s : results) {
    auto it = std::find_if(shown.begin(), shown.end(), [&](const Selection* o) { return o->method == s.method; });
    if (it == shown.end()) {
      shown.push_back(&s);
    } else if (s.n >= (*it)->n) {
      *it = &s;
    }
  }
  for (const Selection* s : shown) {
    std::string names;
    for (uint32_t i : s->chosen) names += (names.empty() ? "" : ", ") + data.candidates[i].name;
    std::string bound;
    if (s->upper_bound)
      bound = s->proven_optimal ? "  (optimal)" : fmt::format("  (bound {:.2f} %)", 100.0 * *s->upper_bound);
    if (s->n_lower_bound) {
      bound = s->proven_optimal ? "  (fewest: optimal)"
                                : fmt::format("  (at least {} sensors)", *s->n_lower_bound);
    }
    if (s->cost) bound += fmt::format("  cost {:g} of {:g}", *s->cost, s->budget.value_or(0.0));
    fmt::print("{:<8} n={:<3}  {:6.2f} %{}  [{}]  {:.3f} s\n", s->method, s->n, 100.0 * s->coverage, bound,
               names, s->seconds);
  }
  PrintCoverageByN(results);
  fmt::print("timings          load {:.3f} s, reference {:.3f} s, observe {:.3f} s, select {:.3f} s, total {:.3f} s\n",
             timings.load, timings.reference, timings.observe, timings.select, timings.total);
  if (!out_dir.empty()) fmt::print("outputs          {}/\n", out_dir);
}

}  // namespace vantage::cli
