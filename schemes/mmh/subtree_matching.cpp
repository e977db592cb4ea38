#include "schemes/mmh/subtree_matching.h"

#include <algorithm>
#include <limits>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "schemes/interface/splitmix.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {

namespace {

constexpr uint32_t kNoParent = std::numeric_limits<uint32_t>::max();

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

SubtreeMatcher::SubtreeMatcher(const MultiresHierarchy& hierarchy, const MatchingOptions& options)
    : hierarchy_(hierarchy), options_(options) {
  const size_t count = hierarchy.nodes.size();
  parent_.assign(count, kNoParent);
  level_.assign(count, 0);
  relativeLo_.assign(count, 0), relativeHi_.assign(count, 0), value_.assign(count, 0);
  topology_.assign(count, 0);
  height_.assign(count, 0);

  // SBE16b §3: every value relative to the reconstructed value of its parent, which starts as the
  // middle of each node's own interval (what MH stores).
  const uint32_t root = hierarchy.root();
  const KeyInterval& top = hierarchy.nodes[root].interval;
  relativeLo_[root] = top.lo, relativeHi_[root] = top.hi, value_[root] = top.middle();
  struct Visit {
    uint32_t node;
    int64_t reconstructed;
  };
  std::vector<Visit> stack{{root, value_[root]}};
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    const MhNode& node = hierarchy.nodes[visit.node];
    if (!node.hasChildren()) continue;
    depthFirst_.push_back(visit.node);
    Visit children[kMhChildren];
    int pushed = 0;
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      if (node.child(k) == MhChild::None) continue;
      parent_[child] = visit.node;
      level_[child] = uint8_t(level_[visit.node] + 1);
      int64_t reconstructed = visit.reconstructed;
      if (node.child(k) != MhChild::Empty) {
        const KeyInterval& own = hierarchy.nodes[child].interval;
        relativeLo_[child] = int64_t(own.lo) - visit.reconstructed;
        relativeHi_[child] = int64_t(own.hi) - visit.reconstructed;
        value_[child] = int64_t(own.middle()) - visit.reconstructed;
        reconstructed = own.middle();
      }
      children[pushed++] = {child++, reconstructed};
    }
    while (pushed > 0) stack.push_back(children[--pushed]);
  }

  // SBE16b Alg. 2: the topology hash and height of each subtree, bottom-up (packs are stored
  // before their parents).
  for (uint32_t n = 0; n < count; ++n) {
    const MhNode& node = hierarchy.nodes[n];
    if (!node.hasChildren()) continue;
    uint64_t hash = mixBits(node.childFlags);
    uint16_t height = 0;
    for (uint32_t c = node.firstChild; c < node.firstChild + MultiresHierarchy::childCount(node);
         ++c) {
      height = std::max<uint16_t>(height, height_[c]);
      if (hierarchy.nodes[c].hasChildren()) hash = mixBits(hash * 31 + topology_[c]);
    }
    topology_[n] = hash;
    height_[n] = uint16_t(height + 1);
  }
}

