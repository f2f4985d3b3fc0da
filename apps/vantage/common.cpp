#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

constexpr double kMiB = 1024.0 * 1024.0;

// --max-memory, or 75 % of the machine's RAM when it is not given (0).
double MemoryLimitMiB(double limit_mib) {
  if (limit_mib > 0) return limit_mib;
  const double ram = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                     static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  return 0.75 * ram / kMiB;
}

// Refuses a run whose estimate exceeds the limit, before any ray is cast (issue #8).
void CheckMemory(const MemoryEstimate& estimate, double limit_mib, const std::string& source) {
  spdlog::info("memory estimate: {:.0f} MiB (scene {:.0f}, images {:.0f}, visibility {:.0f}, selection {:.0f})",
               estimate.Total() / kMiB, estimate.scene / kMiB, estimate.hit_buffers / kMiB,
               estimate.observations / kMiB, estimate.selection / kMiB);
  limit_mib = MemoryLimitMiB(limit_mib);
  if (estimate.Total() / kMiB > limit_mib)
    throw InputError(AtPlace(source, 0, fmt::format(
        "this run needs about {:.0f} MiB, above the {:.0f} MiB limit — use fewer candidates, lower "
        "resolutions, a larger --cell-size, fewer --threads, or raise --max-memory",
        estimate.Total() / kMiB, limit_mib)));
}

// Refuses a cell size too fine for the memory before R is built (issue #8: 1e-5 m on the example
// asked for 4·10⁸ cells and ran out of memory). R is estimated from the targets' triangles
// (EstimateReferenceCells, within 20 % of the cells appended on the example from 2 mm to 50 µm).
// Building R holds about 32 bytes per appended cell (per-thread keys and the merged copy, each up
// to twice its size while growing); afterwards each cell keeps its 8-byte key plus about 64 bytes
// of outputs (the PLY voxel centres, report.html's voxel arrays and their copies), besides the
// visibility lists and selection bitsets of EstimateMemory. Measured on the example at 50 µm:
// 55 bytes per cell of R in all, so this errs on the safe side by about 1.5.
void CheckReferenceMemory(const Problem& problem, std::span<const Candidate> candidates,
                          double limit_mib, bool cell_size_from_option) {
  const double cells = EstimateReferenceCells(problem.scene, problem.cell_size);
  const double build = 32.0 * cells;
  const size_t capped = static_cast<size_t>(std::min(cells, 1e18));
  const MemoryEstimate later =
      EstimateMemory(problem.scene, capped, candidates,
                     static_cast<size_t>(tbb::this_task_arena::max_concurrency()));
  // The stages that grow with |R|: building it; then R, the outputs, visibility lists, bitsets.
  const double with_r = std::max(
      build, (8.0 + 64.0) * cells + static_cast<double>(later.observations + later.selection));
  const double others = static_cast<double>(later.scene + later.hit_buffers);
  spdlog::debug("reference estimate: about {:.3g} cells, {:.0f} MiB with them", cells,
                with_r / kMiB);
  limit_mib = MemoryLimitMiB(limit_mib);
  const double total = with_r + others;
  if (total / kMiB <= limit_mib) return;
  if (with_r < others) {
    CheckMemory(later, limit_mib, problem.source);  // the images dominate: the general message
    return;
  }
  throw InputError(AtPlace(problem.source, 0, fmt::format(
      "a cell size of {} m ({}) makes a reference R of about {:.2g} cells on the targets' "
      "surface, so this run needs about {:.0f} MiB, above the {:.0f} MiB limit — {}, or raise "
      "--max-memory",
      problem.cell_size, cell_size_from_option ? "--cell-size" : "the scene's cell_size", cells,
      total / kMiB, limit_mib,
      cell_size_from_option
          ? "give a larger --cell-size"
          : "use a larger cell_size in the scene (or override it with --cell-size)")));
}

// --seed: CLI11 reads "-1" into an unsigned as 2^64 - 1; refuse a sign instead.
std::string NonNegativeWholeNumber(std::string& text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first != std::string::npos && text[first] == '-')
    return fmt::format("{} is negative — give a whole number from 0 to {}", text,
                       std::numeric_limits<uint64_t>::max());
  return {};
}

// --max-memory: a positive, finite number of MiB.
std::string PositiveMiB(std::string& text) {
  double value = 0;
  if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value <= 0)
    return fmt::format("{} is not a positive number of MiB — give e.g. --max-memory 4096", text);
  return {};
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

