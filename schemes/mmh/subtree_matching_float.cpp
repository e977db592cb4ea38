// Matching with float differences (issue 14): relative values as SBE16b §3 forms them, a float32
// depth less the parent's reconstructed float32 depth, summed by lookups in float32. Two packs
// merge when their corresponding nodes' relative intervals, in depth units, intersect (the
// paper's test, taken in doubles), and when a float value inside the intersection reconstructs,
// in the decoder's float32 sums, inside the interval of every reading of the node: rounding
// makes the sum from each parent's depth land on its own grid, so every reading is checked.
//
// A merged pack is read from several parents, each with its own reconstructed depth, and the
// float sums below them round differently; unlike key deltas, narrowing the survivor's intervals
// cannot stand for the other readings. Instead each stored node keeps the ring of the original
// nodes that read it (itself first), each with its reconstructed depth, and a merge tests and
// sets the values against every reading of both packs.
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "schemes/mmh/subtree_matching.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {

namespace {

// Floats in an unsigned order (-0 just below +0), so that ranges of float values are searched.
uint32_t orderOf(float f) {
  const uint32_t bits = std::bit_cast<uint32_t>(f);
  return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}
float floatOfOrder(uint32_t order) {
  return std::bit_cast<float>(order & 0x80000000u ? order & 0x7fffffffu : ~order);
}

// One reading of a node: its parent's reconstructed depth on that path and the node's interval.
struct Reading {
  float frame, lo, hi;
  bool accepts(float value) const {
    const float depth = frame + value;  // the decoder's sum (OffsetQuadtree::combine)
    return lo <= depth && depth <= hi;
  }
};

// The float values a reading accepts, in float order: a float32 sum is monotonic in either
// operand, so they are a range.
struct OrderRange {
  uint32_t first, last;
  bool empty() const { return first > last; }
};

OrderRange acceptedRange(const Reading& r) {
  const uint32_t bottom = orderOf(-FLT_MAX), top = orderOf(FLT_MAX);
  const auto firstWhere = [&](auto&& above) {  // the first order in [bottom, top] where above()
    uint32_t a = bottom, b = top + 1;
    while (a < b) {
      const uint32_t m = a + (b - a) / 2;
      if (above(r.frame + floatOfOrder(m)))
        b = m;
      else
        a = m + 1;
    }
    return a;
  };
  return {firstWhere([&](float d) { return d >= r.lo; }),
          firstWhere([&](float d) { return d > r.hi; }) - 1};
}

enum class Choice { Value, NoIntersection, Rounding };

// The value a node stores for its readings: the middle of the intersection of their relative
// intervals (in doubles; above depth 1, where only unbounded intervals reach, capped at 1), or
// where that middle rounds outside some reading's interval, the float nearest it that every
// reading accepts.
Choice chooseValue(std::span<const Reading> readings, float& value) {
  double lo = -INFINITY, hi = INFINITY, cap = INFINITY;
  for (const Reading& r : readings) {
    lo = std::max(lo, double(r.lo) - r.frame);
    hi = std::min(hi, double(r.hi) - r.frame);
    cap = std::min(cap, double(std::max(r.lo, 1.0f)) - r.frame);
  }
  if (!(lo <= hi)) return Choice::NoIntersection;
  const double top = std::max(lo, std::min(hi, cap));
  value = float(lo + (top - lo) / 2);
  if (std::all_of(readings.begin(), readings.end(),
                  [&](const Reading& r) { return r.accepts(value); }))
    return Choice::Value;
  OrderRange range{0, UINT32_MAX};
  for (const Reading& r : readings) {
    const OrderRange own = acceptedRange(r);
    range = {std::max(range.first, own.first), std::min(range.last, own.last)};
  }
  if (range.empty()) return Choice::Rounding;
  value = floatOfOrder(std::clamp(orderOf(value), range.first, range.last));
  return Choice::Value;
}

Reading readingOf(float frame, const KeyInterval& interval) {
  return {frame, depthOfKey(interval.lo), depthOfKey(interval.hi)};
}

// The aggregated bounds of a pack's subtree in its frame, in depth units, widened by what float
// sums may round along a path of the merged levels, so that they reject only pairs the full
// test would.
struct FloatBounds {
  double minLo, maxLo, minHi, maxHi;
  bool outside(const FloatBounds& other) const {
    return minHi < other.minLo || maxLo > other.maxHi;
  }
};
constexpr double kRoundingSlack = 1e-5;

enum class PackState : uint8_t { Kept, Redirected, Removed };

}  // namespace

