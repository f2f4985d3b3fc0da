// Symmetry of set systems (select/symmetry.cpp, nauty) and the fewest sensors seeing every cell
// by orbital branching (select/set_cover_search.cpp), checked against enumeration: orbits
// against every column permutation of small systems, covers against every subset, on covering
// designs built here from their definitions (affine and projective planes and spaces, cyclic
// designs, the cube's 4-cycles, 2-colourings) and on random cyclic instances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/symmetry.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

using Blocks = std::vector<std::vector<uint32_t>>;  // cells, each the candidates that see it

// Candidates' observations from blocks: candidate i sees cell c when i is in block c.
std::vector<Observation> FromBlocks(const Blocks& blocks, size_t candidates) {
  std::vector<Observation> obs(candidates);
  for (uint32_t c = 0; c < blocks.size(); ++c)
    for (const uint32_t i : blocks[c]) obs[i].reference_indices.push_back(c);
  return obs;
}

// The fewest candidates meeting every block, by enumerating every subset.
size_t FewestByEnumeration(const Blocks& blocks, size_t candidates) {
  size_t fewest = candidates + 1;
  for (uint32_t mask = 0; mask < (1u << candidates); ++mask) {
    const auto size = static_cast<size_t>(__builtin_popcount(mask));
    if (size >= fewest) continue;
    const bool covers = std::all_of(blocks.begin(), blocks.end(), [&](const auto& block) {
      return std::any_of(block.begin(), block.end(), [&](uint32_t i) { return mask >> i & 1; });
    });
    if (covers) fewest = size;
  }
  return fewest;
}

bool Covers(const Blocks& blocks, const std::vector<uint32_t>& chosen) {
  const std::set<uint32_t> in(chosen.begin(), chosen.end());
  return std::all_of(blocks.begin(), blocks.end(), [&](const auto& block) {
    return std::any_of(block.begin(), block.end(), [&](uint32_t i) { return in.count(i) > 0; });
  });
}

// AG(2, 3), the Steiner triple system of order 9: the lines {p + t d} of Z_3^2.
Blocks AffinePlane3() {
  std::set<std::vector<uint32_t>> lines;
  const int directions[4][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}};
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (const auto& d : directions) {
        std::vector<uint32_t> line;
        for (int t = 0; t < 3; ++t)
          line.push_back(static_cast<uint32_t>(((x + t * d[0]) % 3) * 3 + (y + t * d[1]) % 3));
        std::sort(line.begin(), line.end());
        lines.insert(line);
      }
  return Blocks(lines.begin(), lines.end());
}

// PG(3, 2), a Steiner triple system of order 15: points the nonzero vectors of F_2^4, lines
// {a, b, a + b}.
Blocks ProjectiveSpace32() {
  std::set<std::vector<uint32_t>> lines;
  for (uint32_t a = 1; a < 16; ++a)
    for (uint32_t b = a + 1; b < 16; ++b) {
      std::vector<uint32_t> line{a - 1, b - 1, (a ^ b) - 1};
      std::sort(line.begin(), line.end());
      lines.insert(line);
    }
  return Blocks(lines.begin(), lines.end());
}

// The cyclic design of the base blocks over Z_n: every shift of every base block.
Blocks Cyclic(uint32_t n, const Blocks& base) {
  std::set<std::vector<uint32_t>> blocks;
  for (const std::vector<uint32_t>& b : base)
    for (uint32_t s = 0; s < n; ++s) {
      std::vector<uint32_t> shifted;
      for (const uint32_t x : b) shifted.push_back((x + s) % n);
      std::sort(shifted.begin(), shifted.end());
      shifted.erase(std::unique(shifted.begin(), shifted.end()), shifted.end());
      blocks.insert(shifted);
    }
  return Blocks(blocks.begin(), blocks.end());
}