CLI::Validator SeedValidator() { return CLI::Validator(NonNegativeWholeNumber, "0 or more"); }

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
  app->add_option("--max-incidence", options->max_incidence_deg,
                  "quality: a pixel counts only when its ray meets the surface within this many "
                  "degrees of the normal (0-90]");
  app->add_option("--max-depth-noise", options->max_depth_noise_mm,
                  "quality: a pixel counts only when its sensor's depth noise sigma(z) is at most "
                  "this many mm (docs/sensor-models.md)");
  app->add_option("--max-memory", options->max_memory_mib,
                  "refuse runs estimated above this many MiB (default: 75 % of RAM)")
      ->check(CLI::Validator(PositiveMiB, "MiB > 0"));
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
  app->add_option("--over-states", options->over_states,
                  "a scene with states: maximise the mean or the worst (min) coverage over them "
                  "(default mean)");
  app->add_option("--fov-tolerance", options->fov_tolerance_deg,
                  "robustness: degrees the chosen sensors' fields of view are shrunk by (datasheet "
                  "tolerance)")
      ->check(CLI::Range(0.0, 45.0))
      ->capture_default_str();
  app->add_option("--alternatives-within", options->alternatives_within,
                  "robustness: list one-sensor alternatives losing at most this many coverage points")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
}

QualityFilter QualityOf(const SceneOptions& options) {
  QualityFilter quality;
  quality.max_incidence_deg = options.max_incidence_deg;
  if (options.max_depth_noise_mm) quality.max_depth_noise = *options.max_depth_noise_mm / 1000.0;
  quality.Validate();
  return quality;
}

Problem LoadScene(const SceneOptions& options) {
  LoadOptions load;
  load.model_paths = options.model_paths;
  load.resource_paths = options.resource_paths;
  load.targets = options.targets;
  Problem problem = LoadProblem(options.scene, load);
  if (options.cell_size) {
    ReferenceOptions given;
    given.cell_size = *options.cell_size;
    try {
      given.Validate();
    } catch (const InputError& e) {
      throw InputError(AtPlace("--cell-size", 0, e.what()));
    }
    problem.cell_size = *options.cell_size;
  }
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
  const QualityFilter quality = QualityOf(options);  // option errors before any work
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
  // -n names the option before any ray is cast (the scene's own n is checked with the others).
  if (selection && selection->n &&
      (*selection->n < 1 || static_cast<size_t>(*selection->n) > candidates.size())) {
    throw InputError(AtPlace("-n", 0, fmt::format(
        "n = {} is out of range: there are {} candidates, so n must be between 1 and {} — "
        "give -n in that range",
        *selection->n, candidates.size(), candidates.size())));
  }
  if (problem.expected_candidates && *problem.expected_candidates != static_cast<int>(candidates.size())) {
    const std::string note = fmt::format(
        "{}: numberOfSamplingSensors is {} but the populations yield {} sensors", problem.source,
        *problem.expected_candidates, candidates.size());
    spdlog::warn("{}", note);
    result.notes.push_back(note);
  }
  // A scene with states: the first state is the scene everything below measures; the others
  // are observed after it with the same candidates.
  std::vector<Scene> state_scenes;
  for (const SceneState& state : problem.states) state_scenes.push_back(ApplyState(problem.scene, state));
  if (!state_scenes.empty()) problem.scene = state_scenes.front();
  result.timings.load = SecondsSince(start);

  start = std::chrono::steady_clock::now();
  Reference reference;
  try {
    CheckTargetsFitGrid(problem.scene, problem.cell_size);
    CheckReferenceMemory(problem, candidates, options.max_memory_mib,
                         options.cell_size.has_value());
    reference = BuildReference(problem.scene, reference_options);
  } catch (const InputError& e) {
    // Targets beyond the grid name no place of their own; the memory check names the scene.
    const std::string message = e.what();
    if (message.rfind(problem.source + ":", 0) == 0) throw;
    throw InputError(AtPlace(problem.source, 0, message));
  }
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
  observe_options.quality = quality;
  observe_options.progress = ProgressBar("observe");
  std::vector<Observation> observations = Observe(problem.scene, reference, candidates, observe_options);
  result.timings.observe = SecondsSince(start);
  uint64_t rays = 0;
  for (const Observation& o : observations) rays += o.rays_traced;
  spdlog::info("observe: {:.1f} M rays traced in {:.3f} s", rays / 1e6, result.timings.observe);
  for (size_t i = 0; i < state_scenes.size(); ++i) {
    ObservedState state;
    state.name = problem.states[i].name;
    for (size_t j = 0; j < i && state.same_as < 0; ++j) {
      if (SameGeometry(state_scenes[j], state_scenes[i])) state.same_as = static_cast<int>(j);
    }
    if (i == 0) {
      state.reference = reference;
      state.observations = observations;
    } else if (state.same_as >= 0) {  // unchanged geometry: no ray is traced twice
      state.reference = result.states[static_cast<size_t>(state.same_as)].reference;
      state.observations = result.states[static_cast<size_t>(state.same_as)].observations;
    } else {
      const auto state_start = std::chrono::steady_clock::now();
      try {
        CheckTargetsFitGrid(state_scenes[i], problem.cell_size);
        state.reference = BuildReference(state_scenes[i], reference_options);
      } catch (const InputError& e) {
        throw InputError(AtPlace(problem.source, problem.states[i].line,
                                 fmt::format("state '{}': {}", state.name, e.what())));
      }
      state.observations = Observe(state_scenes[i], state.reference, candidates, observe_options);
      result.timings.observe += SecondsSince(state_start);
    }
    spdlog::info("state '{}': {} reference voxels{}", state.name, state.reference.size(),
                 state.same_as >= 0 ? fmt::format(", same geometry as '{}' (not traced again)",
                                                  result.states[static_cast<size_t>(state.same_as)].name)
                                    : std::string());
    result.states.push_back(std::move(state));
  }

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
  data.quality = quality;
  result.notes.insert(result.notes.end(), problem.notes.begin(), problem.notes.end());
  result.scene = std::move(problem.scene);
  result.populations = std::move(problem.populations);
  result.observation_point = problem.observation_point;
  result.sensors = std::move(problem.sensors);
  return result;
}

