// MMH's subtree matching on maps built to repeat: every occurrence of a merged subtree still
// answers inside its own intervals, merges shrink the structure, and the statistics add up.
#include <algorithm>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include <catch2/catch.hpp>

#include "schemes/interface/scheme.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "schemes/mmh/subtree_matching.h"
#include "schemes/shared/offset_quadtree.h"
#include "tests/support/hierarchy_map.h"

namespace sb {
namespace {

using testing::hierarchyOf;
using testing::SyntheticMap;
constexpr float kInf = std::numeric_limits<float>::infinity();

// A 64² map of one motif repeated, each copy raised by a different depth, with bands wide enough
// that the copies' intervals meet: subtrees MMH must find and merge, whose inner values move.
SyntheticMap repeatedMotif(uint64_t seed, uint32_t motifSize = 8) {
  SyntheticMap motif = SyntheticMap::random(motifSize, DepthMode::Closed, seed);
  SyntheticMap map{64, DepthMode::Closed, std::vector<float>(64 * 64), std::vector<float>(64 * 64)};
  for (uint32_t j = 0; j < 64; ++j)
    for (uint32_t i = 0; i < 64; ++i) {
      const size_t at = size_t(j) * 64 + i, m = size_t(j % motifSize) * motifSize + i % motifSize;
      const float raise = float((i / motifSize + j / motifSize) % 3) * 0.001f;
      map.lo[at] = std::min(motif.lo[m] * 0.5f + raise, 1.0f);
      map.hi[at] = motif.hi[m] == kInf ? kInf : map.lo[at] + 0.05f;
    }
  return map;
}

// Texels whose lookup in `tree` falls outside their interval.
uint64_t texelsOutside(const SyntheticMap& map, const OffsetQuadtree& tree) {
  uint64_t wrong = 0;
  for (uint32_t j = 0; j < map.resolution; ++j)
    for (uint32_t i = 0; i < map.resolution; ++i)
      wrong += !testing::insideInterval(
          map, i, j, tree.texelKey<OffsetQuadtree::Values::Relative>(i, j, tree.levels));
  return wrong;
}

TEST_CASE("merged subtrees answer every occurrence inside its intervals", "[mmh]") {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const SyntheticMap map = repeatedMotif(seed, seed % 2 ? 8 : 16);
    uint64_t mhWords = 0;
    for (uint32_t distance : {0u, 1u, 1000u}) {
      MultiresHierarchy h = hierarchyOf(map, 16);
      const MergedHierarchy merged = SubtreeMatcher(h, {distance, 12, 24}).match();
      const MatchingStatistics& s = merged.statistics;
      CHECK(s.pairsTested == s.rejectedInterval + s.rejectedOffset + s.rejectedFullTest + s.merges);
      CHECK((s.merges > 0) == (distance > 0));
      const OffsetQuadtree tree =
          layoutOffsetQuadtree(h, merged.values, merged.sharedChildren, 24, "test");
      CHECK(texelsOutside(map, tree) == 0);
      if (distance == 0)
        mhWords = tree.words.size();
      else
        CHECK(tree.words.size() < mhWords);
    }
  }
}

// Copies of one motif, each raised and with bands of its own widths: merged packs take values
// that move, so the intervals below them are tested in frames that shift, level after level.
SyntheticMap jitteredCopies(uint64_t seed) {
  const SyntheticMap motif = SyntheticMap::random(32, DepthMode::Closed, seed);
  SyntheticMap map{128, DepthMode::Closed, std::vector<float>(128 * 128),
                   std::vector<float>(128 * 128)};
  uint64_t state = seed;
  for (uint32_t j = 0; j < 128; ++j)
    for (uint32_t i = 0; i < 128; ++i) {
      const size_t at = size_t(j) * 128 + i, m = size_t(j % 32) * 32 + i % 32;
      const uint32_t copy = (j / 32) * 4 + i / 32;
      map.lo[at] = std::min(motif.lo[m] * 0.5f + float(copy % 5) * 0.002f, 1.0f);
      const float width = 0.01f + 0.04f * unitFloat(nextRandom(state));
      map.hi[at] = motif.hi[m] == kInf ? kInf : map.lo[at] + width;
    }
  return map;
}

TEST_CASE("merged packs whose values move keep every occurrence inside its intervals", "[mmh]") {
  for (uint64_t seed = 1; seed <= 16; ++seed) {
    const SyntheticMap map = jitteredCopies(seed);
    MultiresHierarchy h = hierarchyOf(map, 32);
    const MergedHierarchy merged = SubtreeMatcher(h, {1000, 12, 24}).match();
    CHECK(merged.statistics.merges > 0);
    CHECK(texelsOutside(
              map, layoutOffsetQuadtree(h, merged.values, merged.sharedChildren, 24, "test")) == 0);
  }
}

// Alg. 3 without the early rejection, written from the paper rather than from the matcher: every
// pair within the search distance meets the offset bound and the full test, corresponding nodes
// compared in their packs' frames (intervals less the pack's reconstructed key); a merge narrows
// the survivor's intervals to the intersections in its frame and takes its keys again, top-down.
// Its collision lists hold one topology each, the matcher's one topology hash each.
MergedHierarchy referenceMatch(MultiresHierarchy& h, const MatchingOptions& options) {
  std::vector<MhNode>& nodes = h.nodes;
  const size_t count = nodes.size();
  const auto children = [&](uint32_t node, auto&& visit) {
    for (int k = 0, c = 0; k < kMhChildren; ++k)
      if (nodes[node].child(k) != MhChild::None)
        visit(nodes[node].firstChild + uint32_t(c++), nodes[node].child(k));
  };
  std::vector<uint32_t> keys(count);
  const auto rekey = [&](auto&& self, uint32_t node) -> void {
    children(node, [&](uint32_t child, MhChild kind) {
      keys[child] = hasValue(kind) ? nodes[child].interval.middle() : keys[node];
      if (kind != MhChild::Leaf) self(self, child);
    });
  };
  keys[h.root()] = nodes[h.root()].interval.middle();
  rekey(rekey, h.root());

  std::vector<std::string> topology(count);
  std::vector<int> height(count, 0);
  for (uint32_t n = 0; n < count; ++n) {
    if (!nodes[n].hasChildren()) continue;
    topology[n] = std::to_string(nodes[n].childFlags);
    children(n, [&](uint32_t child, MhChild) {
      topology[n] += "(" + topology[child] + ")";
      height[n] = std::max(height[n], height[child] + 1);
    });
  }
  std::map<std::pair<int, std::string>, std::vector<uint32_t>> lists;  // tallest first
  const auto collect = [&](auto&& self, uint32_t node, int level) -> void {
    if (!nodes[node].hasChildren()) return;
    if (level + options.mergeLevels >= h.levels)
      lists[{-height[node], topology[node]}].push_back(node);
    children(node, [&](uint32_t child, MhChild) { self(self, child, level + 1); });
  };
  collect(collect, h.root(), 0);

  // The corresponding nodes with values of the packs under a and b.
  const auto pairs = [&](auto&& self, uint32_t a, uint32_t b, auto&& visit) -> void {
    children(a, [&](uint32_t childA, MhChild kind) {
      const uint32_t childB = nodes[b].firstChild + (childA - nodes[a].firstChild);
      if (hasValue(kind)) visit(nodes[childA].interval, nodes[childB].interval);
      if (kind != MhChild::Leaf) self(self, childA, childB, visit);
    });
  };
  const std::vector<uint32_t> positions = unmergedPositions(h, "reference");
  const uint32_t maxOffset = (uint32_t(1) << options.offsetBits) - 1;
  MergedHierarchy merged;
  MatchingStatistics& s = merged.statistics;
  merged.sharedChildren.resize(count);
  for (uint32_t n = 0; n < count; ++n) merged.sharedChildren[n] = nodes[n].firstChild;
  std::vector<bool> gone(count, false);
  const auto remove = [&](auto&& self, uint32_t node) -> void {
    children(node, [&](uint32_t child, MhChild kind) {
      ++s.nodesRemoved;
      gone[child] = true;
      if (kind != MhChild::Leaf) self(self, child);
    });
  };
  for (const auto& [key, list] : lists)
    for (size_t i = list.size(); i-- > 0;) {
      const uint32_t earlier = list[i];
      if (gone[earlier]) continue;
      for (size_t j = i + 1; j < std::min<size_t>(list.size(), i + 1 + options.searchDistance);
           ++j) {
        const uint32_t later = list[j];
        if (gone[later]) continue;
        ++s.pairsTested;
        if (positions[nodes[later].firstChild] - positions[earlier] > maxOffset) {
          ++s.rejectedOffset;
          continue;
        }
        const int64_t frameA = keys[earlier], frameB = keys[later];
        bool meet = true;
        pairs(pairs, earlier, later, [&](const KeyInterval& a, const KeyInterval& b) {
          meet = meet &&
                 std::max(a.lo - frameA, b.lo - frameB) <= std::min(a.hi - frameA, b.hi - frameB);
        });
        if (!meet) {
          ++s.rejectedFullTest;
          continue;
        }
        pairs(pairs, earlier, later, [&](const KeyInterval& a, KeyInterval& b) {
          b = {uint32_t(std::max(a.lo - frameA, b.lo - frameB) + frameB),
               uint32_t(std::min(a.hi - frameA, b.hi - frameB) + frameB)};
        });
        rekey(rekey, later);
        ++s.merges;
        remove(remove, earlier);
        gone[earlier] = true;
        merged.sharedChildren[earlier] = nodes[later].firstChild;
        break;
      }
    }
  merged.values.assign(count, 0);
  for (uint32_t n = 0; n < count; ++n)
    children(n, [&](uint32_t child, MhChild) {
      merged.values[child] = nodes[child].interval.middle() - keys[n];
    });
  merged.values[h.root()] = nodes[h.root()].interval.middle();
  return merged;
}

TEST_CASE("matching with aggregated bounds merges as the reference without them", "[mmh]") {
  for (uint64_t seed = 1; seed <= 8; ++seed)
    for (MatchingOptions options :
         {MatchingOptions{1, 12, 24}, MatchingOptions{10, 12, 24}, MatchingOptions{1000, 12, 24},
          MatchingOptions{1000, 4, 24}, MatchingOptions{1000, 12, 7}})
      for (const IntervalTest test : {IntervalTest::BothWays, IntervalTest::Paper}) {
        options.intervalTest = test;
        INFO("seed " << seed << ", distance " << options.searchDistance << ", levels "
                     << options.mergeLevels << ", offset bits " << options.offsetBits
                     << (test == IntervalTest::Paper ? ", Alg. 3's test" : ", both ways"));
        const SyntheticMap map = seed % 2 ? jitteredCopies(seed) : repeatedMotif(seed);
        MultiresHierarchy matched = hierarchyOf(map, 32), reference = matched;
        const MergedHierarchy got = SubtreeMatcher(matched, options).match();
        const MergedHierarchy want = referenceMatch(reference, options);
        const MatchingStatistics &g = got.statistics, &w = want.statistics;
        CHECK(g.merges == w.merges);
        CHECK(g.merges > 0);
        CHECK(g.nodesRemoved == w.nodesRemoved);
        CHECK(g.pairsTested == w.pairsTested);
        CHECK(g.rejectedInterval + g.rejectedOffset + g.rejectedFullTest ==
              w.rejectedOffset + w.rejectedFullTest);
        CHECK(got.sharedChildren == want.sharedChildren);
        CHECK(got.values == want.values);
        CHECK(std::equal(matched.nodes.begin(), matched.nodes.end(), reference.nodes.begin(),
                         [](const MhNode& a, const MhNode& b) {
                           return a.interval.lo == b.interval.lo && a.interval.hi == b.interval.hi;
                         }));
      }
}

// The early rejection either way gives the same merges: both tests reject only pairs the full
// test would. Alg. 3's one-way test leaves some of them to the full test.
TEST_CASE("Alg. 3's interval test merges as the test both ways, rejecting fewer pairs early",
          "[mmh]") {
  uint64_t leftToFullTest = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed)
    for (const auto& [distance, offsetBits] : {std::pair{10u, 24}, {1000u, 24}, {1000u, 7}}) {
      INFO("seed " << seed << ", distance " << distance << ", offset bits " << offsetBits);
      const SyntheticMap map = seed % 2 ? jitteredCopies(seed) : repeatedMotif(seed);
      MultiresHierarchy both = hierarchyOf(map, 32), paper = both;
      const MergedHierarchy ours =
          SubtreeMatcher(both, {distance, 12, offsetBits, IntervalTest::BothWays}).match();
      const MergedHierarchy printed =
          SubtreeMatcher(paper, {distance, 12, offsetBits, IntervalTest::Paper}).match();
      CHECK(printed.values == ours.values);
      CHECK(printed.sharedChildren == ours.sharedChildren);
      const MatchingStatistics &o = ours.statistics, &p = printed.statistics;
      CHECK(p.merges == o.merges);
      CHECK(p.nodesRemoved == o.nodesRemoved);
      CHECK(p.pairsTested == o.pairsTested);
      CHECK(p.rejectedInterval <= o.rejectedInterval);
      CHECK(p.rejectedInterval + p.rejectedOffset + p.rejectedFullTest ==
            o.rejectedInterval + o.rejectedOffset + o.rejectedFullTest);
      if (offsetBits == 24) {
        CHECK(o.rejectedOffset + p.rejectedOffset == 0);
        CHECK(p.rejectedFullTest - o.rejectedFullTest == o.rejectedInterval - p.rejectedInterval);
        leftToFullTest += o.rejectedInterval - p.rejectedInterval;
      }
    }
  CHECK(leftToFullTest > 0);
}

