// The fewest (or cheapest) sensors that see every cell, by branch and bound with orbital
// branching (see methods.hpp, OrbitalSetCover).
//
// A node fixes some columns in and some out; what is left is a set-cover problem of its own, the
// free columns over the rows no fixed-in column covers. Its bound is the fixed-in cost plus the
// LP relaxation's value, made a proof whatever CLP's round-off: CLP's duals y >= 0 are scaled so
// that no column's sum exceeds its cost, and any such y bounds the LP (weak duality) and so every
// cover; costs are whole, so the bound is rounded up.
// Branching follows Ostrowski, Linderoth, Rossi, Smriglio (Math. Prog. 2011, "Orbital
// branching"): nauty finds the symmetry group of the node's own problem (columns coloured by
// cost); for an orbit O of free columns and a representative j in O, the children are x_j = 1 and
// x_k = 0 for every k in O. A cover that uses some k in O maps, by the automorphism taking k to
// j, to a cover as cheap that uses j, so the two children hold an optimum between them. Nodes are taken best bound first
// (deepest first among equal bounds), so the smallest open bound is a proven lower bound when
// the time runs out.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <queue>
#include <span>
#include <string>
#include <vector>

#include "select/cbc_module.hpp"
#include "select/coverage_matrix.hpp"
#include "select/milp.hpp"
#include "select/methods.hpp"
#include "select/symmetry.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Above these sizes the search is not tried (each node solves an LP and a graph automorphism
// problem over the whole residual).
constexpr size_t kMaxCandidates = 3000;
constexpr size_t kMaxNonzeros = 200000;
// Open nodes are kept while they take less than this many bytes of column states.
constexpr size_t kMaxOpenBytes = size_t{1} << 29;
// Round-off allowed when the certified LP value is rounded up to whole sensors.
constexpr double kRoundOff = 1e-6;

enum : int8_t { kOut = -1, kFree = 0, kIn = 1 };

struct Node {
  std::vector<int8_t> state;  // per column
  double bound = 0;           // proven, whole: no cover in this node costs less
  size_t depth = 0;
  uint64_t sequence = 0;  // creation order: later first among equals (depth first)
};

struct LaterFirst {
  bool operator()(const Node& a, const Node& b) const {
    if (a.bound != b.bound) return a.bound > b.bound;
    if (a.depth != b.depth) return a.depth < b.depth;
    return a.sequence < b.sequence;
  }
};

// The set-cover instance the search works on: the candidates left after dominance, as columns
// over the matrix's elements (every element must be covered).
struct Instance {
  std::vector<uint32_t> candidate;             // column -> candidate
  std::vector<double> cost;                    // column -> its cost (whole, > 0)
  std::vector<std::vector<uint32_t>> columns;  // column -> sorted elements
  std::vector<std::vector<uint32_t>> rows;     // element -> columns
};

Instance Reduce(const CoverageMatrix& matrix, std::span<const double> costs) {
  // A candidate whose elements another candidate also sees, at no more cost, is never needed
  // (swapping it for the other keeps a cover and its cost); of equals, the first is kept
  // (the MILP's reduction, milp.hpp).
  const std::vector<bool> dominated = DominatedCandidates(matrix, costs);
  Instance instance;
  for (uint32_t a = 0; a < matrix.candidate_count(); ++a) {
    if (dominated[a]) continue;
    instance.candidate.push_back(a);
    instance.cost.push_back(costs.empty() ? 1.0 : costs[a]);
    instance.columns.push_back(matrix.Row(a));
  }
  instance.rows.resize(matrix.element_count());
  for (size_t j = 0; j < instance.columns.size(); ++j)
    for (const uint32_t e : instance.columns[j]) instance.rows[e].push_back(static_cast<uint32_t>(j));
  return instance;
}

// A node's problem after propagation: which rows are uncovered and which free columns touch
// them. Empty `feasible` when some row cannot be covered any more.
struct Residual {
  bool feasible = true;
  double fixed_in = 0;  // the cost of the columns fixed in
  std::vector<uint32_t> rows;     // uncovered rows
  std::vector<uint32_t> columns;  // free columns that cover one of them
};

