// The installation constraints of a run (docs/constraints.md): the request checked against the
// selection it would constrain, then turned into pairs and a calibration rule over the observed
// candidates.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>

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

// Kept sensors (--keep-existing) must satisfy the constraints among themselves: the others are
// then chosen to keep them satisfied (docs/constraints.md, Kept sensors).
void CheckKeptSensors(const ConstraintsInfo& info,
                      const SelectOptions& options,
                      std::span<const Candidate> candidates,
                      std::span<const Observation> observations) {
  const std::vector<uint32_t>& kept = options.fixed;
  if (kept.empty()) return;
  const ConstraintCheck check = CheckConstraints(observations, kept, info.constraints);
  if (!check.conflicts.empty()) {
    std::string pairs;
    for (const Conflict& c : check.conflicts) {
      pairs += fmt::format("{}'{}' and '{}' ({}{})", pairs.empty() ? "" : ", ",
                           candidates[c.a].name, candidates[c.b].name, ConflictKindName(c.kind),
                           c.kind == ConflictKind::kSeparation
                               ? fmt::format(", {:.3f} m apart", c.value)
                               : fmt::format(", {:.0f} % shared", 100.0 * c.value));
    }
    throw InputError(AtPlace("--keep-existing", 0,
                             fmt::format("the kept sensors conflict: {} — move one of them, or "
                                         "drop the constraint or --keep-existing",
                                         pairs)));
  }
  if (info.constraints.calibration && !check.connected()) {
    // Parts are joined by a chain of other candidates, which every answer then holds.
    std::string parts;
    for (const std::vector<uint32_t>& part : check.components) {
      std::string names;
      for (const uint32_t i : part) names += (names.empty() ? "" : ", ") + candidates[i].name;
      parts += fmt::format("{}[{}]", parts.empty() ? "" : " ", names);
    }
    const std::vector<uint32_t> joined = ConnectKept(observations, kept, info.constraints);
    if (joined.empty())
      throw InputError(AtPlace("--keep-existing", 0,
                               fmt::format("the kept sensors are not connected by the calibration "
                                           "rule ({} parts: {}), and no chain of candidates joins "
                                           "them — lower the calibration overlap, add candidates "
                                           "between them, or drop --keep-existing",
                                           check.components.size(), parts)));
    std::string chain;
    double chain_cost = 0;
    for (size_t p = 0; p < joined.size(); ++p) {
      if (!options.costs.empty()) chain_cost += options.costs[joined[p]];
      if (p >= kept.size()) chain += (chain.empty() ? "" : ", ") + candidates[joined[p]].name;
    }
    const size_t more = joined.size() - kept.size();
    const std::string what = fmt::format("joining the kept sensors' {} parts ({}) takes {} more "
                                         "sensor{} ({})",
                                         check.components.size(), parts, more,
                                         more == 1 ? "" : "s", chain);
    const Objective objective = options.objective();
    if (options.budget && chain_cost > *options.budget)
      throw InputError(AtPlace("--budget", 0,
                               fmt::format("{}: together they cost {:g}, over the budget {:g}",
                                           what, chain_cost, *options.budget)));
    if (options.method == Method::kBest && more > 1)
      throw InputError(AtPlace("--method", 0,
                               what + "; best adds one — use another method"));
    if (!options.budget && objective != Objective::kSetCover &&
        static_cast<size_t>(options.n) < joined.size())
      throw InputError(AtPlace("-n", 0, fmt::format("{} — give -n {} or more", what,
                                                    joined.size())));
    spdlog::info("constraints: {}; every answer holds them", what);
  }
}

// Interference over the states of a scene: a pair conflicts when it does in any state (both
// projectors are on in every state), with the largest shared share.
std::vector<Conflict> InterferenceOverStates(std::span<const Observation> first,
                                             std::span<const ObservedState> states,
                                             const std::vector<bool>& projecting,
                                             double max_overlap) {
  // Each scan stops past kMaxConflictPairs (the caller refuses that many); so does the union.
  std::vector<Conflict> all =
      InterferenceConflicts(first, projecting, max_overlap, kMaxConflictPairs);
  for (size_t s = 1; s < states.size() && all.size() <= kMaxConflictPairs; ++s) {
    if (states[s].same_as >= 0) continue;  // the observations of an earlier state
    std::vector<Conflict> more =
        InterferenceConflicts(states[s].observations, projecting, max_overlap, kMaxConflictPairs);
    all.insert(all.end(), more.begin(), more.end());
  }
  std::sort(all.begin(), all.end(), [](const Conflict& x, const Conflict& y) {
    return std::tie(x.a, x.b, y.value) < std::tie(y.a, y.b, x.value);  // largest share first
  });
  all.erase(
      std::unique(all.begin(), all.end(),
                  [](const Conflict& x, const Conflict& y) { return x.a == y.a && x.b == y.b; }),
      all.end());
  return all;
}

bool HasCalibration(const ConstraintOptions& c) {
  return c.calibration_overlap.has_value() || c.calibration_overlap_frac.has_value();
}

}  // namespace

