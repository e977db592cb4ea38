// delta-dag against independent answers: the simplest number of an interval by brute force, every
// texel's key inside its interval on seeded maps, sharing on maps built to repeat, and the
// structure read back from its bytes answering as built. (The correctness matrix and the
// interface tests check it like every scheme; these pin what is its own.)
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include "schemes/delta-dag/delta_dag.h"
#include "schemes/delta-dag/pack_layout.h"
#include "schemes/interface/scheme.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "tests/support/hierarchy_map.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using delta_dag::DeltaDag;
using delta_dag::Options;
using delta_dag::ValueChoice;
using testing::hierarchyOf;
using testing::SyntheticMap;
constexpr float kInf = std::numeric_limits<float>::infinity();

// The number with the most trailing zeros in [lo, hi] by trying them all (0 counts as having
// the most).
int64_t simplestByBruteForce(int64_t lo, int64_t hi) {
  int64_t best = lo;
  for (int64_t v = lo; v <= hi; ++v) {
    if (v == 0) return 0;
    if (std::countr_zero(uint64_t(v)) > std::countr_zero(uint64_t(best))) best = v;
  }
  return best;
}

uint64_t texelsOutside(const SyntheticMap& map, const DeltaDag& dag) {
  uint64_t wrong = 0;
  for (uint32_t j = 0; j < map.resolution; ++j)
    for (uint32_t i = 0; i < map.resolution; ++i)
      wrong += !testing::insideInterval(map, i, j, dag.texelKey(i, j));
  return wrong;
}

// A random rectangle of sides 1 to maxSide within a map of side `resolution`.
TexelRect randomRect(uint64_t& state, uint32_t resolution, uint32_t maxSide) {
  const uint32_t width = 1 + uint32_t(nextRandom(state) % maxSide);
  const uint32_t height = 1 + uint32_t(nextRandom(state) % maxSide);
  const uint32_t i0 = uint32_t(nextRandom(state) % (resolution + 1 - width));
  const uint32_t j0 = uint32_t(nextRandom(state) % (resolution + 1 - height));
  return {i0, j0, i0 + width - 1, j0 + height - 1};
}

// Whether one kernel walk over `rect` gives each key as many texels as a point walk per texel.
bool kernelWalkMatchesPointWalks(const DeltaDag& dag, const TexelRect& rect) {
  std::map<uint32_t, uint64_t> walked, pointwise;
  dag.forEachKeyBlock(rect, [&](uint32_t key, uint64_t texels) { walked[key] += texels; });
  for (uint32_t j = rect.j0; j <= rect.j1; ++j)
    for (uint32_t i = rect.i0; i <= rect.i1; ++i) ++pointwise[dag.texelKey(i, j)];
  return walked == pointwise;
}

// A 64² map of one motif repeated, each copy raised by its own depth, with bands of the same
// width: the copies' relative intervals are equal, so their packs must be shared.
SyntheticMap repeatedMotif(uint64_t seed, uint32_t motifSize) {
  const SyntheticMap motif = SyntheticMap::random(motifSize, DepthMode::Closed, seed);
  SyntheticMap map{64, DepthMode::Closed, std::vector<float>(64 * 64), std::vector<float>(64 * 64)};
  for (uint32_t j = 0; j < 64; ++j)
    for (uint32_t i = 0; i < 64; ++i) {
      const size_t at = size_t(j) * 64 + i, m = size_t(j % motifSize) * motifSize + i % motifSize;
      map.lo[at] = motif.lo[m] == 1.0f ? 1.0f : motif.lo[m] * 0.5f;
      map.hi[at] = motif.hi[m] == kInf ? kInf : map.lo[at] + 0.05f;
    }
  return map;
}

DeltaDag roundTrip(const DeltaDag& dag, const MapInfo& map) {
  ByteWriter out;
  dag.save(out);
  ByteReader in(out.bytes());
  DeltaDag loaded = DeltaDag::load(in, map);
  in.expectEnd();
  return loaded;
}

