// The 8 symmetries of a square (the dihedral group D4): mirrorings in x and in y and the
// transposition, and their compositions. delta-dag shares packs equal under them (SSVDAG's
// symmetry-aware merging, Villanueva et al. 2017 §4, in 2D): a reference names a pack and the
// symmetry under which it is read.
//
// A symmetry t is 3 bits: bit 2 swaps x and y, then bits 0 and 1 complement x and y. It acts on
// every bit of a node's local coordinates alike, so on a child index k (x in bit 0, y in bit 1)
// at every level by the same permutation apply(t, k): a walk carries one symmetry down the
// tree, the one that maps the map's coordinates to the stored pack's.
#pragma once

#include <array>
#include <cstdint>

namespace sb::delta_dag {

using Symmetry = uint8_t;
constexpr Symmetry kIdentity = 0;
constexpr int kSymmetries = 8;

constexpr uint32_t applySymmetry(Symmetry t, uint32_t k) {
  uint32_t x = k & 1, y = k >> 1 & 1;
  if (t & 4) {
    const uint32_t swapped = x;
    x = y, y = swapped;
  }
  return (x ^ (t & 1)) | (y ^ (t >> 1 & 1)) << 1;
}

struct SymmetryTables {
  std::array<std::array<uint8_t, 4>, kSymmetries> apply{};            // [t][k]
  std::array<std::array<Symmetry, kSymmetries>, kSymmetries> then{};  // [u][t]: t, then u
  std::array<Symmetry, kSymmetries> inverse{};
};
constexpr SymmetryTables makeSymmetryTables() {
  SymmetryTables tables;
  for (Symmetry t = 0; t < kSymmetries; ++t)
    for (uint32_t k = 0; k < 4; ++k) tables.apply[t][k] = uint8_t(applySymmetry(t, k));
  // The group acts faithfully on the 4 quadrants: a composition is the one whose permutation
  // matches.
  for (Symmetry u = 0; u < kSymmetries; ++u)
    for (Symmetry t = 0; t < kSymmetries; ++t)
      for (Symmetry w = 0; w < kSymmetries; ++w) {
        bool same = true;
        for (uint32_t k = 0; k < 4; ++k)
          same = same && tables.apply[w][k] == tables.apply[u][tables.apply[t][k]];
        if (same) tables.then[u][t] = w;
        if (same && w == kIdentity) tables.inverse[t] = u;
      }
  return tables;
}
inline constexpr SymmetryTables kSymmetry = makeSymmetryTables();

}  // namespace sb::delta_dag
