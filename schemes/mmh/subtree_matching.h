// Merging the MH's redundant subtrees (Scandolo, Bauszat & Eisemann 2016b §3.1–3.2): values
// relative to the parent, a topology hash per sibling pack, local matching within a search
// distance along each collision list, early rejection by aggregated interval bounds, and merging
// by intersecting intervals.
#pragma once

#include <cstdint>
#include <vector>

#include "schemes/shared/multires_hierarchy.h"

namespace sb {

struct MatchingStatistics {
  uint64_t pairsTested = 0;
  uint64_t rejectedInterval = 0;  // aggregated bounds cannot intersect (SBE16b Fig. 6)
  uint64_t rejectedOffset = 0;    // the merged offset might not fit 24 bits (§3.3)
  uint64_t rejectedFullTest = 0;  // some corresponding nodes' intervals do not intersect
  uint64_t merges = 0;
  uint64_t nodesRemoved = 0;
};

// The hierarchy with merged subtrees: what MMH serialises.
struct MergedHierarchy {
  // Per node, the word it stores: the depth key relative to its parent's reconstructed key
  // (wrapping uint32 arithmetic, SBE16b Alg. 1), the root's absolute.
  std::vector<uint32_t> values;
  // Per node, the first child of the pack its offset points to: its own, or after a merge the
  // surviving pack, which lies later in depth-first order.
  std::vector<uint32_t> sharedChildren;
  MatchingStatistics statistics;
};

struct MatchingOptions {
  uint32_t searchDistance = 1000;  // entries of a collision list tested after each one
  int mergeLevels = 12;            // merged packs lie in the lowest levels, where scales are 1
  int offsetBits = 24;
};

// The phases the harness times: values relative and hashed, then matched and merged.
class SubtreeMatcher {
 public:
  SubtreeMatcher(const MultiresHierarchy& hierarchy, const MatchingOptions& options);
  MergedHierarchy match();

 private:
  const MultiresHierarchy& hierarchy_;
  MatchingOptions options_;
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> level_;
  // Per node with a value: the interval its value may take and the value, both relative to the
  // parent's reconstructed key, as exact integers.
  std::vector<int64_t> relativeLo_, relativeHi_, value_;
  std::vector<uint64_t> topology_;    // per inner node: hash of its descendants' flags
  std::vector<uint16_t> height_;      // per node: levels below it (0 for a leaf)
  std::vector<uint32_t> depthFirst_;  // inner nodes in depth-first order
};

}  // namespace sb