// The 3-cube's 4-cycles (its faces) as blocks over its 12 edges.
Blocks CubeFaces() {
  std::map<std::pair<int, int>, uint32_t> edge;
  for (int v = 0; v < 8; ++v)
    for (int b = 0; b < 3; ++b)
      if (!(v >> b & 1)) edge.emplace(std::pair(v, v | 1 << b), static_cast<uint32_t>(edge.size()));
  Blocks faces;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      for (int v = 0; v < 8; ++v) {
        if (v >> a & 1 || v >> b & 1) continue;
        const int va = v | 1 << a, vb = v | 1 << b, vab = v | 1 << a | 1 << b;
        std::vector<uint32_t> face{edge.at({v, va}), edge.at({v, vb}), edge.at({va, vab}),
                                   edge.at({vb, vab})};
        std::sort(face.begin(), face.end());
        faces.push_back(face);
      }
  return faces;
}

// The 3-subsets of 6 points (candidates) and the 2-colourings with both colours up to swapping
// (cells): a subset sees a colouring in which it is monochromatic (one colour has 3 points or
// more, so every cell is seen).
Blocks Colourings6(size_t* candidates) {
  std::vector<uint32_t> subsets;
  for (uint32_t s = 0; s < 64; ++s)
    if (__builtin_popcount(s) == 3) subsets.push_back(s);
  *candidates = subsets.size();
  Blocks blocks;
  for (uint32_t colour = 1; colour < 32; ++colour) {  // point 5 always colour 0
    std::vector<uint32_t> block;
    for (uint32_t i = 0; i < subsets.size(); ++i)
      if ((subsets[i] & colour) == 0 || (subsets[i] & colour) == subsets[i]) block.push_back(i);
    EXPECT_FALSE(block.empty());
    blocks.push_back(block);
  }
  return blocks;
}

// Column orbits by enumeration: a column permutation s is a symmetry when some row permutation
// goes with it, i.e. when the rows' column sets, mapped by s, are the same multiset.
std::vector<uint32_t> OrbitsByEnumeration(const std::vector<std::vector<uint32_t>>& columns,
                                          size_t row_count, const std::vector<uint32_t>& colours) {
  const size_t m = columns.size();
  std::vector<std::vector<uint32_t>> rows(row_count);
  for (uint32_t j = 0; j < m; ++j)
    for (const uint32_t r : columns[j]) rows[r].push_back(j);
  std::multiset<std::vector<uint32_t>> original(rows.begin(), rows.end());
  std::vector<uint32_t> orbit(m);
  std::iota(orbit.begin(), orbit.end(), 0u);
  std::vector<uint32_t> s(m);
  std::iota(s.begin(), s.end(), 0u);
  do {
    bool keeps = true;
    for (size_t j = 0; j < m && keeps; ++j) keeps = colours.empty() || colours[s[j]] == colours[j];
    if (!keeps) continue;
    std::multiset<std::vector<uint32_t>> mapped;
    for (const std::vector<uint32_t>& row : rows) {
      std::vector<uint32_t> image;
      for (const uint32_t j : row) image.push_back(s[j]);
      std::sort(image.begin(), image.end());
      mapped.insert(image);
    }
    if (mapped != original) continue;
    for (size_t j = 0; j < m; ++j) {  // j and s[j] share an orbit: merge, smallest as label
      const uint32_t a = orbit[j], b = orbit[s[j]];
      if (a == b) continue;
      for (uint32_t& o : orbit)
        if (o == std::max(a, b)) o = std::min(a, b);
    }
  } while (std::next_permutation(s.begin(), s.end()));
  return orbit;
}

