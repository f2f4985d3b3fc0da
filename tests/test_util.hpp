#pragma once
/// Helpers shared by the tests: temporary folders, running the CLI, reading files.
#include <cstdint>
#include <string>
#include <vector>

#include "vantage/scene.hpp"
#include "vantage/visibility.hpp"

namespace vantage::test {

/// Whether this suite is built with ASan + UBSan (scripts/sanitize.sh). There CBC and the code
/// around it run several times slower, so a proof Release finishes in milliseconds can meet its
/// wall-clock limit on a loaded machine. Tests that require a proof within a limit still check
/// every answer and bound there, and that a proven answer is the optimum, but not that the proof
/// finished: the sanitizers check memory and undefined behaviour, not speed.
inline constexpr bool kSanitized = VANTAGE_SANITIZED != 0;

/// A fresh empty folder under the system temp dir, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  /// path() + "/" + name
  std::string File(const std::string& name) const;

 private:
  std::string path_;
};

/// Writes text to a file (creating parent folders).
void WriteText(const std::string& path, const std::string& text);
std::string ReadText(const std::string& path);

struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};
/// Runs the vantage binary with the given argument string (shell-quoted by the caller).
CommandResult RunVantage(const std::string& args);

/// Absolute path of a file in tests/data.
std::string DataPath(const std::string& name);
/// Absolute path of the shared costa2017 folder (../shared/worlds/costa2017).
std::string Costa2017Dir();

/// The first difference between two scenes (object names, roles, vertices and triangles compared
/// exactly), or "" when they are the same.
std::string SceneDifference(const Scene& a, const Scene& b);
/// Vertices of `mesh` on the circle of `radius` about the z axis in the plane z = `z` (1e-12).
int RimVertices(const TriangleMesh& mesh, double z, double radius);

/// A weighted coverage LP written out cell by cell (no merging), for CoverageLpOptimum:
///   max sum_c weights_c y_c   (groups empty), or
///   max t s.t. t <= sum_{c in group g} weights_c y_c for every group g   (groups: per cell),
///   s.t. k y_c <= sum_{i sees c} x_i,  sum_i coefficients_i x_i <= capacity,  x, y in [0, 1],
/// with x_i = 0 where coefficients_i > capacity and y_c = 0 where fewer than k candidates with
/// x_i free see c (no integer answer covers it).
struct CoverageLpSpec {
  std::vector<std::vector<uint32_t>> rows;  ///< cells each candidate sees
  std::vector<double> weights;              ///< per cell
  std::vector<int> groups;                  ///< per cell (0, 1, ...), or empty
  int k = 1;
  std::vector<double> coefficients;  ///< per candidate
  double capacity = 0;
};

/// The LP optimum of `spec`, solved by CLP (coin-or-clp) on the explicit model.
double CoverageLpOptimum(const CoverageLpSpec& spec);

/// Candidates seeing contiguous patches (cells merge into elements of many cells: weights with
/// several bits) with a share of ragged cells (elements of one cell); with `hits`, each seen cell
/// gets 1 to 5 points. Deterministic for a seed.
std::vector<Observation> PatchInstance(uint64_t seed, size_t candidates, size_t cells,
                                       bool hits = false);

/// a < b for the aggregate of the fractions cells[s] / sizes[s]: plain (one state), the mean, or
/// the minimum then the mean. Exact: every fraction in units of 1 / prod(sizes).
bool AggregateLess(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
                   const std::vector<size_t>& sizes, bool by_min);

}  // namespace vantage::test
