// Shards for job arrays: the cost split, --shard, and `vantage merge`.
#include <fmt/format.h>

#include <charconv>
#include <cstdlib>
#include <limits>
#include <map>

#include "vantage/distribute.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// What observing a candidate costs besides its rays (setup, sorting its cells), in rays.
constexpr uint64_t kOverheadRays = 256;
constexpr uint32_t kMaxShards = 1u << 20;
constexpr uint64_t kFnvOffset = 1469598103934665603ull, kFnvPrime = 1099511628211ull;

// VisibilityFingerprint (which leaves the observations out) without the scene's path (issue 44:
// content, not path).
uint64_t PartFingerprint(VisibilityFile* file) {
  std::string path = std::move(file->scene);
  file->scene.clear();
  const uint64_t fingerprint = VisibilityFingerprint(*file);
  file->scene = std::move(path);
  return fingerprint;
}

// A whole number in plain decimal: no sign, no leading zero (issue 44: "01/2" was accepted while
// every other whole number of the command line refuses it).
bool ParseWhole(std::string_view text, uint32_t* value) {
  if (text.size() > 1 && text.front() == '0') return false;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, *value);
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

std::vector<uint64_t> TraceCosts(const Reference& reference, std::span<const Candidate> candidates,
                                 const ObserveOptions& options) {
  std::vector<uint64_t> costs = CountRaysToTrace(reference, candidates, options);
  for (uint64_t& cost : costs) cost += kOverheadRays;
  return costs;
}

std::vector<size_t> SplitByCost(std::span<const uint64_t> costs, size_t parts) {
  VANTAGE_CHECK(parts >= 1);
  // Part p ends at the first candidate whose prefix cost reaches p/parts of the total; long double
  // holds the products exactly enough, and every process computes the same boundaries.
  long double total = 0;
  for (uint64_t c : costs) total += static_cast<long double>(c);
  std::vector<size_t> bounds(parts + 1, costs.size());
  bounds[0] = 0;
  size_t i = 0;
  long double prefix = 0;
  for (size_t p = 1; p < parts; ++p) {
    const long double target = total * static_cast<long double>(p) / parts;
    // Take the candidate when that brings the prefix closer to the target than leaving it (a
    // tie leaves it to the next part).
    while (i < costs.size() && prefix + static_cast<long double>(costs[i]) / 2 < target) {
      prefix += static_cast<long double>(costs[i]);
      ++i;
    }
    bounds[p] = i;
  }
  return bounds;
}

ShardSpec ParseShard(const std::string& text) {
  const auto bad = [&](const std::string& what) {
    return InputError(AtPlace("--shard", 0,
                              fmt::format("'{}' {} — give i/K with 0 <= i < K (e.g. --shard 0/4), "
                                          "or env/K to take i from SLURM_ARRAY_TASK_ID or "
                                          "JOB_COMPLETION_INDEX",
                                          text, what)));
  };
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw bad("has no '/'");
  ShardSpec shard;
  const std::string_view index(text.data(), slash);
  const std::string_view count(text.data() + slash + 1, text.size() - slash - 1);
  for (const std::string_view number : {index, count}) {
    if (number.size() > 1 && number.front() == '0')
      throw bad(fmt::format("has '{}' with a leading zero (it could be read as octal) — write i "
                            "and K in decimal without leading zeros",
                            number));
  }
  if (!ParseWhole(count, &shard.count) || shard.count < 1 || shard.count > kMaxShards)
    throw bad(fmt::format("has no shard count K from 1 to {}", kMaxShards));
  if (index == "env") {
    std::string variable;
    for (const char* name : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
      if (const char* value = std::getenv(name)) {
        variable = name;
        if (!ParseWhole(value, &shard.index))
          throw bad(fmt::format("takes i from {}, which is '{}', not a whole number", name,
                                value));
        break;
      }
    }
    if (variable.empty())
      throw bad("takes i from the job array, but neither SLURM_ARRAY_TASK_ID nor "
                "JOB_COMPLETION_INDEX is set");
    if (shard.index >= shard.count)
      throw bad(fmt::format("takes i = {} from {}, not below K = {} (number the array 0 to K-1, "
                            "e.g. sbatch --array=0-{})",
                            shard.index, variable, shard.count, shard.count - 1));
    return shard;
  }
  if (!ParseWhole(index, &shard.index)) throw bad("has no shard index i");
  if (shard.index >= shard.count) throw bad("has i not below K");
  return shard;
}