TEST(Symmetry, OrbitsMatchEnumeration) {
  Rng rng(42, Stream::kTest, 0);
  int symmetric = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const size_t m = 3 + trial % 5;  // up to 7 columns: 5,040 permutations
    const size_t row_count = 2 + trial % 6;
    std::vector<std::vector<uint32_t>> columns(m);
    // Half the trials copy columns with the rows relabelled, so that symmetries are common.
    for (size_t j = 0; j < m; ++j) {
      if (trial % 2 == 1 && j >= m / 2 && j - m / 2 < m / 2) {
        for (const uint32_t r : columns[j - m / 2])
          columns[j].push_back(static_cast<uint32_t>(row_count - 1 - r));
        std::sort(columns[j].begin(), columns[j].end());
        continue;
      }
      for (uint32_t r = 0; r < row_count; ++r)
        if (rng.Uniform01() < 0.4) columns[j].push_back(r);
    }
    std::vector<uint32_t> colours;
    if (trial % 3 == 2)
      for (size_t j = 0; j < m; ++j) colours.push_back(static_cast<uint32_t>(rng.Uniform01() * 2));
    const detail::ColumnOrbits found = detail::FindColumnOrbits(columns, row_count, colours);
    const std::vector<uint32_t> expected = OrbitsByEnumeration(columns, row_count, colours);
    EXPECT_EQ(found.orbit, expected) << "trial " << trial;
    size_t moved = 0;
    for (size_t j = 0; j < m; ++j)
      moved += std::count(expected.begin(), expected.end(), expected[j]) > 1;
    EXPECT_EQ(found.moved_columns, moved);
    symmetric += moved > 0;
  }
  EXPECT_GE(symmetric, 20);
}

TEST(Symmetry, AffinePlaneGroupOrder) {
  // Aut(AG(2, 3)) = AGL(2, 3): 9 translations times |GL(2, 3)| = 48, transitive on the points.
  const Blocks lines = AffinePlane3();
  ASSERT_EQ(lines.size(), 12u);
  std::vector<std::vector<uint32_t>> columns(9);
  for (uint32_t c = 0; c < lines.size(); ++c)
    for (const uint32_t p : lines[c]) columns[p].push_back(c);
  const detail::ColumnOrbits orbits = detail::FindColumnOrbits(columns, lines.size());
  EXPECT_EQ(orbits.moved_columns, 9u);
  EXPECT_EQ(orbits.orbit, std::vector<uint32_t>(9, 0));
  EXPECT_NEAR(orbits.log10_group_size, std::log10(432.0), 1e-9);
}

// Runs OrbitalSetCover on the blocks and checks it against enumeration: a cover, a valid bound,
// and with time enough the optimum proved. Returns whether it applied.
bool CheckAgainstEnumeration(const Blocks& blocks, size_t candidates, double seconds) {
  const std::vector<Observation> obs = FromBlocks(blocks, candidates);
  const detail::CoverageMatrix matrix(obs, blocks.size());
  const size_t fewest = FewestByEnumeration(blocks, candidates);
  std::vector<uint32_t> all(candidates);
  std::iota(all.begin(), all.end(), 0u);
  // A start that sees everything: every candidate that sees something.
  std::vector<uint32_t> start;
  for (const uint32_t i : all)
    if (!obs[i].reference_indices.empty()) start.push_back(i);
  const detail::OrbitalSetCoverResult r = detail::OrbitalSetCover(matrix, {}, start, 1, seconds);
  EXPECT_TRUE(Covers(blocks, r.chosen));
  EXPECT_LE(r.lower_bound, fewest);
  EXPECT_GE(r.chosen.size(), fewest);
  if (r.applied && seconds >= 10) {
    EXPECT_TRUE(r.proven_optimal) << r.note;
    EXPECT_EQ(r.chosen.size(), fewest) << r.note;
  }
  if (!r.applied) {
    EXPECT_EQ(r.chosen, start);
  }
  return r.applied;
}

TEST(OrbitalSetCover, CoveringDesignsMatchEnumeration) {
  // STS(9): 5 points meet every line; PG(3, 2): a plane, 7 points (Bose, Burton 1966);
  // PG(2, 3) from the difference set {0, 1, 3, 9} mod 13: a line, 4 points; the cube's faces:
  // 3 edges. Enumeration derives each; the search must prove it.
  EXPECT_EQ(FewestByEnumeration(AffinePlane3(), 9), 5u);
  EXPECT_TRUE(CheckAgainstEnumeration(AffinePlane3(), 9, 20));
  EXPECT_EQ(FewestByEnumeration(ProjectiveSpace32(), 15), 7u);
  EXPECT_TRUE(CheckAgainstEnumeration(ProjectiveSpace32(), 15, 20));
  EXPECT_EQ(FewestByEnumeration(Cyclic(13, {{0, 1, 3, 9}}), 13), 4u);
  EXPECT_TRUE(CheckAgainstEnumeration(Cyclic(13, {{0, 1, 3, 9}}), 13, 20));
  EXPECT_EQ(FewestByEnumeration(CubeFaces(), 12), 3u);
  EXPECT_TRUE(CheckAgainstEnumeration(CubeFaces(), 12, 20));
  size_t candidates = 0;
  const Blocks colourings = Colourings6(&candidates);
  EXPECT_TRUE(CheckAgainstEnumeration(colourings, candidates, 20));
}

