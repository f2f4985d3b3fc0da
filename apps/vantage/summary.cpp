// The human summary of a run on stdout (the library only logs): read from the derived report.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "commands.hpp"
#include "vantage/selection_options.hpp"

namespace vantage::cli {
namespace {

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
    if (std::any_of(results.begin(), results.end(),
                    [&](const Selection& s) { return s.method == m; }))
      methods.emplace_back(m);
  }
  const int k = results.front().k;
  fmt::print("coverage by n{}\n",
             k >= 2 ? fmt::format(" ({}-coverage, %)", k) : std::string(" (%)"));
  std::string header = fmt::format("{:>4}", "n");
  for (const std::string& m : methods) header += fmt::format(" {:>8}", m);
  fmt::print("{} {:>8}\n", header, "bound");
  for (const int n : ns) {
    std::string line = fmt::format("{:>4}", n);
    std::string bound = fmt::format("{:>8}", "-");
    for (const std::string& m : methods) {
      const auto it = std::find_if(results.begin(), results.end(),
                                   [&](const Selection& s) { return s.n == n && s.method == m; });
      line += it == results.end() ? fmt::format(" {:>8}", "-")
                                  : fmt::format(" {:8.2f}", 100.0 * it->coverage);
      if (it != results.end() && it->upper_bound)
        bound = fmt::format("{:8.2f}{}", 100.0 * *it->upper_bound, it->proven_optimal ? "*" : "");
    }
    fmt::print("{} {}\n", line, bound);
  }
  fmt::print("(* = proven optimal)\n");
}

// The robustness read-outs: the worst failure, the shrunk fields of view, the alternatives.
void PrintRobustness(const VisibilityFile& data,
                     const std::vector<Selection>& results,
                     const Robustness& robustness) {
  const Selection& result = results.at(static_cast<size_t>(robustness.result));
  const auto name = [&](uint32_t i) { return data.candidates.at(i).name; };
  std::vector<std::string> parts;
  // With one sensor its failure leaves nothing: the read-out says nothing (issue 16).
  if (robustness.worst && result.n >= 2) {
    parts.push_back(fmt::format("worst single failure {} -> {:.2f} % ({:+.2f})",
                                name(robustness.worst->sensor), 100.0 * robustness.worst->coverage,
                                100.0 * (robustness.worst->coverage - result.coverage)));
  }
  if (robustness.fov_shrunk_coverage) {
    parts.push_back(fmt::format("fields of view -{:g} deg -> {:.2f} % ({:+.2f})",
                                *robustness.fov_tolerance_deg,
                                100.0 * *robustness.fov_shrunk_coverage,
                                100.0 * (*robustness.fov_shrunk_coverage - result.coverage)));
  }
  if (!robustness.fov_note.empty()) parts.push_back(robustness.fov_note);
  if (!parts.empty())
    fmt::print("robustness       of {}: {}\n", ResultLabel(results, robustness.result),
               fmt::join(parts, "; "));
  if (robustness.fov_shrunk_coverage)
    fmt::print(
        "                 (a narrower field of view can also raise coverage: the same pixels, "
        "denser)\n");
  for (const Alternative& a : robustness.alternatives) {
    const std::string cost =
        a.cost && result.cost
            ? fmt::format(", cost {:g} ({:+g})", *a.cost, *a.cost - *result.cost)
            : std::string();
    fmt::print("alternative      {} instead of {}: {:.2f} % ({:+.2f}){}\n", name(a.replacement),
               name(a.replaced), 100.0 * a.coverage, 100.0 * (a.coverage - result.coverage),
               cost);
  }
  if (robustness.alternatives.empty())
    fmt::print("alternative      none within {:g} points by replacing one sensor{}\n",
               100.0 * robustness.alternatives_within,
               result.budget ? " within the budget" : "");
}

