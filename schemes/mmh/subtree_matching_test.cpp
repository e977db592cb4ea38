// MMH's subtree matching on maps built to repeat: every occurrence of a merged subtree still
// answers inside its own intervals, merges shrink the structure, and the statistics add up.
#include <algorithm>
#include <limits>

#include <catch2/catch.hpp>

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
