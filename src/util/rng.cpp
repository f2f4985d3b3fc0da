#include "vantage/rng.hpp"

namespace vantage {
namespace {

uint64_t SplitMix64(uint64_t* state) {
  uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

Rng::Rng(uint64_t seed, Stream stream, uint64_t index, uint64_t sub_index) {
  // Mix every key part through SplitMix64 so neighbouring indices give unrelated streams.
  uint64_t state = seed;
  uint64_t mixed = SplitMix64(&state);
  state = mixed ^ (static_cast<uint64_t>(stream) * 0xD1B54A32D192ED03ULL);
  mixed = SplitMix64(&state);
  state = mixed ^ (index * 0xAEF17502108EF2D9ULL);
  mixed = SplitMix64(&state);
  state = mixed ^ (sub_index * 0x9E6C63D0676A9A99ULL);
  for (uint64_t& s : s_) s = SplitMix64(&state);
}

uint64_t Rng::NextU64() {
  const uint64_t result = Rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = Rotl(s_[3], 45);
  return result;
}

double Rng::Uniform01() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }

uint64_t Rng::Below(uint64_t n) {
  // Lemire's rejection keeps the draw unbiased and identical on every platform.
  const uint64_t threshold = (0 - n) % n;
  while (true) {
    const uint64_t x = NextU64();
    __extension__ using U128 = unsigned __int128;
    const U128 m = static_cast<U128>(x) * n;
    if (static_cast<uint64_t>(m) >= threshold) return static_cast<uint64_t>(m >> 64);
  }
}

}  // namespace vantage