// What all candidates reach together, and the share of R no viewpoint can see: why a goal above
// the ceiling is out of reach.
void PrintCeiling(const Report& report) {
  const VisibilityFile& data = *report.data;
  const double r = static_cast<double>(data.reference.size());
  std::string unexposed;
  if (report.exposure_known && data.reference.exposed_only) {
    unexposed = fmt::format(
        "; R counts exposed surface only (--exposed-only: {} unexposed voxels left out)",
        report.unexposed);
  } else if (report.exposure_known) {
    unexposed = fmt::format(
        "; {:.2f} % of R is unexposed (resting on or enclosed by other geometry), so no layout "
        "exceeds {:.2f} %",
        r ? 100.0 * report.unexposed / r : 0.0, r ? 100.0 * (1.0 - report.unexposed / r) : 0.0);
  }
  fmt::print("ceiling          {:.2f} % with all {} candidates together{}\n", 100.0 * *report.ceiling,
             data.candidates.size(), unexposed);
}

std::string ConflictText(const Conflict& c, const VisibilityFile& data) {
  return fmt::format("{} ~ {} ({})", data.candidates.at(c.a).name, data.candidates.at(c.b).name,
                     c.kind == ConflictKind::kInterference
                         ? fmt::format("interference, {:.0f} % shared", 100.0 * c.value)
                         : fmt::format("separation, {:.3f} m", c.value));
}

}  // namespace

// Per target part: its voxels, unexposed share, ceiling and each shown result's coverage.
void PrintParts(const Report& report, const std::vector<size_t>& shown) {
  if (report.parts.size() < 2) return;
  const bool exposed_only = report.data->reference.exposed_only;
  constexpr size_t kRows = 12;
  size_t width = 4;
  for (size_t p = 0; p < std::min(kRows, report.parts.size()); ++p)
    width = std::max(width, std::min<size_t>(ShownOnOneLine(report.parts[p].name).size(), 24));
  std::string header = fmt::format("  {:<{}} {:>8}", "part", width, "voxels");
  if (report.exposure_known) header += fmt::format(" {:>9}", exposed_only ? "left out" : "unexposed");
  header += fmt::format(" {:>8}", "ceiling");
  for (const size_t index : shown) header += fmt::format(" {:>8}", report.results[index].method);
  fmt::print("by part (%)\n{}\n", header);
  for (size_t p = 0; p < std::min(kRows, report.parts.size()); ++p) {
    const TargetPart& part = report.parts[p];
    std::string name = ShownOnOneLine(part.name);
    if (name.size() > width) name = name.substr(0, width - 1) + "~";
    std::string line = fmt::format("  {:<{}} {:>8}", name, width, part.cells);
    if (report.exposure_known) {
      line += exposed_only ? fmt::format(" {:>9}", part.left_out)
                           : fmt::format(" {:9.2f}", part.cells ? 100.0 * part.unexposed / part.cells : 0.0);
    }
    line += fmt::format(" {:8.2f}", 100.0 * part.ceiling);
    for (const size_t index : shown)
      line += fmt::format(" {:8.2f}", 100.0 * report.result_part_coverage[index][p]);
    fmt::print("{}\n", line);
  }
  if (report.parts.size() > kRows)
    fmt::print("  ... {} more parts (report.json)\n", report.parts.size() - kRows);
}

// --pose-tolerance: per result shown, its coverage over the perturbed layouts and the sensor
// whose mounting error alone costs the most.
void PrintPoseTolerance(const Report& report) {
  if (!report.pose_tolerance) return;
  const PoseTolerance& t = *report.pose_tolerance;
  fmt::print("pose tolerance   sensors off by up to {:g} m and {:g} deg, {} layouts per result\n",
             t.options.position, t.options.angle_deg, t.options.samples);
  // The same results as the method lines: each method at its largest n.
  std::vector<const PoseSpread*> shown;
  for (const PoseSpread& s : t.results) {
    const Selection& result = report.results.at(static_cast<size_t>(s.result));
    auto same = std::find_if(shown.begin(), shown.end(), [&](const PoseSpread* o) {
      return report.results.at(static_cast<size_t>(o->result)).method == result.method;
    });
    if (same == shown.end()) {
      shown.push_back(&s);
    } else if (result.n >= report.results.at(static_cast<size_t>((*same)->result)).n) {
      *same = &s;
    }
  }
  for (const PoseSpread* s : shown) {
    const Selection& result = report.results.at(static_cast<size_t>(s->result));
    std::string costliest;
    if (!s->sensor_loss.empty()) {
      const size_t at = static_cast<size_t>(
          std::find(result.chosen.begin(), result.chosen.end(), s->costliest) -
          result.chosen.begin());
      costliest = fmt::format("; costliest {} ({:+.2f} alone)",
                              report.data->candidates.at(s->costliest).name,
                              -100.0 * s->sensor_loss.at(at));
    }
    fmt::print("  {}: {:.2f} % planned; mean {:.2f}, 5th percentile {:.2f}, worst {:.2f}{}\n",
               ResultLabel(report.results, s->result), 100.0 * s->nominal, 100.0 * s->mean,
               100.0 * s->p5, 100.0 * s->worst, costliest);
  }
}

