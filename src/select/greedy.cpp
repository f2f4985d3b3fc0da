// Best single candidate, lazy greedy and the greedy-based upper bound (SYSTEM.md, Select).
#include <algorithm>
#include <functional>
#include <queue>

#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {

uint32_t BestCandidate(const CoverageMatrix& matrix) {
  VANTAGE_CHECK(matrix.candidate_count() > 0);
  uint32_t best = 0;
  for (uint32_t i = 1; i < matrix.candidate_count(); ++i) {
    if (matrix.RowWeight(i) > matrix.RowWeight(best)) best = i;  // strict: ties keep the lower
  }
  return best;
}

std::vector<uint32_t> GreedyComplete(const CoverageMatrix& matrix,
                                     std::vector<uint32_t> chosen,
                                     size_t n) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(n <= m && chosen.size() <= n);
  std::vector<bool> is_chosen(m, false);
  Bitset covered = matrix.EmptySet();
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < m && !is_chosen[c]);
    is_chosen[c] = true;
    matrix.AddTo(c, &covered);
  }
  // Lazy greedy (Minoux): gains only shrink as the cover grows (submodularity), so a gain computed
  // in an earlier round is an upper bound. An entry whose gain is fresh (computed this round) and
  // on top of the heap is the true maximum; the heap's order (gain, then lower index first) makes
  // it the lowest-index maximum, as plain greedy would choose.
  struct Entry {
    uint64_t gain;
    uint32_t candidate;
    size_t round;
  };
  const auto lower_priority = [](const Entry& a, const Entry& b) {
    return a.gain != b.gain ? a.gain < b.gain : a.candidate > b.candidate;
  };
  std::vector<Entry> entries;
  entries.reserve(m);
  size_t round = chosen.size();
  for (uint32_t i = 0; i < m; ++i) {
    if (is_chosen[i]) continue;
    entries.push_back({chosen.empty() ? matrix.RowWeight(i) : matrix.Gain(i, covered), i, round});
  }
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower_priority)> heap(lower_priority,
                                                                                std::move(entries));
  while (chosen.size() < n && !heap.empty()) {
    Entry top = heap.top();
    heap.pop();
    if (top.round == round) {
      if (top.gain == 0) break;  // nothing adds anything any more: fill by index below
      chosen.push_back(top.candidate);
      is_chosen[top.candidate] = true;
      matrix.AddTo(top.candidate, &covered);
      ++round;
    } else {
      top.gain = matrix.Gain(top.candidate, covered);
      top.round = round;
      heap.push(top);
    }
  }
  for (uint32_t i = 0; i < m && chosen.size() < n; ++i) {
    if (!is_chosen[i]) {
      chosen.push_back(i);
      is_chosen[i] = true;
    }
  }
  return chosen;
}

uint64_t SimpleUpperBound(const CoverageMatrix& matrix,
                          std::span<const uint32_t> chosen,
                          size_t n) {
  // f(OPT) <= f(S) + sum over OPT \ S of gain(j | S) <= f(S) + the n largest gains (submodular).
  Bitset covered = matrix.EmptySet();
  for (const uint32_t c : chosen) matrix.AddTo(c, &covered);
  const uint64_t base = matrix.SetWeight(covered);
  std::vector<uint64_t> gains(matrix.candidate_count());
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) gains[i] = matrix.Gain(i, covered);
  const size_t k = std::min(n, gains.size());
  std::partial_sort(gains.begin(), gains.begin() + static_cast<std::ptrdiff_t>(k), gains.end(),
                    std::greater<>());
  uint64_t bound = base;
  for (size_t i = 0; i < k; ++i) bound += gains[i];
  return std::min(bound, matrix.seen_weight());
}

}  // namespace vantage::detail