VisibilityShard ObserveShard(const ObserveRunOptions& options, const ShardSpec& shard,
                             const RunSettings& settings) {
  VANTAGE_CHECK(shard.count >= 1 && shard.index < shard.count);
  VisibilityShard result;
  result.index = shard.index;
  result.count = shard.count;
  result.build = BuildIdentity();
  result.settings = settings;
  result.geometry = kFnvOffset;
  bool first = true;
  ObserveRunOptions run = options;
  run.trace = [&](const RayScene& rays, const Reference& reference,
                  std::span<const Candidate> candidates, const ObserveOptions& observe) {
    // Every traced geometry (each state's) is the scene's content as observed.
    result.geometry = (result.geometry ^ rays.GeometryFingerprint()) * kFnvPrime;
    const std::vector<size_t> bounds =
        SplitByCost(TraceCosts(reference, candidates, observe), shard.count);
    const size_t begin = bounds[shard.index], end = bounds[shard.index + 1];
    std::vector<Observation> mine =
        Observe(rays, reference, candidates.subspan(begin, end - begin), observe);
    std::vector<Observation> all(candidates.size());
    for (size_t i = begin; i < end; ++i) all[i] = std::move(mine[i - begin]);
    if (first) {  // the file holds the first geometry's matrix
      for (size_t i = begin; i < end; ++i) result.candidates.push_back(static_cast<uint32_t>(i));
      first = false;
    }
    return all;
  };
  result.file = ObserveRun(run).data;
  result.fingerprint = PartFingerprint(&result.file);
  return result;
}

VisibilityFile MergeShards(std::span<const std::string> paths) {
  if (paths.empty())
    throw InputError(AtPlace("merge", 0, "no parts given — give the files of `vantage observe "
                                         "--shard i/K`, e.g. vantage merge part_*.vis --out all.vis"));
  std::vector<VisibilityShard> parts;
  std::map<uint32_t, size_t> by_index;  // shard index: position in `parts` and `paths`
  for (const std::string& path : paths) {
    VisibilityShard part = LoadVisibilityShard(path);
    if (!parts.empty()) {
      // What differs first, in the order a user finds it: the build, an option, the scene's
      // content, then anything else the file holds (candidates, R) — each naming both files.
      const VisibilityShard& first = parts.front();
      const std::string& first_path = paths.front();
      const auto refuse = [&](const std::string& what) {
        return InputError(AtPlace(path, 0, fmt::format("{} — merge only the parts of one run, all "
                                                       "observed with the same scene, options "
                                                       "and vantage",
                                                       what)));
      };
      if (part.build != first.build)
        throw refuse(fmt::format("was observed by another vantage build ({}) than {} ({})",
                                 part.build, first_path, first.build));
      if (const std::string difference =
              SettingsDifference(part.settings, path, first.settings, first_path);
          !difference.empty())
        throw refuse(fmt::format("was observed with other options than {}: {}", first_path,
                                 difference));
      if (part.geometry != first.geometry)
        throw refuse(fmt::format(
            "was observed in another scene geometry than {}: the scene, or a file it includes "
            "(a mesh, a URDF, an included model), was changed between the two `vantage observe "
            "--shard` runs",
            first_path));
      if (part.fingerprint != first.fingerprint)
        throw refuse(fmt::format("comes from another scene or other settings than {}: other "
                                 "candidates, R, seed or selection settings (fingerprint {:016x}, "
                                 "not {:016x})",
                                 first_path, part.fingerprint, first.fingerprint));
      if (part.count != first.count)
        throw InputError(AtPlace(
            path, 0, fmt::format("is shard {}/{}, but {} is of {} shards — merge the parts of one "
                                 "--shard i/K run",
                                 part.index, part.count, first_path, first.count)));
    }
    const auto [it, fresh] = by_index.emplace(part.index, parts.size());
    if (!fresh)
      throw InputError(AtPlace(
          path, 0, fmt::format("repeats shard {}/{} of {} — give each shard once", part.index,
                               part.count, paths[it->second])));
    parts.push_back(std::move(part));
  }
  const uint32_t count = parts.front().count;
  for (uint32_t i = 0; i < count; ++i) {
    if (!by_index.count(i))
      throw InputError(AtPlace(
          "merge", 0,
          fmt::format("shard {}/{} is missing (given: {} of {}) — add the part that `vantage "
                      "observe ... --shard {}/{}` wrote",
                      i, count, parts.size(), count, i, count)));
  }
  // Shard 0's file, whatever the order given: parts of one content from two paths merge into
  // the file of shard 0's path.
  const size_t base = by_index.at(0);
  VisibilityFile merged = std::move(parts[base].file);
  std::vector<int64_t> owner(merged.candidates.size(), -1);  // the part that observed each
  for (const auto& [index, p] : by_index) {
    VisibilityShard& part = parts[p];
    for (uint32_t c : part.candidates) {
      // Parts of one build, settings and content split alike: only a forged part gets here.
      if (owner[c] >= 0)
        throw InputError(AtPlace(paths[p], 0,
                                 fmt::format("observed candidate {} that {} observed too — the "
                                             "parts split the candidates differently; observe "
                                             "them again with one command",
                                             c, paths[static_cast<size_t>(owner[c])])));
      owner[c] = static_cast<int64_t>(p);
      if (p != base) merged.observations[c] = std::move(part.file.observations[c]);
    }
  }
  for (size_t c = 0; c < owner.size(); ++c) {
    if (owner[c] < 0)
      throw InputError(AtPlace("merge", 0,
                               fmt::format("no part observed candidate {} — the parts split the "
                                           "candidates differently; observe them again with one "
                                           "command",
                                           c)));
  }
  return merged;
}

}  // namespace vantage
