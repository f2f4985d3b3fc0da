// A visibility matrix from elsewhere as a VisibilityFile (issue 42): checked as the .vis reader
// checks a file, with placeholders for what only a scene gives. scripts/vis_writer.py writes the
// same placeholders; tests/python/test_from_matrix.py compares the two files byte for byte.
#include "vantage/external_matrix.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "pipeline/common.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/sensors.hpp"

namespace vantage {
namespace {

constexpr uint64_t kCellsPerAxis = uint64_t{1} << 20;  // the packed keys' positive side
constexpr double kCellSize = 0.01;                     // [m]

// The placeholder camera: small, valid for CheckCandidate, of no catalog type.
SensorType PlaceholderSensor(size_t row, double cost) {
  SensorType s;
  s.id = fmt::format("t{}", row);
  s.name = "placeholder sensor";
  s.technology = "external";
  s.width = 64;
  s.height = 48;
  s.fx = 50.0;
  s.fy = 50.0;
  s.cx = 31.5;
  s.cy = 23.5;
  s.near = 0.1;
  s.far = 5.0;
  s.fps = 30.0;
  s.cost = cost;
  return s;
}

void CheckStructure(const ExternalMatrix& m) {
  if (m.cells < 1 || m.cells > kMaxExternalCells)
    throw InputError(
        fmt::format("cells: {} is out of range — give 1 to {} (R needs a cell; "
                    "indices into R are 32-bit)",
                    m.cells, kMaxExternalCells));
  if (m.indptr.size() < 2)
    throw InputError("csr: has no rows — give one row per candidate (indptr: rows + 1 entries)");
  if (m.indptr.front() != 0)
    throw InputError(fmt::format("csr: indptr starts at {} — it starts at 0", m.indptr.front()));
  for (size_t i = 0; i + 1 < m.indptr.size(); ++i) {
    if (m.indptr[i + 1] < m.indptr[i])
      throw InputError(
          fmt::format("csr: indptr decreases at row {} ({} then {}) — row starts "
                      "are non-decreasing",
                      i, m.indptr[i], m.indptr[i + 1]));
  }
  if (static_cast<uint64_t>(m.indptr.back()) != m.indices.size())
    throw InputError(
        fmt::format("csr: indptr ends at {} but indices has {} entries — they are "
                    "equal",
                    m.indptr.back(), m.indices.size()));
  if (!m.counts.empty() && m.counts.size() != m.indices.size())
    throw InputError(
        fmt::format("csr: data has {} entries for {} indices — give one point count "
                    "per index, or no data",
                    m.counts.size(), m.indices.size()));
  const size_t rows = m.indptr.size() - 1;
  if (!m.names.empty() && m.names.size() != rows)
    throw InputError(
        fmt::format("names: {} names for {} rows — give one per row", m.names.size(), rows));
  if (!m.costs.empty() && m.costs.size() != rows)
    throw InputError(
        fmt::format("costs: {} costs for {} rows — give one per row", m.costs.size(), rows));
}

void CheckRow(const ExternalMatrix& m, size_t row) {
  const auto start = static_cast<size_t>(m.indptr[row]);
  const auto end = static_cast<size_t>(m.indptr[row + 1]);
  for (size_t at = start; at < end; ++at) {
    const int64_t cell = m.indices[at];
    if (cell < 0 || static_cast<uint64_t>(cell) >= m.cells)
      throw InputError(
          fmt::format("csr: row {} has cell {}, outside [0, {}) — give indices below "
                      "the number of cells",
                      row, cell, m.cells));
    if (at > start && cell == m.indices[at - 1])
      throw InputError(
          fmt::format("csr: row {} lists cell {} twice — merge them (SciPy: "
                      "csr.sum_duplicates(), which adds their counts)",
                      row, cell));
    if (at > start && cell < m.indices[at - 1])
      throw InputError(
          fmt::format("csr: row {} lists cell {} after cell {} — sort each row's "
                      "indices (SciPy: csr.sort_indices())",
                      row, cell, m.indices[at - 1]));
    if (m.counts.empty()) continue;
    const double count = m.counts[at];
    if (!(count >= 1) || !std::isfinite(count) || count != std::floor(count))
      throw InputError(
          fmt::format("csr: data at row {}, cell {} is {} — point counts are whole "
                      "numbers >= 1 (drop stored zeros: csr.eliminate_zeros(); no "
                      "counts: give (indptr, indices) only)",
                      row, cell, count));
  }
}

void CheckNames(const std::vector<std::string>& names) {
  std::set<std::string_view> seen;
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    if (name.empty()) throw InputError(fmt::format("names: names[{}] is empty — name it", i));
    if (const size_t at = detail::FirstNonUtf8Byte(name); at != std::string::npos)
      throw InputError(fmt::format("names: names[{}] has byte 0x{:02X}, which is not UTF-8", i,
                                   static_cast<unsigned char>(name[at])));
    if (const std::string problem = detail::NameProblem(name); !problem.empty())
      throw InputError(fmt::format("names: names[{}] '{}' {}", i, detail::Escaped(name), problem));
    if (!seen.insert(name).second)
      throw InputError(fmt::format("names: '{}' is used twice (names[{}]) — names must be unique",
                                   detail::Escaped(name), i));
  }
}

// A matrix too large for this machine is refused before it is built (as observe refuses a run
// before any ray): R's keys, each seen cell's index and count, each candidate's sensor and pose,
// and twice that again for selection's working copies.
void CheckMemory(const ExternalMatrix& m) {
  const double bytes =
      2.0 * (8.0 * static_cast<double>(m.cells) + 6.0 * static_cast<double>(m.indices.size()) +
             1024.0 * static_cast<double>(m.indptr.size()));
  const double limit_mib = detail::MemoryLimitMiB(0);
  if (bytes / detail::kMiB > limit_mib)
    throw InputError(
        fmt::format("cells: {} cells and {} candidates need about {:.0f} MiB, above "
                    "75 % of this machine's RAM ({:.0f} MiB) — give fewer cells",
                    m.cells, m.indptr.size() - 1, bytes / detail::kMiB, limit_mib));
}

void CheckCosts(const std::vector<double>& costs) {
  for (size_t i = 0; i < costs.size(); ++i) {
    if (!(costs[i] >= 0 && costs[i] <= kMaxUnitCost))
      throw InputError(fmt::format("costs[{}]: {} is not a cost — give a number from 0 to {:g}",
                                   i, costs[i], kMaxUnitCost));
  }
}

}  // namespace

