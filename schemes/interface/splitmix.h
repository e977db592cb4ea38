// SplitMix64 (Steele, Lea & Flood 2014): a seeded hash of integers and the small generator built
// on it, for sample positions, query sets and synthetic maps that must be the same everywhere.
#pragma once

#include <cstdint>

namespace sb {

inline constexpr uint64_t kSplitMixIncrement = 0x9e3779b97f4a7c15ull;

inline uint64_t mixBits(uint64_t x) {
  x += kSplitMixIncrement;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// The next number of the sequence that `state` is at.
inline uint64_t nextRandom(uint64_t& state) {
  const uint64_t value = mixBits(state);
  state += kSplitMixIncrement;
  return value;
}

// The top 24 bits of a hash as a float in [0, 1).
inline float unitFloat(uint64_t hash) {
  return float(hash >> 40) * 0x1.0p-24f;
}

}  // namespace sb
