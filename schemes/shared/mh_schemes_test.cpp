// The multiresolution hierarchy and the offset-pointer quadtree MH and MMH serialise it into,
// against answers worked out by hand and against the maps' own intervals: the group rule on
// single 2×2 groups, the deepest stored interval of every texel whatever the tile size, and
// scaled offsets with their padding.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/splitmix.h"
#include "schemes/shared/multires_hierarchy.h"
#include "schemes/shared/offset_quadtree.h"
#include "tests/support/hierarchy_map.h"

namespace sb {
namespace {

using testing::hierarchyOf;
using testing::SyntheticMap;
constexpr float kInf = std::numeric_limits<float>::infinity();

SyntheticMap mapOf(uint32_t resolution, std::vector<float> lo, std::vector<float> hi) {
  return {resolution, DepthMode::Closed, std::move(lo), std::move(hi)};
}

TEST_CASE("depth keys order as the floats do and refuse negative or NaN depths", "[mh]") {
  const float depths[] = {0.0f, 1e-30f, 0.25f, 0.5f, 0.99999994f, 1.0f, 3e38f, kInf};
  for (size_t a = 0; a + 1 < std::size(depths); ++a) {
    CHECK(depthKey(depths[a]) < depthKey(depths[a + 1]));
    CHECK(depthOfKey(depthKey(depths[a])) == depths[a]);
  }
  CHECK(depthKey(-0.0f) == depthKey(0.0f));
  CHECK_THROWS_AS(depthKey(-0.5f), std::invalid_argument);
  CHECK_THROWS_AS(depthKey(std::nanf("")), std::invalid_argument);
}

TEST_CASE("a 2×2 group moves its largest intersecting subset up", "[mh]") {
  SECTION("three of four intersect: the parent takes their intersection, the fourth is a leaf") {
    const MultiresHierarchy h =
        hierarchyOf(mapOf(2, {0.1f, 0.4f, 0.45f, 0.7f}, {0.5f, 0.6f, 0.9f, 0.8f}), 2);
    REQUIRE(h.nodes.size() == 2);
    const MhNode& root = h.nodes[h.root()];
    CHECK(depthOfKey(root.interval.lo) == 0.45f);
    CHECK(depthOfKey(root.interval.hi) == 0.5f);
    CHECK(root.child(0) == MhChild::None);
    CHECK(root.child(3) == MhChild::Leaf);
    CHECK(depthOfKey(h.nodes[MultiresHierarchy::childNode(root, 3)].interval.lo) == 0.7f);
  }
  SECTION("one shared interval: a single leaf root") {
    const MultiresHierarchy h =
        hierarchyOf(mapOf(2, {0.3f, 0.3f, 0.3f, 0.3f}, {kInf, kInf, kInf, kInf}), 2);
    CHECK(h.nodes.size() == 1);
    CHECK(!h.nodes[0].hasChildren());
  }
  SECTION("disjoint points: equal groups of one, the widest wins, the first on a tie") {
    const MultiresHierarchy h =
        hierarchyOf(mapOf(2, {0.1f, 0.2f, 0.3f, 0.4f}, {0.1f, 0.25f, 0.3f, 0.4f}), 2);
    const MhNode& root = h.nodes[h.root()];
    CHECK(depthOfKey(root.interval.lo) == 0.2f);
    CHECK(root.child(1) == MhChild::None);
    CHECK(MultiresHierarchy::childCount(root) == 3);
  }
}

TEST_CASE("every texel's deepest stored interval lies inside its own, whatever the tiles", "[mh]") {
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    for (uint64_t seed : {1, 2, 3}) {
      const SyntheticMap map = SyntheticMap::random(64, mode, seed);
      size_t nodes = 0;
      for (uint32_t tile : {8u, 16u, 64u}) {
        const MultiresHierarchy h = hierarchyOf(map, tile);
        if (nodes) CHECK(h.nodes.size() == nodes);
        nodes = h.nodes.size();
        uint64_t outside = 0;
        for (uint32_t j = 0; j < 64; ++j)
          for (uint32_t i = 0; i < 64; ++i) {
            const KeyInterval in = h.texelInterval(i, j);
            outside += !testing::insideInterval(map, i, j, in.lo) ||
                       !testing::insideInterval(map, i, j, in.hi) ||
                       !testing::insideInterval(map, i, j, in.middle());
          }
        CHECK(outside == 0);
      }
      CHECK(nodes < 64 * 64);
    }
}

TEST_CASE("tiles out of Morton order or not square are refused", "[mh]") {
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Closed, 4);
  MhBuilder builder(map.info(SchemeKind::Depth));
  DualDepthTile tile;
  tile.resize(8, 0, 8, 8);
  CHECK_THROWS_WITH(builder.consume(tile), Catch::Contains("Morton order"));
  tile.resize(0, 0, 8, 4);
  CHECK_THROWS_WITH(builder.consume(tile), Catch::Contains("square"));
  CHECK_THROWS_AS(builder.finish(), std::logic_error);
}

// Builds in parts (parts.h): each part reduced to its undecided root, then the parts joined in
// index order, as the part encoders and the merger of schemes/shared/mh_parts do.
MultiresHierarchy hierarchyInParts(const SyntheticMap& map, uint32_t tileSize, uint32_t partSize) {
  const MapInfo info = map.info(SchemeKind::Depth);
  const uint64_t tilesPerPart = uint64_t(partSize / tileSize) * (partSize / tileSize);
  MhBuilder merged(info);
  for (uint64_t index = 0; index < MapPart::countFor(info, partSize); ++index) {
    const MapPart part = MapPart::of(index, partSize);
    MhBuilder builder(info, part);
    map.stream(
        tileSize, [&](const DualDepthTile& tile) { builder.consume(tile); }, index * tilesPerPart,
        (index + 1) * tilesPerPart);
    merged.consume(part, builder.finishPart());
  }
  return merged.finish();
}

// Node for node: the same intervals, flags and child indices in the same order.
size_t differingNodes(const MultiresHierarchy& a, const MultiresHierarchy& b) {
  size_t differing =
      std::max(a.nodes.size(), b.nodes.size()) - std::min(a.nodes.size(), b.nodes.size());
  for (size_t n = 0; n < std::min(a.nodes.size(), b.nodes.size()); ++n) {
    const MhNode &x = a.nodes[n], &y = b.nodes[n];
    differing += x.interval.lo != y.interval.lo || x.interval.hi != y.interval.hi ||
                 x.firstChild != y.firstChild || x.childFlags != y.childFlags;
  }
  return differing;
}

TEST_CASE("a hierarchy joined from parts is the whole build's, node for node", "[mh][parts]") {
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    for (uint64_t seed : {11, 12}) {
      const SyntheticMap map = SyntheticMap::random(128, mode, seed);
      for (uint32_t tile : {8u, 16u}) {
        // Node order follows the tiles (each tile's levels are stored row by row).
        const MultiresHierarchy whole = hierarchyOf(map, tile);
        REQUIRE(whole.nodes.size() > 100);
        for (uint32_t part : {tile, 2 * tile, 64u}) {
          INFO(toString(mode) << " seed " << seed << ", tiles " << tile << "², parts " << part
                              << "²");
          const MultiresHierarchy joined = hierarchyInParts(map, tile, part);
          CHECK(joined.resolution == whole.resolution);
          CHECK(joined.levels == whole.levels);
          CHECK(joined.nodes.size() == whole.nodes.size());
          CHECK(differingNodes(joined, whole) == 0);
        }
      }
    }
  // One interval everywhere: every part's root is a childless leaf, and so is the map's root.
  const SyntheticMap flat = SyntheticMap::uniform(64, 0.5f, 0.75f);
  const MultiresHierarchy joined = hierarchyInParts(flat, 8, 16);
  CHECK(joined.nodes.size() == 1);
  CHECK(differingNodes(joined, hierarchyOf(flat, 8)) == 0);
}

TEST_CASE("parts out of order, unfinished or finished as the wrong kind are refused",
          "[mh][parts]") {
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 13);
  const MapInfo info = map.info(SchemeKind::Depth);
  const auto partOf = [&](uint64_t index) {
    MhBuilder builder(info, MapPart::of(index, 16));
    map.stream(
        8, [&](const DualDepthTile& tile) { builder.consume(tile); }, index * 4, index * 4 + 4);
    return builder.finishPart();
  };
  MhBuilder merged(info);
  CHECK_THROWS_WITH(merged.consume(MapPart::of(1, 16), partOf(1)), Catch::Contains("Morton order"));
  merged.consume(MapPart::of(0, 16), partOf(0));
  CHECK_THROWS_WITH(merged.finish(), Catch::Contains("did not all arrive"));

