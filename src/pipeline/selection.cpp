// The selection of a run: the request over the scene's settings, validated once, the problem
// blamed on the option that was given; then selection plain or over the scene's states.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <utility>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// The request's options in the order a FieldError blames them: by the field a message is most
// about (a cost asked without a goal before the goal, k before n's other faults...), then any
// option whose field is not listed, in the table's order.
std::vector<const SelectionOption*> OptionsInBlameOrder() {
  static constexpr std::array<std::string_view, 11> kFieldOrder = {
      "minimize_cost", "min_points",           "n",          "k",      "goal", "budget",
      "ransac_iterations", "ransac_stop_coverage", "time_limit", "method", "fixed"};
  std::vector<const SelectionOption*> ordered;
  for (const std::string_view field : kFieldOrder)
    for (const SelectionOption& option : SelectionOptionTable())
      if (option.field == field) ordered.push_back(&option);
  for (const SelectionOption& option : SelectionOptionTable())
    if (std::find(kFieldOrder.begin(), kFieldOrder.end(), option.field) == kFieldOrder.end())
      ordered.push_back(&option);
  return ordered;
}

}  // namespace

SelectOptions ResolveSelection(const SelectionSettings& settings, const SelectionRequest& request,
                               uint64_t seed, std::span<const Candidate> candidates,
                               const std::string& source, Method default_method,
                               double cell_size) {
  // The request over the scene's settings, each option copied into its field by its row.
  const SelectionRequest given = RequestOverScene(request, settings);
  // The parts partition R: their cells counted together are R's, and their sum its coverage.
  if (request.over_parts == OverStates::kSum)
    throw InputError(AtPlace("--over-parts", 0,
                             "sum counts every part's cells together, which is the coverage of "
                             "all cells (the default objective) — drop --over-parts, or give "
                             "mean or min"));
  SelectOptions options;
  options.method = default_method;
  options.seed = seed;
  for (const SelectionOption& option : SelectionOptionTable()) option.ApplyTo(given, &options);
  if (options.goal && !request.goal) {
    const auto line = settings.lines.find("goal");
    options.goal_source = line == settings.lines.end() || line->second <= 0
                              ? source
                              : fmt::format("{}:{}", source, line->second);
  }
  options.min_points =
      detail::ResolveMinPoints(request.min_points, request.min_density, cell_size);
  if (options.budget || options.minimize_cost) {
    options.costs.reserve(candidates.size());
    for (const Candidate& c : candidates) {
      // A catalog entry whose vendor publishes no price carries none (issue 43): a budget
      // cannot count it as free.
      if (!UnitCostGiven(c.sensor, c.type_id)) {
        // The type as the scene names it: a custom type keeps its own id (its candidates carry
        // the catalog id its intrinsics match, e.g. the Azure Kinect's for a Femto Bolt).
        const bool custom = !c.sensor.id.empty() && c.sensor.id != c.type_id;
        const std::string& type = custom ? c.sensor.id : c.type_id;
        throw InputError(AtPlace(
            options.minimize_cost ? "--cheapest" : "--budget", 0,
            custom ? fmt::format("sensor type '{}' has no unit cost (its base publishes none) — "
                                 "give it one in the scene: `cost: ...` in its sensor_types entry",
                                 type)
                   : fmt::format("sensor type '{}' has no unit cost (its vendor publishes none) "
                                 "— give one in the scene: sensor_types: [{{id: my_{}, base: {}, "
                                 "cost: ...}}]",
                                 type, type, type)));
      }
      options.costs.push_back(c.sensor.cost);
    }
  }
  if (request.keep_existing) {
    for (uint32_t i = 0; i < candidates.size(); ++i)
      if (candidates[i].population.empty()) options.fixed.push_back(i);
    if (options.fixed.empty())
      throw InputError(AtPlace("--keep-existing", 0,
                               fmt::format("{} declares no sensors of its own to keep (only "
                                           "populations) — drop --keep-existing",
                                           source)));
  }
  try {
    options.Validate(candidates.size());
  } catch (const FieldError& e) {
    // The first field at fault that the request gave names its flag; else the scene's own.
    const auto is_at_fault = [&](std::string_view field) {
      return std::find(e.fields().begin(), e.fields().end(), field) != e.fields().end();
    };
    for (const SelectionOption* option : OptionsInBlameOrder())
      if (is_at_fault(option->field) && option->GivenIn(request))
        throw InputError(AtPlace(std::string(option->flag), 0, e.what()));
    // Else the scene's line of the first field at fault that the scene gives.
    for (const std::string& field : e.fields()) {
      if (const auto line = settings.lines.find(field); line != settings.lines.end())
        throw InputError(AtPlace(source, line->second, e.what()));
    }
    throw InputError(AtPlace(source, 0, e.what()));
  } catch (const InputError& e) {
    throw InputError(AtPlace(source, 0, e.what()));
  }
  return options;
}

