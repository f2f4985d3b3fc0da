// The installation constraints of a run (docs/constraints.md): the request checked against the
// selection it would constrain, then turned into pairs and a calibration rule over the observed
// candidates.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"

namespace vantage {

void ConstraintOptions::Validate() const {
  if (interference_overlap && !(*interference_overlap >= 0.0 && *interference_overlap <= 1.0))
    throw InputError(AtPlace("--interference-overlap", 0,
                             fmt::format("{} must be a fraction in [0, 1] (default 0.1)",
                                         *interference_overlap)));
  if (interference_overlap && interference == false)
    throw InputError(AtPlace("--interference-overlap", 0,
                             "has no effect with --interference false — drop one of them"));
  if (calibration_overlap && calibration_overlap_frac)
    throw InputError(AtPlace("--calibration-overlap-frac", 0,
                             "give one of --calibration-overlap (cells) and "
                             "--calibration-overlap-frac (share of the smaller set)"));
  if (calibration_overlap && *calibration_overlap < 1)
    throw InputError(AtPlace("--calibration-overlap", 0,
                             "must be at least 1 common cell — e.g. --calibration-overlap 20"));
  if (calibration_overlap_frac &&
      !(*calibration_overlap_frac > 0.0 && *calibration_overlap_frac <= 1.0))
    throw InputError(AtPlace("--calibration-overlap-frac", 0,
                             fmt::format("{} must be a fraction in (0, 1], e.g. 0.05",
                                         *calibration_overlap_frac)));
}

namespace detail {
namespace {

// Why constraints cannot apply to this selection; empty when they can.
std::string Unsupported(const SelectOptions& options, bool has_states, bool refine) {
  if (options.objective() != Objective::kCoverage)
    return fmt::format("works with the coverage objective only, not {} — drop it or the "
                       "objective",
                       ObjectiveName(options.objective()));
  if (!options.fixed.empty()) return "does not combine with --keep-existing yet — drop one";
  if (has_states) return "does not work over scene states yet — drop it or the scene's states";
  if (refine) return "does not combine with --refine yet — drop one of them";
  return {};
}

bool HasCalibration(const ConstraintOptions& c) {
  return c.calibration_overlap.has_value() || c.calibration_overlap_frac.has_value();
}

}  // namespace

void CheckConstraintRequest(const ConstraintOptions& request, const SelectOptions& options,
                            bool has_states, bool refine) {
  request.Validate();
  const std::string why = Unsupported(options, has_states, refine);
  if (why.empty()) return;
  if (request.interference == true)
    throw InputError(AtPlace("--interference", 0, why));
  if (request.interference_overlap) throw InputError(AtPlace("--interference-overlap", 0, why));
  if (request.calibration_overlap) throw InputError(AtPlace("--calibration-overlap", 0, why));
  if (request.calibration_overlap_frac)
    throw InputError(AtPlace("--calibration-overlap-frac", 0, why));
}

std::vector<bool> ProjectingCandidates(std::span<const Candidate> candidates) {
  std::vector<bool> projecting;
  projecting.reserve(candidates.size());
  for (const Candidate& c : candidates) projecting.push_back(ProjectsLight(c.sensor, c.type_id));
  return projecting;
}

std::optional<ConstraintsInfo> ResolveConstraints(const ConstraintOptions& request,
                                                  const SelectOptions& options,
                                                  std::span<const Candidate> candidates,
                                                  std::span<const Observation> observations,
                                                  bool has_states, bool refine) {
  if (!Unsupported(options, has_states, refine).empty()) return std::nullopt;
  ConstraintsInfo info;
  const std::vector<bool> projecting = ProjectingCandidates(candidates);
  for (const bool p : projecting) info.projecting += p ? 1 : 0;
  // Off unless asked (--interference true, or an --interference-overlap): the default-on the issue
  // asks for waits until the Python module applies constraints too.
  const bool interference =
      request.interference.value_or(request.interference_overlap.has_value()) &&
      info.projecting >= 2;
  if (interference) {
    info.interference_overlap = request.Overlap();
    info.constraints.conflicts =
        InterferenceConflicts(observations, projecting, request.Overlap());
    spdlog::info("constraints: {} of {} candidates project light, {} interfering pairs (shared "
                 "share > {})",
                 info.projecting, candidates.size(), info.constraints.conflicts.size(),
                 request.Overlap());
  }
  if (HasCalibration(request)) {
    CalibrationRule rule;
    rule.min_cells = request.calibration_overlap;
    rule.min_fraction = request.calibration_overlap_frac;
    info.constraints.calibration = rule;
  }
  if (!info.interference_overlap && !info.constraints.calibration) return std::nullopt;
  return info;
}

void DropInfeasibleAlternatives(const ConstraintsInfo& info, const VisibilityFile& data,
                                Robustness* robustness) {
  if (!info.is_applied) return;
  std::erase_if(robustness->alternatives, [&](const Alternative& a) {
    const ConstraintCheck check = CheckConstraints(data.observations, a.chosen, info.constraints);
    return !check.conflicts.empty() || (info.constraints.calibration && !check.connected());
  });
}

}  // namespace detail
}  // namespace vantage