// Fixes in the only free column of a row that has one, until none is left; columns that cover
// nothing uncovered are fixed out (no cost is negative: they are never needed).
Residual Propagate(const Instance& instance, std::vector<int8_t>* state) {
  const size_t m = instance.columns.size();
  const size_t rows = instance.rows.size();
  Residual residual;
  std::vector<uint8_t> covered(rows, 0);
  for (size_t j = 0; j < m; ++j) {
    if ((*state)[j] != kIn) continue;
    for (const uint32_t r : instance.columns[j]) covered[r] = 1;
  }
  bool changed = true;
  while (changed) {
    changed = false;
    for (size_t r = 0; r < rows; ++r) {
      if (covered[r]) continue;
      uint32_t only = 0;
      size_t free = 0;
      for (const uint32_t j : instance.rows[r]) {
        if ((*state)[j] == kFree) {
          only = j;
          if (++free > 1) break;
        }
      }
      if (free == 0) {
        residual.feasible = false;
        return residual;
      }
      if (free == 1) {
        (*state)[only] = kIn;
        for (const uint32_t q : instance.columns[only]) covered[q] = 1;
        changed = true;
      }
    }
  }
  for (size_t r = 0; r < rows; ++r)
    if (!covered[r]) residual.rows.push_back(static_cast<uint32_t>(r));
  for (size_t j = 0; j < m; ++j) {
    if ((*state)[j] == kIn) residual.fixed_in += instance.cost[j];
    if ((*state)[j] != kFree) continue;
    const bool useful = std::any_of(instance.columns[j].begin(), instance.columns[j].end(),
                                    [&](uint32_t r) { return !covered[r]; });
    if (useful) {
      residual.columns.push_back(static_cast<uint32_t>(j));
    } else {
      (*state)[j] = kOut;
    }
  }
  return residual;
}

// The residual's columns as lists of positions in residual.rows.
std::vector<std::vector<uint32_t>> ResidualColumns(const Instance& instance,
                                                   const Residual& residual) {
  std::vector<int64_t> position(instance.rows.size(), -1);
  for (size_t p = 0; p < residual.rows.size(); ++p) position[residual.rows[p]] = static_cast<int64_t>(p);
  std::vector<std::vector<uint32_t>> columns(residual.columns.size());
  for (size_t c = 0; c < residual.columns.size(); ++c) {
    for (const uint32_t r : instance.columns[residual.columns[c]])
      if (position[r] >= 0) columns[c].push_back(static_cast<uint32_t>(position[r]));
  }
  return columns;
}

// The LP relaxation of the residual (min sum c x, each row covered at least once, x >= 0; every
// c > 0): the certified value (see the file's comment) and CLP's x, within `seconds` (the duals
// of an unfinished solve still give a valid, weaker value).
struct LpOutcome {
  double value = 0;
  std::vector<double> x;
};

LpOutcome SolveLp(const std::vector<std::vector<uint32_t>>& columns,
                  const std::vector<double>& cost, size_t row_count, double seconds) {
  LpOutcome outcome;
  outcome.x.assign(columns.size(), 0.0);
  if (row_count == 0) return outcome;
  std::vector<int> starts{0};
  std::vector<int> indices;
  for (const std::vector<uint32_t>& column : columns) {
    indices.insert(indices.end(), column.begin(), column.end());
    starts.push_back(static_cast<int>(indices.size()));
  }
  constexpr double kInfinity = std::numeric_limits<double>::max();  // CLP's COIN_DBL_MAX
  const std::vector<double> values(indices.size(), 1.0);
  const std::vector<double> lower(columns.size(), 0.0), upper(columns.size(), kInfinity);
  const std::vector<double> row_lower(row_count, 1.0), row_upper(row_count, kInfinity);
  const CbcModuleApi& clp = Cbc();
  const auto deleter = [&clp](ClpHandle* model) { clp.clp_delete(model); };
  const std::unique_ptr<ClpHandle, decltype(deleter)> owner(
      clp.clp_new(static_cast<int>(columns.size()), static_cast<int>(row_count), starts.data(),
                  indices.data(), values.data(), lower.data(), upper.data(), cost.data(),
                  row_lower.data(), row_upper.data()),
      deleter);
  ClpHandle* model = owner.get();
  clp.clp_set_maximum_seconds(model, std::max(seconds, 1e-3));
  clp.clp_dual(model);
  const double* duals = clp.clp_dual_row_solution(model);
  const double* primal = clp.clp_primal_column_solution(model);
  std::vector<double> y(row_count);
  for (size_t r = 0; r < row_count; ++r) y[r] = duals[r] > 0 ? duals[r] : 0.0;  // NaN -> 0
  double largest = 1.0, total = 0.0;  // the scale that brings each column's sum to its cost
  for (size_t c = 0; c < columns.size(); ++c) {
    double sum = 0;
    for (const uint32_t r : columns[c]) sum += y[r];
    largest = std::max(largest, sum / cost[c]);
  }
  for (const double value : y) total += value;
  outcome.value = total / largest;
  for (size_t c = 0; c < columns.size(); ++c)
    outcome.x[c] = std::isfinite(primal[c]) ? primal[c] : 0.0;
  return outcome;
}