uint32_t MinPointsOfDensity(double per_cm2, double cell_size) {
  const double face_cm2 = std::pow(100.0 * cell_size, 2);
  // The tolerance keeps an exact product (2 per cm² on a 1 cm² face) from rounding up.
  return static_cast<uint32_t>(std::max(1.0, std::ceil(per_cm2 * face_cm2 - 1e-9)));
}

namespace detail {

std::optional<uint32_t> ResolveMinPoints(std::optional<int64_t> min_points,
                                         std::optional<double> min_density, double cell_size,
                                         const std::string& origin) {
  // The flag, or the key of the file the values came from (issue 44: an edited report.json's
  // value was blamed on the flag the user never typed).
  const auto where = [&](const char* flag, const char* key) {
    return origin.empty() ? std::string(flag) : fmt::format("{}: inputs.{}", origin, key);
  };
  if (min_points && min_density)
    throw InputError(AtPlace(where("--min-density", "min_density"), 0,
                             origin.empty()
                                 ? "give --min-points (per cell) or --min-density (per cm²), not both"
                                 : "min_points and min_density are both set — keep one"));
  if (min_points) {
    if (*min_points < 1 || *min_points > kMaxMinPoints)
      throw InputError(AtPlace(where("--min-points", "min_points"), 0,
                               fmt::format("{} is not a number of points in 1..{} (a sensor's "
                                           "count per cell saturates there)",
                                           *min_points, kMaxMinPoints)));
    return static_cast<uint32_t>(*min_points);
  }
  if (!min_density) return std::nullopt;
  const double d = *min_density;
  VANTAGE_CHECK(cell_size > 0);
  const double face_cm2 = std::pow(100.0 * cell_size, 2);
  if (!(d > 0) || !std::isfinite(d) || d * face_cm2 > static_cast<double>(kMaxMinPoints))
    throw InputError(AtPlace(
        where("--min-density", "min_density"), 0,
        fmt::format("{} points per cm² is not a positive density of at most {} points on a {:g} "
                    "cm² cell face",
                    d, kMaxMinPoints, face_cm2)));
  return MinPointsOfDensity(d, cell_size);
}

void CheckSelectionTime(std::span<const Observation> observations, const SelectOptions& options,
                        size_t state_count, double limit_seconds, const std::string& source) {
  if (options.method != Method::kRansac && options.method != Method::kAll) return;
  if (observations.empty()) return;
  double cells = 0;  // the mean visibility list: what scoring one drawn sensor reads
  for (const Observation& o : observations) cells += static_cast<double>(o.reference_indices.size());
  cells /= static_cast<double>(observations.size());
  // --method all runs RANSAC for every n up to the one asked. RANSAC stops once it has drawn
  // every subset (tracked up to 100 000 of them): a coupon collector's C (ln C + 1) draws on
  // average, taken here with a margin. Per drawn sensor and iteration: its list at about 1 ns a
  // cell plus the draw, 2.6 times what 20 million iterations over 406 candidates took, so that
  // the estimate errs on the long side as the ray casting estimate does.
  const double m = static_cast<double>(observations.size());
  double seconds = 0;
  for (int n = options.method == Method::kAll ? 1 : options.n; n <= options.n; ++n) {
    const double subsets = std::exp(std::lgamma(m + 1) - std::lgamma(n + 1.0) - std::lgamma(m - n + 1));
    double iterations = options.ransac_iterations;
    if (subsets <= 1e5) iterations = std::min(iterations, subsets * (std::log(subsets) + 10));
    seconds += iterations * n * (cells + 32.0) * 1e-9;
  }
  seconds *= static_cast<double>(std::max<size_t>(1, state_count));
  if (seconds >= 1)  // below, not worth a line
    spdlog::info("time estimate: RANSAC's {} iterations of n = {} take at most about {:.3g} s",
                 options.ransac_iterations, options.n, seconds);
  if (limit_seconds > 0 && seconds > limit_seconds)
    throw InputError(AtPlace(
        "--iterations", 0,
        fmt::format("RANSAC's {} iterations of n = {} over {} candidates are estimated at about "
                    "{:.3g} s, above the --max-seconds limit of {:g} s (from {}) — lower "
                    "--iterations, or raise --max-seconds",
                    options.ransac_iterations, options.n, observations.size(), seconds,
                    limit_seconds, source)));
}

std::vector<Selection> SelectExplained(std::span<const Observation> observations,
                                       const Reference& reference, const SelectOptions& options) {
  try {
    return Select(observations, reference.size(), options);
  } catch (const InputError& e) {
    // A goal above what all candidates reach: say how much of R no viewpoint can see at all
    // (issue 46: the parts' undersides on the tote floor were never mentioned).
    const std::string message = e.what();
    if (!options.goal || message.find("reach together") == std::string::npos ||
        reference.exposed.size() != reference.size() || reference.exposed_only)
      throw;
    const auto unexposed = static_cast<double>(
        std::count(reference.exposed.begin(), reference.exposed.end(), uint8_t{0}));
    const double share = unexposed / static_cast<double>(reference.size());
    throw InputError(fmt::format(
        "{} ({:.2f} % of R is unexposed — resting on or enclosed by other geometry, no camera "
        "sees it — so no layout exceeds {:.2f} %; --exposed-only counts only exposed surface)",
        message, 100.0 * share, 100.0 * (1.0 - share)));
  }
}

namespace {

// The target parts as the groups that selection over states aggregates (--over-parts): part p's
// cells of R, renumbered in key order, are group p's R, and each candidate's observations
// (points included) are restricted to them. A part without cells in R (--exposed-only can leave
// one none) is no group. Keys outside R belong to no part: a group's paper coverage is its
// coverage. A scene with states adds every state's parts ("state/part"): one aggregation over
// every (state, part) group.
struct PartGroups {
  std::vector<std::vector<Observation>> observations;  // per group, per candidate
  std::vector<std::string> names;
  std::vector<size_t> sizes;              // cells of each group's R
  std::vector<StateObservations> groups;  // views of the above, made once all are added
};

void AddPartGroups(const Reference& reference, std::span<const Observation> observations,
                   const std::string& prefix, PartGroups* parts) {
  if (reference.part_of.size() != reference.size())
    throw InputError(AtPlace("--over-parts", 0,
                             "the visibility matrix records no target part per cell (a .vis file "
                             "before format 6, or a matrix from elsewhere) — observe the scene "
                             "again, or drop --over-parts"));
  std::vector<uint32_t> index_in_part(reference.size());
  std::vector<size_t> part_size(reference.part_names.size(), 0);
  for (size_t cell = 0; cell < reference.size(); ++cell)
    index_in_part[cell] = static_cast<uint32_t>(part_size[reference.part_of[cell]]++);
  std::vector<std::vector<Observation>> by_part(part_size.size(),
                                                std::vector<Observation>(observations.size()));
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& seen = observations[i];
    for (size_t j = 0; j < seen.reference_indices.size(); ++j) {
      const uint32_t cell = seen.reference_indices[j];
      Observation& part = by_part[reference.part_of[cell]][i];
      part.reference_indices.push_back(index_in_part[cell]);
      if (seen.has_point_counts()) part.reference_hits.push_back(seen.reference_hits[j]);
    }
  }
  for (size_t p = 0; p < part_size.size(); ++p) {
    if (part_size[p] == 0) continue;
    parts->observations.push_back(std::move(by_part[p]));
    parts->names.push_back(prefix + reference.part_names[p]);
    parts->sizes.push_back(part_size[p]);
  }
}

void MakeGroupViews(PartGroups* parts) {
  for (size_t g = 0; g < parts->observations.size(); ++g)
    parts->groups.push_back({parts->names[g], parts->sizes[g], parts->observations[g]});
}

}  // namespace

