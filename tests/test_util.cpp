#include "test_util.hpp"

#include <coin/Clp_C_Interface.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "vantage/rng.hpp"

namespace vantage::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  const fs::path base = fs::temp_directory_path() /
                        ("vantage_test_" + std::to_string(::getpid()) + "_" +
                         std::to_string(counter++));
  fs::remove_all(base);
  fs::create_directories(base);
  path_ = base.string();
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempDir::File(const std::string& name) const { return path_ + "/" + name; }

void WriteText(const std::string& path, const std::string& text) {
  const fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CommandResult RunVantage(const std::string& args) {
  TempDir dir;
  const std::string out_file = dir.File("stdout");
  const std::string err_file = dir.File("stderr");
  const std::string command =
      std::string(VANTAGE_BINARY) + " " + args + " >" + out_file + " 2>" + err_file + " </dev/null";
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = ReadText(out_file);
  result.err = ReadText(err_file);
  return result;
}

std::string DataPath(const std::string& name) { return std::string(VANTAGE_TEST_DATA) + "/" + name; }

std::string Costa2017Dir() {
  return fs::weakly_canonical(fs::path(VANTAGE_SHARED_DIR) / "worlds" / "costa2017").string();
}

std::string SceneDifference(const Scene& a, const Scene& b) {
  if (a.objects.size() != b.objects.size())
    return std::to_string(a.objects.size()) + " objects vs " + std::to_string(b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    const SceneObject& x = a.objects[i];
    const SceneObject& y = b.objects[i];
    const std::string which = "object " + std::to_string(i) + " (" + x.name + "): ";
    if (x.name != y.name) return which + "named " + y.name + " in the other";
    if (x.role != y.role) return which + "another role";
    if (x.mesh.vertices.size() != y.mesh.vertices.size() ||
        x.mesh.triangles.size() != y.mesh.triangles.size()) {
      return which + std::to_string(x.mesh.vertices.size()) + " vertices, " +
             std::to_string(x.mesh.triangles.size()) + " triangles vs " +
             std::to_string(y.mesh.vertices.size()) + ", " +
             std::to_string(y.mesh.triangles.size());
    }
    for (size_t v = 0; v < x.mesh.vertices.size(); ++v)
      if (x.mesh.vertices[v] != y.mesh.vertices[v]) return which + "vertex " + std::to_string(v);
    for (size_t t = 0; t < x.mesh.triangles.size(); ++t)
      if (x.mesh.triangles[t] != y.mesh.triangles[t])
        return which + "triangle " + std::to_string(t);
  }
  return "";
}

int RimVertices(const TriangleMesh& mesh, double z, double radius) {
  int rim = 0;
  for (const Vec3& v : mesh.vertices) {
    if (std::abs(v.z() - z) < 1e-12 && std::abs(v.head<2>().norm() - radius) < 1e-12) ++rim;
  }
  return rim;
}

double CoverageLpOptimum(const CoverageLpSpec& spec) {
  const size_t m = spec.rows.size();
  const size_t cells = spec.weights.size();
  const bool by_group = !spec.groups.empty();
  int group_count = 0;
  for (const int g : spec.groups) group_count = std::max(group_count, g + 1);
  // Columns: x_0..x_{m-1}, y_0..y_{cells-1}, then t (groups). Rows: one per cell, the capacity
  // row, then one per group.
  std::vector<std::vector<std::pair<int, double>>> columns(m + cells + (by_group ? 1 : 0));
  std::vector<int> seers(cells, 0);
  for (size_t i = 0; i < m; ++i) {
    const bool usable = spec.coefficients[i] <= spec.capacity;
    for (const uint32_t c : spec.rows[i]) {
      columns[i].push_back({static_cast<int>(c), -1.0});
      if (usable) ++seers[c];
    }
    columns[i].push_back({static_cast<int>(cells), spec.coefficients[i]});
  }
  std::vector<double> lower(columns.size(), 0.0), upper(columns.size(), 1.0);
  std::vector<double> objective(columns.size(), 0.0);
  for (size_t i = 0; i < m; ++i) upper[i] = spec.coefficients[i] <= spec.capacity ? 1.0 : 0.0;
  for (size_t c = 0; c < cells; ++c) {
    const size_t q = m + c;
    columns[q].push_back({static_cast<int>(c), static_cast<double>(spec.k)});
    if (by_group) {
      columns[q].push_back({static_cast<int>(cells) + 1 + spec.groups[c], -spec.weights[c]});
    } else {
      objective[q] = spec.weights[c];
    }
    upper[q] = seers[c] >= spec.k ? 1.0 : 0.0;
  }
  if (by_group) {
    for (int g = 0; g < group_count; ++g)
      columns.back().push_back({static_cast<int>(cells) + 1 + g, 1.0});
    objective.back() = 1.0;
  }
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> indices;
  std::vector<double> values;
  for (const auto& column : columns) {
    for (const auto& [row, value] : column) {
      indices.push_back(row);
      values.push_back(value);
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
  }
  const size_t row_count = cells + 1 + static_cast<size_t>(group_count);
  std::vector<double> row_lower(row_count, -1e30), row_upper(row_count, 0.0);
  row_upper[cells] = spec.capacity;
  Clp_Simplex* clp = Clp_newModel();
  Clp_setLogLevel(clp, 0);
  Clp_loadProblem(clp, static_cast<int>(columns.size()), static_cast<int>(row_count), starts.data(),
                  indices.data(), values.data(), lower.data(), upper.data(), objective.data(),
                  row_lower.data(), row_upper.data());
  Clp_setObjSense(clp, -1);
  Clp_initialSolve(clp);
  const int status = Clp_status(clp);
  const double optimum = Clp_objectiveValue(clp);
  Clp_deleteModel(clp);
  if (status != 0) throw std::runtime_error("CLP did not solve the LP");
  return optimum;
}

bool AggregateLess(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
                   const std::vector<size_t>& sizes, bool by_min) {
  __extension__ typedef __int128 Int;
  Int denominator = 1;
  for (const size_t r : sizes) denominator *= static_cast<Int>(r);
  const auto units = [&](const std::vector<uint64_t>& cells, size_t s) {
    return static_cast<Int>(cells[s]) * (denominator / static_cast<Int>(sizes[s]));
  };
  Int sum_a = 0, sum_b = 0, min_a = denominator, min_b = denominator;
  for (size_t s = 0; s < sizes.size(); ++s) {
    sum_a += units(a, s);
    sum_b += units(b, s);
    min_a = std::min(min_a, units(a, s));
    min_b = std::min(min_b, units(b, s));
  }
  if (by_min && min_a != min_b) return min_a < min_b;
  return sum_a < sum_b;
}

std::vector<Observation> PatchInstance(uint64_t seed, size_t candidates, size_t cells,
                                       bool hits) {
  std::vector<Observation> obs(candidates);
  for (size_t i = 0; i < candidates; ++i) {
    Rng rng(seed, Stream::kTest, i);
    const auto length = static_cast<size_t>(rng.Uniform(0.05, 0.4) * static_cast<double>(cells));
    const size_t first = rng.Below(cells - length);
    for (size_t c = 0; c < cells; ++c) {
      const bool in_patch = c >= first && c < first + length;
      if ((in_patch && rng.Uniform01() > 0.05) || rng.Uniform01() < 0.02) {
        obs[i].reference_indices.push_back(static_cast<uint32_t>(c));
        if (hits) obs[i].reference_hits.push_back(static_cast<uint16_t>(1 + rng.Below(5)));
      }
    }
  }
  return obs;
}

}  // namespace vantage::test
