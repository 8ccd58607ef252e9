// The game's one source of randomness: xoshiro256** seeded through splitmix64.
//
// Written out here rather than taken from <random>: the standard engines are pinned, but the
// distributions (uniform_int_distribution, ...) are not, and differ between standard libraries, so a
// replay recorded with one would not replay with another. Every draw below is plain integer arithmetic
// or an exact conversion, the same on every platform.
#pragma once

#include <cstdint>

namespace rts {

class Rng {
 public:
  explicit Rng(uint64_t seed = 0) { reseed(seed); }

  void reseed(uint64_t seed) {
    uint64_t x = seed;
    for (uint64_t& word : s_) word = splitmix64(x);
  }

  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// A whole number in [0, n), n > 0, without modulo bias (Lemire's method with rejection).
  uint32_t below(uint32_t n) {
    uint64_t m = uint64_t(uint32_t(next() >> 32)) * n;
    if (uint32_t(m) < n) {
      const uint32_t threshold = uint32_t(-n) % n;
      while (uint32_t(m) < threshold) m = uint64_t(uint32_t(next() >> 32)) * n;
    }
    return uint32_t(m >> 32);
  }

  /// A double in [0, 1): the top 53 bits, scaled exactly.
  double unit() { return double(next() >> 11) * 0x1.0p-53; }

  /// A double in [lo, hi).
  double between(double lo, double hi) { return lo + (hi - lo) * unit(); }

  /// true with probability num/den.
  bool chance(uint32_t num, uint32_t den) { return below(den) < num; }

  uint64_t state(int i) const { return s_[i & 3]; }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static uint64_t splitmix64(uint64_t& x) {
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t s_[4];
};

}  // namespace rts