  MhBuilder part(info, MapPart::of(2, 16));
  DualDepthTile tile;
  tile.resize(0, 0, 8, 8);  // a tile of part 0
  tile.lo.assign(64, 0.5f), tile.hi = tile.lo;
  CHECK_THROWS_WITH(part.consume(tile), Catch::Contains("within the 16² at (0, 16)"));
  tile.x0 = 8, tile.y0 = 16;  // part 2's second tile, before its first
  CHECK_THROWS_WITH(part.consume(tile), Catch::Contains("Morton order"));
  tile.x0 = 0;
  part.consume(tile);
  CHECK_THROWS_WITH(part.finishPart(), Catch::Contains("did not all arrive"));
  CHECK_THROWS_AS(part.finish(), std::logic_error);
  CHECK_THROWS_AS(MhBuilder(info, MapPart{0, 8, 0, 16}), std::invalid_argument);
}

TEST_CASE("offsets too long for their bits scale up, and lookups follow the padding", "[mh]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Static, 5);
  const MultiresHierarchy h = hierarchyOf(map, 16);
  std::vector<uint32_t> values(h.nodes.size());
  for (size_t n = 0; n < values.size(); ++n) values[n] = h.nodes[n].interval.middle();
  for (int bits : {3, 5, 16}) {
    const OffsetQuadtree tree = layoutOffsetQuadtree(h, values, {}, bits, "test");
    const bool scaled = std::any_of(tree.levelScale.begin(), tree.levelScale.end(),
                                    [](uint32_t s) { return s > 1; });
    CHECK(scaled == (bits < 16));
    uint64_t wrong = 0;
    for (uint32_t j = 0; j < 64; ++j)
      for (uint32_t i = 0; i < 64; ++i)
        wrong += tree.texelKey<OffsetQuadtree::Values::Absolute>(i, j, tree.levels) !=
                 h.texelInterval(i, j).middle();
    CHECK(wrong == 0);
  }
}

