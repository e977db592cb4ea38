#include "schemes/mmh/subtree_matching.h"

#include <algorithm>
#include <bit>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "schemes/interface/splitmix.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {

namespace {

struct Interval {
  int64_t lo, hi;
  bool empty() const { return lo > hi; }
  int64_t middle() const { return lo + (hi - lo) / 2; }
};

// The aggregated interval bounds of a pack's subtree in the pack's frame (SBE16b §3.2, Fig. 6):
// its nodes' intervals less the pack's reconstructed key, as the full test compares them.
struct Bounds {
  int64_t minLo, maxLo, minHi, maxHi;
  // Some node of this subtree meets no node of the other: its hi below every lo there, or its lo
  // above every hi there (§3.2's two tests). No merge can keep both.
  bool outside(const Bounds& other) const { return minHi < other.minLo || maxLo > other.maxHi; }
};

bool intervalsDisjoint(const Bounds& earlier, const Bounds& later, IntervalTest test) {
  return earlier.outside(later) || (test == IntervalTest::BothWays && later.outside(earlier));
}

enum class PackState : uint8_t { Kept, Redirected, Removed };

}  // namespace

SubtreeMatcher::SubtreeMatcher(MultiresHierarchy& hierarchy, const MatchingOptions& options)
    : hierarchy_(hierarchy), options_(options) {
  std::vector<MhNode>& nodes = hierarchy.nodes;
  const size_t count = nodes.size();
  reconstructed_.assign(count, 0);
  isCandidate_.assign((count + 63) / 64, 0);

  // SBE16b §3: every value relative to the reconstructed value of its parent, which starts as the
  // middle of each node's own interval (what MH stores). The walk is depth-first, so the packs
  // that may merge (below the top levels, §3.3) are found in depth-first order.
  const uint32_t root = hierarchy.root();
  reconstructed_[root] = nodes[root].interval.middle();
  struct Visit {
    uint32_t node;
    int level;
  };
  std::vector<Visit> stack{{root, 0}};
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    const MhNode& node = nodes[visit.node];
    if (!node.hasChildren()) continue;
    if (visit.level + options_.mergeLevels >= hierarchy.levels) {
      candidates_.push_back(visit.node);
      isCandidate_[visit.node / 64] |= uint64_t(1) << (visit.node % 64);
    }
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = node.child(k);
      if (kind == MhChild::None) continue;
      reconstructed_[child] =
          hasValue(kind) ? nodes[child].interval.middle() : reconstructed_[visit.node];
      ++child;
    }
    while (child-- > node.firstChild) stack.push_back({child, visit.level + 1});
  }

  candidatesBefore_.resize(isCandidate_.size());
  for (uint32_t before = 0, word = 0; word < isCandidate_.size(); ++word) {
    candidatesBefore_[word] = before;
    before += uint32_t(std::popcount(isCandidate_[word]));
  }

  // SBE16b Alg. 2: the topology hash and height of each subtree, bottom-up (packs are stored
  // before their parents), and in the same sweep each candidate's aggregated bounds (§3.2); then
  // the candidates in collision lists by height and topology. A candidate's inner children lie
  // in lower levels, so they are candidates too.
  bounds_.resize(candidates_.size());
  std::vector<uint64_t> topology(count, 0);
  std::vector<uint8_t> height(count, 0);
  for (uint32_t n = 0; n < count; ++n) {
    const MhNode& node = nodes[n];
    if (!node.hasChildren()) continue;
    uint64_t hash = mixBits(node.childFlags);
    uint8_t below = 0;
    for (uint32_t c = node.firstChild; c < node.firstChild + MultiresHierarchy::childCount(node);
         ++c) {
      below = std::max(below, height[c]);
      if (nodes[c].hasChildren()) hash = mixBits(hash * 31 + topology[c]);
    }
    topology[n] = hash;
    height[n] = uint8_t(below + 1);
    if (isCandidate_[n / 64] >> (n % 64) & 1) bounds_[candidateRank(n)] = boundsFromChildren(n);
  }
  std::stable_sort(candidates_.begin(), candidates_.end(), [&](uint32_t a, uint32_t b) {
    if (height[a] != height[b]) return height[a] > height[b];
    return topology[a] < topology[b];
  });
  for (size_t c = 0; c < candidates_.size(); ++c) {
    const uint32_t pack = candidates_[c];
    if (c == 0 || height[pack] != height[candidates_[c - 1]] ||
        topology[pack] != topology[candidates_[c - 1]])
      lists_.push_back({uint32_t(c), height[pack]});
  }
  lists_.push_back({uint32_t(candidates_.size()), 0});
}

