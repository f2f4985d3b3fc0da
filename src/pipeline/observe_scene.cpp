// Memory checks → R → observe, for every state of the scene: the first half of optimize and all
// of `vantage observe`.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include "pipeline/common.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/error.hpp"
#include "vantage/scene_states.hpp"

namespace vantage {
namespace detail {
namespace {

size_t Threads() { return static_cast<size_t>(tbb::this_task_arena::max_concurrency()); }

// A number of MiB in the refusal: whole MiB, or 3 digits below 1 MiB (a --max-memory of 1e-9 was
// "0 MiB above the 0 MiB limit").
std::string MiBText(double mib) {
  return mib >= 1 ? fmt::format("{:.0f} MiB", mib) : fmt::format("{:.3g} MiB", mib);
}

// Refuses a run whose estimate exceeds the limit, before any ray is cast (issue #8).
void CheckMemory(const MemoryEstimate& estimate, double limit_mib, const std::string& source) {
  spdlog::info(
      "memory estimate: {:.0f} MiB (scene {:.0f}, images {:.0f}, visibility {:.0f}, selection "
      "{:.0f})",
      estimate.Total() / kMiB, estimate.scene / kMiB, estimate.hit_buffers / kMiB,
      estimate.observations / kMiB, estimate.selection / kMiB);
  limit_mib = MemoryLimitMiB(limit_mib);
  if (estimate.Total() / kMiB > limit_mib)
    throw InputError(AtPlace(
        source, 0,
        fmt::format("this run needs about {}, above the {} limit — {}, or raise --max-memory",
                    MiBText(estimate.Total() / kMiB), MiBText(limit_mib),
                    estimate.scene > estimate.Total() / 2
                        ? "use simpler meshes or fewer states"
                        : "use fewer candidates, lower resolutions, a larger --cell-size, fewer "
                          "--threads")));
}

}  // namespace

double MemoryLimitMiB(double limit_mib) {
  if (limit_mib > 0) return limit_mib;
  const double ram = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                     static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  return 0.75 * ram / kMiB;
}

// Targets beyond the grid name no place of their own: the scene is named.
Reference BuildRunReference(const Scene& scene, const ReferenceOptions& options,
                            const std::string& source, const std::function<void()>& before_build) {
  try {
    CheckTargetsFitGrid(scene, options.cell_size);
    if (before_build) before_build();
    return BuildReference(scene, options);
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.rfind(source + ":", 0) == 0) throw;
    throw InputError(AtPlace(source, 0, message));
  }
}

Selection GivenSelection(const CoverageEvaluator& evaluator) {
  Selection given;
  given.method = "given";
  given.chosen.resize(evaluator.observations().size());
  for (size_t i = 0; i < given.chosen.size(); ++i) given.chosen[i] = static_cast<uint32_t>(i);
  given.n = static_cast<int>(given.chosen.size());
  given.coverage = evaluator.Coverage(given.chosen);
  given.paper_coverage = evaluator.PaperCoverage(given.chosen);
  return given;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void CheckWorldPoint(const Vec3& point, const std::string& option) {
  const std::string problem = WorldPointProblem(point);
  if (!problem.empty()) throw InputError(AtPlace(option, 0, problem));
}

void CheckCandidates(std::span<const Candidate> candidates,
                     const std::function<std::string(size_t)>& where) {
  // The place is built only for a candidate that fails: finding it searches the populations and
  // sensors, which for every one of 10⁵ sensors took most of a minute.
  for (size_t i = 0; i < candidates.size(); ++i) {
    try {
      CheckCandidate(candidates[i], {});
    } catch (const InputError&) {
      CheckCandidate(candidates[i], where(i));  // throws again, with the place
      throw;
    }
  }
}

void CheckDeployedCandidates(std::span<const Candidate> candidates, const Problem& problem) {
  CheckCandidates(candidates, [&](size_t i) {
    const Candidate& c = candidates[i];
    for (const Population& p : problem.populations) {
      if (!c.population.empty() && p.name == c.population)
        return AtPlace(p.file, p.line, fmt::format("population '{}': {}", p.name, c.name));
    }
    for (const ExplicitSensor& s : problem.sensors) {
      if (c.population.empty() && s.name == c.name)
        return AtPlace(s.file, s.line, fmt::format("sensor '{}'", s.name));
    }
    return AtPlace(problem.source, 0, fmt::format("candidate {} ('{}')", i, c.name));
  });
}

uint64_t MeshBytes(const Scene& scene) {
  uint64_t bytes = 0;
  for (const SceneObject& object : scene.objects) bytes += object.mesh.Bytes();
  return bytes;
}

void CheckObserveMemory(const Scene& scene, size_t reference_size,
                        std::span<const Candidate> candidates, double limit_mib,
                        const std::string& source, std::span<const Scene> state_scenes) {
  MemoryEstimate estimate = EstimateMemory(scene, reference_size, candidates, Threads());
  // Every state keeps its own lists and bitsets (was: counted once, whatever the states).
  const size_t states = std::max<size_t>(1, state_scenes.size());
  estimate.observations *= states;
  estimate.selection *= states;
  // The meshes themselves, and each state's copy of them; while a later state is traced its ray
  // caster's scene stands beside the first's (was: the first's alone — a 4-million-triangle
  // scene in 8 states was estimated at 355 MiB and peaked at 1.7 GiB).
  estimate.scene += MeshBytes(scene);
  uint64_t largest_later = 0;
  for (size_t i = 0; i < state_scenes.size(); ++i) {
    estimate.scene += MeshBytes(state_scenes[i]);
    if (i > 0)
      largest_later = std::max(largest_later, EstimateMemory(state_scenes[i], 0, {}, 1).scene);
  }
  estimate.scene += largest_later;
  CheckMemory(estimate, limit_mib, source);
}

// Issue 15: a 1000 x 1000 grid population passed the memory estimate and ray cast for hours
// without a word. The rays after culling are counted (no ray is cast) and priced. Counting
// costs about 20 µs per candidate, so under a limit the candidates are counted in chunks that
// double in size, and the run is refused as soon as the ones counted already cost more: 10⁶
// candidates were refused after 20 s of counting, now at once.
// Candidates the logged estimate counts when no --max-seconds asks for a refusal, where there are
// more than four times as many (fewer are all counted: it costs little).
constexpr size_t kEstimateSample = 64;

void CheckObserveTime(const Reference& reference, std::span<const Candidate> candidates,
                      const ObserveOptions& observe, double limit_seconds, const Scene& scene,
                      std::span<const Scene> state_scenes, const std::string& source) {
  // Without a limit the estimate feeds the log line at the end alone: where that line is not
  // logged (-q), nothing is counted (issue 47: 3-7 ms of the occlusion world's run).
  if (limit_seconds <= 0 && !spdlog::should_log(spdlog::level::info)) return;
  // Was the first state's alone: 2·10⁴ states were announced as 0.03 s and ran for hours.
  const size_t states = std::max<size_t>(1, state_scenes.size());
  const double per_state = static_cast<double>(states);
  // Was the rays alone: a scene of 4 M triangles in 8 states, announced as 0.06 s, took 17 s
  // (each state's BVH) and writing its report.html as long again.
  uint64_t built_triangles = state_scenes.empty() ? scene.TriangleCount() : 0;
  for (const Scene& state_scene : state_scenes) built_triangles += state_scene.TriangleCount();
  const double scene_seconds =
      EstimateSceneSeconds(built_triangles, scene.TriangleCount(), Threads());
  uint64_t rays = 0;
  size_t counted = 0;
  double seconds = 0;
  // Without a limit the estimate is only logged: counting every candidate cost 8 % of the
  // occlusion world's run, so it is counted on evenly spaced ones and scaled to all of them.
  const bool sampled = limit_seconds <= 0 && candidates.size() > 4 * kEstimateSample;
  if (sampled) {
    std::vector<Candidate> sample;
    sample.reserve(kEstimateSample);
    for (size_t i = 0; i < kEstimateSample; ++i)
      sample.push_back(candidates[i * candidates.size() / kEstimateSample]);
    uint64_t sample_rays = 0;
    for (const uint64_t r : CountRaysToTrace(reference, sample, observe)) sample_rays += r;
    rays = static_cast<uint64_t>(static_cast<double>(sample_rays) *
                                 static_cast<double>(candidates.size()) / kEstimateSample);
    counted = candidates.size();
    seconds = per_state * EstimateObserveSeconds(rays, counted, Threads()) + scene_seconds;
  }
  for (size_t chunk = 1024; counted < candidates.size(); chunk *= 2) {
    const size_t size = std::min(chunk, candidates.size() - counted);
    for (const uint64_t r : CountRaysToTrace(reference, candidates.subspan(counted, size), observe))
      rays += r;
    counted += size;
    seconds = per_state * EstimateObserveSeconds(rays, counted, Threads()) + scene_seconds;
    if (limit_seconds > 0 && seconds > limit_seconds) break;
  }
  const std::string in_states = states > 1 ? fmt::format(" in each of {} states", states) : "";
  const std::string count = built_triangles >= 1000000
                                ? fmt::format("{:.3g} M", built_triangles / 1e6)
                                : fmt::format("{}", built_triangles);
  const std::string triangles = states > 1
                                    ? fmt::format("{} triangles to build in all", count)
                                    : fmt::format("a scene of {} triangles to build", count);
  const std::string estimate =
      sampled ? fmt::format("ray casting about {:.3g} M rays of {} candidates{} (counted on {} "
                            "of them; {}) and selecting",
                            rays / 1e6, candidates.size(), in_states, kEstimateSample, triangles)
      : counted == candidates.size()
          ? fmt::format("ray casting {:.3g} M rays of {} candidates{} ({}) and selecting",
                        rays / 1e6, candidates.size(), in_states, triangles)
          : fmt::format("ray casting the first {} of {} candidates{} alone ({:.3g} M rays; {})",
                        counted, candidates.size(), in_states, rays / 1e6, triangles);
  if (limit_seconds > 0 && seconds > limit_seconds)
    throw InputError(AtPlace(
        source, 0,
        fmt::format("{} is estimated at about {:.3g} s, above the --max-seconds limit of {:g} s "
                    "— {}, or raise --max-seconds",
                    estimate, seconds, limit_seconds,
                    scene_seconds > seconds / 2
                        ? "use simpler meshes or fewer states"
                        : "use fewer candidates or lower resolutions")));
  spdlog::info("time estimate: {} takes at most about {:.3g} s on {} threads", estimate, seconds,
               Threads());
}

// Issue #8: 1e-5 m on the example asked for 4·10⁸ cells and ran out of memory. R is estimated
// from the targets' triangles (EstimateReferenceCells, within 20 % of the cells appended on the
// example from 2 mm to 50 µm). Building R holds about 32 bytes per appended cell (per-thread keys
// and the merged copy, each up to twice its size while growing); afterwards each cell keeps its
// 8-byte key plus about 64 bytes of outputs (the PLY voxel centres, report.html's voxel arrays and
// their copies), besides the visibility lists and selection bitsets of EstimateMemory. Measured
// on the example at 50 µm: 55 bytes per cell of R in all, so this errs on the safe side by 1.5.
void CheckReferenceMemory(const PreparedScene& prepared, double limit_mib) {
  const Problem& problem = prepared.problem;
  limit_mib = MemoryLimitMiB(limit_mib);
  double cells = 0, with_r = 0, others = 0, total = 0;
  MemoryEstimate later;
  const auto estimate = [&](bool fine_triangles_by_cell) {
    cells = EstimateReferenceCells(problem.scene, problem.cell_size, fine_triangles_by_cell);
    // Plus the exposure grid (ComputeExposure): a byte per cell of the targets' box and at most
    // 0.8 for its columns' offsets (four bytes per column of five cells or more).
    const double build =
        32.0 * cells +
        2.0 * static_cast<double>(ExposureGridCells(problem.scene, problem.cell_size));
    const size_t capped = static_cast<size_t>(std::min(cells, 1e18));
    later = EstimateMemory(problem.scene, capped, prepared.candidates, Threads());
    // The stages that grow with |R|: building it; then R, the outputs, visibility lists, bitsets.
    with_r = std::max(build, (8.0 + 64.0) * cells +
                                 static_cast<double>(later.observations + later.selection));
    others = static_cast<double>(later.scene + later.hit_buffers);
    total = with_r + others;
  };
  estimate(false);
  // Over the limit: a second, tighter look at meshes finer than the cells, when its own memory
  // (≤ 8 box cells of 8 bytes per triangle) is a small part of the limit.
  double target_triangles = 0;
  for (const SceneObject& object : problem.scene.objects)
    if (object.is_target()) target_triangles += static_cast<double>(object.mesh.triangles.size());
  if (total / kMiB > limit_mib && 64.0 * target_triangles / kMiB < limit_mib / 8) estimate(true);
  spdlog::debug("reference estimate: about {:.3g} cells, {:.0f} MiB with them", cells,
                with_r / kMiB);
  if (total / kMiB <= limit_mib) return;
  // The images dominate, or the candidates' visibility lists do (a population's count of 10^6
  // was blamed on the cell size): the general message, which names the candidates first.
  const double per_candidate = static_cast<double>(later.observations + later.selection);
  const bool lists_dominate = per_candidate > (8.0 + 64.0) * cells &&
                              static_cast<double>(later.Total()) / kMiB > limit_mib;
  if (with_r < others || lists_dominate) {
    CheckMemory(later, limit_mib, problem.source);
    return;
  }
  const bool from_option = prepared.cell_size_from_option;
  throw InputError(AtPlace(
      problem.source, 0,
      fmt::format("a cell size of {} m ({}) makes a reference R of about {:.2g} cells on the "
                  "targets' surface, so this run needs about {}, above the {} limit — {}, or "
                  "raise --max-memory",
                  problem.cell_size, from_option ? "--cell-size" : "the scene's cell_size", cells,
                  MiBText(total / kMiB), MiBText(limit_mib),
                  from_option
                      ? "give a larger --cell-size"
                      : "use a larger cell_size in the scene (or override it with --cell-size)")));
}

bool AnyApertureIn(std::span<const Candidate> candidates) {
  return std::any_of(candidates.begin(), candidates.end(), [](const Candidate& c) {
    return HasPhysicalModel(c.sensor, c.type_id);
  });
}

ObserveOptions WithSensorModel(ObserveOptions observe, const std::string& scene_path) {
  // A Gazebo world of the original system is read as that system: the paper's ideal pinhole.
  if (!observe.physical) observe.physical = !IsGazeboWorldPath(scene_path);
  spdlog::info("sensor model: {}", *observe.physical ? "physical (second apertures, stereo range)"
                                                     : "ideal pinhole");
  return observe;
}

}  // namespace detail

ObservedScene ObservePrepared(PreparedScene prepared, const ObserveOptions& given,
                              const RunLimits& limits, const TraceFunction& trace) {
  given.Validate();
  ObserveOptions observe = detail::WithSensorModel(given, prepared.problem.source);
  // Physical only where some candidate has a second aperture: otherwise both models see the
  // same, and the run is reported (and stored) as ideal, exactly as before issue 43.
  bool any_aperture = detail::AnyApertureIn(prepared.candidates);
  for (const std::vector<Candidate>& state : prepared.state_candidates)
    any_aperture = any_aperture || detail::AnyApertureIn(state);
  if (*observe.physical && !any_aperture) {
    // Say which types the physical model cannot judge (issue 43) rather than stay silent: the
    // run is the ideal pinhole's, and report.json records it so.
    std::vector<std::string> gaps;
    for (const Candidate& c : prepared.candidates) {
      const std::string gap = PhysicalModelGap(c.sensor, c.type_id);
      const std::string line = fmt::format("{} ({})", c.type_id, gap);
      if (!gap.empty() && std::find(gaps.begin(), gaps.end(), line) == gaps.end())
        gaps.push_back(line);
    }
    if (!gaps.empty())
      spdlog::warn("sensor model: no candidate's type has a physical model, so the run is the "
                   "ideal pinhole's; {}",
                   fmt::join(gaps, "; "));
  }
  observe.physical = *observe.physical && any_aperture;
  limits.Validate();
  Problem& problem = prepared.problem;
  ObservedScene result;
  result.timings = prepared.timings;
  auto start = std::chrono::steady_clock::now();
  const ReferenceOptions reference_options{problem.cell_size, prepared.exposed_only};
  reference_options.Validate();
  Reference reference =
      detail::BuildRunReference(problem.scene, reference_options, problem.source, [&] {
        detail::CheckReferenceMemory(prepared, limits.max_memory_mib);
      });
  result.timings.reference = detail::SecondsSince(start);
  spdlog::info("reference: {} voxels of {} m in {:.3f} s", reference.size(), problem.cell_size,
               result.timings.reference);

  const std::vector<Candidate>& candidates = prepared.candidates;
  const auto trace_all = [&](const RayScene& rays, const Reference& cells,
                             const std::vector<Candidate>& sensors) {
    return trace ? trace(rays, cells, sensors, observe) : Observe(rays, cells, sensors, observe);
  };
  int64_t pixels = 0;
  for (const Candidate& c : candidates) pixels += c.sensor.PixelCount();
  spdlog::info("observe: {} candidates, {:.1f} Mpx in all images", candidates.size(),
               pixels / 1e6);
  detail::CheckObserveMemory(problem.scene, reference.size(), candidates, limits.max_memory_mib,
                             problem.source, prepared.state_scenes);
  detail::CheckObserveTime(reference, candidates, observe, limits.max_seconds, problem.scene,
                           prepared.state_scenes, problem.source);
  start = std::chrono::steady_clock::now();
  result.rays = std::make_unique<RayScene>(problem.scene);
  std::vector<Observation> observations = trace_all(*result.rays, reference, candidates);
  result.timings.observe = detail::SecondsSince(start);
  uint64_t rays = 0;
  for (const Observation& o : observations) rays += o.rays_traced;
  spdlog::info("observe: {:.1f} M rays traced in {:.3f} s", rays / 1e6, result.timings.observe);

  const std::vector<Scene>& state_scenes = prepared.state_scenes;
  for (size_t i = 0; i < state_scenes.size(); ++i) {
    ObservedState state;
    state.name = problem.states[i].name;
    // A state's candidates differ from the first's only when it moves sensors on robot links.
    const auto candidates_of = [&](size_t s) -> const std::vector<Candidate>& {
      return prepared.state_candidates.empty() ? candidates : prepared.state_candidates[s];
    };
    const auto same_candidates = [&](size_t a, size_t b) {
      const std::vector<Candidate>& x = candidates_of(a);
      const std::vector<Candidate>& y = candidates_of(b);
      return &x == &y ||
             std::equal(x.begin(), x.end(), y.begin(), y.end(),
                        [](const Candidate& p, const Candidate& q) {
                          return p.world_from_body.position == q.world_from_body.position &&
                                 p.world_from_body.rotation.coeffs() ==
                                     q.world_from_body.rotation.coeffs();
                        });
    };
    for (size_t j = 0; j < i && state.same_as < 0; ++j) {
      if (SameGeometry(state_scenes[j], state_scenes[i]) && same_candidates(j, i))
        state.same_as = static_cast<int>(j);
    }
    if (i == 0) {
      state.reference = reference;
      state.observations = observations;
    } else if (state.same_as >= 0) {  // unchanged geometry: no ray is traced twice
      const ObservedState& same = result.states[static_cast<size_t>(state.same_as)];
      state.reference = same.reference;
      state.observations = same.observations;
    } else {
      const auto state_start = std::chrono::steady_clock::now();
      try {
        state.reference =
            detail::BuildRunReference(state_scenes[i], reference_options, problem.source);
      } catch (const InputError& e) {
        throw InputError(AtPlace(problem.source, problem.states[i].line,
                                 fmt::format("state '{}': {}", state.name, e.what())));
      }
      state.observations =
          trace_all(RayScene(state_scenes[i]), state.reference, candidates_of(i));
      result.timings.observe += detail::SecondsSince(state_start);
    }
    spdlog::info("state '{}': {} reference voxels{}", state.name, state.reference.size(),
                 state.same_as >= 0
                     ? fmt::format(", same geometry as '{}' (not traced again)",
                                   result.states[static_cast<size_t>(state.same_as)].name)
                     : std::string());
    result.states.push_back(std::move(state));
  }

  VisibilityFile& data = result.data;
  data.scene = problem.source;
  data.scene_path = detail::AbsoluteText(problem.source);
  data.load = detail::AbsoluteFolders(prepared.load);
  data.seed = problem.seed;
  data.selection = problem.selection;
  data.reference = std::move(reference);
  data.candidates = std::move(prepared.candidates);
  data.observations = std::move(observations);
  data.quality = observe.quality;
  data.physical = *observe.physical;
  data.mounting = problem.mounting;
  data.kept_out = prepared.kept_out.size();
  result.notes = std::move(prepared.notes);
  result.notes.insert(result.notes.end(), problem.notes.begin(), problem.notes.end());
  result.scene = std::move(problem.scene);
  result.state_scenes = std::move(prepared.state_scenes);
  result.populations = std::move(problem.populations);
  result.arms = std::move(prepared.arms);
  result.observation_point = problem.observation_point;
  result.sensors = std::move(problem.sensors);
  return result;
}

ObserveRunResult ObserveRun(const ObserveRunOptions& options) {
  options.observe.Validate();  // option errors before any work
  options.limits.Validate();
  PreparedScene prepared = Prepare(options.scene);
  // The selection stored with the matrix is checked before any ray is cast, as optimize checks
  // it: -n names the option, the scene's own n (or any other setting) its line.
  SelectionRequest request;
  request.n = options.n;
  ResolveSelection(prepared.problem.selection, request, prepared.problem.seed,
                   prepared.candidates, prepared.problem.source, Method::kAll);
  if (options.n) prepared.problem.selection.n = *options.n;
  ObservedScene observed =
      ObservePrepared(std::move(prepared), options.observe, options.limits, options.trace);
  ObserveRunResult result;
  for (const ObservedState& state : observed.states) result.state_names.push_back(state.name);
  if (!result.state_names.empty())
    spdlog::warn(
        "{}: the visibility file holds the first state '{}' only; `vantage optimize` selects "
        "over all {} states",
        observed.data.scene, result.state_names.front(), result.state_names.size());
  result.data = std::move(observed.data);
  result.timings = observed.timings;
  return result;
}

}  // namespace vantage