MergedHierarchy SubtreeMatcher::match() {
  const MultiresHierarchy& h = hierarchy_;
  const size_t count = h.nodes.size();
  const std::vector<uint64_t> positions = unmergedPositions(h);
  const uint64_t maxOffset = (uint64_t(1) << options_.offsetBits) - 1;

  MergedHierarchy merged;
  merged.sharedChildren.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.sharedChildren[n] = h.nodes[n].firstChild;
  std::vector<PackState> state(count, PackState::Kept);

  // The packs that may merge: below the top levels (SBE16b §3.3), in collision lists by height
  // and topology, each list in depth-first order (§3.1) for local matching.
  std::vector<uint32_t> candidates;
  for (uint32_t q : depthFirst_)
    if (level_[q] + options_.mergeLevels >= h.levels) candidates.push_back(q);
  std::stable_sort(candidates.begin(), candidates.end(), [&](uint32_t a, uint32_t b) {
    if (height_[a] != height_[b]) return height_[a] > height_[b];
    return topology_[a] < topology_[b];
  });

  // Per pack, the subtree's intervals in the pack's frame: relative to the reconstructed value
  // of the pack's parent, adding the values of full nodes on the way down.
  const auto forEachValued = [&](uint32_t pack, auto&& visit) {
    struct Visit {
      uint32_t node;
      int64_t sum;
    };
    std::vector<Visit> stack{{pack, 0}};
    while (!stack.empty()) {
      const Visit at = stack.back();
      stack.pop_back();
      const MhNode& node = h.nodes[at.node];
      const uint32_t first = merged.sharedChildren[at.node];
      for (int k = 0, c = 0; k < kMhChildren; ++k) {
        const MhChild kind = node.child(k);
        if (kind == MhChild::None) continue;
        const uint32_t child = first + uint32_t(c++);
        int64_t sum = at.sum;
        if (kind != MhChild::Empty) {
          visit(child, at.sum);
          sum += value_[child];
        }
        if (kind != MhChild::Leaf) stack.push_back({child, sum});
      }
    }
  };

  // The full test (and, with `commit`, the merge) of the packs under a and b, in lockstep. A
  // change of a full node's value shifts its children's relative intervals, tracked as the
  // change of the reconstructed value in each occurrence (shiftA, shiftB); whether the
  // intersections are empty does not depend on which value each node takes.
  const auto lockstep = [&](auto&& self, uint32_t a, uint32_t b, int64_t shiftA, int64_t shiftB,
                            bool commit) -> bool {
    const MhNode& nodeA = h.nodes[a];
    const MhNode& nodeB = h.nodes[b];
    if (nodeA.childFlags != nodeB.childFlags) return false;
    const uint32_t firstA = merged.sharedChildren[a], firstB = merged.sharedChildren[b];
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild kind = nodeA.child(k);
      if (kind == MhChild::None) continue;
      const uint32_t childA = firstA + uint32_t(c), childB = firstB + uint32_t(c);
      ++c;
      int64_t nextA = shiftA, nextB = shiftB;
      if (kind != MhChild::Empty) {
        const Interval shared{std::max(relativeLo_[childA] - shiftA, relativeLo_[childB] - shiftB),
                              std::min(relativeHi_[childA] - shiftA, relativeHi_[childB] - shiftB)};
        if (shared.empty()) return false;
        const int64_t value = shared.middle();
        nextA += value - value_[childA];
        nextB += value - value_[childB];
        if (commit) {
          relativeLo_[childB] = shared.lo, relativeHi_[childB] = shared.hi;
          value_[childB] = value;
        }
      }
      if (kind != MhChild::Leaf && !self(self, childA, childB, nextA, nextB, commit)) return false;
    }
    return true;
  };

  tbb::combinable<MatchingStatistics> statistics;
  std::vector<Bounds> bounds(candidates.size());  // by candidate
  // §3.2: heights from large to small, so that larger merges remove more before smaller ones
  // are tried; lists of one height share no node and are matched in parallel.
  for (size_t first = 0; first < candidates.size();) {
    size_t last = first;
    while (last < candidates.size() && height_[candidates[last]] == height_[candidates[first]])
      ++last;
    tbb::parallel_for(first, last, [&](size_t c) {
      const uint32_t pack = candidates[c];
      if (state[pack] != PackState::Kept) return;
      Bounds b;
      forEachValued(pack, [&](uint32_t node, int64_t sum) {
        b.minLo = std::min(b.minLo, relativeLo_[node] + sum);
        b.maxLo = std::max(b.maxLo, relativeLo_[node] + sum);
        b.minHi = std::min(b.minHi, relativeHi_[node] + sum);
        b.maxHi = std::max(b.maxHi, relativeHi_[node] + sum);
      });
      bounds[c] = b;
    });
    std::vector<size_t> lists{first};
    for (size_t c = first + 1; c < last; ++c)
      if (topology_[candidates[c]] != topology_[candidates[c - 1]]) lists.push_back(c);
    lists.push_back(last);

    tbb::parallel_for(size_t(0), lists.size() - 1, [&](size_t list) {
      MatchingStatistics& local = statistics.local();
      const size_t begin = lists[list], end = lists[list + 1];
      // Alg. 3: back to front, so that the outer pack is never one already merged away; the
      // earlier pack of a pair is removed, so that offsets stay positive.
      for (size_t i = end; i-- > begin;) {
        const uint32_t earlier = candidates[i];
        if (state[earlier] != PackState::Kept) continue;
        const size_t stop = std::min<size_t>(end, i + 1 + options_.searchDistance);
        for (size_t j = i + 1; j < stop; ++j) {
          const uint32_t later = candidates[j];
          if (state[later] != PackState::Kept) continue;
          ++local.pairsTested;
          if (bounds[i].disjointFrom(bounds[j])) {
            ++local.rejectedInterval;
            continue;
          }
          if (positions[h.nodes[later].firstChild] - positions[earlier] > maxOffset) {
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
            const uint32_t node = removed.back();
            removed.pop_back();
            const MhNode& inner = h.nodes[node];
            for (uint32_t c = inner.firstChild;
                 c < inner.firstChild + MultiresHierarchy::childCount(inner); ++c) {
              ++local.nodesRemoved;
              if (h.nodes[c].hasChildren()) {
                state[c] = PackState::Removed;
                removed.push_back(c);
              }
            }
          }
          state[earlier] = PackState::Redirected;
          merged.sharedChildren[earlier] = h.nodes[later].firstChild;
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
  merged.values.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.values[n] = uint32_t(value_[n]);
  return merged;
}

}  // namespace sb