// The installation constraints (docs/constraints.md) and the primary result's check: what it
// avoided (or, when only checked, breaks) and its overlap graph.
void PrintConstraints(const Report& report) {
  const ConstraintsInfo& info = *report.constraints;
  const VisibilityFile& data = *report.data;
  const InstallConstraints& constraints = info.constraints;
  if (info.interference_overlap) {
    size_t pairs = 0;
    for (const Conflict& c : constraints.conflicts) pairs += c.kind == ConflictKind::kInterference;
    fmt::print(
        "constraints      interference: {} of {} candidates project light; {} pairs light "
        "up more than {:g} % of each other's cells{}\n",
        info.projecting, data.candidates.size(), pairs, 100.0 * *info.interference_overlap,
        info.is_applied ? " (never both chosen)" : "");
  }
  if (info.min_separation) {
    size_t pairs = 0;
    for (const Conflict& c : constraints.conflicts) pairs += c.kind == ConflictKind::kSeparation;
    fmt::print("constraints      separation: {} pairs closer than {:g} m{}\n", pairs,
               *info.min_separation, info.is_applied ? " (never both chosen)" : "");
  }
  if (!info.keep_out_boxes.empty()) {
    fmt::print(
        "constraints      keep-out: {} box{}; {}\n", info.keep_out_boxes.size(),
        info.keep_out_boxes.size() == 1 ? "" : "es",
        info.is_applied
            ? fmt::format("{} candidates inside excluded before observing", info.keep_out_excluded)
            : fmt::format("{} of the sensors inside", info.keep_out_violations.size()));
  }
  if (constraints.calibration) {
    const CalibrationRule& rule = *constraints.calibration;
    fmt::print("constraints      calibration: the chosen must be connected by views sharing {}\n",
               rule.min_cells ? fmt::format("at least {} cells", *rule.min_cells)
                              : fmt::format("at least {:g} % of the smaller set",
                                            100.0 * rule.min_fraction.value_or(0.0)));
  }
  if (report.primary < 0) return;
  const Selection& primary = report.results.at(static_cast<size_t>(report.primary));
  const ConstraintCheck check = CheckConstraints(data.observations, primary.chosen, constraints);
  for (const Conflict& c : check.conflicts)
    fmt::print("breaks           {}\n", ConflictText(c, data));
  for (const uint32_t i : primary.chosen) {
    if (std::binary_search(info.keep_out_violations.begin(), info.keep_out_violations.end(), i))
      fmt::print("breaks           {} lies inside a keep-out box\n", data.candidates.at(i).name);
  }
  if (info.is_applied) {
    const std::vector<Conflict> avoided = ConflictsAvoided(primary.chosen, constraints);
    const size_t shown = std::min<size_t>(avoided.size(), 5);
    for (size_t i = 0; i < shown; ++i)
      fmt::print("avoided          {}\n", ConflictText(avoided[i], data));
    if (avoided.size() > shown)
      fmt::print("avoided          ... {} more (report.json)\n", avoided.size() - shown);
  }
  std::vector<std::string> edges;
  for (const OverlapEdge& e : check.edges) {
    edges.push_back(fmt::format("{} - {} {}", data.candidates.at(e.a).name,
                                data.candidates.at(e.b).name, e.cells));
  }
  if (constraints.calibration || !edges.empty()) {
    fmt::print("overlap graph    of {}: {}{}\n", ResultLabel(report.results, report.primary),
               edges.empty() ? "no edges" : fmt::format("{}", fmt::join(edges, ", ")),
               constraints.calibration
                   ? (check.connected()
                          ? " (connected)"
                          : fmt::format(" (NOT connected: {} parts)", check.components.size()))
                   : std::string(" (common cells)"));
  }
}