std::vector<Conflict> SeparationConflicts(std::span<const Candidate> candidates,
                                          double min_separation, size_t max_pairs) {
  // Hashing the centres into cubes of edge min_separation: a closer pair lies in neighbouring
  // cubes, so only those are compared.
  using Key = std::array<int64_t, 3>;
  const auto key_of = [&](const Vec3& p) {
    return Key{static_cast<int64_t>(std::floor(p.x() / min_separation)),
               static_cast<int64_t>(std::floor(p.y() / min_separation)),
               static_cast<int64_t>(std::floor(p.z() / min_separation))};
  };
  std::map<Key, std::vector<uint32_t>> cubes;
  for (size_t i = 0; i < candidates.size(); ++i)
    cubes[key_of(candidates[i].world_from_body.position)].push_back(static_cast<uint32_t>(i));
  std::vector<Conflict> conflicts;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Vec3& p = candidates[i].world_from_body.position;
    const Key k = key_of(p);
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const auto cube = cubes.find(Key{k[0] + dx, k[1] + dy, k[2] + dz});
          if (cube == cubes.end()) continue;
          for (const uint32_t j : cube->second) {
            if (j <= i) continue;
            const double distance = (candidates[j].world_from_body.position - p).norm();
            if (distance < min_separation) {
              conflicts.push_back({static_cast<uint32_t>(i), j, ConflictKind::kSeparation,
                                   distance});
              if (conflicts.size() > max_pairs) return conflicts;
            }
          }
        }
      }
    }
  }
  std::sort(conflicts.begin(), conflicts.end(), [](const Conflict& x, const Conflict& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  });
  return conflicts;
}

void CheckSeparationPairs(std::span<const Candidate> candidates, const MountingRules& mounting) {
  if (!mounting.min_separation) return;
  const size_t pairs = SeparationConflicts(candidates, *mounting.min_separation).size();
  if (pairs <= kMaxConflictPairs) return;
  throw InputError(AtPlace(
      mounting.min_separation_file, mounting.min_separation_line,
      fmt::format("min_separation {} m puts more than {} pairs of the {} candidates in conflict "
                  "(most candidates lie closer than it) — lower it, or thin the populations",
                  *mounting.min_separation, kMaxConflictPairs, candidates.size())));
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
                                                  const MountingRules& mounting,
                                                  size_t kept_out,
                                                  std::span<const ObservedState> states) {
  request.Validate();
  ConstraintsInfo info;
  const std::vector<bool> projecting = ProjectingCandidates(candidates);
  for (const bool p : projecting) info.projecting += p ? 1 : 0;
  // Off unless asked (--interference true, or an --interference-overlap): docs/constraints.md says
  // why it is not on by default.
  const bool interference =
      request.interference.value_or(request.interference_overlap.has_value()) &&
      info.projecting >= 2;
  if (interference) {
    info.interference_overlap = request.Overlap();
    info.constraints.conflicts =
        InterferenceOverStates(observations, states, projecting, request.Overlap());
    // As many pairs as most of a large projecting population: refused before selection instead
    // of filling the memory (12 M pairs of 6,000 candidates took 1 GB).
    if (info.constraints.conflicts.size() > kMaxConflictPairs)
      throw InputError(AtPlace(
          request.interference_overlap ? "--interference-overlap" : "--interference", 0,
          fmt::format("more than {} pairs of the {} projecting candidates light up more than {} "
                      "of each other's cells — raise --interference-overlap, or thin the "
                      "populations",
                      kMaxConflictPairs, info.projecting, request.Overlap())));
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
  if (mounting.min_separation) {
    info.min_separation = mounting.min_separation;
    std::vector<Conflict> pairs = SeparationConflicts(candidates, *mounting.min_separation);
    spdlog::info("constraints: {} pairs of candidates closer than min_separation {} m",
                 pairs.size(), *mounting.min_separation);
    MergeConflicts(std::move(pairs), &info.constraints.conflicts);
  }
  info.keep_out_boxes = mounting.keep_out;
  info.keep_out_excluded = kept_out;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (InKeepOut(mounting.keep_out, candidates[i].world_from_body.position))
      info.keep_out_violations.push_back(static_cast<uint32_t>(i));
  }
  if (!info.interference_overlap && !info.constraints.calibration && !info.min_separation &&
      info.keep_out_boxes.empty())
    return std::nullopt;
  CheckKeptSensors(info, options, candidates, observations);
  return info;
}

InstallConstraints ConstraintsOverGrown(const ConstraintsInfo& info,
                                        std::span<const Candidate> candidates,
                                        std::span<const Observation> observations) {
  InstallConstraints grown;
  grown.calibration = info.constraints.calibration;
  if (info.interference_overlap) {
    grown.conflicts = InterferenceConflicts(observations, ProjectingCandidates(candidates),
                                            *info.interference_overlap, kMaxConflictPairs);
  }
  if (info.min_separation)
    MergeConflicts(SeparationConflicts(candidates, *info.min_separation), &grown.conflicts);
  if (grown.conflicts.size() > kMaxConflictPairs)
    throw InputError(AtPlace("--refine", 0,
                             fmt::format("more than {} conflicting pairs among the {} candidates "
                                         "and new poses — lower --refine-rounds or relax the "
                                         "constraints",
                                         kMaxConflictPairs, candidates.size())));
  return grown;
}

void AddRobustness(const VisibilityFile& data, const SelectOptions& select,
                   RobustnessOptions robustness, const RayScene* rays,
                   const ObserveOptions& observe, Report* report) {
  robustness.kept = select.fixed;   // installed sensors get no alternative
  robustness.costs = select.costs;  // a budget kept, --cheapest ranked by cost
  report->robustness =
      AssessRobustness(data, report->results, report->primary, rays, observe, robustness);
  if (!report->constraints || !report->constraints->is_applied) return;
  const InstallConstraints& rules = report->constraints->constraints;
  std::erase_if(report->robustness->alternatives, [&](const Alternative& a) {
    const ConstraintCheck check = CheckConstraints(data.observations, a.chosen, rules);
    return !check.conflicts.empty() || (rules.calibration && !check.connected());
  });
}

}  // namespace detail
}  // namespace vantage
