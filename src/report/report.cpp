#include "vantage/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <nlohmann/json.hpp>

#include "report/arm_export.hpp"
#include "report/by_type_json.hpp"
#include "report/constraints_json.hpp"
#include "report/run_inputs.hpp"
#include "util/atomic_file.hpp"
#include "vantage/error.hpp"

#ifndef VANTAGE_VERSION
#define VANTAGE_VERSION "0.0.0"
#endif

namespace vantage {
namespace {

using nlohmann::ordered_json;

double Fraction(size_t count, size_t total) {
  return total == 0 ? 0.0 : static_cast<double>(count) / static_cast<double>(total);
}

ordered_json CandidateJson(const Candidate& c, const Observation& o, size_t reference_size) {
  const Vec3& p = c.world_from_body.position;
  const SensorType& s = c.sensor;
  ordered_json j;
  j["name"] = c.name;
  j["type"] = c.type_id.empty() ? s.id : c.type_id;
  j["position"] = ordered_json::array({p.x(), p.y(), p.z()});
  j["quaternion"] = WxyzOf(c.world_from_body.rotation);
  j["width"] = s.width;
  j["height"] = s.height;
  j["fx"] = s.fx;
  j["fy"] = s.fy;
  j["cx"] = s.cx;
  j["cy"] = s.cy;
  j["near"] = s.near;
  j["far"] = s.far;
  j["coverage"] = Fraction(o.reference_indices.size(), reference_size);
  j["paper_coverage"] = Fraction(o.reference_indices.size() + o.outside_keys.size(), reference_size);
  j["population"] = c.population;
  j["observed_voxels"] = o.reference_indices.size();
  j["rays_traced"] = o.rays_traced;
  return j;
}

// With a quality filter (issue 9): the filter, the types it could not judge by noise, and each
// candidate's plain coverage and pixel counts beside the filtered ones.
ordered_json QualityJson(const VisibilityFile& data) {
  const QualityFilter& q = data.quality;
  ordered_json j;
  if (q.max_incidence_deg) j["max_incidence_deg"] = *q.max_incidence_deg;
  if (q.max_depth_noise) {
    j["max_depth_noise_mm"] = *q.max_depth_noise * 1000.0;
    ordered_json unknown = ordered_json::array();
    for (const Candidate& c : data.candidates) {
      const std::string type = c.type_id.empty() ? c.sensor.id : c.type_id;
      if (!NoiseModelOf(c) && std::find(unknown.begin(), unknown.end(), type) == unknown.end())
        unknown.push_back(type);
    }
    j["types_without_noise_model"] = std::move(unknown);
    // Per type, the model its pixels were judged by and where it comes from (issue 43).
    ordered_json models = ordered_json::array();
    std::vector<std::string> seen;
    for (const Candidate& c : data.candidates) {
      const std::string type = c.type_id.empty() ? c.sensor.id : c.type_id;
      const DepthNoise* noise = NoiseModelOf(c);
      if (!noise || std::find(seen.begin(), seen.end(), type) != seen.end()) continue;
      seen.push_back(type);
      ordered_json m = {{"type", type}, {"a", noise->a}, {"b", noise->b}, {"c", noise->c}};
      if (noise->incidence != 0) m["incidence"] = noise->incidence;
      m["source"] = noise->source;
      models.push_back(std::move(m));
    }
    j["noise_models"] = std::move(models);
  }
  return j;
}

// report.json's `sensor_model` (issue 43), written when the physical model was on: per sensor
// type among the candidates, its second aperture and stereo's nearest depth beside the
// datasheet's.
ordered_json SensorModelJson(const VisibilityFile& data) {
  ordered_json types = ordered_json::array();
  std::vector<std::string> seen;
  for (const Candidate& c : data.candidates) {
    if (std::find(seen.begin(), seen.end(), c.type_id) != seen.end()) continue;
    seen.push_back(c.type_id);
    ordered_json t = {{"type", c.type_id}};
    const SecondAperture* a = SecondApertureOf(c.sensor, c.type_id);
    // A structured-light or stereo type whose aperture no source gave is not "none": the
    // physical model sees it as the ideal pinhole and says so.
    const std::string gap = PhysicalModelGap(c.sensor, c.type_id);
    t["second_aperture"] = a ? KindName(a->kind) : gap.empty() ? "none" : "not modelled";
    if (!gap.empty()) t["physical_model"] = gap;
    if (a) {
      t["baseline"] = a->baseline;
      if (a->toe_in != 0) t["toe_in_deg"] = a->toe_in * 180.0 / std::numbers::pi;
      if (const double nearest = StereoNearestDepth(c.sensor, *a); nearest > 0) {
        t["disparity_range"] = *a->disparity_range;
        t["stereo_nearest_depth"] = nearest;
      }
    }
    t["datasheet_near"] = c.sensor.near;
    if (const auto flying = FlyingPixelThresholdOf(c.sensor, c.type_id))
      t["flying_pixel_threshold"] = *flying;
    types.push_back(std::move(t));
  }
  return {{"model", "physical"}, {"types", std::move(types)}};
}

// One entry of report.json's `results` (or `curve`); `plain_coverage` may be null.
ordered_json ResultJson(const Selection& s, const VisibilityFile& data,
                        const double* plain_coverage) {
  ordered_json r;
  r["method"] = s.method;
  r["n"] = s.n;
  ordered_json names = ordered_json::array();
  for (uint32_t index : s.chosen) names.push_back(data.candidates.at(index).name);
  r["sensors"] = std::move(names);
  r["coverage"] = s.coverage;
  r["paper_coverage"] = s.paper_coverage;
  if (plain_coverage) r["plain_coverage"] = *plain_coverage;
  if (!s.state_coverage.empty()) r["state_coverage"] = s.state_coverage;
  if (s.upper_bound) {
    r["upper_bound"] = *s.upper_bound;
    r["gap"] = std::max(0.0, *s.upper_bound - s.coverage);
    r["optimal"] = s.proven_optimal;
  }
  r["seconds"] = s.seconds;
  // The objective (SYSTEM.md, Select: further objectives); coverage is measured under it.
  r["objective"] = s.objective;
  if (s.goal) r["goal"] = *s.goal;
  if (s.k >= 2) r["k"] = s.k;
  if (s.min_points) r["min_points"] = *s.min_points;
  if (s.budget) r["budget"] = *s.budget;
  if (s.cost) r["cost"] = *s.cost;
  if (s.n_lower_bound) {
    r["n_lower_bound"] = *s.n_lower_bound;
    r["optimal"] = s.proven_optimal;
  }
  if (s.cost_lower_bound) {
    r["cost_lower_bound"] = *s.cost_lower_bound;
    r["optimal"] = s.proven_optimal;
  }
  return r;
}

// report.json's `pose_tolerance`: per result its coverage over the perturbed layouts.
ordered_json PoseToleranceJson(const PoseTolerance& tolerance, const VisibilityFile& data) {
  ordered_json j;
  j["position_m"] = tolerance.options.position;
  j["angle_deg"] = tolerance.options.angle_deg;
  j["samples"] = tolerance.options.samples;
  ordered_json results = ordered_json::array();
  for (const PoseSpread& s : tolerance.results) {
    ordered_json one = {{"result", s.result}, {"nominal", s.nominal}, {"mean", s.mean},
                        {"p5", s.p5},         {"worst", s.worst}};
    if (!s.sensor_loss.empty()) one["costliest_sensor"] = data.candidates.at(s.costliest).name;
    results.push_back(std::move(one));
  }
  j["results"] = std::move(results);
  return j;
}

ordered_json RobustnessJson(const Robustness& robustness, const VisibilityFile& data) {
  const auto name = [&](uint32_t index) { return data.candidates.at(index).name; };
  const auto failure = [&](const SensorFailure& f) {
    return ordered_json{{"sensor", name(f.sensor)}, {"coverage", f.coverage}};
  };
  ordered_json j;
  j["result"] = robustness.result;
  ordered_json failures = ordered_json::array();
  for (const SensorFailure& f : robustness.failures) failures.push_back(failure(f));
  j["sensor_failures"] = std::move(failures);
  if (robustness.worst) j["worst_failure"] = failure(*robustness.worst);
  if (robustness.fov_tolerance_deg && robustness.fov_shrunk_coverage) {
    j["fov_tolerance_deg"] = *robustness.fov_tolerance_deg;
    j["fov_shrunk_coverage"] = *robustness.fov_shrunk_coverage;
  }
  if (!robustness.fov_note.empty()) j["fov_note"] = robustness.fov_note;
  j["alternatives_within"] = robustness.alternatives_within;
  ordered_json alternatives = ordered_json::array();
  for (const Alternative& a : robustness.alternatives) {
    ordered_json sensors = ordered_json::array();
    for (uint32_t index : a.chosen) sensors.push_back(name(index));
    ordered_json alternative = {{"sensors", std::move(sensors)},
                                {"replaced", name(a.replaced)},
                                {"replacement", name(a.replacement)},
                                {"coverage", a.coverage}};
    if (a.cost) alternative["cost"] = *a.cost;
    alternatives.push_back(std::move(alternative));
  }
  j["alternatives"] = std::move(alternatives);
  return j;
}

// Per cell of R, whether `chosen` covers it as a result counts: `needed` sensors (k), or with
// min_points that many pixels' hits.
std::vector<char> CoveredCells(const VisibilityFile& data, const std::vector<uint32_t>& chosen,
                               int k, const std::optional<uint32_t>& min_points) {
  const uint64_t needed = min_points ? *min_points : static_cast<uint64_t>(std::max(k, 1));
  std::vector<uint64_t> amount(data.reference.size(), 0);
  for (uint32_t index : chosen) {
    VANTAGE_CHECK(index < data.observations.size());
    const Observation& o = data.observations[index];
    VANTAGE_CHECK(!min_points || o.has_point_counts());
    for (size_t j = 0; j < o.reference_indices.size(); ++j)
      amount[o.reference_indices[j]] += min_points ? o.reference_hits[j] : 1;
  }
  std::vector<char> covered(amount.size());
  for (size_t i = 0; i < amount.size(); ++i) covered[i] = amount[i] >= needed;
  return covered;
}

// Per part, the share of its cells that `covered` holds.
std::vector<double> PartShares(const Reference& reference, const std::vector<char>& covered,
                               const std::vector<TargetPart>& parts) {
  std::vector<size_t> count(parts.size(), 0);
  for (size_t i = 0; i < covered.size(); ++i) count[reference.part_of[i]] += covered[i] ? 1 : 0;
  std::vector<double> shares;
  for (size_t p = 0; p < parts.size(); ++p) shares.push_back(Fraction(count[p], parts[p].cells));
  return shares;
}

// report.json's `ceiling`: what all candidates reach together, in all and per part, and the
// surface no viewpoint can see.
ordered_json CeilingJson(const Report& report) {
  const VisibilityFile& data = *report.data;
  ordered_json j;
  j["coverage"] = *report.ceiling;
  j["candidates"] = data.candidates.size();
  j["exposed_only"] = data.reference.exposed_only;
  if (report.exposure_known) {
    j[data.reference.exposed_only ? "left_out_voxels" : "unexposed_voxels"] = report.unexposed;
    if (!data.reference.exposed_only)
      j["unexposed"] = Fraction(report.unexposed, data.reference.size());
  }
  ordered_json parts = ordered_json::array();
  for (const TargetPart& part : report.parts) {
    ordered_json one = {{"name", part.name}, {"voxels", part.cells}, {"coverage", part.ceiling}};
    if (report.exposure_known) {
      if (data.reference.exposed_only) {
        one["left_out_voxels"] = part.left_out;
      } else {
        one["unexposed_voxels"] = part.unexposed;
      }
    }
    parts.push_back(std::move(one));
  }
  j["parts"] = std::move(parts);
  return j;
}

// A result's coverage per target part (report.json's "part_coverage"), or null without parts.
ordered_json PartCoverageJson(const Report& report, size_t index) {
  if (report.result_part_coverage.empty()) return ordered_json();
  ordered_json parts = ordered_json::object();
  for (size_t p = 0; p < report.parts.size(); ++p)
    parts[report.parts[p].name] = report.result_part_coverage[index][p];
  return parts;
}

// report.json's "pose_tolerance", with each sensor's own cost by name in the result's chosen
// order.
ordered_json PoseToleranceEntry(const PoseTolerance& pose_tolerance, const Report& report,
                                const VisibilityFile& data) {
  ordered_json tolerance = PoseToleranceJson(pose_tolerance, data);
  for (size_t i = 0; i < pose_tolerance.results.size(); ++i) {
    const PoseSpread& s = pose_tolerance.results[i];
    const Selection& result = report.results.at(static_cast<size_t>(s.result));
    ordered_json losses = ordered_json::object();
    for (size_t k = 0; k < s.sensor_loss.size(); ++k)
      losses[data.candidates.at(result.chosen.at(k)).name] = s.sensor_loss[k];
    tolerance["results"][i]["sensor_loss"] = std::move(losses);
  }
  return tolerance;
}

}  // namespace

const char* Version() { return VANTAGE_VERSION; }

int PrimaryResult(const std::vector<Selection>& results) {
  int best = -1;
  for (size_t i = 0; i < results.size(); ++i) {
    // Set cover: every answer reaches the goal, so the fewest sensors (the cheapest, when the
    // goal minimises cost) stand for the run.
    const Selection& held = results[best < 0 ? 0 : best];
    const bool is_more = results[i].goal && results[i].cost && held.cost
                             ? *results[i].cost < *held.cost
                         : results[i].goal ? results[i].n < held.n
                                           : results[i].n > held.n;
    if (best < 0 || is_more ||
        (results[i].n == results[best].n && results[i].coverage > results[best].coverage))
      best = static_cast<int>(i);
  }
  return best;
}

int ProvenBy(const std::vector<Selection>& results, int index) {
  const Selection& s = results.at(static_cast<size_t>(index));
  if (s.proven_optimal) return index;
  for (size_t j = 0; j < results.size(); ++j) {
    const Selection& p = results[j];
    if (!p.proven_optimal || p.n != s.n || p.objective != s.objective || p.k != s.k ||
        p.goal != s.goal || p.budget != s.budget || p.min_points != s.min_points ||
        p.state_coverage.size() != s.state_coverage.size())
      continue;
    if (s.budget && (!s.cost || *s.cost > *s.budget)) continue;
    // Set cover: the same n is as few sensors; the others: the proven best coverage at n.
    if (s.goal || s.coverage >= p.coverage) return static_cast<int>(j);
  }
  return -1;
}

std::string ResultLabel(const std::vector<Selection>& results, int index) {
  const Selection& s = results.at(static_cast<size_t>(index));
  const int proof = ProvenBy(results, index);
  std::string label = fmt::format("{} n={}", s.method, s.n);
  if (proof == index) return label + " (proven optimal)";
  if (proof >= 0)
    return label + fmt::format(" (proven optimal by {})", results[static_cast<size_t>(proof)].method);
  return label;
}

const std::vector<uint32_t>& Report::PrimaryChosen() const {
  VANTAGE_CHECK(is_derived);
  static const std::vector<uint32_t> kNone;
  return primary >= 0 ? results.at(static_cast<size_t>(primary)).chosen : kNone;
}

bool Report::CountsGroups() const {
  if (states) return true;
  if (!inputs) return false;
  for (const SelectionOption& option : SelectionOptionTable())
    if (option.aggregates_groups && option.GivenIn(inputs->selection)) return true;
  return false;
}

void DeriveReport(Report* report) {
  VANTAGE_CHECK(report->data != nullptr);
  const VisibilityFile& data = *report->data;
  const size_t reference_size = data.reference.size();
  report->primary = PrimaryResult(report->results);
  report->result_plain_coverage.clear();
  report->candidate_plain_coverage.clear();
  if (data.quality.active()) {
    // Plain coverage differs only under a quality filter, so only then are the sets copied.
    const std::vector<Observation> plain = WithoutQuality(data.observations);
    const CoverageEvaluator plain_evaluator(plain, reference_size);
    for (const Observation& o : plain)
      report->candidate_plain_coverage.push_back(Fraction(o.reference_indices.size(), reference_size));
    // With states, `data` holds the first state's sets only: no plain coverage of a result (nor
    // where an objective's coverage aggregates groups of cells).
    if (!report->CountsGroups()) {
      for (const Selection& s : report->results)
        report->result_plain_coverage.push_back(plain_evaluator.Coverage(s.chosen, s.k));
    }
  }
  report->result_ideal_coverage.clear();
  report->candidate_ideal_coverage.clear();
  if (data.physical) {
    const std::vector<Observation> ideal = IdealObservations(data.observations);
    const CoverageEvaluator ideal_evaluator(ideal, reference_size);
    for (const Observation& o : ideal)
      report->candidate_ideal_coverage.push_back(Fraction(o.reference_indices.size(), reference_size));
    if (!report->CountsGroups()) {
      for (const Selection& s : report->results)
        report->result_ideal_coverage.push_back(ideal_evaluator.Coverage(s.chosen, s.k));
    }
  }
  report->best_single = data.observations.empty() ? -1 : 0;
  for (size_t i = 1; i < data.observations.size(); ++i) {
    if (data.observations[i].reference_indices.size() >
        data.observations[static_cast<size_t>(report->best_single)].reference_indices.size())
      report->best_single = static_cast<int>(i);
  }
  // The ceiling and each part (issue 46); with states the results count over states instead.
  report->ceiling.reset();
  report->parts.clear();
  report->result_part_coverage.clear();
  const Reference& reference = data.reference;
  report->exposure_known = reference.exposed_only || reference.exposed.size() == reference_size;
  report->unexposed = 0;
  if (reference.exposed_only) {
    for (uint64_t cells : reference.left_out) report->unexposed += cells;
  } else if (report->exposure_known) {
    report->unexposed = static_cast<size_t>(std::count(reference.exposed.begin(), reference.exposed.end(), 0));
  }
  if (!report->states && !data.observations.empty()) {
    const Selection* first = report->results.empty() ? nullptr : &report->results.front();
    std::vector<uint32_t> all(data.observations.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
    const std::optional<uint32_t> min_points =
        first && first->min_points ? std::optional<uint32_t>(*first->min_points) : std::nullopt;
    const std::vector<char> ceiling = CoveredCells(data, all, first ? first->k : 1, min_points);
    report->ceiling = Fraction(static_cast<size_t>(std::count(ceiling.begin(), ceiling.end(), 1)),
                               reference_size);
    if (!reference.part_names.empty() && reference.part_of.size() == reference_size) {
      report->parts.resize(reference.part_names.size());
      for (size_t p = 0; p < report->parts.size(); ++p) {
        report->parts[p].name = reference.part_names[p];
        if (reference.exposed_only) report->parts[p].left_out = reference.left_out.at(p);
      }
      for (size_t i = 0; i < reference_size; ++i) {
        TargetPart& part = report->parts[reference.part_of[i]];
        ++part.cells;
        if (!reference.exposed_only && report->exposure_known && !reference.exposed[i])
          ++part.unexposed;
      }
      const std::vector<double> shares = PartShares(reference, ceiling, report->parts);
      for (size_t p = 0; p < report->parts.size(); ++p) report->parts[p].ceiling = shares[p];
      for (const Selection& s : report->results) {
        const std::optional<uint32_t> points =
            s.min_points ? std::optional<uint32_t>(*s.min_points) : std::nullopt;
        report->result_part_coverage.push_back(
            PartShares(reference, CoveredCells(data, s.chosen, s.k, points), report->parts));
      }
    }
  }
  report->primary_sensors.clear();
  if (report->primary >= 0) {
    // A cell counts as the result's coverage does: once it holds min_points points, or is seen
    // by k sensors (1 for plain coverage), so that the last step equals the result's coverage.
    const Selection& primary = report->results[static_cast<size_t>(report->primary)];
    const uint64_t needed = primary.min_points ? *primary.min_points
                                               : static_cast<uint64_t>(std::max(primary.k, 1));
    std::vector<uint64_t> amount(reference_size, 0);
    size_t covered = 0;
    for (uint32_t index : primary.chosen) {
      VANTAGE_CHECK(index < data.observations.size());
      const Observation& o = data.observations[index];
      VANTAGE_CHECK(!primary.min_points || o.has_point_counts());
      size_t gained = 0;
      for (size_t j = 0; j < o.reference_indices.size(); ++j) {
        uint64_t& cell = amount[o.reference_indices[j]];
        const bool was_covered = cell >= needed;
        cell += primary.min_points ? o.reference_hits[j] : 1;
        if (!was_covered && cell >= needed) ++gained;
      }
      covered += gained;
      report->primary_sensors.push_back(
          {index, Fraction(gained, reference_size), Fraction(covered, reference_size)});
    }
  }
  report->is_derived = true;
}

std::string ReportJson(const Report& report) {
  VANTAGE_CHECK(report.data != nullptr && report.is_derived);
  const VisibilityFile& data = *report.data;
  const size_t reference_size = data.reference.keys.size();
  ordered_json j;
  j["schema"] = "vantage.report/1";
  j["version"] = Version();
  j["seed"] = report.seed;
  j["scene"] = report.scene;
  j["cell_size"] = data.reference.cell_size;
  j["reference_voxels"] = reference_size;
  ordered_json candidates = ordered_json::array();
  const bool quality = data.quality.active();
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    candidates.push_back(CandidateJson(data.candidates[i], data.observations[i], reference_size));
    if (data.physical) candidates.back()["ideal_coverage"] = report.candidate_ideal_coverage.at(i);
    if (!quality) continue;
    candidates.back()["plain_coverage"] = report.candidate_plain_coverage.at(i);
    candidates.back()["target_pixels"] = data.observations[i].target_pixels;
    candidates.back()["quality_pixels"] = data.observations[i].quality_pixels;
  }
  j["candidates"] = std::move(candidates);
  if (quality) j["quality"] = QualityJson(data);
  if (data.physical) j["sensor_model"] = SensorModelJson(data);
  ordered_json results = ordered_json::array();
  for (size_t index = 0; index < report.results.size(); ++index) {
    // Plain coverage from `data` is the first state's: shown only without states.
    const double* plain =
        report.result_plain_coverage.empty() ? nullptr : &report.result_plain_coverage.at(index);
    results.push_back(ResultJson(report.results[index], data, plain));
    if (!report.result_part_coverage.empty())
      results.back()["part_coverage"] = PartCoverageJson(report, index);
    if (!report.result_ideal_coverage.empty())
      results.back()["ideal_coverage"] = report.result_ideal_coverage.at(index);
    if (report.constraints) {
      results.back()["constraints"] =
          detail::ResultConstraintsJson(report.results[index], *report.constraints, data);
    }
    // A camera on an arm (issue 45): the tour of the result's views.
    if (index < report.tours.size() && report.tours[index])
      results.back()["tour"] = detail::ArmTourJson(*report.tours[index], data);
  }
  if (report.cycle_time) j["cycle_time"] = *report.cycle_time;
  if (report.track) j["track"] = detail::ArmTrackJson(*report.track, data);
  j["results"] = std::move(results);
  // The coverage-versus-n curve's extra answers (docs/outputs.md), shaped as results entries.
  ordered_json curve = ordered_json::array();
  for (size_t index = 0; index < report.curve.size(); ++index) {
    curve.push_back(ResultJson(report.curve[index], data, nullptr));
    // A camera on an arm (issue 45): the tour of the answer's views.
    if (index < report.curve_tours.size() && report.curve_tours[index])
      curve.back()["tour"] = detail::ArmTourJson(*report.curve_tours[index], data);
  }
  j["curve"] = std::move(curve);
  if (report.by_type) j["by_type"] = detail::ByTypeJson(*report.by_type, data);
  if (report.primary >= 0) j["primary_result"] = report.primary;
  if (report.ceiling) j["ceiling"] = CeilingJson(report);
  if (report.constraints) j["constraints"] = detail::ConstraintsJson(*report.constraints);
  if (const auto p = std::find_if(report.results.begin(), report.results.end(),
                                  [](const Selection& s) { return s.min_points.has_value(); });
      p != report.results.end()) {
    // Point density (docs/constraints.md): the points a cell needs, and the density given.
    const double face_cm2 = std::pow(100.0 * data.reference.cell_size, 2);
    ordered_json density = {{"points", *p->min_points}, {"cell_face_cm2", face_cm2}};
    if (report.inputs && report.inputs->selection.min_density)
      density["per_cm2"] = *report.inputs->selection.min_density;
    j["min_points"] = std::move(density);
  }
  if (report.robustness) j["robustness"] = RobustnessJson(*report.robustness, data);
  if (report.pose_tolerance)
    j["pose_tolerance"] = PoseToleranceEntry(*report.pose_tolerance, report, data);
  if (report.states) {
    ordered_json states = ordered_json::array();
    for (const StatesInfo::State& state : report.states->states) {
      ordered_json one = {{"name", state.name}, {"reference_voxels", state.reference_voxels}};
      if (state.same_as >= 0) one["same_as"] = state.same_as;
      states.push_back(std::move(one));
    }
    j["states"] = {{"over", report.states->over}, {"states", std::move(states)}};
  }
  if (report.refinement) {
    const RefinementInfo& r = *report.refinement;
    j["refinement"] = {{"from_result", r.from_result},   {"result", r.result},
                       {"coverage_before", r.coverage_before}, {"coverage_after", r.coverage_after},
                       {"gain", r.coverage_after - r.coverage_before}, {"history", r.history},
                       {"rounds", r.rounds},           {"new_candidates", r.new_candidates},
                       {"extra_rays", r.extra_rays},   {"seconds", r.seconds}};
  }
  j["timings"] = {{"load", report.timings.load},
                  {"reference", report.timings.reference},
                  {"observe", report.timings.observe},
                  {"select", report.timings.select},
                  {"total", report.timings.total}};
  if (!report.notes.empty()) j["notes"] = report.notes;
  if (report.inputs) j["inputs"] = detail::RunInputsJson(*report.inputs);
  // A path that is not UTF-8 (legal on Linux) is written with U+FFFD instead of throwing.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string ReportAnswersJsonText(const Report& report) {
  VANTAGE_CHECK(report.data != nullptr && report.is_derived);
  ordered_json part_coverage = ordered_json::array();
  for (size_t index = 0; index < report.results.size(); ++index)
    part_coverage.push_back(PartCoverageJson(report, index));
  const ordered_json answers = {
      {"ceiling", report.ceiling ? CeilingJson(report) : ordered_json()},
      {"part_coverage", std::move(part_coverage)},
      {"pose_tolerance", report.pose_tolerance
                             ? PoseToleranceEntry(*report.pose_tolerance, report, *report.data)
                             : ordered_json()}};
  return answers.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string RobustnessJsonText(const Robustness& robustness, const VisibilityFile& data) {
  return RobustnessJson(robustness, data)
      .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string CandidatesCsv(const Report& report) {
  VANTAGE_CHECK(report.data != nullptr);
  const VisibilityFile& data = *report.data;
  const size_t reference_size = data.reference.keys.size();
  std::string csv =
      "index,name,type,population,x,y,z,qw,qx,qy,qz,width,height,fx,fy,cx,cy,near,far,"
      "observed_voxels,coverage,paper_coverage,rays_traced\n";
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    const Candidate& c = data.candidates[i];
    const Observation& o = data.observations[i];
    const std::array<double, 4> q = WxyzOf(c.world_from_body.rotation);
    const Vec3& p = c.world_from_body.position;
    const SensorType& s = c.sensor;
    csv += fmt::format("{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{},{},{:.4f},{:.4f},"
                       "{:.4f},{:.4f},{},{},{},{:.6f},{:.6f},{}\n",
                       i, c.name, c.type_id.empty() ? s.id : c.type_id, c.population, p.x(), p.y(),
                       p.z(), q[0], q[1], q[2], q[3], s.width, s.height, s.fx, s.fy, s.cx, s.cy,
                       s.near, s.far, o.reference_indices.size(),
                       Fraction(o.reference_indices.size(), reference_size),
                       Fraction(o.reference_indices.size() + o.outside_keys.size(), reference_size),
                       o.rays_traced);
  }
  return csv;
}

std::string VoxelPly(const std::vector<uint64_t>& keys, double cell_size) {
  std::string ply = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment vantage voxel centres, cell size {} m\n"
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
      cell_size, keys.size());
  const size_t header = ply.size();
  ply.resize(header + keys.size() * 12);
  char* out = ply.data() + header;
  for (uint64_t key : keys) {
    const Vec3 c = VoxelCenter(key, cell_size);
    const float xyz[3] = {static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())};
    std::memcpy(out, xyz, 12);
    out += 12;
  }
  return ply;
}