TEST(OrbitalSetCover, RandomCyclicDesignsMatchEnumeration) {
  Rng rng(7, Stream::kTest, 0);
  int applied = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const auto n = static_cast<uint32_t>(7 + trial % 8);  // up to 14 candidates
    Blocks base(1 + trial % 3);
    for (std::vector<uint32_t>& b : base) {
      for (uint32_t x = 0; x < n; ++x)
        if (rng.Uniform01() < 0.3) b.push_back(x);
      if (b.empty()) b.push_back(0);
    }
    Blocks blocks = Cyclic(n, base);
    // Some cells twice (weights after the merge) and, in a third of the trials, one extra
    // block that breaks the symmetry.
    blocks.push_back(blocks.front());
    if (trial % 3 == 0) blocks.push_back({0, 1});
    applied += CheckAgainstEnumeration(blocks, n, 20);
  }
  EXPECT_GE(applied, 20);
}

// The cheapest candidates meeting every block, by enumerating every subset.
double CheapestByEnumeration(const Blocks& blocks, const std::vector<double>& costs) {
  double cheapest = 1e300;
  for (uint32_t mask = 0; mask < (1u << costs.size()); ++mask) {
    double cost = 0;
    for (uint32_t i = 0; i < costs.size(); ++i)
      if (mask >> i & 1) cost += costs[i];
    if (cost >= cheapest) continue;
    const bool covers = std::all_of(blocks.begin(), blocks.end(), [&](const auto& block) {
      return std::any_of(block.begin(), block.end(), [&](uint32_t i) { return mask >> i & 1; });
    });
    if (covers) cheapest = cost;
  }
  return cheapest;
}

TEST(OrbitalSetCover, CostsMatchEnumeration) {
  // Cyclic designs over Z_n whose costs repeat with a period d dividing n (shifting by d keeps
  // them), whole costs; every fourth trial has half costs, where the search does not apply.
  // Checked directly and through Select (--goal 1 --cheapest, method exact).
  Rng rng(11, Stream::kTest, 0);
  int applied = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const auto n = static_cast<uint32_t>(8 + trial % 7);
    uint32_t period = 1;
    for (uint32_t d = 2; d < n; ++d)
      if (n % d == 0 && rng.Uniform01() < 0.5) period = d;
    std::vector<double> base(period);
    for (double& c : base) c = 1.0 + static_cast<double>(rng.Below(4)) + (trial % 4 == 3 ? 0.5 : 0);
    std::vector<double> costs(n);
    for (uint32_t x = 0; x < n; ++x) costs[x] = base[x % period];
    Blocks blocks_base(1 + trial % 2);
    for (std::vector<uint32_t>& b : blocks_base) {
      for (uint32_t x = 0; x < n; ++x)
        if (rng.Uniform01() < 0.3) b.push_back(x);
      if (b.empty()) b.push_back(0);
    }
    const Blocks blocks = Cyclic(n, blocks_base);
    SCOPED_TRACE(testing::Message() << "trial " << trial << " n " << n << " period " << period);
    const double cheapest = CheapestByEnumeration(blocks, costs);
    const std::vector<Observation> obs = FromBlocks(blocks, n);
    const detail::CoverageMatrix matrix(obs, blocks.size());
    std::vector<uint32_t> start;
    for (uint32_t i = 0; i < n; ++i)
      if (!obs[i].reference_indices.empty()) start.push_back(i);
    const detail::OrbitalSetCoverResult r = detail::OrbitalSetCover(matrix, costs, start, 0, 20);
    double cost = 0;
    for (const uint32_t i : r.chosen) cost += costs[i];
    EXPECT_TRUE(Covers(blocks, r.chosen));
    EXPECT_GE(cost, cheapest - 1e-9);
    EXPECT_LE(r.lower_bound, cheapest + 1e-9);
    if (r.applied) {
      ++applied;
      EXPECT_TRUE(r.proven_optimal) << r.note;
      EXPECT_NEAR(cost, cheapest, 1e-9) << r.note;
    }
    if (trial % 4 == 3) {
      EXPECT_FALSE(r.applied);
    }
    SelectOptions options;
    options.method = Method::kExact;
    options.time_limit = 20;
    options.goal = 1.0;
    options.minimize_cost = true;
    options.costs = costs;
    const std::vector<Selection> results = Select(obs, blocks.size(), options);
    ASSERT_FALSE(results.empty());
    const Selection& s = results.back();
    EXPECT_TRUE(Covers(blocks, s.chosen));
    ASSERT_TRUE(s.cost.has_value());
    EXPECT_TRUE(s.proven_optimal);
    EXPECT_NEAR(*s.cost, cheapest, 1e-9);
    ASSERT_TRUE(s.cost_lower_bound.has_value());
    EXPECT_LE(*s.cost_lower_bound, cheapest + 1e-9);
  }
  EXPECT_GE(applied, 10);
}