// A cover of the residual by greedy (most uncovered rows per cost, then the larger LP value),
// without the columns that turn out redundant: positions in the residual's columns.
std::vector<uint32_t> GreedyCover(const std::vector<std::vector<uint32_t>>& columns,
                                  const std::vector<double>& cost, size_t row_count,
                                  const std::vector<double>& x) {
  std::vector<uint32_t> times(row_count, 0);
  std::vector<uint32_t> chosen;
  size_t left = row_count;
  std::vector<uint8_t> taken(columns.size(), 0);
  while (left > 0) {
    size_t best = columns.size();
    double best_gain = 0;
    for (size_t c = 0; c < columns.size(); ++c) {
      if (taken[c]) continue;
      size_t covers = 0;
      for (const uint32_t r : columns[c]) covers += times[r] == 0;
      const double gain = static_cast<double>(covers) / cost[c];
      if (gain > best_gain || (gain == best_gain && gain > 0 && x[c] > x[best])) {
        best = c;
        best_gain = gain;
      }
    }
    if (best == columns.size()) return {};  // cannot happen on a feasible residual
    taken[best] = 1;
    chosen.push_back(static_cast<uint32_t>(best));
    for (const uint32_t r : columns[best]) left -= times[r]++ == 0;
  }
  // Drop redundant columns, the last chosen first.
  for (size_t p = chosen.size(); p-- > 0;) {
    const std::vector<uint32_t>& column = columns[chosen[p]];
    if (std::all_of(column.begin(), column.end(), [&](uint32_t r) { return times[r] >= 2; })) {
      for (const uint32_t r : column) --times[r];
      chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(p));
    }
  }
  return chosen;
}

}  // namespace