void RefuseGroupObjectiveBeside(const SelectionRequest& request, const char* conflict) {
  if (conflict == nullptr) return;
  for (const SelectionOption& option : SelectionOptionTable()) {
    if (!option.aggregates_groups || !option.GivenIn(request)) continue;
    throw InputError(AtPlace(std::string(option.flag), 0,
                             fmt::format("counts an aggregate of groups of cells, which {} does "
                                         "not — drop one of {} and {}",
                                         conflict, option.flag, conflict)));
  }
}

void SelectOnMatrix(const VisibilityFile& data, const SelectionRequest& request,
                    const SelectOptions& options, Report* report) {
  if (!request.over_parts) {
    report->results = SelectExplained(data.observations, data.reference, options);
    report->curve =
        CoverageCurve(data.observations, data.reference.size(), options, report->results);
    return;
  }
  // Each part's coverage is in the report's parts table; `coverage` is their mean or minimum.
  // No curve: it would count all cells together.
  PartGroups parts;
  AddPartGroups(data.reference, data.observations, "", &parts);
  MakeGroupViews(&parts);
  SelectOptions over_parts = options;
  over_parts.groups = "target parts";
  // The calibration graph joins sensors by their common cells of all of R, not of one part.
  for (StateSelection& result :
       SelectOverStates(parts.groups, *request.over_parts, over_parts, data.observations))
    report->results.push_back(std::move(result.selection));
}

