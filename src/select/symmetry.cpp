// Column orbits of a set system with nauty (see symmetry.hpp).
//
// The set system becomes its bipartite incidence graph: vertices 0..m-1 are the columns, m.. the
// rows, an edge where a column holds a row. An automorphism of that graph which keeps columns
// among columns (and each column in its colour) is a symmetry of the set system and conversely;
// nauty's initial partition (lab, ptn) keeps the colour classes and the rows apart.
#include "select/symmetry.hpp"

#include <nauty.h>
#include <nausparse.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>

#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

// nauty keeps work space in static storage: one call at a time.
std::mutex nauty_mutex;

}  // namespace

ColumnOrbits FindColumnOrbits(std::span<const std::vector<uint32_t>> columns, size_t row_count,
                              std::span<const uint32_t> colours) {
  VANTAGE_CHECK(colours.empty() || colours.size() == columns.size());
  const size_t m = columns.size();
  ColumnOrbits result;
  result.orbit.resize(m);
  std::iota(result.orbit.begin(), result.orbit.end(), uint32_t{0});
  if (m <= 1) return result;
  const size_t n = m + row_count;
  VANTAGE_CHECK(n < static_cast<size_t>(NAUTY_INFINITY) - 2);
  // Adjacency in nauty's sparse form: each edge both ways.
  std::vector<size_t> row_degree(row_count, 0);
  size_t edges = 0;
  for (size_t j = 0; j < m; ++j) {
    for (const uint32_t r : columns[j]) {
      VANTAGE_CHECK(r < row_count);
      ++row_degree[r];
    }
    edges += columns[j].size();
  }
  std::vector<size_t> v(n);
  std::vector<int> d(n);
  std::vector<int> e(2 * edges);
  std::vector<size_t> fill(n);
  size_t at = 0;
  for (size_t j = 0; j < m; ++j) {
    v[j] = at;
    d[j] = static_cast<int>(columns[j].size());
    at += columns[j].size();
  }
  for (size_t r = 0; r < row_count; ++r) {
    v[m + r] = at;
    d[m + r] = static_cast<int>(row_degree[r]);
    at += row_degree[r];
  }
  for (size_t i = 0; i < n; ++i) fill[i] = v[i];
  for (size_t j = 0; j < m; ++j) {
    for (const uint32_t r : columns[j]) {
      e[fill[j]++] = static_cast<int>(m + r);
      e[fill[m + r]++] = static_cast<int>(j);
    }
  }
  // Colour classes: the columns by colour (then index), then the rows.
  std::vector<int> lab(n), ptn(n, 1), orbits(n);
  std::iota(lab.begin(), lab.end(), 0);
  if (!colours.empty()) {
    std::stable_sort(lab.begin(), lab.begin() + static_cast<std::ptrdiff_t>(m),
                     [&](int a, int b) { return colours[a] < colours[b]; });
    for (size_t p = 0; p + 1 < m; ++p) {
      if (colours[lab[p]] != colours[lab[p + 1]]) ptn[p] = 0;
    }
  }
  ptn[m - 1] = 0;
  ptn[n - 1] = 0;

  sparsegraph graph;
  SG_INIT(graph);
  graph.nv = static_cast<int>(n);
  graph.nde = 2 * edges;
  graph.v = v.data();
  graph.d = d.data();
  graph.e = e.data();
  graph.vlen = n;
  graph.dlen = n;
  graph.elen = e.size();
  DEFAULTOPTIONS_SPARSEGRAPH(options);
  options.defaultptn = FALSE;
  options.getcanon = FALSE;
  statsblk stats;
  {
    const std::lock_guard<std::mutex> lock(nauty_mutex);
    sparsenauty(&graph, lab.data(), ptn.data(), orbits.data(), &options, &stats, nullptr);
  }
  VANTAGE_CHECK(stats.errstatus == 0);
  result.log10_group_size = std::log10(stats.grpsize1) + stats.grpsize2;
  // nauty's orbits[i] is the smallest vertex of i's orbit; columns map to columns only.
  for (size_t j = 0; j < m; ++j) {
    VANTAGE_CHECK(orbits[j] >= 0 && static_cast<size_t>(orbits[j]) < m);
    result.orbit[j] = static_cast<uint32_t>(orbits[j]);
  }
  std::vector<size_t> size(m, 0);
  for (size_t j = 0; j < m; ++j) ++size[result.orbit[j]];
  for (size_t j = 0; j < m; ++j) {
    if (size[result.orbit[j]] > 1) ++result.moved_columns;
  }
  return result;
}

}  // namespace vantage::detail