uint64_t CellOfExternalIndex(uint64_t index) {
  const auto k = static_cast<int64_t>(index % kCellsPerAxis);
  const auto j = static_cast<int64_t>((index / kCellsPerAxis) % kCellsPerAxis);
  const auto i = static_cast<int64_t>(index / kCellsPerAxis / kCellsPerAxis);
  return PackVoxel({i, j, k});
}

VisibilityFile VisibilityOfMatrix(const ExternalMatrix& m) {
  CheckStructure(m);
  const size_t rows = m.indptr.size() - 1;
  for (size_t row = 0; row < rows; ++row) CheckRow(m, row);
  CheckNames(m.names);
  CheckCosts(m.costs);
  CheckMemory(m);

  VisibilityFile file;
  file.scene = "external matrix";
  file.seed = 1;
  file.reference.cell_size = kCellSize;
  file.reference.keys.resize(m.cells);
  for (uint64_t e = 0; e < m.cells; ++e) file.reference.keys[e] = CellOfExternalIndex(e);
  file.candidates.reserve(rows);
  file.observations.reserve(rows);
  for (size_t row = 0; row < rows; ++row) {
    Candidate c;
    c.name = m.names.empty() ? fmt::format("c{}", row) : m.names[row];
    c.sensor = PlaceholderSensor(row, m.costs.empty() ? 1.0 : m.costs[row]);
    c.type_id = c.sensor.id;  // one type per candidate, so that each has its own cost
    c.population = "external";
    c.world_from_body.position = Vec3(static_cast<double>(row), 0.0, 1.0);
    c.world_from_body.rotation = Quat::Identity();
    file.candidates.push_back(std::move(c));

    Observation o;
    const auto start = static_cast<size_t>(m.indptr[row]);
    const auto end = static_cast<size_t>(m.indptr[row + 1]);
    o.reference_indices.reserve(end - start);
    o.reference_hits.reserve(end - start);
    for (size_t at = start; at < end; ++at) {
      o.reference_indices.push_back(static_cast<uint32_t>(m.indices[at]));
      const double count = m.counts.empty() ? 1.0 : m.counts[at];
      o.reference_hits.push_back(
          static_cast<uint16_t>(std::min(count, static_cast<double>(kMaxPointCount))));
    }
    const auto pixels = static_cast<uint64_t>(file.candidates.back().sensor.PixelCount());
    o.rays_traced = pixels;
    o.target_pixels = pixels;
    o.quality_pixels = pixels;
    file.observations.push_back(std::move(o));
  }
  return file;
}

}  // namespace vantage