uint32_t SubtreeMatcher::candidateRank(uint32_t node) const {
  const uint64_t below = (uint64_t(1) << (node % 64)) - 1;
  return candidatesBefore_[node / 64] + uint32_t(std::popcount(isCandidate_[node / 64] & below));
}

SubtreeMatcher::AggregatedBounds SubtreeMatcher::boundsFromChildren(uint32_t n) const {
  const std::vector<MhNode>& nodes = hierarchy_.nodes;
  const MhNode& node = nodes[n];
  AggregatedBounds b;
  const auto add = [&](uint32_t minLo, uint32_t maxLo, uint32_t minHi, uint32_t maxHi) {
    b.minLo = std::min(b.minLo, minLo), b.maxLo = std::max(b.maxLo, maxLo);
    b.minHi = std::min(b.minHi, minHi), b.maxHi = std::max(b.maxHi, maxHi);
  };
  uint32_t child = node.firstChild;
  for (int k = 0; k < kMhChildren; ++k) {
    const MhChild kind = node.child(k);
    if (kind == MhChild::None) continue;
    if (hasValue(kind)) {
      const KeyInterval& own = nodes[child].interval;
      add(own.lo, own.lo, own.hi, own.hi);
    }
    if (kind != MhChild::Leaf) {
      const AggregatedBounds& below = bounds_[candidateRank(child)];
      add(below.minLo, below.maxLo, below.minHi, below.maxHi);
    }
    ++child;
  }
  return b;
}

MergedHierarchy SubtreeMatcher::match() {
  if (options_.values == RelativeValues::KeyDeltas) return matchKeys();
  uint64_t unrepresentable = 0;
  MergedHierarchy floats = matchFloat(unrepresentable);
  if (floats.floatValues) return floats;
  const MatchingStatistics trial = floats.statistics;
  const uint64_t trialWords = layoutOffsetQuadtree(hierarchy_, floats.values, floats.sharedChildren,
                                                   options_.offsetBits, "mmh")
                                  .words.size();
  floats = {};
  MergedHierarchy keyDeltas = matchKeys();
  keyDeltas.statistics.unrepresentable = unrepresentable;
  keyDeltas.floatTrial = trial;
  keyDeltas.floatTrialWords = trialWords;
  return keyDeltas;
}