// --by-type (issue 43): one row per sensor type, its best coverage alone at each n, then the
// run's best (the mix) and what the mix gains over the best single type.
void PrintByType(const TypeComparisonTable& table) {
  if (table.mix.empty()) return;
  const int first_n = table.mix.front().n, last_n = table.mix.back().n;
  size_t width = 26;
  for (const TypeComparison& type : table.types) width = std::max(width, type.type_id.size());
  fmt::print("by type          each type alone: coverage % at n = {}..{} (* proven optimal), its "
             "candidates and unit cost\n",
             first_n, last_n);
  const auto cells = [&](const std::vector<Selection>& best) {
    std::string row;
    for (int n = first_n; n <= last_n; ++n) {
      const auto s = std::find_if(best.begin(), best.end(),
                                  [n](const Selection& x) { return x.n == n; });
      row += s == best.end() ? fmt::format(" {:>8}", "-")
                             : fmt::format(" {:>7.2f}{}", 100.0 * s->coverage,
                                           s->proven_optimal ? "*" : " ");
    }
    return row;
  };
  for (const TypeComparison& type : table.types)
    fmt::print("  {:<{}} {:>4} × {:<8}{}\n", type.type_id, width, type.candidates,
               type.unit_cost_given ? fmt::format("{:g}", type.unit_cost) : std::string("-"),
               cells(type.best));
  fmt::print("  {:<{}} {:>15}{}\n", "mix (the run's best)", width, "", cells(table.mix));
  std::string gains;
  for (const Selection& s : table.mix) {
    double best_single = -1;
    for (const TypeComparison& type : table.types)
      for (const Selection& t : type.best)
        if (t.n == s.n) best_single = std::max(best_single, t.coverage);
    gains += best_single < 0 ? fmt::format(" {:>8}", "-")
                             : fmt::format(" {:>+7.2f} ", 100.0 * (s.coverage - best_single));
  }
  fmt::print("  {:<{}} {:>15}{}\n", "gain over the best type", width, "", gains);
  // Types the physical model sees as the ideal pinhole (issue 43): their rows are not physical.
  if (table.physical)
    for (const TypeComparison& type : table.types)
      if (!type.physical_gap.empty())
        fmt::print("  {}: physical model {}\n", type.type_id, type.physical_gap);
  for (const TypeComparison& type : table.types)
    if (!type.unit_cost_given)
      fmt::print("  {}: unit cost not given (its vendor publishes none)\n", type.type_id);
}

// optimize --track (docs/arm.md): each state's view, its coverage there and the move to it.
void PrintTrack(const VisibilityFile& data, const TrackInfo& track) {
  fmt::print("track            one arm view per state, exact (dynamic programme): summed coverage "
             "{:.2f} %, {:.2f} s moving, value {:.4f} (move penalty {:g} per s{})\n",
             100.0 * track.coverage_sum, track.move_seconds, track.value, track.move_penalty,
             track.state_interval ? fmt::format(", states {:g} s apart", *track.state_interval)
                                  : std::string());
  size_t width = 5;
  for (const TrackInfo::State& s : track.states) width = std::max(width, s.name.size());
  for (const TrackInfo::State& s : track.states)
    fmt::print("  {:<{}}  {:>6.2f} %  {:>6.2f} s{}  {}\n", s.name, width, 100.0 * s.coverage,
               s.move_seconds, s.planned ? " (planned)" : "", data.candidates.at(s.view).name);
}

