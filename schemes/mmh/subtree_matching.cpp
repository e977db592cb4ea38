#include "schemes/mmh/subtree_matching.h"

#include <algorithm>
#include <limits>

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

// The aggregated interval bounds of a pack's subtree, in the pack's frame (SBE16b §3.2, Fig. 6).
struct Bounds {
  int64_t minLo = std::numeric_limits<int64_t>::max(), maxLo = std::numeric_limits<int64_t>::min();
  int64_t minHi = std::numeric_limits<int64_t>::max(), maxHi = std::numeric_limits<int64_t>::min();
  // Some node of one subtree meets no node of the other: no merge can keep both.
  bool disjointFrom(const Bounds& other) const {
    return maxLo > other.maxHi || other.maxLo > maxHi || minHi < other.minLo || other.minHi < minLo;
  }
};

enum class PackState : uint8_t { Kept, Redirected, Removed };

}  // namespace

SubtreeMatcher::SubtreeMatcher(MultiresHierarchy& hierarchy, const MatchingOptions& options)
    : hierarchy_(hierarchy), options_(options) {
  std::vector<MhNode>& nodes = hierarchy.nodes;
  const size_t count = nodes.size();
  reconstructed_.assign(count, 0);

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
    if (visit.level + options_.mergeLevels >= hierarchy.levels) candidates_.push_back(visit.node);
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

  // SBE16b Alg. 2: the topology hash and height of each subtree, bottom-up (packs are stored
  // before their parents), then the candidates in collision lists by height and topology.
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

MergedHierarchy SubtreeMatcher::match() {
  std::vector<MhNode>& nodes = hierarchy_.nodes;
  const size_t count = nodes.size();
  const std::vector<uint32_t> positions = unmergedPositions(hierarchy_, "mmh");
  const uint64_t maxOffset = (uint64_t(1) << options_.offsetBits) - 1;

  MergedHierarchy merged;
  merged.sharedChildren.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.sharedChildren[n] = nodes[n].firstChild;
  std::vector<PackState> state(count, PackState::Kept);

  // The aggregated bounds of a pack's subtree in the pack's frame: its nodes' intervals relative
  // to the pack's reconstructed key. No pack below one of the current height has merged yet, so
  // its subtree's intervals are all in one frame.
  const auto boundsOf = [&](uint32_t pack) {
    Bounds b;
    const int64_t frame = reconstructed_[pack];
    std::vector<uint32_t> stack{pack};
    while (!stack.empty()) {
      const MhNode& node = nodes[stack.back()];
      const uint32_t first = merged.sharedChildren[stack.back()];
      stack.pop_back();
      for (int k = 0, c = 0; k < kMhChildren; ++k) {
        const MhChild kind = node.child(k);
        if (kind == MhChild::None) continue;
        const uint32_t child = first + uint32_t(c++);
        if (hasValue(kind)) {
          const KeyInterval& own = nodes[child].interval;
          b.minLo = std::min(b.minLo, own.lo - frame), b.maxLo = std::max(b.maxLo, own.lo - frame);
          b.minHi = std::min(b.minHi, own.hi - frame), b.maxHi = std::max(b.maxHi, own.hi - frame);
        }
        if (kind != MhChild::Leaf) stack.push_back(child);
      }
    }
    return b;
  };

  // The full test (and, with `commit`, the merge) of the packs under a and b, in lockstep. A
  // change of a full node's value shifts its children's relative intervals, tracked as the
  // change of the reconstructed key in each occurrence (shiftA, shiftB); whether the
  // intersections are empty does not depend on which value each node takes. A merge narrows b's
  // intervals to the intersections, in b's frame, and moves b's reconstructed keys.
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
    return true;
  };

  tbb::combinable<MatchingStatistics> statistics;
  std::vector<Bounds> bounds;  // by candidate of the current height
  // §3.2: heights from large to small, so that larger merges remove more before smaller ones
  // are tried; lists of one height share no node and are matched in parallel.
  for (size_t first = 0; first + 1 < lists_.size();) {
    size_t last = first;
    while (last + 1 < lists_.size() && lists_[last].height == lists_[first].height) ++last;
    const size_t begin = lists_[first].begin;
    bounds.assign(lists_[last].begin - begin, {});
    tbb::parallel_for(begin, size_t(lists_[last].begin), [&](size_t c) {
      if (state[candidates_[c]] == PackState::Kept) bounds[c - begin] = boundsOf(candidates_[c]);
    });

    tbb::parallel_for(first, last, [&](size_t list) {
      MatchingStatistics& local = statistics.local();
      const size_t end = lists_[list + 1].begin;
      // Alg. 3: back to front, so that the outer pack is never one already merged away; the
      // earlier pack of a pair is removed, so that offsets stay positive.
      for (size_t i = end; i-- > lists_[list].begin;) {
        const uint32_t earlier = candidates_[i];
        if (state[earlier] != PackState::Kept) continue;
        const size_t stop = std::min<size_t>(end, i + 1 + options_.searchDistance);
        for (size_t j = i + 1; j < stop; ++j) {
          const uint32_t later = candidates_[j];
          if (state[later] != PackState::Kept) continue;
          ++local.pairsTested;
          if (bounds[i - begin].disjointFrom(bounds[j - begin])) {
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
