// Treelets (Scandolo & Eisemann 2021 §3.2, §3.4, Alg. 1): a subtree of at most `height` levels
// stored as the bitmap of a full quadtree in depth-first order, one bit per node (set = the node
// has a value), after the count of its set bits. Pointers inside small subtrees would cost more
// than the bits; the depth-first order is the order of the value list, so a node's value index is
// the treelet's first index plus the set bits before it.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <optional>

#include "schemes/shared/multires_hierarchy.h"

namespace sb::dag_mh {

inline constexpr int kMaxTreeletHeight = 5;
// Words of the tallest treelet: a 16-bit count and 341 node bits.
inline constexpr uint32_t kMaxTreeletWords = (16 + 341 + 31) / 32;

struct TreeletShape {
  int height = 0;
  uint32_t bits = 0;       // (4^h − 1)/3 nodes of the full quadtree
  uint32_t countBits = 0;  // §3.4: 8 bits hold the 85 of h = 4; h = 5 (341) needs 16
  uint32_t words = 0;      // 32-bit words per treelet: the count, then the bitmap
  // Nodes of a full subtree rooted at depth d of the treelet: (4^(h−d) − 1)/3.
  uint32_t subtreeBits[kMaxTreeletHeight + 1] = {};

  static TreeletShape of(int height) {
    TreeletShape shape;
    shape.height = height;
    for (int d = height; d >= 0; --d) shape.subtreeBits[d] = ((1u << (2 * (height - d))) - 1) / 3;
    shape.bits = shape.subtreeBits[0];
    shape.countBits = height <= 4 ? 8 : 16;
    shape.words = (shape.countBits + shape.bits + 31) / 32;
    return shape;
  }

  // The treelet's words: bit p of the stream is bit p % 32 of word p / 32; the count takes bits
  // [0, countBits), node n of the depth-first order is bit countBits + n.
  uint32_t count(const uint32_t* treelet) const { return treelet[0] & ((1u << countBits) - 1); }
  bool hasValue(const uint32_t* treelet, uint32_t node) const {
    const uint32_t at = countBits + node;
    return (treelet[at / 32] >> (at % 32)) & 1;
  }
  void setValue(uint32_t* treelet, uint32_t node) const {
    const uint32_t at = countBits + node;
    treelet[at / 32] |= 1u << (at % 32);
  }
  // Alg. 1: the deepest node with a value on texel (i, j)'s path through the treelet rooted at
  // `rootLevel` of a map with `levels` levels, as the set bits before it; none if no node on the
  // path has one (the last value seen above answers). Depth-first index of the node at depth n:
  // n + Σ_{d<n} l_d · subtreeBits[d + 1], l_d the child index taken at depth d (§3.5: for h = 4,
  // n + 21·l0 + 5·l1 + l2).
  std::optional<uint32_t> lookup(const uint32_t* treelet, uint32_t i, uint32_t j, int rootLevel,
                                 int levels) const;
};

// Set bits of a bit stream (bit p is bit p % 32 of word p / 32) before bit `bit`.
inline uint32_t setBitsBefore(const uint32_t* words, uint32_t bit) {
  uint32_t bits = 0;
  for (uint32_t w = 0; w < bit / 32; ++w) bits += uint32_t(std::popcount(words[w]));
  if (bit % 32 != 0) bits += uint32_t(std::popcount(words[bit / 32] & ((1u << (bit % 32)) - 1)));
  return bits;
}

inline std::optional<uint32_t> TreeletShape::lookup(const uint32_t* treelet, uint32_t i, uint32_t j,
                                                    int rootLevel, int levels) const {
  const int deepest = std::min(height - 1, levels - rootLevel);
  uint32_t node = 0;
  std::optional<uint32_t> found;
  for (int d = 0;; ++d) {
    if (hasValue(treelet, node)) found = node;
    if (d == deepest) break;
    node += 1 + uint32_t(mhChildIndex(i, j, levels - rootLevel - d - 1)) * subtreeBits[d + 1];
  }
  if (!found) return std::nullopt;
  return setBitsBefore(treelet, countBits + *found) - setBitsBefore(treelet, countBits);
}

// Set bits before each node of one treelet, from the words' prefix counts taken once: a kernel
// walk (issue 13) asks for the value index of many nodes of a treelet and whether subtrees hold
// values, so each answer costs one popcount instead of a pass over the words.
class TreeletRanks {
 public:
  TreeletRanks(const TreeletShape& shape, const uint32_t* treelet)
      : treelet_(treelet), countBits_(shape.countBits) {
    for (uint32_t w = 0; w < shape.words; ++w)
      before_[w + 1] = before_[w] + uint32_t(std::popcount(treelet[w]));
    first_ = rank(countBits_);
  }
  // Values of the nodes before `node` in depth-first order: its value's index in the treelet.
  uint32_t valuesBefore(uint32_t node) const { return rank(countBits_ + node) - first_; }
  // Values of the nodes [first, end): a subtree's nodes are consecutive in depth-first order, so
  // this counts the values below a node.
  uint32_t valuesIn(uint32_t first, uint32_t end) const {
    return rank(countBits_ + end) - rank(countBits_ + first);
  }

 private:
  uint32_t rank(uint32_t bit) const {
    const uint32_t w = bit / 32, within = bit % 32;
    return before_[w] + (within ? uint32_t(std::popcount(treelet_[w] & ((1u << within) - 1))) : 0u);
  }

  const uint32_t* treelet_;
  uint32_t countBits_, first_ = 0;
  uint32_t before_[kMaxTreeletWords + 1] = {};
};

}  // namespace sb::dag_mh