// Two packs of two leaves under a 4² map's root, [0, 100] and [0, 100] in the earlier pack's
// frame and [0, 100] and [200, 300] in the later's: the later pack's second leaf lies above
// every interval of the earlier pack, but no leaf of the earlier pack lies outside the later's.
// Only the test both ways sees it; Alg. 3's leaves the pair to the full test.
TEST_CASE("a pair only the test both ways rejects goes to the full test under Alg. 3's", "[mmh]") {
  const auto flags = [](MhChild first, MhChild second) {
    return uint8_t(uint8_t(first) | uint8_t(second) << 2);
  };
  MultiresHierarchy h;
  h.resolution = 4, h.levels = 2;
  h.nodes = {
      {{1000, 1100}, 0, 0},  // the earlier pack's leaves, its frame 1000
      {{1000, 1100}, 0, 0},
      {{5000, 5100}, 0, 0},  // the later pack's leaves, its frame 5000
      {{5200, 5300}, 0, 0},
      {{1000, 1000}, 0, flags(MhChild::Leaf, MhChild::Leaf)},
      {{5000, 5000}, 2, flags(MhChild::Leaf, MhChild::Leaf)},
      {{3000, 3000}, 4, flags(MhChild::Full, MhChild::Full)},
  };
  for (const IntervalTest test : {IntervalTest::BothWays, IntervalTest::Paper}) {
    MultiresHierarchy matched = h;
    const MatchingStatistics s = SubtreeMatcher(matched, {1000, 12, 24, test}).match().statistics;
    CHECK(s.pairsTested == 1);
    CHECK(s.merges == 0);
    CHECK(s.rejectedInterval == (test == IntervalTest::BothWays ? 1 : 0));
    CHECK(s.rejectedFullTest == (test == IntervalTest::Paper ? 1 : 0));
  }
}

