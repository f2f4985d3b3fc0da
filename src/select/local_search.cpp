// Swap local search after greedy (SYSTEM.md, Select: `local`).
#include <algorithm>

#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {

std::vector<uint32_t> LocalSearch(const CoverageMatrix& matrix, std::vector<uint32_t> chosen) {
  const size_t m = matrix.candidate_count();
  const size_t n = chosen.size();
  if (n == 0 || n >= m) return chosen;
  std::vector<bool> is_chosen(m, false);
  // How many chosen candidates see each element: removing one frees the elements it alone sees.
  std::vector<uint32_t> cover_count(matrix.element_count(), 0);
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < m && !is_chosen[c]);
    is_chosen[c] = true;
    for (const uint32_t e : matrix.Row(c)) ++cover_count[e];
  }
  const size_t words = matrix.word_count();
  Bitset uncovered(words);
  while (true) {
    // Elements no chosen candidate sees (bits past the last element never meet a row).
    std::fill(uncovered.begin(), uncovered.end(), ~uint64_t{0});
    for (const uint32_t c : chosen) {
      for (const uint32_t e : matrix.Row(c)) uncovered[e >> 6] &= ~(uint64_t{1} << (e & 63));
    }
    int64_t best_delta = 0;
    size_t best_position = 0;
    uint32_t best_in = 0;
    Bitset freed;
    for (size_t p = 0; p < n; ++p) {
      const uint32_t out = chosen[p];
      freed = uncovered;
      uint64_t loss = 0;
      for (const uint32_t e : matrix.Row(out)) {
        if (cover_count[e] == 1) {
          freed[e >> 6] |= uint64_t{1} << (e & 63);
          loss += matrix.Weight(e);
        }
      }
      for (uint32_t j = 0; j < m; ++j) {
        if (is_chosen[j]) continue;
        // A candidate cannot add more than it sees: skip those that cannot beat the best swap.
        if (static_cast<int64_t>(matrix.RowWeight(j)) - static_cast<int64_t>(loss) <= best_delta)
          continue;
        const int64_t delta =
            static_cast<int64_t>(matrix.WeightIn(j, freed)) - static_cast<int64_t>(loss);
        if (delta > best_delta) {
          best_delta = delta;
          best_position = p;
          best_in = j;
        }
      }
    }
    if (best_delta <= 0) break;
    const uint32_t out = chosen[best_position];
    for (const uint32_t e : matrix.Row(out)) --cover_count[e];
    for (const uint32_t e : matrix.Row(best_in)) ++cover_count[e];
    is_chosen[out] = false;
    is_chosen[best_in] = true;
    chosen[best_position] = best_in;
  }
  return chosen;
}

}  // namespace vantage::detail