// The partwise layout of a merge of parts (PartwiseLayout) against the whole layout: the same
// words and scales, also where few offset bits make the scales grow over several rounds, with
// the parts read again every round as the merge reads them.
TEST_CASE("an offset quadtree laid out part by part is the whole layout, word for word",
          "[mh][parts]") {
  for (DepthMode mode : {DepthMode::Open, DepthMode::Static})
    for (uint32_t partSize : {8u, 32u}) {
      const SyntheticMap map = SyntheticMap::random(64, mode, 21);
      const MapInfo info = map.info(SchemeKind::Depth);
      const MultiresHierarchy whole = hierarchyOf(map, 8);
      std::vector<uint32_t> values(whole.nodes.size());
      for (size_t n = 0; n < values.size(); ++n) values[n] = whole.nodes[n].interval.middle();
      const uint64_t partCount = MapPart::countFor(info, partSize);
      std::vector<MultiresHierarchy> trees;
      MhBuilder upperBuilder(info);
      for (uint64_t index = 0; index < partCount; ++index) {
        const MapPart part = MapPart::of(index, partSize);
        MhBuilder builder(info, part);
        const uint64_t tiles = uint64_t(partSize / 8) * (partSize / 8);
        map.stream(
            8, [&](const DualDepthTile& tile) { builder.consume(tile); }, index * tiles,
            (index + 1) * tiles);
        MhBuilder::PartHierarchy hierarchy = builder.finishPart();
        upperBuilder.consume(part, {{}, hierarchy.root});
        MultiresHierarchy tree{64, 6, std::move(hierarchy.nodes)};
        tree.nodes.push_back(
            {hierarchy.root.interval, hierarchy.root.firstChild, hierarchy.root.childFlags});
        trees.push_back(std::move(tree));
      }
      const MultiresHierarchy upper = upperBuilder.finish();
      for (int bits : {3, 5, 16}) {
        INFO(toString(mode) << ", parts " << partSize << "², " << bits << "-bit offsets");
        const OffsetQuadtree expected = layoutOffsetQuadtree(whole, values, {}, bits, "test");
        PartwiseLayout layout(6, 6 - std::countr_zero(partSize), partCount, bits, "test");
        int rounds = 0;
        do {
          ++rounds;
          for (uint64_t index = 0; index < partCount; ++index) layout.measure(index, trees[index]);
        } while (!layout.settle(upper));
        for (uint64_t index = 0; index < partCount; ++index) layout.write(index, trees[index]);
        const OffsetQuadtree got = layout.finish();
        if (bits == 16) CHECK(rounds == 1);
        if (bits == 3) CHECK(rounds > 1);
        CHECK(got.rootKind == expected.rootKind);
        CHECK(got.levelScale == expected.levelScale);
        CHECK(got.words == expected.words);
      }
    }
}