std::vector<uint64_t> ObservedKeys(const VisibilityFile& data, const std::vector<uint32_t>& chosen) {
  std::vector<uint64_t> keys;
  for (uint32_t index : chosen) {
    const Observation& o = data.observations.at(index);
    for (uint32_t r : o.reference_indices) keys.push_back(data.reference.keys[r]);
    keys.insert(keys.end(), o.outside_keys.begin(), o.outside_keys.end());
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

std::map<std::string, std::string> ReportFiles(const Report& report) {
  VANTAGE_CHECK(report.data != nullptr && report.is_derived);
  std::map<std::string, std::string> files;
  files["report.json"] = ReportJson(report);
  files["candidates.csv"] = CandidatesCsv(report);
  files["reference.ply"] = VoxelPly(report.data->reference.keys, report.data->reference.cell_size);
  files["observed.ply"] =
      VoxelPly(ObservedKeys(*report.data, report.PrimaryChosen()), report.data->reference.cell_size);
  // A camera on an arm: the primary result's tour for the robot (docs/arm.md).
  const auto primary = static_cast<size_t>(report.primary);
  if (report.primary >= 0 && primary < report.tours.size() && report.tours[primary]) {
    files["views.yaml"] = detail::ViewsYaml(*report.tours[primary], *report.data);
    files["trajectory.json"] = detail::TrajectoryJson(*report.tours[primary]);
  }
  return files;
}

const std::set<std::string>& RunFolderFileNames() {
  static const std::set<std::string> names = {
      "report.json",         "report.html",   "candidates.csv",      "reference.ply",
      "observed.ply",        "view.png",      "constellation.world", "constellation.yaml",
      "static_transforms.yaml", "constellation.sdf", "cameras.urdf.xacro",
      "static_transforms.launch.py", "views.yaml", "trajectory.json"};
  return names;
}

void WriteOutputs(const std::string& out_dir, const Report& report,
                  const std::map<std::string, std::string>& extra_files) {
  std::map<std::string, std::string> files = ReportFiles(report);
  files.insert(extra_files.begin(), extra_files.end());
  detail::WriteFolderAtomically(out_dir, files, RunFolderFileNames());
}

}  // namespace vantage