MergedHierarchy SubtreeMatcher::matchKeys() {
  std::vector<MhNode>& nodes = hierarchy_.nodes;
  const size_t count = nodes.size();
  const std::vector<uint32_t> positions = unmergedPositions(hierarchy_, "mmh");
  const uint64_t maxOffset = (uint64_t(1) << options_.offsetBits) - 1;

  MergedHierarchy merged;
  merged.sharedChildren.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.sharedChildren[n] = nodes[n].firstChild;
  std::vector<PackState> state(count, PackState::Kept);

  // A pack's aggregated bounds in its frame, taken when tested: in the frame of now, which a
  // merge above the pack may have moved.
  const auto boundsInFrame = [&](uint32_t pack) {
    const AggregatedBounds& keys = bounds_[candidateRank(pack)];
    const int64_t frame = reconstructed_[pack];
    return Bounds{keys.minLo - frame, keys.maxLo - frame, keys.minHi - frame, keys.maxHi - frame};
  };

  // The full test (and, with `commit`, the merge) of the packs under a and b, in lockstep. A
  // change of a full node's value shifts its children's relative intervals, tracked as the
  // change of the reconstructed key in each occurrence (shiftA, shiftB); whether the
  // intersections are empty does not depend on which value each node takes. A merge narrows b's
  // intervals to the intersections, in b's frame, and moves b's reconstructed keys. It also
  // takes the bounds of b's packs again from the narrowed intervals, bottom-up, for what the walk
  // costs already: bounds left as they were would still hold every interval (a merge only
  // narrows), so the early rejection would stay sound, but reject fewer pairs. No pack of b's
  // subtree has merged yet (they are lower), so its nodes' first children are their packs.
  const auto lockstep = [&](auto&& self, uint32_t a, uint32_t b, int64_t shiftA, int64_t shiftB,
                            bool commit) -> bool {
    const MhNode& nodeA = nodes[a];
    const MhNode& nodeB = nodes[b];
    if (nodeA.childFlags != nodeB.childFlags) return false;
    const int64_t frameA = int64_t(reconstructed_[a]) + shiftA;
    const int64_t frameB = int64_t(reconstructed_[b]) + shiftB;
    const uint32_t firstA = merged.sharedChildren[a], firstB = merged.sharedChildren[b];
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild kind = nodeA.child(k);
      if (kind == MhChild::None) continue;
      const uint32_t childA = firstA + uint32_t(c), childB = firstB + uint32_t(c);
      ++c;
      int64_t nextA = shiftA, nextB = shiftB;
      if (hasValue(kind)) {
        const KeyInterval& ownA = nodes[childA].interval;
        KeyInterval& ownB = nodes[childB].interval;
        const Interval shared{std::max(ownA.lo - frameA, ownB.lo - frameB),
                              std::min(ownA.hi - frameA, ownB.hi - frameB)};
        if (shared.empty()) return false;
        const int64_t value = shared.middle();
        // The change of the reconstructed key: the new value, in the shifted frame, less the
        // old one, in the frame before this merge.
        nextA += value - (int64_t(ownA.middle()) - reconstructed_[a]);
        nextB += value - (int64_t(ownB.middle()) - reconstructed_[b]);
        if (commit) ownB = {uint32_t(shared.lo + frameB), uint32_t(shared.hi + frameB)};
      }
      if (kind != MhChild::Leaf && !self(self, childA, childB, nextA, nextB, commit)) return false;
      // After the walk below, which reads childB's key as it was.
      if (commit) reconstructed_[childB] = uint32_t(reconstructed_[childB] + nextB);
    }
    if (commit) bounds_[candidateRank(b)] = boundsFromChildren(b);
    return true;
  };

  tbb::combinable<MatchingStatistics> statistics;
  // §3.2: heights from large to small, so that larger merges remove more before smaller ones
  // are tried; lists of one height share no node and are matched in parallel.
  for (size_t first = 0; first + 1 < lists_.size();) {
    size_t last = first;
    while (last + 1 < lists_.size() && lists_[last].height == lists_[first].height) ++last;

    tbb::parallel_for(first, last, [&](size_t list) {
      MatchingStatistics& local = statistics.local();
      const size_t end = lists_[list + 1].begin;
      // Alg. 3: back to front, so that the outer pack is never one already merged away; the
      // earlier pack of a pair is removed, so that offsets stay positive.
      for (size_t i = end; i-- > lists_[list].begin;) {
        const uint32_t earlier = candidates_[i];
        if (state[earlier] != PackState::Kept) continue;
        const Bounds earlierBounds = boundsInFrame(earlier);
        const size_t stop = std::min<size_t>(end, i + 1 + options_.searchDistance);
        for (size_t j = i + 1; j < stop; ++j) {
          const uint32_t later = candidates_[j];
          if (state[later] != PackState::Kept) continue;
          ++local.pairsTested;
          if (intervalsDisjoint(earlierBounds, boundsInFrame(later), options_.intervalTest)) {
            ++local.rejectedInterval;
            continue;
          }
          // A pack placed before `earlier` wraps to a distance beyond every offset.
          if (uint32_t(positions[nodes[later].firstChild] - positions[earlier]) > maxOffset) {
            ++local.rejectedOffset;
            continue;
          }
          if (!lockstep(lockstep, earlier, later, 0, 0, false)) {
            ++local.rejectedFullTest;
            continue;
          }
          lockstep(lockstep, earlier, later, 0, 0, true);
          ++local.merges;
          std::vector<uint32_t> removed{earlier};
          while (!removed.empty()) {
            const MhNode& inner = nodes[removed.back()];
            removed.pop_back();
            for (uint32_t c = inner.firstChild;
                 c < inner.firstChild + MultiresHierarchy::childCount(inner); ++c) {
              ++local.nodesRemoved;
              if (nodes[c].hasChildren()) {
                state[c] = PackState::Removed;
                removed.push_back(c);
              }
            }
          }
          state[earlier] = PackState::Redirected;
          merged.sharedChildren[earlier] = nodes[later].firstChild;
          break;
        }
      }
    });
    first = last;
  }
  // The bounds are spent: their bytes go before the values' come (the budget in mmh.cpp).
  std::vector<AggregatedBounds>().swap(bounds_);

  merged.statistics = statistics.combine([](MatchingStatistics a, const MatchingStatistics& b) {
    a.pairsTested += b.pairsTested, a.rejectedInterval += b.rejectedInterval;
    a.rejectedOffset += b.rejectedOffset, a.rejectedFullTest += b.rejectedFullTest;
    a.merges += b.merges, a.nodesRemoved += b.nodesRemoved;
    return a;
  });
  // Alg. 1: each surviving node stores its value relative to its parent's reconstructed key.
  merged.values.assign(count, 0);
  for (uint32_t n = 0; n < count; ++n) {
    const MhNode& node = nodes[n];
    for (uint32_t c = node.firstChild; c < node.firstChild + MultiresHierarchy::childCount(node);
         ++c)
      merged.values[c] = nodes[c].interval.middle() - reconstructed_[n];
  }
  merged.values[hierarchy_.root()] = nodes[hierarchy_.root()].interval.middle();
  return merged;
}

}  // namespace sb