TEST_CASE("hierarchical PCF reads a blocky map's coarse levels exactly", "[mh]") {
  // 8×8 blocks of one depth each: the hierarchy holds each block's depth at level 3, so the maps
  // 1, 2 and 3 levels up answer as the blocks do, and 3×3 at level 3 averages 3×3 blocks.
  const uint32_t r = 64, block = 8, blocks = r / block;
  SyntheticMap map{r, DepthMode::Open, std::vector<float>(r * r), {}};
  uint64_t state = 12;
  std::vector<float> depth(blocks * blocks);
  for (float& d : depth) d = 0.1f + 0.8f * unitFloat(nextRandom(state));
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i) map.lo[j * r + i] = depth[(j / block) * blocks + i / block];
  map.hi = map.lo;
  const auto blockDepth = [&](int64_t bi, int64_t bj) {
    const bool outside = bi < 0 || bj < 0 || bi >= int64_t(blocks) || bj >= int64_t(blocks);
    return outside ? 1.0f : depth[size_t(bj) * blocks + size_t(bi)];
  };
  int hierarchical = 0;
  for (const SchemeInfo& scheme : schemes()) {
    const auto decoder = map.build(scheme, {}, 16);
    const auto* levels = dynamic_cast<const HierarchicalLookup*>(decoder.get());
    if (!levels) continue;
    ++hierarchical;
    INFO(scheme.name);
    CHECK(levels->levels() == 6);
    for (int coarser = 0; coarser <= 3; ++coarser) {
      const uint32_t side = r >> coarser;
      std::vector<Query> queries;
      std::vector<float> expected;
      for (uint32_t j = 0; j < side; ++j)
        for (uint32_t i = 0; i < side; ++i) {
          const float d = blockDepth((i << coarser) / block, (j << coarser) / block);
          const float x = (float(i) + 0.5f) / float(side), y = (float(j) + 0.5f) / float(side);
          queries.push_back({x, y, d});
          expected.push_back(1.0f);
          queries.push_back({x, y, std::nextafter(d, 2.0f)});
          expected.push_back(0.0f);
        }
      std::vector<float> got(queries.size());
      levels->lookupCoarse(queries, coarser, 1, got);
      CHECK(got == expected);
    }
    std::vector<Query> queries;
    std::vector<float> expected;
    for (uint32_t bj = 0; bj < blocks; ++bj)
      for (uint32_t bi = 0; bi < blocks; ++bi) {
        const float z = blockDepth(bi, bj);
        queries.push_back(
            {(float(bi) + 0.5f) / float(blocks), (float(bj) + 0.5f) / float(blocks), z});
        int lit = 0;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di)
            lit += z <= blockDepth(int64_t(bi) + di, int64_t(bj) + dj);
        expected.push_back(float(lit) / 9.0f);
      }
    std::vector<float> got(queries.size());
    levels->lookupCoarse(queries, 3, 3, got);
    CHECK(got == expected);
    CHECK_THROWS_AS(levels->lookupCoarse(queries, 7, 1, got), std::invalid_argument);
  }
  CHECK(hierarchical >= 2);  // mh and mmh
}

}  // namespace
}  // namespace sb