void SelectResults(const ObservedScene& observed, const SelectionRequest& request,
                   const SelectOptions& given, Report* report) {
  SelectOptions options = given;
  if (report->constraints) options.constraints = report->constraints->constraints;
  if (observed.states.empty()) {
    SelectOnMatrix(observed.data, request, options, report);
    return;
  }
  if (request.over_parts) options.groups = "states' target parts";
  // With --over-parts the states take its aggregation (optimize refuses two different ones).
  const OverStates over =
      request.over_states.value_or(request.over_parts.value_or(OverStates::kMean));
  std::vector<StateObservations> states;
  for (const ObservedState& state : observed.states)
    states.push_back({state.name, state.reference.size(), state.observations});
  // --over-parts: one aggregation over every state's parts; each result still lists each
  // state's own coverage.
  PartGroups parts;
  if (request.over_parts) {
    for (const ObservedState& state : observed.states)
      AddPartGroups(state.reference, state.observations, state.name + "/", &parts);
    MakeGroupViews(&parts);
  }
  const std::span<const StateObservations> groups =
      request.over_parts ? std::span<const StateObservations>(parts.groups) : states;
  // The calibration graph is the first state's, over all its cells (not its first part's).
  for (StateSelection& result :
       SelectOverStates(groups, over, options, observed.states.front().observations)) {
    if (request.over_parts) {
      result.state_coverage = ScoreChosenOverStates(states, over, result.selection.chosen, "",
                                                    options)
                                  .state_coverage;
    }
    result.selection.state_coverage = std::move(result.state_coverage);
    report->results.push_back(std::move(result.selection));
  }
  StatesInfo info;
  info.over = OverStatesName(over);
  for (const ObservedState& state : observed.states)
    info.states.push_back({state.name, state.reference.size(), state.same_as});
  report->states = std::move(info);
}

}  // namespace detail
}  // namespace vantage