void PrintSummary(const Report& report, const std::string& out_dir) {
  const VisibilityFile& data = *report.data;
  const std::vector<Selection>& results = report.results;
  const std::optional<RefinementInfo>& refinement = report.refinement;
  const size_t r = data.reference.size();
  // A path may hold any byte but '/' and NUL: one line, valid UTF-8, as in the messages.
  fmt::print("scene            {}\n", ShownOnOneLine(data.scene));
  fmt::print("reference        {} voxels of {} m\n", r, data.reference.cell_size);
  fmt::print("candidates       {}\n", data.candidates.size());
  if (report.best_single >= 0) {
    const size_t best = static_cast<size_t>(report.best_single);
    const Candidate& c = data.candidates[best];
    // It is ranked by plain coverage; say so where the results count something else.
    const bool plain_only =
        !results.empty() && (results.front().min_points || results.front().k > 1);
    fmt::print("best single      {} ({}) {:.2f} %{}\n", c.name, c.type_id,
               r ? 100.0 * data.observations[best].reference_indices.size() / r : 0.0,
               plain_only ? " (plain coverage: every pixel counts)" : "");
  }
  if (report.ceiling) PrintCeiling(report);
  // The objective, when it is not plain coverage (all results share it).
  if (!results.empty()) {
    const Selection& first = results.front();
    const std::string counted =
        first.min_points ? fmt::format(" (cells holding {} points)", *first.min_points)
        : first.k >= 2   ? fmt::format(" (cells seen {} times)", first.k)
                         : std::string();
    if (first.goal) {
      fmt::print("objective        set cover: the {} reaching {:.2f} % coverage{}\n",
                 first.cost ? "cheapest sensors" : "fewest sensors", 100.0 * *first.goal,
                 counted);
    } else if (first.budget) {
      fmt::print("objective        budget: the most coverage{} for a total sensor cost <= {:g}\n",
                 counted, *first.budget);
    } else if (first.k >= 2) {
      fmt::print(
          "objective        {0}-coverage: a cell counts once {0} chosen sensors see it "
          "(coverages below are {0}-coverages)\n",
          first.k);
    } else if (first.min_points) {
      const double face_cm2 = std::pow(100.0 * data.reference.cell_size, 2);
      fmt::print(
          "objective        point density: a cell counts once the chosen sensors put >= "
          "{} points in it ({:.3g} per cm² of its {:.3g} cm² face; coverages below "
          "count such cells)\n",
          *first.min_points, *first.min_points / face_cm2, face_cm2);
    }
  }
  // The objectives the selection options' table describes itself (a row with a summary line);
  // over states, groups of cells are every state's, and the states' line says so.
  if (report.inputs) {
    for (const SelectionOption& option : SelectionOptionTable())
      if (option.summary && option.GivenIn(report.inputs->selection) &&
          !(report.states && option.aggregates_groups))
        fmt::print("objective        {}\n", option.summary(report.inputs->selection));
  }
  if (data.quality.active()) {
    std::vector<std::string> limits;
    if (data.quality.max_incidence_deg)
      limits.push_back(fmt::format("incidence <= {:g} deg", *data.quality.max_incidence_deg));
    if (data.quality.max_depth_noise)
      limits.push_back(
          fmt::format("depth noise <= {:g} mm", 1000.0 * *data.quality.max_depth_noise));
    fmt::print(
        "quality          {}: coverages count only such pixels; 'plain' counts every pixel\n",
        fmt::join(limits, ", "));
  }
  // A scene may have up to 1000 states: the summary's lines name the first few and the last.
  const auto elided = [](const std::vector<std::string>& items, std::string_view separator) {
    constexpr size_t kShown = 6;
    if (items.size() <= kShown + 2) return fmt::format("{}", fmt::join(items, separator));
    return fmt::format("{}{}…{}{}", fmt::join(items.begin(), items.begin() + kShown, separator),
                       separator, separator, items.back());
  };
  if (report.states && !report.track) {
    std::vector<std::string> names;
    for (const StatesInfo::State& state : report.states->states) names.push_back(state.name);
    const std::string& over = report.states->over;
    const std::string aggregate(AggregationOf(ParseOverStates(over)).phrase);
    // --over-parts: one aggregation over every state's target parts.
    const std::string what =
        report.inputs && report.inputs->selection.over_parts
            ? fmt::format("the {} of every state's target parts' coverages, each state's coverage",
                          aggregate)
            : fmt::format("the {} of the states' coverages", aggregate);
    fmt::print("states           {} over {} states ({}): coverages below are {}, listed after "
               "each\n",
               over, names.size(), elided(names, ", "), what);
    fmt::print("                 (reference and best single above: state '{}')\n", names.front());
  }
  // One line per method at its largest n: the constellation it recommends.
  std::vector<size_t> shown;
  for (size_t i = 0; i < results.size(); ++i) {
    auto it = std::find_if(shown.begin(), shown.end(),
                           [&](size_t o) { return results[o].method == results[i].method; });
    if (it == shown.end()) {
      shown.push_back(i);
    } else if (results[i].n >= results[*it].n) {
      *it = i;
    }
  }
  for (const size_t index : shown) {
    const Selection* s = &results[index];
    std::string names;
    for (uint32_t i : s->chosen) names += (names.empty() ? "" : ", ") + data.candidates[i].name;
    std::string bound;
    if (s->upper_bound)
      bound = s->proven_optimal ? "  (optimal)"
                                : fmt::format("  (bound {:.2f} %)", 100.0 * *s->upper_bound);
    if (!s->proven_optimal) {
      if (const int proof = ProvenBy(results, static_cast<int>(index)); proof >= 0)
        bound = fmt::format("  (optimal: as good as {}'s proven optimum)",
                            results[static_cast<size_t>(proof)].method);
    }
    if (s->n_lower_bound) {
      bound = s->proven_optimal ? "  (fewest: optimal)"
                                : fmt::format("  (at least {} sensors)", *s->n_lower_bound);
    }
    if (s->cost_lower_bound) {
      bound = s->proven_optimal ? "  (cheapest: optimal)"
                                : fmt::format("  (cost at least {:g})", *s->cost_lower_bound);
    }
    if (s->cost && s->budget) bound += fmt::format("  cost {:g} of {:g}", *s->cost, *s->budget);
    if (s->cost && !s->budget) bound += fmt::format("  cost {:g}", *s->cost);
    if (!report.result_plain_coverage.empty())
      bound += fmt::format("  (plain {:.2f} %)", 100.0 * report.result_plain_coverage[index]);
    if (!s->state_coverage.empty()) {
      std::vector<std::string> per_state;
      for (double c : s->state_coverage) per_state.push_back(fmt::format("{:.2f}", 100.0 * c));
      bound += fmt::format("  (states {} %)", elided(per_state, " / "));
    }
    // A camera on an arm (docs/arm.md): the result's tour, home to home with acquisition.
    if (index < report.tours.size() && report.tours[index])
      bound += fmt::format("  tour {:.2f} s", report.tours[index]->tour.total_seconds);
    fmt::print("{:<8} n={:<3}  {:6.2f} %{}  [{}]  {:.3f} s\n", s->method, s->n, 100.0 * s->coverage,
               bound, names, s->seconds);
  }
  if (report.track) PrintTrack(data, *report.track);
  PrintParts(report, shown);
  PrintCoverageByN(results);
  if (report.by_type) PrintByType(*report.by_type);
  PrintPoseTolerance(report);
  if (report.constraints) PrintConstraints(report);
  if (refinement) {
    fmt::print(
        "refinement       {:+.2f} points over {}: {} rounds, {} new poses, {:.1f} M extra "
        "rays, {:.2f} s\n",
        100.0 * (refinement->coverage_after - refinement->coverage_before),
        ResultLabel(results, refinement->from_result),
        refinement->rounds, refinement->new_candidates, refinement->extra_rays / 1e6,
        refinement->seconds);
  }
  if (report.robustness) PrintRobustness(data, results, *report.robustness);
  fmt::print(
      "timings          load {:.3f} s, reference {:.3f} s, observe {:.3f} s, select {:.3f} s, "
      "total {:.3f} s\n",
      report.timings.load, report.timings.reference, report.timings.observe, report.timings.select,
      report.timings.total);
  if (!out_dir.empty()) fmt::print("outputs          {}/\n", ShownOnOneLine(out_dir));
}

}  // namespace vantage::cli