TEST_CASE("merges stay out of the top levels and within the offset bits", "[mmh]") {
  const SyntheticMap map = repeatedMotif(9);
  MultiresHierarchy h = hierarchyOf(map, 64);
  // No level may merge: nothing changes.
  const MergedHierarchy none = SubtreeMatcher(h, {1000, 0, 24}).match();
  CHECK(none.statistics.merges == 0);
  // Offsets of 4 bits forbid merges across more than 15 words.
  const MergedHierarchy near = SubtreeMatcher(h, {1000, 12, 4}).match();
  CHECK(near.statistics.rejectedOffset > 0);
}

}  // namespace
}  // namespace sb

namespace sb {
namespace {

// Texels whose lookup with float differences falls outside their interval.
uint64_t texelsOutsideFloat(const SyntheticMap& map, const OffsetQuadtree& tree) {
  uint64_t wrong = 0;
  for (uint32_t j = 0; j < map.resolution; ++j)
    for (uint32_t i = 0; i < map.resolution; ++i)
      wrong += !testing::insideInterval(
          map, i, j, tree.texelKey<OffsetQuadtree::Values::RelativeFloat>(i, j, tree.levels));
  return wrong;
}

TEST_CASE("float differences keep every occurrence inside its intervals in float sums", "[mmh]") {
  uint64_t merges = 0;
  for (uint64_t seed = 1; seed <= 16; ++seed) {
    const SyntheticMap map = seed % 2 ? jitteredCopies(seed) : repeatedMotif(seed);
    MultiresHierarchy h = hierarchyOf(map, 32);
    MatchingOptions options{1000, 12, 24};
    options.values = RelativeValues::FloatDifferences;
    const MergedHierarchy merged = SubtreeMatcher(h, options).match();
    const MatchingStatistics& s = merged.statistics;
    CHECK(merged.floatValues);
    CHECK(s.unrepresentable == 0);
    CHECK(s.pairsTested == s.rejectedInterval + s.rejectedOffset + s.rejectedFullTest +
                               s.rejectedRounding + s.merges);
    merges += s.merges;
    const OffsetQuadtree tree =
        layoutOffsetQuadtree(h, merged.values, merged.sharedChildren, 24, "test");
    CHECK(texelsOutsideFloat(map, tree) == 0);
  }
  CHECK(merges > 0);
}

TEST_CASE("float differences fall back to key deltas where float sums cannot be lossless",
          "[mmh]") {
  // Open mode: every interval a single depth, which a float sum from a parent's depth far above
  // it cannot reach in general.
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Open, 7);
  MultiresHierarchy h = hierarchyOf(map, 16);
  MatchingOptions options{1000, 12, 24};
  options.values = RelativeValues::FloatDifferences;
  const MergedHierarchy merged = SubtreeMatcher(h, options).match();
  const OffsetQuadtree tree =
      layoutOffsetQuadtree(h, merged.values, merged.sharedChildren, 24, "test");
  if (merged.floatValues) {
    CHECK(merged.statistics.unrepresentable == 0);
    CHECK(texelsOutsideFloat(map, tree) == 0);
  } else {
    CHECK(merged.statistics.unrepresentable > 0);
    CHECK(texelsOutside(map, tree) == 0);
  }
}

TEST_CASE("the float-differences payload names its values and the loader refuses others",
          "[mmh][format]") {
  const SchemeInfo& scheme = findScheme("mmh");
  const Params params{{"relative-values", "float-differences"}};
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 3);
  const auto decoder = map.build(scheme, params, 64);
  ByteWriter out;
  decoder->save(out);
  std::vector<uint8_t> bytes = out.release();
  REQUIRE(!bytes.empty());
  CHECK(bytes[0] == 1);  // float differences, not the key-delta fallback
  const auto load = [&] {
    ByteReader in(bytes);
    return scheme.load(in, map.info(scheme.kind), scheme.resolve(params));
  };
  CHECK(load()->size() == decoder->size());
  for (uint8_t kind : {uint8_t(2), uint8_t(255)}) {
    bytes[0] = kind;
    CHECK_THROWS_AS(load(), FormatError);
  }
}

}  // namespace
}  // namespace sb