TEST(OrbitalSetCover, BoundsHoldWhenStoppedAtOnce) {
  // No time: the answer is the start or better, and the bound still below the optimum.
  EXPECT_TRUE(CheckAgainstEnumeration(ProjectiveSpace32(), 15, 0));
  EXPECT_TRUE(CheckAgainstEnumeration(Cyclic(13, {{0, 1, 3, 9}}), 13, 0));
}

TEST(OrbitalSetCover, AsymmetricInstancesAreLeftAlone) {
  // A random instance's group is mostly trivial: nothing is done then (the start comes back).
  Rng rng(3, Stream::kTest, 0);
  int left_alone = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const size_t m = 7;
    Blocks blocks;
    for (int c = 0; c < 12; ++c) {
      std::vector<uint32_t> block;
      for (uint32_t i = 0; i < m; ++i)
        if (rng.Uniform01() < 0.35) block.push_back(i);
      if (block.empty()) block.push_back(static_cast<uint32_t>(c % m));
      blocks.push_back(block);
    }
    left_alone += !CheckAgainstEnumeration(blocks, m, 20);
  }
  EXPECT_GE(left_alone, 5);
}

TEST(OrbitalSetCover, SteinerTripleSystem27IsProved) {
  // STS(27) from AG(2, 3) tripled (Fulkerson, Nemhauser, Trotter 1974): 18 points.
  Blocks triples = AffinePlane3();
  for (uint32_t n = 9; n < 27; n *= 3) {
    Blocks next;
    for (uint32_t x = 0; x < n; ++x) next.push_back({x * 3, x * 3 + 1, x * 3 + 2});
    for (const std::vector<uint32_t>& t : triples)
      for (uint32_t i = 0; i < 3; ++i)
        for (uint32_t j = 0; j < 3; ++j) {
          std::vector<uint32_t> b{t[0] * 3 + i, t[1] * 3 + j, t[2] * 3 + (6 - i - j) % 3};
          std::sort(b.begin(), b.end());
          next.push_back(b);
        }
    triples = std::move(next);
  }
  ASSERT_EQ(triples.size(), 117u);
  const std::vector<Observation> obs = FromBlocks(triples, 27);
  const detail::CoverageMatrix matrix(obs, triples.size());
  std::vector<uint32_t> start(27);
  std::iota(start.begin(), start.end(), 0u);
  const detail::OrbitalSetCoverResult r = detail::OrbitalSetCover(matrix, {}, start, 1, 60);
  EXPECT_TRUE(r.applied);
  EXPECT_TRUE(Covers(triples, r.chosen));
  EXPECT_EQ(r.chosen.size(), 18u) << r.note;
  EXPECT_TRUE(r.proven_optimal) << r.note;
}

}  // namespace
}  // namespace vantage
