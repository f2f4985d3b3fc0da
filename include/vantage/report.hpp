#pragma once
/// Outputs of a run (SYSTEM.md, Outputs): report.json (vantage.report/1), candidates.csv,
/// reference.ply, observed.ply; written into a temporary folder and renamed into place.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vantage/observe.hpp"
#include "vantage/robustness.hpp"
#include "vantage/select.hpp"

namespace vantage {

/// Version of vantage, as written in report.json.
const char* Version();

struct Timings {
  double load = 0, reference = 0, observe = 0, select = 0, total = 0;
};

/// What `--refine` did (issue 9): the refined constellation is results[result], grown from
/// results[from_result] by tracing new poses around its sensors.
struct RefinementInfo {
  int from_result = -1;
  int result = -1;
  double coverage_before = 0, coverage_after = 0;
  std::vector<double> history;  ///< coverage after each round, coverage_before first
  int rounds = 0;
  size_t new_candidates = 0;
  uint64_t extra_rays = 0;
  double seconds = 0;
};

/// A scene with states: how results were scored and what each state is.
struct StatesInfo {
  std::string over;  ///< "mean" or "min"
  struct State {
    std::string name;
    size_t reference_voxels = 0;
    int same_as = -1;  ///< an earlier state with the same geometry, whose rays it reuses
  };
  std::vector<State> states;
};

/// Everything one report holds.
struct Report {
  std::string scene;
  uint64_t seed = 1;
  const VisibilityFile* data = nullptr;  ///< reference, candidates, observations (not owned)
  std::vector<Selection> results;
  /// Index into `results` of the constellation that observed.ply shows; -1 = PrimaryResult().
  int primary = -1;
  Timings timings;
  std::vector<std::string> notes;
  /// Read-outs for one result (usually the primary), when computed (issue 9).
  std::optional<Robustness> robustness;
  std::optional<RefinementInfo> refinement;
  /// Set for a scene with states; `data` then holds the first state's reference and sets.
  std::optional<StatesInfo> states;
};

/// The result that stands for the run: among those with the largest n, the highest coverage
/// (ties: the first). -1 when there is no result.
int PrimaryResult(const std::vector<Selection>& results);

/// The report.json text (pretty-printed, keys of SYSTEM.md plus extras).
std::string ReportJson(const Report& report);
/// report.json's "robustness" object alone, as JSON text (report.html shows the same).
std::string RobustnessJsonText(const Robustness& robustness, const VisibilityFile& data);
/// candidates.csv text: one row per candidate.
std::string CandidatesCsv(const Report& report);
/// Binary little-endian PLY of voxel centres (x y z float).
std::string VoxelPly(const std::vector<uint64_t>& keys, double cell_size);
/// Packed keys that the union of `chosen` observes (in R and outside it), sorted.
std::vector<uint64_t> ObservedKeys(const VisibilityFile& data, const std::vector<uint32_t>& chosen);

/// Writes every output into `out_dir` atomically: a temporary sibling folder, renamed over the
/// old one only once complete. `extra_files` (name -> content) are written beside the others.
void WriteOutputs(const std::string& out_dir, const Report& report,
                  const std::map<std::string, std::string>& extra_files = {});

/// A constellation to evaluate: the candidates of a report.json (and, when present, the
/// sensors named by its first `results` entry; otherwise every candidate).
struct Constellation {
  std::vector<Candidate> sensors;
};
/// Reads report.json-shaped input; InputError naming file and problem when malformed.
Constellation LoadConstellation(const std::string& path);

}  // namespace vantage