namespace {

SelectOptions MergeSelectOptions(const VisibilityFile& data, const SelectionOptions& cli,
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
  return options;
}

// Validate's message, or "" when the options are valid.
std::string SelectProblem(const SelectOptions& options, size_t candidates) {
  try {
    options.Validate(candidates);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

SelectOptions ResolveSelectOptions(const VisibilityFile& data, const SelectionOptions& cli,
                                   std::optional<uint64_t> seed, const std::string& method_default) {
  const SelectOptions options = MergeSelectOptions(data, cli, seed, method_default);
  const std::string problem = SelectProblem(options, data.candidates.size());
  if (problem.empty()) return options;
  // Blame the option whose removal changes the problem; none: the scene's own settings.
  using Drop = void (*)(SelectionOptions*);
  const std::pair<const char*, Drop> given[] = {
      {"-n", [](SelectionOptions* o) { o->n.reset(); }},
      {"--k", [](SelectionOptions* o) { o->k.reset(); }},
      {"--goal", [](SelectionOptions* o) { o->goal.reset(); }},
      {"--budget", [](SelectionOptions* o) { o->budget.reset(); }},
      {"--iterations", [](SelectionOptions* o) { o->iterations.reset(); }},
      {"--stop", [](SelectionOptions* o) { o->stop_coverage.reset(); }},
      {"--time-limit", [](SelectionOptions* o) { o->time_limit = SelectionOptions{}.time_limit; }},
      {"--method", [](SelectionOptions* o) { o->method.reset(); }},
  };
  for (const auto& [flag, drop] : given) {
    SelectionOptions without = cli;
    drop(&without);
    const SelectOptions other = MergeSelectOptions(data, without, seed, method_default);
    if (SelectProblem(other, data.candidates.size()) != problem)
      throw InputError(AtPlace(flag, 0, problem));
  }
  throw InputError(AtPlace(data.scene, 0, problem));
}

void SelectResults(const ObservedScene& observed, const SelectionOptions& cli, const SelectOptions& options,
                   Report* report) {
  if (observed.states.empty()) {
    if (cli.over_states)
      throw InputError(AtPlace("--over-states", 0,
                               "the scene has no states — add a `states:` list (docs/scene-format.md) or "
                               "drop --over-states"));
    report->results = Select(observed.data.observations, observed.data.reference.size(), options);
    return;
  }
  const OverStates over = ParseOverStates(cli.over_states.value_or("mean"));
  std::vector<StateObservations> states;
  for (const ObservedState& state : observed.states)
    states.push_back({state.name, state.reference.size(), state.observations});
  for (StateSelection& result : SelectOverStates(states, over, options)) {
    result.selection.state_coverage = std::move(result.state_coverage);
    report->results.push_back(std::move(result.selection));
  }
  StatesInfo info;
  info.over = OverStatesName(over);
  for (const ObservedState& state : observed.states)
    info.states.push_back({state.name, state.reference.size(), state.same_as});
  report->states = std::move(info);
}

namespace {

// The robustness read-outs: the worst failure, the shrunk fields of view, the alternatives.
void PrintRobustness(const VisibilityFile& data, const std::vector<Selection>& results,
                     const Robustness& robustness) {
  const Selection& result = results.at(static_cast<size_t>(robustness.result));
  const auto name = [&](uint32_t i) { return data.candidates.at(i).name; };
  std::string line = fmt::format("of {} n={}:", result.method, result.n);
  if (robustness.worst) {
    line += fmt::format(" worst single failure {} -> {:.2f} % ({:+.2f})", name(robustness.worst->sensor),
                        100.0 * robustness.worst->coverage, 100.0 * (robustness.worst->coverage - result.coverage));
  }
  if (robustness.fov_shrunk_coverage) {
    line += fmt::format("; fields of view -{:g} deg -> {:.2f} % ({:+.2f})", *robustness.fov_tolerance_deg,
                        100.0 * *robustness.fov_shrunk_coverage,
                        100.0 * (*robustness.fov_shrunk_coverage - result.coverage));
  }
  fmt::print("robustness       {}\n", line);
  for (const Alternative& a : robustness.alternatives) {
    fmt::print("alternative      {} instead of {}: {:.2f} % ({:+.2f})\n", name(a.replacement), name(a.replaced),
               100.0 * a.coverage, 100.0 * (a.coverage - result.coverage));
  }
  if (robustness.alternatives.empty() && !result.budget)
    fmt::print("alternative      none within {:g} points by replacing one sensor\n",
               100.0 * robustness.alternatives_within);
}

}  // namespace

void PrintSummary(const Report& report, const std::string& out_dir) {
  const VisibilityFile& data = *report.data;
  const std::vector<Selection>& results = report.results;
  const std::optional<RefinementInfo>& refinement = report.refinement;
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
  // Copies every set: only when a quality filter makes plain coverage differ.
  const std::vector<Observation> plain =
      data.quality.active() ? WithoutQuality(data.observations) : std::vector<Observation>{};
  const CoverageEvaluator plain_evaluator(plain, r);
  if (data.quality.active()) {
    std::vector<std::string> limits;
    if (data.quality.max_incidence_deg) limits.push_back(fmt::format("incidence <= {:g} deg", *data.quality.max_incidence_deg));
    if (data.quality.max_depth_noise)
      limits.push_back(fmt::format("depth noise <= {:g} mm", 1000.0 * *data.quality.max_depth_noise));
    fmt::print("quality          {}: coverages count only such pixels; 'plain' counts every pixel\n",
               fmt::join(limits, ", "));
  }
  if (report.states) {
    std::vector<std::string> names;
    for (const StatesInfo::State& state : report.states->states) names.push_back(state.name);
    fmt::print("states           {} over {} states ({}): coverages below are the {} of the states' "
               "coverages, listed after each\n",
               report.states->over, names.size(), fmt::join(names, ", "),
               report.states->over == "min" ? "worst" : "mean");
    fmt::print("                 (reference and best single above: state '{}')\n", names.front());
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
    if (data.quality.active() && !report.states)
      bound += fmt::format("  (plain {:.2f} %)", 100.0 * plain_evaluator.Coverage(s->chosen, s->k));
    if (!s->state_coverage.empty()) {
      std::vector<std::string> per_state;
      for (double c : s->state_coverage) per_state.push_back(fmt::format("{:.2f}", 100.0 * c));
      bound += fmt::format("  (states {} %)", fmt::join(per_state, " / "));
    }
    fmt::print("{:<8} n={:<3}  {:6.2f} %{}  [{}]  {:.3f} s\n", s->method, s->n, 100.0 * s->coverage, bound,
               names, s->seconds);
  }
  PrintCoverageByN(results);
  if (refinement) {
    const Selection& from = results.at(static_cast<size_t>(refinement->from_result));
    fmt::print("refinement       {:+.2f} points over {} n={}: {} rounds, {} new poses, {:.1f} M extra rays, {:.2f} s\n",
               100.0 * (refinement->coverage_after - refinement->coverage_before), from.method, from.n,
               refinement->rounds, refinement->new_candidates, refinement->extra_rays / 1e6, refinement->seconds);
  }
  if (report.robustness) PrintRobustness(data, results, *report.robustness);
  fmt::print("timings          load {:.3f} s, reference {:.3f} s, observe {:.3f} s, select {:.3f} s, total {:.3f} s\n",
             report.timings.load, report.timings.reference, report.timings.observe, report.timings.select,
             report.timings.total);
  if (!out_dir.empty()) fmt::print("outputs          {}/\n", out_dir);
}

}  // namespace vantage::cli