TEST_CASE("the simplest number of an interval is the one with the most trailing zeros",
          "[delta-dag]") {
  uint64_t state = 16;
  for (int trial = 0; trial < 20000; ++trial) {
    const int64_t a = int64_t(nextRandom(state) % 4001) - 2000;
    const int64_t b = a + int64_t(nextRandom(state) % (trial % 7 == 0 ? 3000 : 40));
    INFO("[" << a << ", " << b << "]");
    CHECK(delta_dag::simplestIn(a, b) == simplestByBruteForce(a, b));
  }
  CHECK(delta_dag::simplestIn(0x3f000001, 0x7f800000) == 0x40000000);
  CHECK(delta_dag::simplestIn(-0x7f800000, -0x3f000001) == -0x40000000);
  CHECK(delta_dag::simplestIn(5, 5) == 5);
}

TEST_CASE("every texel's key lies in its interval, for every option", "[delta-dag]") {
  for (const DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    for (uint64_t seed = 1; seed <= 6; ++seed)
      for (const uint32_t resolution : {1u, 2u, 16u, 64u})
        for (const ValueChoice values : {ValueChoice::Simplest, ValueChoice::Middle})
          for (const bool sharing : {true, false})
            for (const bool symmetry : {true, false}) {
              const SyntheticMap map = SyntheticMap::random(resolution, mode, seed);
              const delta_dag::Encoded encoded =
                  delta_dag::encode(hierarchyOf(map, std::min(resolution, 16u)),
                                    {values, sharing, true, true, symmetry});
              INFO("mode " << toString(mode) << ", seed " << seed << ", R " << resolution
                           << ", symmetry " << symmetry);
              CHECK(texelsOutside(map, encoded.dag) == 0);
              const DeltaDag loaded = roundTrip(encoded.dag, map.info(SchemeKind::Depth));
              for (uint32_t j = 0; j < resolution; ++j)
                for (uint32_t i = 0; i < resolution; ++i)
                  REQUIRE(loaded.texelKey(i, j) == encoded.dag.texelKey(i, j));
              const delta_dag::Statistics& s = encoded.statistics;
              CHECK(s.dagPacks <= s.treePacks);
              CHECK(encoded.dag.bits() ==
                    s.headerBits + s.valueBits + s.pointerBits + s.symmetryBits + s.paddingBits);
              if (!symmetry || !sharing) CHECK(s.symmetryBits == 0);
            }
}

// The README's skip table: entries of 8 bytes (12 where the packs hold 2^29 bits or more) for
// every square of the deepest level whose table takes at most 1 MiB and 1/5 of the packs' bytes,
// or 1/32 of them where that is more.
TEST_CASE("the skip table's level follows its budget", "[delta-dag]") {
  CHECK(DeltaDag::skipEntryWords((uint64_t(1) << 29) - 1) == 2);
  CHECK(DeltaDag::skipEntryWords(uint64_t(1) << 29) == 3);
  CHECK(DeltaDag::skipLevelFor(40'959 * 8, 10) == 4);  // 1/5 just short of 4^5 entries (8 KiB)
  CHECK(DeltaDag::skipLevelFor(40'960 * 8, 10) == 5);  // 1/5: 8 KiB
  CHECK(DeltaDag::skipLevelFor(uint64_t(20) << 23, 14) == 8);  // 1/5 is 4 MiB, but at most 1 MiB
  CHECK(DeltaDag::skipLevelFor((uint64_t(96) << 23) - 256, 14) == 8);  // 1/32 short of 3 MiB
  CHECK(DeltaDag::skipLevelFor(uint64_t(96) << 23, 14) == 9);  // 1/32: 3 MiB of 12-byte entries
  CHECK(DeltaDag::skipLevelFor(uint64_t(1) << 33, 5) == 5);    // no deeper than the map
}

// `skip-budget` moves the cap of 1 MiB and nothing else: 16 MiB of packs (the forest at 16K²)
// take level 9's 2 MiB from a budget of 2 MiB, 8 MiB of packs stay within a fifth of theirs, and
// a budget of 0 leaves the 32nd of the packs.
TEST_CASE("the skip table's budget moves its level", "[delta-dag]") {
  const uint64_t mib = uint64_t(1) << 20, forest = uint64_t(16) << 23;
  CHECK(DeltaDag::skipLevelFor(forest, 14) == 8);
  CHECK(DeltaDag::skipLevelFor(forest, 14, 2 * mib - 1) == 8);
  CHECK(DeltaDag::skipLevelFor(forest, 14, 2 * mib) == 9);
  CHECK(DeltaDag::skipLevelFor(forest, 14, 64 * mib) == 9);  // 1/5 is 3.2 MiB
  CHECK(DeltaDag::skipLevelFor(forest / 2, 14, 64 * mib) == 8);
  CHECK(DeltaDag::skipLevelFor(forest, 14, 0) == 8);            // 1/32: 512 KiB
  CHECK(DeltaDag::skipLevelFor(40'960 * 8, 10, 0) == 3);        // 1/32: 1280 bytes
  CHECK(DeltaDag::skipLevelFor(40'960 * 8, 10, 8 * mib) == 5);  // 1/5: 8 KiB
}

// A structure with a deeper skip table, built or loaded with a larger budget, answers every
// texel and every rectangle as the default's does, and the loaded one keeps the budget it was
// given: a 1024² map (packs of about 530 KB) at budgets of 0, the default and 64 MiB.
TEST_CASE("every skip budget answers alike", "[delta-dag]") {
  const SyntheticMap map = SyntheticMap::random(1024, DepthMode::Closed, 5);
  const MapInfo info = map.info(SchemeKind::Depth);
  const MultiresHierarchy hierarchy = hierarchyOf(map, 16);
  const DeltaDag reference = delta_dag::encode(hierarchy, {}).dag;
  uint64_t state = 19;
  for (const uint64_t budget : {uint64_t(0), delta_dag::kDefaultSkipBudget, uint64_t(64) << 20}) {
    Options options;
    options.skipBudget = budget;
    const DeltaDag built = delta_dag::encode(hierarchy, options).dag;
    ByteWriter out;
    built.save(out);
    ByteReader in(out.bytes());
    const DeltaDag loaded = DeltaDag::load(in, info, budget);
    INFO("budget " << budget);
    CHECK(built.skipLevel() == DeltaDag::skipLevelFor(built.bits(), built.levels(), budget));
    CHECK(loaded.skipLevel() == built.skipLevel());
    CHECK(texelsOutside(map, loaded) == 0);
    for (uint32_t j = 0; j < 1024; ++j)
      for (uint32_t i = 0; i < 1024; ++i)
        REQUIRE(loaded.texelKey(i, j) == reference.texelKey(i, j));
    for (int trial = 0; trial < 300; ++trial) {
      const TexelRect rect = randomRect(state, 1024, trial % 4 == 0 ? 300 : 12);
      REQUIRE(kernelWalkMatchesPointWalks(loaded, rect));
    }
  }
  CHECK(DeltaDag::skipLevelFor(reference.bits(), 10, uint64_t(64) << 20) >
        DeltaDag::skipLevelFor(reference.bits(), 10, 0));
}

// The registry's `skip-budget` reaches the build and the load: on that map, 0 KiB leaves a 32nd
// of the packs (level 5, 8 KiB of entries) where the default takes a fifth (level 6, 32 KiB),
// and a structure loaded with the other budget rebuilds its table at the other level.
TEST_CASE("delta-dag: skip-budget sets the skip table of a build and of a load", "[delta-dag]") {
  const SchemeInfo& scheme = findScheme("delta-dag");
  const SyntheticMap map = SyntheticMap::random(1024, DepthMode::Closed, 5);
  const MapInfo info = map.info(scheme.kind);
  const auto skipBytes = [](const Decoder& decoder) {
    for (const auto& [part, bytes] : decoder.size())
      if (part == "skip table") return bytes;
    return uint64_t(0);
  };
  const auto defaults = map.build(scheme, {}, 16);
  const auto small = map.build(scheme, {{"skip-budget", "0"}}, 16);
  CHECK(skipBytes(*defaults) == 32 * 1024);
  CHECK(skipBytes(*small) == 8 * 1024);
  ByteWriter out;
  small->save(out);
  ByteReader in(out.bytes());
  const auto reloaded = scheme.load(in, info, scheme.resolve({}));
  CHECK(skipBytes(*reloaded) == 32 * 1024);
  CHECK_THROWS_WITH(scheme.resolve({{"skip-budget", "-1"}}),
                    Catch::Contains("delta-dag") && Catch::Contains("skip-budget"));
}

// A skip entry gives back the walk it was made of at the skip level, in either width, with
// positions up to the width's limit; a walk that ended above the level (a leaf, or a missing
// child whose square takes the walk's key) comes back as a leaf with its key.
TEST_CASE("a skip entry gives back the walk it was made of", "[delta-dag]") {
  const int level = 9;
  const std::pair<DeltaDag::Walk, uint32_t> walks[] = {
      {{(uint64_t(1) << 29) - 2, 0xffffffff, MhChild::Full, delta_dag::Symmetry(7), level}, 2},
      {{0, 77, MhChild::Empty, delta_dag::Symmetry(5), level}, 2},
      {{(uint64_t(1) << 51) - 1, 0xffffffff, MhChild::Empty, delta_dag::Symmetry(7), level}, 3},
      {{(uint64_t(1) << 32) + 12345, 77, MhChild::Full, delta_dag::Symmetry(5), level}, 3}};
  for (const auto& [walk, words] : walks) {
    uint32_t entry[3] = {};
    DeltaDag::putSkipEntry(entry, words, walk, level);
    const DeltaDag::Walk back = DeltaDag::skipEntryWalk(entry, words, level);
    CHECK(back.position == walk.position);
    CHECK(back.key == walk.key);
    CHECK(back.kind != MhChild::Leaf);
    CHECK(back.symmetry == walk.symmetry);
    CHECK(back.level == level);
  }
  const DeltaDag::Walk ended[] = {{123, 5, MhChild::Leaf, delta_dag::Symmetry(3), level - 2},
                                  {123, 6, MhChild::Full, delta_dag::Symmetry(3), level - 1}};
  for (const uint32_t words : {2u, 3u})
    for (const DeltaDag::Walk& walk : ended) {
      uint32_t entry[3] = {};
      DeltaDag::putSkipEntry(entry, words, walk, level);
      const DeltaDag::Walk back = DeltaDag::skipEntryWalk(entry, words, level);
      CHECK(back.kind == MhChild::Leaf);
      CHECK(back.key == walk.key);
    }
}

// The table built is the level's, 8 bytes a square, on random maps of 256² (packs of about 25
// KB), 1024² (about 530 KB) and 2048² (about 2 MB).
TEST_CASE("the skip table holds 8 bytes a square of its level", "[delta-dag]") {
  const std::pair<uint64_t, uint32_t> maps[] = {{1, 256},  {2, 256},  {3, 256}, {4, 256},
                                                {1, 1024}, {2, 1024}, {1, 2048}};
  for (const auto& [seed, resolution] : maps) {
    const SyntheticMap map = SyntheticMap::random(resolution, DepthMode::Closed, seed);
    const DeltaDag dag = delta_dag::encode(hierarchyOf(map, 16), {}).dag;
    uint64_t skipBytes = 0;
    for (const auto& [part, bytes] : dag.size())
      if (part == "skip table") skipBytes = bytes;
    const int level = DeltaDag::skipLevelFor(dag.bits(), dag.levels());
    INFO("seed " << seed << ", R " << resolution << ", packs " << dag.bits() / 8 << " bytes");
    CHECK(level >= 3);
    CHECK(skipBytes == uint64_t(8) << (2 * level));
  }
}

// A walk that ends above the skip level (at a leaf or a missing child) is kept as a leaf with its
// key: on a 512² map of one interval but for two random blocks, where most of the table's squares
// are answered above its level, every texel and every rectangle through the loaded structure.
TEST_CASE("walks that end above the skip level answer their whole square", "[delta-dag]") {
  SyntheticMap map = SyntheticMap::uniform(512, 0.25f, 0.75f);
  for (const auto& [seed, x0, y0, side] : {std::tuple{1u, 64u, 128u, 64u}, {2u, 300u, 400u, 8u}}) {
    const SyntheticMap block = SyntheticMap::random(side, DepthMode::Closed, seed);
    for (uint32_t j = 0; j < side; ++j)
      for (uint32_t i = 0; i < side; ++i) {
        map.lo[size_t(y0 + j) * 512 + x0 + i] = block.lo[size_t(j) * side + i];
        map.hi[size_t(y0 + j) * 512 + x0 + i] = block.hi[size_t(j) * side + i];
      }
  }
  const DeltaDag built = delta_dag::encode(hierarchyOf(map, 16), {}).dag;
  const DeltaDag dag = roundTrip(built, map.info(SchemeKind::Depth));
  const int level = DeltaDag::skipLevelFor(dag.bits(), dag.levels());
  REQUIRE(level >= 2);
  const uint32_t side = 512 >> level;
  uint32_t answeredAbove = 0;
  for (uint32_t j = 0; j < 512; j += side)
    for (uint32_t i = 0; i < 512; i += side)
      answeredAbove += dag.skipWalk(i, j).kind == MhChild::Leaf;
  CHECK(answeredAbove > (1u << (2 * level)) / 2);
  CHECK(dag.skipLevel() == level);
  CHECK(dag.skipSquaresAnsweredAbove() == answeredAbove);
  CHECK(texelsOutside(map, dag) == 0);
  uint64_t state = 5;
  for (int trial = 0; trial < 300; ++trial) {
    const TexelRect rect = randomRect(state, 512, 100);
    INFO("rect " << rect.i0 << ", " << rect.j0 << " to " << rect.i1 << ", " << rect.j1);
    REQUIRE(kernelWalkMatchesPointWalks(dag, rect));
  }
}

// A kernel walk gives each texel of its rectangle the key its point walk gives: rectangles
// within one skip-table square, across the edges of 2 or 4 (walked from each), and across more
// (walked from the root), on maps whose skip table is at level 4.
TEST_CASE("a kernel walk gives every texel of its rectangle its point walk's key", "[delta-dag]") {
  uint64_t state = 13;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const SyntheticMap map = SyntheticMap::random(256, DepthMode::Closed, seed);
    const DeltaDag dag = delta_dag::encode(hierarchyOf(map, 16), {}).dag;
    for (int trial = 0; trial < 400; ++trial) {
      const TexelRect rect = randomRect(state, 256, trial % 4 == 0 ? 200 : 12);
      INFO("seed " << seed << ", rect " << rect.i0 << ", " << rect.j0 << " to " << rect.i1 << ", "
                   << rect.j1);
      REQUIRE(kernelWalkMatchesPointWalks(dag, rect));
    }
  }
}

// Each key-range square holds the least and greatest of its texels' keys, and a kernel that the
// ranges settle counts the texels its point walks light: z at a range's ends (settled) and a float
// inside them (walked), on maps whose ranges lie at level 3.
TEST_CASE("key ranges bound their squares' keys and settle kernels exactly", "[delta-dag]") {
  uint64_t state = 17;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const SyntheticMap map = SyntheticMap::random(256, DepthMode::Closed, seed);
    const MapInfo info = map.info(SchemeKind::Depth);
    const DeltaDag dag = roundTrip(delta_dag::encode(hierarchyOf(map, 16), {}).dag, info);
    REQUIRE(dag.keyRangeLevel() == dag.skipLevel() - 1);
    const uint32_t side = 256 >> dag.keyRangeLevel();
    for (uint32_t y = 0; y < 256; y += side)
      for (uint32_t x = 0; x < 256; x += side) {
        uint32_t least = UINT32_MAX, greatest = 0;
        for (uint32_t j = y; j < y + side; ++j)
          for (uint32_t i = x; i < x + side; ++i)
            least = std::min(least, dag.texelKey(i, j)),
            greatest = std::max(greatest, dag.texelKey(i, j));
        const DeltaDag::KeyRange range = dag.keyRange(x, y);
        INFO("seed " << seed << ", square at " << x << ", " << y);
        CHECK(range.known());
        CHECK(range.least == least);
        CHECK(range.greatest == greatest);
      }
    const delta_dag::Decoder decoder(dag);
    for (int trial = 0; trial < 200; ++trial) {
      const TexelRect rect = randomRect(state, 256, 12);
      const DeltaDag::KeyRange range = dag.keyRange(rect.i0, rect.j0);
      const float least = depthOfKey(range.least), greatest = depthOfKey(range.greatest);
      for (const float z : {least, std::nextafter(least, 2.0f), std::nextafter(greatest, 0.0f),
                            greatest, std::nextafter(greatest, kInf)}) {
        uint64_t lit = 0;
        for (uint32_t j = rect.j0; j <= rect.j1; ++j)
          for (uint32_t i = rect.i0; i <= rect.i1; ++i) lit += z <= depthOfKey(dag.texelKey(i, j));
        INFO("seed " << seed << ", rect " << rect.i0 << ", " << rect.j0 << " to " << rect.i1 << ", "
                     << rect.j1 << ", z " << z);
        REQUIRE(decoder.litTexels(rect, z) == lit);
      }
    }
  }
}

TEST_CASE("a uniform map is one leaf root", "[delta-dag]") {
  const SyntheticMap map = SyntheticMap::uniform(32, 0.25f, 0.75f);
  const delta_dag::Encoded encoded = delta_dag::encode(hierarchyOf(map, 16), {});
  CHECK(encoded.dag.bits() == 0);
  // The simplest key in [0.25, 0.75] is 0.5's: the only key of the interval with 24 trailing zeros.
  CHECK(encoded.dag.texelKey(7, 9) == std::bit_cast<uint32_t>(0.5f));
}

TEST_CASE("the encode step reserves memory as it finds packs, and stops where refused",
          "[delta-dag]") {
  // A random 2K² map keeps more than 2^17 distinct packs: reserved before the store doubles at
  // each power of two from 2^16 on, then once for the layout of all of them.
  const SyntheticMap map = SyntheticMap::random(2048, DepthMode::Closed, 3);
  std::vector<std::pair<uint64_t, std::string>> asked;
  const delta_dag::Encoded encoded = delta_dag::encode(
      hierarchyOf(map, 16), {},
      [&](uint64_t bytes, std::string_view what) { asked.emplace_back(bytes, what); });
  const uint64_t packs = encoded.statistics.dagPacks;
  REQUIRE(packs > (1u << 17));
  std::vector<std::string> expected;
  for (uint64_t count = 1u << 16; count < packs; count *= 2)
    expected.push_back(fmt::format("delta-dag: hash-consing past {} distinct packs", count));
  expected.push_back(fmt::format("delta-dag: laying out {} distinct packs", packs));
  REQUIRE(asked.size() == expected.size());
  for (size_t call = 0; call < asked.size(); ++call) CHECK(asked[call].second == expected[call]);
  // Every byte the pack store takes is among those reserved: 40 a pack, twice over as it doubles.
  CHECK(asked[0].first >= (1u << 16) * 2 * sizeof(delta_dag::Pack));
  CHECK(asked[1].first == 2 * asked[0].first);
  CHECK(asked.back().first >= packs * 2 * sizeof(delta_dag::Pack));
  // A refusal ends the encode step with its message, before the memory is taken.
  CHECK_THROWS_WITH(delta_dag::encode(hierarchyOf(map, 16), {},
                                      [](uint64_t, std::string_view what) {
                                        throw std::runtime_error(std::string(what));
                                      }),
                    expected.front());
}

TEST_CASE("repeated subtrees are stored once, and simplest values find more of them",
          "[delta-dag]") {
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    const SyntheticMap map = repeatedMotif(seed, seed % 2 ? 8 : 16);
    const auto build = [&](ValueChoice values, bool sharing) {
      return delta_dag::encode(hierarchyOf(map, 16), {values, sharing});
    };
    const delta_dag::Encoded tree = build(ValueChoice::Simplest, false);
    const delta_dag::Encoded dag = build(ValueChoice::Simplest, true);
    const delta_dag::Encoded middle = build(ValueChoice::Middle, true);
    INFO("seed " << seed);
    CHECK(texelsOutside(map, dag.dag) == 0);
    CHECK(dag.statistics.treePacks == tree.statistics.treePacks);
    // Every copy of the motif repeats the packs below the motif's root at least.
    CHECK(dag.statistics.dagPacks * 2 < dag.statistics.treePacks);
    CHECK(dag.statistics.sharedPacks > 0);
    CHECK(tree.statistics.sharedPacks == 0);
    CHECK(dag.dag.bits() < tree.dag.bits());
    CHECK(dag.statistics.dagPacks <= middle.statistics.dagPacks);
  }
}

// A random quadrant and its three images: mirrored in x, in y, and transposed. With symmetries the
// quadrants are one shared pack read four ways; without, four packs with little in common.
SyntheticMap mirroredQuadrants(uint64_t seed) {
  const SyntheticMap quadrant = SyntheticMap::random(32, DepthMode::Closed, seed);
  SyntheticMap map{64, DepthMode::Closed, std::vector<float>(64 * 64), std::vector<float>(64 * 64)};
  for (uint32_t j = 0; j < 64; ++j)
    for (uint32_t i = 0; i < 64; ++i) {
      uint32_t x = i % 32, y = j % 32;
      if (i >= 32 && j < 32) x = 31 - x;
      if (i < 32 && j >= 32) y = 31 - y;
      if (i >= 32 && j >= 32) std::swap(x, y);
      map.lo[size_t(j) * 64 + i] = quadrant.lo[size_t(y) * 32 + x];
      map.hi[size_t(j) * 64 + i] = quadrant.hi[size_t(y) * 32 + x];
    }
  return map;
}

TEST_CASE("subtrees equal under a mirroring or a transposition are stored once", "[delta-dag]") {
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    const SyntheticMap map = mirroredQuadrants(seed);
    const auto build = [&](bool symmetry) {
      return delta_dag::encode(hierarchyOf(map, 16),
                               {ValueChoice::Simplest, true, true, true, symmetry});
    };
    const delta_dag::Encoded mirrors = build(true), none = build(false);
    INFO("seed " << seed);
    CHECK(texelsOutside(map, mirrors.dag) == 0);
    const DeltaDag loaded = roundTrip(mirrors.dag, map.info(SchemeKind::Depth));
    CHECK(texelsOutside(map, loaded) == 0);
    // The root's pack, and the quadrant's packs once rather than about four times.
    CHECK(mirrors.statistics.dagPacks * 3 < none.statistics.dagPacks);
    // Three of the root's four references read the quadrant turned.
    CHECK(mirrors.statistics.symmetryBits >= 3 * delta_dag::kSymmetryBits);
    CHECK(mirrors.dag.bits() * 2 < none.dag.bits());
  }
}

// Every texel's key inside its interval, and a sample of texels read back from the bytes alike.
void checkReadsBackAsBuilt(const SyntheticMap& map, const DeltaDag& dag) {
  CHECK(texelsOutside(map, dag) == 0);
  const DeltaDag loaded = roundTrip(dag, map.info(SchemeKind::Depth));
  for (uint32_t j = 0; j < map.resolution; j += 3)
    for (uint32_t i = 0; i < map.resolution; i += 5)
      REQUIRE(loaded.texelKey(i, j) == dag.texelKey(i, j));
}

// Small maps have too few packs for a table to pay (the golden file has none); at 2048² the
// random map's packs repeat formats enough.
TEST_CASE("a layout with a table of formats reads back as built", "[delta-dag]") {
  const SyntheticMap map = SyntheticMap::random(2048, DepthMode::Closed, 7);
  const delta_dag::Encoded encoded = delta_dag::encode(hierarchyOf(map, 256), {});
  REQUIRE(encoded.statistics.formats > 0);
  CHECK(encoded.statistics.escapes < encoded.statistics.dagPacks);
  checkReadsBackAsBuilt(map, encoded.dag);
}

// A pack's shared children are referenced unequally often, so their addresses differ in width:
// table formats that give each its own width take fewer pointer bits than the widest's for all,
// and the structure still reads every texel's key, also from its bytes.
TEST_CASE("a table format's own width for each shared address takes fewer pointer bits",
          "[delta-dag]") {
  for (const uint64_t seed : {3u, 4u}) {
    const SyntheticMap map = SyntheticMap::random(2048, DepthMode::Closed, seed);
    const auto build = [&](bool sharedWidths) {
      Options options;
      options.sharedWidths = sharedWidths;
      return delta_dag::encode(hierarchyOf(map, 256), options);
    };
    const delta_dag::Encoded each = build(true), widest = build(false);
    INFO("seed " << seed);
    REQUIRE(each.statistics.formats > 0);
    CHECK(each.statistics.pointerBits < widest.statistics.pointerBits);
    checkReadsBackAsBuilt(map, each.dag);
  }
}

// An open map of tilted planes, their float depths as a ray caster rounds them (each texel a point
// interval): the keys of a square's corners are on a plane to an ulp or two, so the packs of
// three values predict the fourth child's opposite and take fewer value bits, and every texel
// still reads its exact key, also read back from the bytes, and by kernel walks (which cut a
// texel pack's narrow values, the predicted one too, from one read).
TEST_CASE("values predicted from the plane through a pack read their exact keys", "[delta-dag]") {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    uint64_t state = seed;
    const float dx = 1e-4f * float(1 + nextRandom(state) % 9),
                dy = 0.7e-4f * float(1 + nextRandom(state) % 9);
    SyntheticMap map{128, DepthMode::Open, std::vector<float>(128 * 128), {}};
    for (uint32_t j = 0; j < 128; ++j)
      for (uint32_t i = 0; i < 128; ++i)
        map.lo[size_t(j) * 128 + i] = i < 100 ? 0.3f + dx * float(i) + dy * float(j) : 0.9f;
    map.hi = map.lo;
    const auto build = [&](bool prediction) {
      Options options;
      options.prediction = prediction;
      return delta_dag::encode(hierarchyOf(map, 32), options);
    };
    const delta_dag::Encoded predicted = build(true), plain = build(false);
    INFO("seed " << seed << ", slopes " << dx << ", " << dy);
    CHECK(texelsOutside(map, predicted.dag) == 0);
    CHECK(predicted.statistics.valueBits < plain.statistics.valueBits * 9 / 10);
    const DeltaDag loaded = roundTrip(predicted.dag, map.info(SchemeKind::Depth));
    for (uint32_t j = 0; j < map.resolution; ++j)
      for (uint32_t i = 0; i < map.resolution; ++i)
        REQUIRE(loaded.texelKey(i, j) == depthKey(map.lo[size_t(j) * 128 + i]));
    for (int trial = 0; trial < 200; ++trial) {
      const TexelRect rect = randomRect(state, 128, 12);
      INFO("rect " << rect.i0 << ", " << rect.j0 << " to " << rect.i1 << ", " << rect.j1);
      REQUIRE(kernelWalkMatchesPointWalks(loaded, rect));
    }
  }
}

}  // namespace
}  // namespace sb
