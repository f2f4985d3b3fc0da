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

bool ParseWhole(std::string_view text, uint32_t* value) {
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

VisibilityShard ObserveShard(const ObserveRunOptions& options, const ShardSpec& shard) {
  VANTAGE_CHECK(shard.count >= 1 && shard.index < shard.count);
  VisibilityShard result;
  result.index = shard.index;
  result.count = shard.count;
  bool first = true;
  ObserveRunOptions run = options;
  run.trace = [&](const RayScene& rays, const Reference& reference,
                  std::span<const Candidate> candidates, const ObserveOptions& observe) {
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
  result.fingerprint = VisibilityFingerprint(result.file);
  return result;
}

VisibilityFile MergeShards(std::span<const std::string> paths) {
  if (paths.empty())
    throw InputError(AtPlace("merge", 0, "no parts given — give the files of `vantage observe "
                                         "--shard i/K`, e.g. vantage merge part_*.vis --out all.vis"));
  std::vector<VisibilityShard> parts;
  std::map<uint32_t, std::string> by_index;
  for (const std::string& path : paths) {
    VisibilityShard part = LoadVisibilityShard(path);
    if (!parts.empty()) {
      const VisibilityShard& first = parts.front();
      if (part.fingerprint != first.fingerprint)
        throw InputError(AtPlace(
            path, 0,
            fmt::format("comes from another scene or other settings than {} (fingerprint {:016x}, "
                        "not {:016x}) — merge only the parts of one run, all observed with the "
                        "same scene, options and vantage",
                        paths.front(), part.fingerprint, first.fingerprint)));
      if (part.count != first.count)
        throw InputError(AtPlace(
            path, 0, fmt::format("is shard {}/{}, but {} is of {} shards — merge the parts of one "
                                 "--shard i/K run",
                                 part.index, part.count, paths.front(), first.count)));
    }
    const auto [it, fresh] = by_index.emplace(part.index, path);
    if (!fresh)
      throw InputError(AtPlace(
          path, 0, fmt::format("repeats shard {}/{} of {} — give each shard once", part.index,
                               part.count, it->second)));
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
  VisibilityFile merged = std::move(parts.front().file);
  std::vector<std::string> owner(merged.candidates.size());
  for (size_t p = 0; p < parts.size(); ++p) {
    VisibilityShard& part = parts[p];
    for (uint32_t c : part.candidates) {
      if (!owner[c].empty())
        throw InputError(AtPlace(paths[p], 0,
                                 fmt::format("observed candidate {} that {} observed too — "
                                             "were the parts written by different vantage builds?",
                                             c, owner[c])));
      owner[c] = paths[p];
      if (p > 0) merged.observations[c] = std::move(part.file.observations[c]);
    }
  }
  for (size_t c = 0; c < owner.size(); ++c) {
    if (owner[c].empty())
      throw InputError(AtPlace("merge", 0,
                               fmt::format("no part observed candidate {} — were the parts "
                                           "written by different vantage builds?",
                                           c)));
  }
  return merged;
}

}  // namespace vantage
