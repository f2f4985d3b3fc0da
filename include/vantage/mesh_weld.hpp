#pragma once
/// Vertices welded by position, for the mesh readers (scene) and the closed-mesh test
/// (reference): one pass through an open-addressing hash of the positions' bits.
#include <cstdint>
#include <cstring>
#include <vector>

#include "vantage/types.hpp"

namespace vantage {

/// For each of the `count` positions at(i), the index of its first equal one (equality is
/// exact; -0.0 equals +0.0). The positions must be finite.
template <class At>
std::vector<uint32_t> FirstEqualPositions(size_t count, const At& at) {
  // + 0.0 turns -0.0 into +0.0, so that equal bits are exactly the doubles that compare equal.
  const auto hash = [](const Vec3& v) {
    const double key[3] = {v.x() + 0.0, v.y() + 0.0, v.z() + 0.0};
    uint64_t bits[3];
    std::memcpy(bits, key, sizeof(bits));
    uint64_t h = (bits[0] ^ (bits[0] >> 31)) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits[1]) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 32) ^ bits[2]) * 0x94D049BB133111EBull;
    return static_cast<size_t>(h ^ (h >> 31));
  };
  // A table of vertex indices, at most half full (no allocation per vertex, as the
  // std::unordered_map before it had).
  constexpr uint32_t kUnused = UINT32_MAX;
  size_t capacity = 16;
  while (capacity < 2 * count) capacity *= 2;
  std::vector<uint32_t> first_at(capacity, kUnused);
  std::vector<uint32_t> same_as(count);
  for (uint32_t i = 0; i < count; ++i) {
    const Vec3 v = at(i);
    size_t slot = hash(v) & (capacity - 1);
    while (first_at[slot] != kUnused && at(first_at[slot]) != v)
      slot = (slot + 1) & (capacity - 1);
    if (first_at[slot] == kUnused) first_at[slot] = i;
    same_as[i] = first_at[slot];
  }
  return same_as;
}

}  // namespace vantage
