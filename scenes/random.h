// Deterministic pseudo-random numbers for the scene generators.
//
// The std distributions are implementation-defined (libstdc++ and libc++ draw different numbers
// from the same engine), so every draw here is made from raw 64-bit integers by exact
// arithmetic: the same seed gives the same scene bytes with any compiler or standard library.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace sb::detail {

// The SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mix.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Seed of an independent stream for one part of a scene (a block, a tree, a tube), so that a
// part's geometry depends only on (seed, part) and not on how many parts were drawn before.
constexpr uint64_t streamSeed(uint64_t seed, uint64_t part, uint64_t subpart = 0) {
  constexpr uint64_t kGamma = 0x9e3779b97f4a7c15ULL;
  return mix64(mix64(mix64(seed + kGamma) + part * kGamma) + subpart * kGamma);
}

// SplitMix64: tiny, fast, passes BigCrush, and any 64-bit seed (0 included) is a good one.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return mix64(state_);
  }

  // Uniform on [0, 1) in steps of 2^-24: every value is exact in float.
  float unit() { return static_cast<float>(next() >> 40) * 0x1p-24f; }
  float uniform(float lo, float hi) { return lo + (hi - lo) * unit(); }

  // Uniform integer in [lo, hi], by rejection so that there is no modulo bias.
  int64_t between(int64_t lo, int64_t hi) {
    const uint64_t range = static_cast<uint64_t>(hi - lo) + 1;
    if (range == 0) return static_cast<int64_t>(next());  // the full 64-bit range
    const uint64_t threshold = (0 - range) % range;       // 2^64 mod range
    for (;;) {
      const uint64_t r = next();
      if (r >= threshold) return lo + static_cast<int64_t>(r % range);
    }
  }

  bool percent(int64_t chance) { return between(0, 99) < chance; }

  // Uniform in the unit ball, by rejection from the cube [-1, 1)^3.
  glm::vec3 inUnitBall() {
    for (;;) {
      const glm::vec3 p{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
      if (glm::dot(p, p) < 1.0f) return p;
    }
  }

  // A uniformly distributed direction (rejecting short vectors that normalise badly).
  glm::vec3 direction() {
    for (;;) {
      const glm::vec3 p = inUnitBall();
      const float length2 = glm::dot(p, p);
      if (length2 > 0.01f) return p / std::sqrt(length2);
    }
  }

 private:
  uint64_t state_;
};

}  // namespace sb::detail