MergedHierarchy SubtreeMatcher::matchFloat(uint64_t& unrepresentable) {
  std::vector<MhNode>& nodes = hierarchy_.nodes;
  const size_t count = nodes.size();

  // Per node (original, read on its own path): its reconstructed float depth; per stored node,
  // its value; per node, the next in the ring of nodes reading the same stored node.
  std::vector<float> depth(count, 0.0f), value(count, 0.0f);
  std::vector<uint32_t> ring(count);
  for (uint32_t n = 0; n < count; ++n) ring[n] = n;

  // The unmerged hierarchy, top-down: each value the middle of its relative interval, unless
  // from that depth some node reading it as its frame (its value children, and theirs through
  // empty children) has no float value that reaches inside its interval. Then the node takes
  // another depth in its interval where all of them have one: an end, or the depth of a reader
  // held inside its interval (a degenerate interval far below its parent's depth is reached from
  // a depth near it, Sterbenz).
  const uint32_t root = hierarchy_.root();
  unrepresentable = 0;
  {
    const auto frameReaders = [&](uint32_t n, std::vector<uint32_t>& out) {
      out.clear();
      std::vector<uint32_t> walk{n};
      while (!walk.empty()) {
        const MhNode& node = nodes[walk.back()];
        walk.pop_back();
        for (int k = 0, c = 0; k < kMhChildren; ++k) {
          const MhChild kind = node.child(k);
          if (kind == MhChild::None) continue;
          const uint32_t child = node.firstChild + uint32_t(c++);
          if (hasValue(kind))
            out.push_back(child);
          else
            walk.push_back(child);
        }
      }
    };
    const auto reachable = [&](float frame, const std::vector<uint32_t>& readers) {
      float v;
      return std::all_of(readers.begin(), readers.end(), [&](uint32_t r) {
        const Reading reading = readingOf(frame, nodes[r].interval);
        return chooseValue({&reading, 1}, v) == Choice::Value;
      });
    };
    // The value of node n below `frame`: false where none reaches inside its interval.
    std::vector<uint32_t> readers;
    const auto assign = [&](uint32_t n, float frame) {
      const Reading own = readingOf(frame, nodes[n].interval);
      if (chooseValue({&own, 1}, value[n]) != Choice::Value) return false;
      if (!nodes[n].hasChildren()) return true;
      frameReaders(n, readers);
      if (reachable(frame + value[n], readers)) return true;
      const OrderRange range = acceptedRange(own);
      std::vector<float> targets{own.lo, std::min(own.hi, std::max(own.lo, 1.0f))};
      for (uint32_t r : readers)
        targets.push_back(std::clamp(depthOfKey(nodes[r].interval.lo), own.lo, own.hi));
      for (float target : targets) {
        const float v = floatOfOrder(std::clamp(orderOf(target - frame), range.first, range.last));
        if (reachable(frame + v, readers)) {
          value[n] = v;
          return true;
        }
      }
      return true;  // its readers count themselves unrepresentable
    };
    if (!assign(root, 0.0f)) ++unrepresentable;
    depth[root] = value[root];
    std::vector<uint32_t> stack{root};
    while (!stack.empty()) {
      const uint32_t n = stack.back();
      stack.pop_back();
      const MhNode& node = nodes[n];
      uint32_t child = node.firstChild;
      for (int k = 0; k < kMhChildren; ++k) {
        const MhChild kind = node.child(k);
        if (kind == MhChild::None) continue;
        depth[child] = depth[n];
        if (hasValue(kind)) {
          if (assign(child, depth[n]))
            depth[child] = depth[n] + value[child];
          else
            ++unrepresentable;
        }
        if (kind != MhChild::Leaf) stack.push_back(child);
        ++child;
      }
    }
  }
  // Where some node is unrepresentable, the matching still runs, for its counters and size
  // (match() then stores key deltas): packs holding such a node never merge, since no value
  // reaches inside its interval.
  const bool trial = unrepresentable > 0;
  if (!trial) std::vector<uint32_t>().swap(reconstructed_);  // the key frames: unused from here

  const std::vector<uint32_t> positions = unmergedPositions(hierarchy_, "mmh");
  const uint64_t maxOffset = (uint64_t(1) << options_.offsetBits) - 1;
  MergedHierarchy merged;
  merged.floatValues = !trial;
  merged.sharedChildren.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.sharedChildren[n] = nodes[n].firstChild;
  std::vector<PackState> state(count, PackState::Kept);

  const auto boundsInFrame = [&](uint32_t pack) {
    const AggregatedBounds& keys = bounds_[candidateRank(pack)];
    const double frame = depth[pack];
    const auto d = [&](uint32_t key) { return double(depthOfKey(key)) - frame; };
    return FloatBounds{d(keys.minLo) - kRoundingSlack, d(keys.maxLo) + kRoundingSlack,
                       d(keys.minHi) - kRoundingSlack, d(keys.maxHi) + kRoundingSlack};
  };

  // The full test (and, with `commit`, the merge) of the packs under stored nodes a and b, whose
  // readings `readers` (original nodes) reconstruct `frames`. Both walks choose the same values.
  const auto lockstep = [&](auto&& self, uint32_t a, uint32_t b,
                            const std::vector<uint32_t>& readers, const std::vector<float>& frames,
                            bool commit, MatchingStatistics& local) -> bool {
    if (nodes[a].childFlags != nodes[b].childFlags) {
      ++local.rejectedFullTest;
      return false;
    }
    std::vector<uint32_t> childReaders(readers.size());
    std::vector<float> childFrames(readers.size());
    std::vector<Reading> readings(readers.size());
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild kind = nodes[a].child(k);
      if (kind == MhChild::None) continue;
      const uint32_t childA = nodes[a].firstChild + uint32_t(c);
      const uint32_t childB = nodes[b].firstChild + uint32_t(c);
      for (size_t r = 0; r < readers.size(); ++r)
        childReaders[r] = nodes[readers[r]].firstChild + uint32_t(c);
      ++c;
      childFrames = frames;
      if (hasValue(kind)) {
        for (size_t r = 0; r < readers.size(); ++r)
          readings[r] = readingOf(frames[r], nodes[childReaders[r]].interval);
        float v = 0;
        const Choice choice = chooseValue(readings, v);
        if (choice != Choice::Value) {
          ++(choice == Choice::Rounding ? local.rejectedRounding : local.rejectedFullTest);
          return false;
        }
        for (size_t r = 0; r < readers.size(); ++r) childFrames[r] = frames[r] + v;
        if (commit) value[childB] = v;
      }
      if (commit)
        for (size_t r = 0; r < readers.size(); ++r) depth[childReaders[r]] = childFrames[r];
      if (kind != MhChild::Leaf &&
          !self(self, childA, childB, childReaders, childFrames, commit, local))
        return false;
      if (commit) std::swap(ring[childA], ring[childB]);  // one ring of both
    }
    return true;
  };

  tbb::combinable<MatchingStatistics> statistics;
  for (size_t first = 0; first + 1 < lists_.size();) {
    size_t last = first;
    while (last + 1 < lists_.size() && lists_[last].height == lists_[first].height) ++last;

    tbb::parallel_for(first, last, [&](size_t list) {
      MatchingStatistics& local = statistics.local();
      const size_t end = lists_[list + 1].begin;
      std::vector<uint32_t> readers;
      std::vector<float> frames;
      const auto addRing = [&](uint32_t stored) {
        uint32_t n = stored;
        do {
          readers.push_back(n);
          frames.push_back(depth[n]);
          n = ring[n];
        } while (n != stored);
      };
      for (size_t i = end; i-- > lists_[list].begin;) {
        const uint32_t earlier = candidates_[i];
        if (state[earlier] != PackState::Kept) continue;
        const FloatBounds earlierBounds = boundsInFrame(earlier);
        const size_t stop = std::min<size_t>(end, i + 1 + options_.searchDistance);
        for (size_t j = i + 1; j < stop; ++j) {
          const uint32_t later = candidates_[j];
          if (state[later] != PackState::Kept) continue;
          ++local.pairsTested;
          const FloatBounds laterBounds = boundsInFrame(later);
          if (earlierBounds.outside(laterBounds) ||
              (options_.intervalTest == IntervalTest::BothWays &&
               laterBounds.outside(earlierBounds))) {
            ++local.rejectedInterval;
            continue;
          }
          if (uint32_t(positions[nodes[later].firstChild] - positions[earlier]) > maxOffset) {
            ++local.rejectedOffset;
            continue;
          }
          readers.clear(), frames.clear();
          addRing(earlier), addRing(later);
          if (!lockstep(lockstep, earlier, later, readers, frames, false, local)) continue;
          lockstep(lockstep, earlier, later, readers, frames, true, local);
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
          // The earlier pack's readers now read the later pack's children: one ring of both.
          std::swap(ring[earlier], ring[later]);
          break;
        }
      }
    });
    first = last;
  }
  if (!trial) std::vector<AggregatedBounds>().swap(bounds_);

  merged.statistics = statistics.combine([](MatchingStatistics a, const MatchingStatistics& b) {
    a.pairsTested += b.pairsTested, a.rejectedInterval += b.rejectedInterval;
    a.rejectedOffset += b.rejectedOffset, a.rejectedFullTest += b.rejectedFullTest;
    a.rejectedRounding += b.rejectedRounding;
    a.merges += b.merges, a.nodesRemoved += b.nodesRemoved;
    return a;
  });

  merged.values.assign(count, 0);
  for (uint32_t n = 0; n < count; ++n) merged.values[n] = std::bit_cast<uint32_t>(value[n]);

  // The check of DESIGN §4 in the decoder's arithmetic: every original node, read through the
  // stored nodes its path reaches, reconstructs inside its own interval.
  struct Visit {
    uint32_t original, stored;
    float depth;
  };
  uint64_t outside = 0;
  const auto inside = [&](uint32_t original, float d) {
    const Reading r = readingOf(0.0f, nodes[original].interval);
    return r.lo <= d && d <= r.hi;
  };
  outside += !inside(root, value[root]);
  std::vector<Visit> stack{{root, root, value[root]}};
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    const MhNode& node = nodes[visit.original];
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild kind = node.child(k);
      if (kind == MhChild::None) continue;
      const uint32_t original = node.firstChild + uint32_t(c);
      const uint32_t stored = merged.sharedChildren[visit.stored] + uint32_t(c);
      ++c;
      float d = visit.depth;
      if (hasValue(kind)) {
        d = std::bit_cast<float>(OffsetQuadtree::combine<OffsetQuadtree::Values::RelativeFloat>(
            std::bit_cast<uint32_t>(visit.depth), merged.values[stored]));
        outside += !inside(original, d);
      }
      if (kind != MhChild::Leaf) stack.push_back({original, stored, d});
    }
  }
  if (outside > 0 && !trial)
    throw std::logic_error(fmt::format(
        "mmh: {} nodes reconstruct outside their intervals with float differences", outside));
  return merged;
}

}  // namespace sb
