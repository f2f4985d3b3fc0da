// The selection of a run: the request over the scene's settings, validated once, the problem
// blamed on the option that was given; then selection plain or over the scene's states.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <utility>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"

namespace vantage {

SelectOptions ResolveSelection(const SelectionSettings& settings, const SelectionRequest& request,
                               uint64_t seed, std::span<const Candidate> candidates,
                               const std::string& source, Method default_method) {
  SelectOptions options;
  options.n = request.n.value_or(settings.n);
  options.method = request.method.value_or(settings.method.value_or(default_method));
  options.ransac_iterations = request.ransac_iterations.value_or(settings.ransac_iterations);
  options.ransac_stop_coverage =
      request.ransac_stop_coverage.value_or(settings.ransac_stop_coverage);
  options.seed = seed;
  options.time_limit = request.time_limit.value_or(options.time_limit);
  // An objective in the request replaces the scene's (so --k 2 over a scene's goal works).
  const bool requested_objective = request.goal || request.k || request.budget;
  options.goal = requested_objective ? request.goal : settings.goal;
  options.k = requested_objective ? request.k.value_or(1) : settings.k;
  options.budget = requested_objective ? request.budget : settings.budget;
  if (options.budget) {
    options.costs.reserve(candidates.size());
    for (const Candidate& c : candidates) options.costs.push_back(c.sensor.cost);
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
    const std::array<std::pair<const char*, bool>, 9> given = {{
        {"n", request.n.has_value()},
        {"k", request.k.has_value()},
        {"goal", request.goal.has_value()},
        {"budget", request.budget.has_value()},
        {"ransac_iterations", request.ransac_iterations.has_value()},
        {"ransac_stop_coverage", request.ransac_stop_coverage.has_value()},
        {"time_limit", request.time_limit.has_value()},
        {"method", request.method.has_value()},
        {"fixed", request.keep_existing},
    }};
    static constexpr std::array<const char*, 9> kFlags = {
        "-n",         "--k",          "--goal",   "--budget",         "--iterations",
        "--stop",     "--time-limit", "--method", "--keep-existing"};
    for (size_t i = 0; i < given.size(); ++i) {
      const bool is_at_fault = std::find(e.fields().begin(), e.fields().end(), given[i].first) !=
                               e.fields().end();
      if (is_at_fault && given[i].second) throw InputError(AtPlace(kFlags[i], 0, e.what()));
    }
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

namespace detail {

void SelectResults(const ObservedScene& observed, const SelectionRequest& request,
                   const SelectOptions& given, Report* report) {
  SelectOptions options = given;
  if (report->constraints) options.constraints = report->constraints->constraints;
  if (observed.states.empty()) {
    report->results =
        Select(observed.data.observations, observed.data.reference.size(), options);
    report->curve = CoverageCurve(observed.data.observations, observed.data.reference.size(),
                                  options, report->results);
    return;
  }
  const OverStates over = request.over_states.value_or(OverStates::kMean);
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

}  // namespace detail
}  // namespace vantage
