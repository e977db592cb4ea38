// Morton (Z-order) codes: the order in which the harness streams tiles, and the natural order
// of the hierarchical schemes' quadtrees.
#pragma once

#include <cstdint>

namespace sb {

// Spreads the low 32 bits of x over the even bits of the result.
inline uint64_t spreadBits(uint64_t x) {
  x &= 0x00000000ffffffffull;
  x = (x | (x << 16)) & 0x0000ffff0000ffffull;
  x = (x | (x << 8)) & 0x00ff00ff00ff00ffull;
  x = (x | (x << 4)) & 0x0f0f0f0f0f0f0f0full;
  x = (x | (x << 2)) & 0x3333333333333333ull;
  x = (x | (x << 1)) & 0x5555555555555555ull;
  return x;
}

// The inverse of spreadBits: the even bits of x, packed.
inline uint32_t compactBits(uint64_t x) {
  x &= 0x5555555555555555ull;
  x = (x | (x >> 1)) & 0x3333333333333333ull;
  x = (x | (x >> 2)) & 0x0f0f0f0f0f0f0f0full;
  x = (x | (x >> 4)) & 0x00ff00ff00ff00ffull;
  x = (x | (x >> 8)) & 0x0000ffff0000ffffull;
  x = (x | (x >> 16)) & 0x00000000ffffffffull;
  return uint32_t(x);
}

inline uint64_t mortonCode(uint32_t x, uint32_t y) {
  return spreadBits(x) | spreadBits(y) << 1;
}
inline uint32_t mortonX(uint64_t code) {
  return compactBits(code);
}
inline uint32_t mortonY(uint64_t code) {
  return compactBits(code >> 1);
}

}  // namespace sb
