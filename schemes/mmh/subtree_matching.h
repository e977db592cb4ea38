// Merging the MH's redundant subtrees (Scandolo, Bauszat & Eisemann 2016b §3.1–3.2): values
// relative to the parent, a topology hash per sibling pack, local matching within a search
// distance along each collision list, early rejection by aggregated interval bounds, and merging
// by intersecting intervals.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "schemes/shared/multires_hierarchy.h"

namespace sb {

struct MatchingStatistics {
  uint64_t pairsTested = 0;
  uint64_t rejectedInterval = 0;  // aggregated bounds cannot intersect (SBE16b Fig. 6)
  uint64_t rejectedOffset = 0;    // the merged offset might not fit 24 bits (§3.3)
  uint64_t rejectedFullTest = 0;  // some corresponding nodes' intervals do not intersect
  // Float differences: the relative intervals intersect, but no float value reconstructs, in
  // float32 sums, inside every occurrence's interval.
  uint64_t rejectedRounding = 0;
  // Float differences: nodes of the unmerged hierarchy whose interval no float32 sum from their
  // parent's reconstructed depth reaches (degenerate intervals far below the parent's depth);
  // where any is, the structure falls back to key deltas.
  uint64_t unrepresentable = 0;
  uint64_t merges = 0;
  uint64_t nodesRemoved = 0;
};

// The hierarchy with merged subtrees: what MMH serialises.
struct MergedHierarchy {
  // Per node, the word it stores: the depth key relative to its parent's reconstructed key
  // (wrapping uint32 arithmetic, SBE16b Alg. 1), the root's absolute; with float differences, the
  // bits of a float32 that the parent's reconstructed depth plus it gives, in float32, a depth
  // inside the node's interval.
  std::vector<uint32_t> values;
  // Whether `values` are float differences (RelativeValues::FloatDifferences, unless it fell back).
  bool floatValues = false;
  // Where float differences fell back to key deltas: what the float matching merged anyway, as a
  // trial (its packs holding unrepresentable nodes unmerged), and the words its layout takes.
  MatchingStatistics floatTrial;
  uint64_t floatTrialWords = 0;
  // Per node, the first child of the pack its offset points to: its own, or after a merge the
  // surviving pack, which lies later in depth-first order.
  std::vector<uint32_t> sharedChildren;
  MatchingStatistics statistics;
};

// The early rejection by aggregated interval bounds (SBE16b §3.2, Fig. 6). The text tests
// whether some node of one subtree meets no node of the other in two ways: its lo above every hi
// of the other, or its hi below every lo. Both reject only pairs the full test would, so merges are
// the same with either choice; only how the rejections split between the tests differs.
enum class IntervalTest : uint8_t {
  // Each subtree's nodes against the other's (the text's "a subtree", "another subtree").
  BothWays,
  // Alg. 3 as printed: (n1.lMax < n2.lMin) || (n1.hMin > n2.hMax), only the earlier pack's (n1)
  // nodes against the later's (n2). In our names n1.minHi < n2.minLo || n1.maxLo > n2.maxHi (l, h:
  // lowest, highest; Min, Max: of the intervals' minimum and maximum depths).
  Paper,
};

// How relative values are formed (issue 14): exact key deltas in units of float ulps, or float32
// depth differences summed in float32, as SBE16b §3 does.
enum class RelativeValues : uint8_t { KeyDeltas, FloatDifferences };

struct MatchingOptions {
  uint32_t searchDistance = 1000;  // entries of a collision list tested after each one
  int mergeLevels = 12;            // merged packs lie in the lowest levels, where scales are 1
  int offsetBits = 24;
  IntervalTest intervalTest = IntervalTest::BothWays;
  RelativeValues values = RelativeValues::KeyDeltas;
};

// The phases the harness times: values relative and hashed, then matched and merged. The
// matcher keeps few bytes a node beside the hierarchy (its budget: mmh.cpp), since a merge of
// parts holds the whole hierarchy of a 256K² map: instead of relative intervals it narrows the
// hierarchy's own intervals, each node's in the frame of the occurrence that survives, and keeps
// each node's reconstructed key, from which relative values follow.
class SubtreeMatcher {
 public:
  // `hierarchy` must outlive the matcher; merges narrow its nodes' intervals.
  SubtreeMatcher(MultiresHierarchy& hierarchy, const MatchingOptions& options);
  // Once per matcher: it merges the hierarchy it was given.
  MergedHierarchy match();

 private:
  // A collision list: the packs of one height and topology, in depth-first order (§3.1).
  struct CollisionList {
    uint32_t begin;  // in candidates_
    uint8_t height;
  };
  // The aggregated interval bounds of a pack's subtree (SBE16b §3.2, Fig. 6): the lowest and
  // highest lo and hi over its nodes' intervals. Kept as keys, 16 bytes (in a pack's frame they
  // take 33 bits each), and combined bottom-up without shifts; the early rejection takes them
  // into the packs' frames, less their reconstructed keys.
  struct AggregatedBounds {
    uint32_t minLo = UINT32_MAX, maxLo = 0, minHi = UINT32_MAX, maxHi = 0;
  };
  // The bounds of the pack under `node` from its children's intervals and its inner children's
  // bounds: each subtree's bounds once, bottom-up (§3.2: "during the previously described
  // bottom-up traversal").
  AggregatedBounds boundsFromChildren(uint32_t node) const;
  // The index of candidate `node` among the candidates in node order, where its bounds are:
  // a bit per node and a count per 64 nodes instead of an index per node.
  uint32_t candidateRank(uint32_t node) const;
  // match() with float differences (subtree_matching_float.cpp). Where the unmerged hierarchy
  // itself is not lossless in float sums (`unrepresentable` nodes), a trial: the hierarchy and
  // the matcher's state are left for matchKeys(), and the result's floatValues is false.
  MergedHierarchy matchFloat(uint64_t& unrepresentable);
  MergedHierarchy matchKeys();

  MultiresHierarchy& hierarchy_;
  MatchingOptions options_;
  // Per node: the key a lookup reconstructs at it (Alg. 1), the middle of its interval if it has
  // a value, else its parent's. A node's relative interval is its interval minus its parent's
  // reconstructed key.
  std::vector<uint32_t> reconstructed_;
  // The inner nodes whose packs may merge, list after list, heights from large to small.
  std::vector<uint32_t> candidates_;
  std::vector<CollisionList> lists_;        // and a last entry that ends them
  std::vector<uint64_t> isCandidate_;       // a bit per node
  std::vector<uint32_t> candidatesBefore_;  // per 64 nodes, the candidates before them
  // Per candidate in node order, its subtree's bounds as they stand: computed bottom-up once,
  // and again for the survivor's subtree after each merge, whose intervals it narrows.
  std::vector<AggregatedBounds> bounds_;
};

}  // namespace sb
