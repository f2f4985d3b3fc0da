// The selection table of issue #5: for each visibility matrix (files written by `vantage observe`,
// and optionally a generated instance of 1,000 candidates) and every N = 1..N_max, the coverage of
// ransac, greedy, local and exact, exact's proven bound and gap, and the seconds of each method run
// alone (matrix building included). Ends with the targets: greedy and local never below ransac at
// the same N; exact optimal or within 0.1 point (0.5 on the second 450-candidate world, *_b, and
// the generated instance) for N <= 10 within the time limit (issue 14).
//
// Usage: selection_table [--n-min 1] [--n-max 10] [--time-limit 10] [--iterations 1000] [--seed 1]
//                        [--generated] [FILE.vis ...]
#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/visibility_file.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

struct Instance {
  std::string name;
  std::vector<Observation> observations;
  size_t reference_size = 0;
};

// 1,000 candidates over 100,000 cells, each seeing one patch of 2-10 % of the cells with 5 % of
// the patch missing at random (bench_select.cpp's generator, between its clean and ragged cases).
Instance Generated() {
  constexpr size_t kCandidates = 1000;
  constexpr size_t kCells = 100000;
  Instance instance;
  instance.name = "generated (1000 x 100k)";
  instance.reference_size = kCells;
  instance.observations.resize(kCandidates);
  for (size_t i = 0; i < kCandidates; ++i) {
    Rng rng(1, Stream::kTest, i);
    const auto length = static_cast<size_t>(rng.Uniform(0.02, 0.10) * kCells);
    const size_t first = rng.Below(kCells - length);
    for (size_t c = first; c < first + length; ++c) {
      if (rng.Uniform01() >= 0.05) {
        instance.observations[i].reference_indices.push_back(static_cast<uint32_t>(c));
      }
    }
  }
  return instance;
}

struct Row {
  std::string method;
  int n = 0;
  double coverage = 0;
  std::optional<double> bound;
  bool is_optimal = false;
  double seconds = 0;
};

Row Run(const Instance& instance, Method method, int n, const SelectOptions& base) {
  SelectOptions options = base;
  options.method = method;
  options.n = n;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Selection> results =
      Select(instance.observations, instance.reference_size, options);
  Row row;
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  row.method = MethodName(method);
  row.n = n;
  row.coverage = results.at(0).coverage;
  row.bound = results.at(0).upper_bound;
  row.is_optimal = results.at(0).proven_optimal;
  return row;
}

int Main(int argc, char** argv) {
  // The library logs (e.g. exact's warnings) to the "vantage" logger: stderr, as the CLI does.
  spdlog::set_default_logger(spdlog::stderr_color_mt("vantage"));
  int n_min = 1;
  int n_max = 10;
  SelectOptions base;
  base.ransac_iterations = 1000;  // the paper's
  base.time_limit = 10;
  bool with_generated = false;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto next = [&]() -> std::string {
      if (a + 1 >= argc) throw InputError(arg + " needs a value");
      return argv[++a];
    };
    if (arg == "--n-min") {
      n_min = std::stoi(next());
    } else if (arg == "--n-max") {
      n_max = std::stoi(next());
    } else if (arg == "--time-limit") {
      base.time_limit = std::stod(next());
    } else if (arg == "--iterations") {
      base.ransac_iterations = std::stoi(next());
    } else if (arg == "--seed") {
      base.seed = std::stoull(next());
    } else if (arg == "--generated") {
      with_generated = true;
    } else {
      files.push_back(arg);
    }
  }
  std::vector<Instance> instances;
  for (const std::string& file : files) {
    VisibilityFile data = LoadVisibilityFile(file);
    Instance instance;
    instance.name = std::filesystem::path(file).stem().string();
    instance.observations = std::move(data.observations);
    instance.reference_size = data.reference.size();
    instances.push_back(std::move(instance));
  }
  if (with_generated) instances.push_back(Generated());

  fmt::print("RANSAC {} iterations, seed {}; exact time limit {} s per N.\n\n",
             base.ransac_iterations, base.seed, base.time_limit);
  fmt::print(
      "| instance | candidates | method | N | coverage % | bound % | gap (pp) | seconds |\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> misses;
  int greedy_checks = 0, exact_checks = 0;
  for (const Instance& instance : instances) {
    const int top = std::min<int>(n_max, static_cast<int>(instance.observations.size()));
    for (int n = n_min; n <= top; ++n) {
      std::vector<Row> rows;
      for (const Method m : {Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact})
        rows.push_back(Run(instance, m, n, base));
      for (const Row& r : rows) {
        const std::string bound =
            r.bound ? fmt::format("{:.2f}{}", 100 * *r.bound, r.is_optimal ? " (optimal)" : "")
                    : "";
        const std::string gap = r.bound ? fmt::format("{:.2f}", 100 * (*r.bound - r.coverage)) : "";
        fmt::print("| {} | {} | {} | {} | {:.2f} | {} | {} | {:.3f} |\n", instance.name,
                   instance.observations.size(), r.method, r.n, 100 * r.coverage, bound, gap,
                   r.seconds);
      }
      std::fflush(stdout);
      const double ransac = rows[0].coverage;
      for (size_t i = 1; i <= 2; ++i) {
        ++greedy_checks;
        if (rows[i].coverage < ransac) {
          misses.push_back(fmt::format("{} N={}: {} {:.2f} % < ransac {:.2f} %", instance.name, n,
                                       rows[i].method, 100 * rows[i].coverage, 100 * ransac));
        }
      }
      const Row& exact = rows[3];
      // Issue 14: proven or within `max_gap` points in the time limit, for every N <= 10; the
      // 450-candidate second draw (name ending in _b) and the generated instance: 0.5 points.
      const bool loose = instance.name.ends_with("_b") || instance.name.starts_with("generated");
      const double max_gap = loose ? 0.5 : 0.1;
      if (n <= 10) {
        ++exact_checks;
        const double gap = exact.bound ? 100 * (*exact.bound - exact.coverage) : 0.0;
        if (!exact.is_optimal && gap > max_gap + 1e-9) {
          misses.push_back(fmt::format("{} N={}: exact gap {:.2f} points > {}", instance.name, n,
                                       gap, max_gap));
        }
        if (exact.seconds > 1.1 * base.time_limit) {
          misses.push_back(
              fmt::format("{} N={}: exact took {:.1f} s", instance.name, n, exact.seconds));
        }
      }
    }
  }
  fmt::print(
      "\nTargets: greedy and local >= ransac at the same N ({} checks); exact optimal or gap <= "
      "0.1 point (0.5 on *_b and generated) within 1.1 x the time limit for N <= 10 ({} "
      "checks).\n",
      greedy_checks, exact_checks);
  if (misses.empty()) fmt::print("All targets met.\n");
  for (const std::string& miss : misses) fmt::print("MISSED: {}\n", miss);
  return misses.empty() ? 0 : 3;
}

}  // namespace
}  // namespace vantage

int main(int argc, char** argv) {
  try {
    return vantage::Main(argc, argv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "selection_table: {}\n", e.what());
    return 2;
  }
}