OrbitalSetCoverResult OrbitalSetCover(const CoverageMatrix& matrix,
                                      std::span<const double> costs,
                                      const std::vector<uint32_t>& start,
                                      double lower,
                                      double time_limit) {
  VANTAGE_CHECK(!matrix.has_counts() && matrix.CoveredWeight(start) == matrix.seen_weight() &&
                (costs.empty() || costs.size() == matrix.candidate_count()));
  const auto start_time = std::chrono::steady_clock::now();
  const auto cost_of = [&](const std::vector<uint32_t>& chosen) {
    return costs.empty() ? static_cast<double>(chosen.size()) : TotalCost(costs, chosen);
  };
  OrbitalSetCoverResult result;
  result.chosen = start;
  double best = cost_of(start);
  result.lower_bound = std::min(std::ceil(lower - kRoundOff), best);
  size_t nonzeros = 0;
  for (const std::vector<uint32_t>& row : matrix.rows()) nonzeros += row.size();
  if (matrix.candidate_count() > kMaxCandidates || nonzeros > kMaxNonzeros) return result;
  // Whole, positive costs only: the bound is then rounded up, and proofs are exact.
  if (!costs.empty() && (!AllWhole(costs) || std::any_of(costs.begin(), costs.end(),
                                                         [](double c) { return c <= 0; })))
    return result;
  const Instance instance = Reduce(matrix, costs);
  std::vector<uint32_t> colours;  // cost classes for nauty
  if (!costs.empty()) {
    std::vector<double> distinct = instance.cost;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    for (const double c : instance.cost)
      colours.push_back(static_cast<uint32_t>(
          std::lower_bound(distinct.begin(), distinct.end(), c) - distinct.begin()));
  }
  const ColumnOrbits root = FindColumnOrbits(instance.columns, instance.rows.size(), colours);
  if (root.moved_columns == 0) return result;  // no symmetry: the other methods are as good
  result.applied = true;
  const size_t m = instance.columns.size();

  std::priority_queue<Node, std::vector<Node>, LaterFirst> open;
  uint64_t sequence = 0;
  open.push(Node{std::vector<int8_t>(m, kFree), result.lower_bound, 0, sequence++});
  bool stopped = false;
  const auto take = [&](const std::vector<int8_t>& state, const Residual& residual,
                        const std::vector<uint32_t>& cover) {
    result.chosen.clear();
    for (size_t j = 0; j < m; ++j)
      if (state[j] == kIn) result.chosen.push_back(instance.candidate[j]);
    for (const uint32_t c : cover) result.chosen.push_back(instance.candidate[residual.columns[c]]);
    best = cost_of(result.chosen);
  };
  while (!open.empty()) {
    if (open.top().bound >= best) break;  // every open node is bounded: proven
    ThrowIfInterrupted();
    const double left = time_limit - SecondsSince(start_time);
    if (left <= 0 || open.size() * m > kMaxOpenBytes) {
      stopped = true;
      break;
    }
    Node node = open.top();
    open.pop();
    ++result.nodes;
    const Residual residual = Propagate(instance, &node.state);
    if (!residual.feasible) continue;
    if (residual.rows.empty()) {
      if (residual.fixed_in < best) take(node.state, residual, {});
      continue;
    }
    const std::vector<std::vector<uint32_t>> columns = ResidualColumns(instance, residual);
    std::vector<double> cost;
    for (const uint32_t j : residual.columns) cost.push_back(instance.cost[j]);
    const LpOutcome lp = SolveLp(columns, cost, residual.rows.size(), left);
    const double bound =
        std::max(node.bound, residual.fixed_in + std::ceil(lp.value - kRoundOff));
    // A cover from the LP's guidance may improve the best.
    const std::vector<uint32_t> cover = GreedyCover(columns, cost, residual.rows.size(), lp.x);
    double cover_cost = residual.fixed_in;
    for (const uint32_t c : cover) cover_cost += cost[c];
    if (!cover.empty() && cover_cost < best) take(node.state, residual, cover);
    if (bound >= best) continue;
    // Branch on the orbit with the largest LP mass (the largest orbit where the LP is uniform).
    std::vector<uint32_t> node_colours;
    for (const uint32_t j : residual.columns)
      node_colours.push_back(colours.empty() ? 0 : colours[j]);
    const ColumnOrbits orbits =
        FindColumnOrbits(columns, residual.rows.size(), colours.empty() ? std::span<const uint32_t>()
                                                                        : node_colours);
    std::vector<double> mass(columns.size(), 0.0);
    std::vector<size_t> size(columns.size(), 0);
    for (size_t c = 0; c < columns.size(); ++c) {
      mass[orbits.orbit[c]] += lp.x[c];
      ++size[orbits.orbit[c]];
    }
    size_t chosen_orbit = columns.size();
    for (size_t c = 0; c < columns.size(); ++c) {
      if (orbits.orbit[c] != c) continue;
      if (chosen_orbit == columns.size() || mass[c] > mass[chosen_orbit] + 1e-9 ||
          (mass[c] > mass[chosen_orbit] - 1e-9 && size[c] > size[chosen_orbit])) {
        chosen_orbit = c;
      }
    }
    Node out{node.state, bound, node.depth + 1, sequence++};
    for (size_t c = 0; c < columns.size(); ++c)
      if (orbits.orbit[c] == chosen_orbit) out.state[residual.columns[c]] = kOut;
    Node in{std::move(node.state), bound, node.depth + 1, sequence++};
    in.state[residual.columns[chosen_orbit]] = kIn;
    open.push(std::move(out));
    open.push(std::move(in));
  }
  result.lower_bound = open.empty() ? best : std::min(best, open.top().bound);
  result.lower_bound = std::max(result.lower_bound, std::min(std::ceil(lower - kRoundOff), best));
  result.proven_optimal = result.lower_bound >= best;
  result.note = fmt::format(
      "orbital branching: {} nodes, {} of {} candidates in symmetric orbits (group 10^{:.1f}){}",
      result.nodes, root.moved_columns, m, root.log10_group_size,
      stopped ? " — reached the time limit" : "");
  return result;
}

}  // namespace vantage::detail
