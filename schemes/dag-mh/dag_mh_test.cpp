// DAG-MH against independent answers: the value chunks against the intervals they encode, the
// DAG's traversal against MultiresHierarchy::texelInterval (a plain walk of the hierarchy), the
// scheme against the synthetic map's intervals, and the loader against corrupted structures.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "schemes/dag-mh/dag.h"
#include "schemes/dag-mh/value_chunks.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "tests/support/hierarchy_map.h"

using namespace sb;
using namespace sb::dag_mh;
using sb::testing::hierarchyOf;
using sb::testing::SyntheticMap;

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

KeyInterval interval(float lo, float hi) {
  return {depthKey(lo), depthKey(hi)};
}

bool inside(float value, const KeyInterval& in) {
  return !std::isnan(value) && depthOfKey(in.lo) <= value && value <= depthOfKey(in.hi);
}

// Intervals of every kind a hierarchy holds, in runs that share a depth the way neighbouring
// values of the depth-first list do: points (open mode, intersections), open-ended bands (empty
// sky, closed mode), a few ulps wide, huge ranges, zeros and subnormals.
std::vector<KeyInterval> randomIntervals(size_t count, uint64_t seed) {
  uint64_t state = seed;
  auto unit = [&] { return unitFloat(nextRandom(state)); };
  std::vector<KeyInterval> intervals;
  float base = unit();
  while (intervals.size() < count) {
    if (nextRandom(state) % 8 == 0) base = unit();
    const float lo = std::clamp(base + (unit() - 0.5f) * 0.01f * unit(), 0.0f, 0.99f);
    switch (nextRandom(state) % 9) {
      case 0:
      case 1:
        intervals.push_back(interval(lo, lo));
        break;
      case 2:
        intervals.push_back(interval(nextRandom(state) % 2 ? 1.0f : lo, kInfinity));
        break;
      case 3: {
        float hi = lo;
        for (uint64_t ulps = nextRandom(state) % 4; ulps > 0; --ulps) hi = std::nextafter(hi, 2.0f);
        intervals.push_back(interval(lo, hi));
        break;
      }
      case 4:
        intervals.push_back(interval(unit() * 1e-6f, 1e30f * unit()));
        break;
      case 5:
        intervals.push_back(interval(0.0f, nextRandom(state) % 2 ? 0.0f : unit()));
        break;
      case 6: {
        const float subnormal =
            std::numeric_limits<float>::denorm_min() * float(nextRandom(state) % 100);
        intervals.push_back(interval(subnormal, subnormal * 2));
        break;
      }
      default:
        intervals.push_back(interval(lo, std::min(1.0f, lo + unit() * 0.2f)));
        break;
    }
  }
  return intervals;
}

void checkChunks(std::span<const KeyInterval> intervals, uint32_t chunkSize) {
  ValueChunkStats stats;
  const ValueChunks chunks(intervals, chunkSize, &stats);
  REQUIRE(chunks.valueCount() == intervals.size());
  size_t outside = 0;
  for (uint32_t v = 0; v < intervals.size(); ++v) {
    const float value = chunks.value(v);
    if (!inside(value, intervals[v])) {
      ++outside;
      UNSCOPED_INFO("value " << v << " = " << value << " outside [" << depthOfKey(intervals[v].lo)
                             << ", " << depthOfKey(intervals[v].hi) << "]");
    }
  }
  CHECK(outside == 0);
  CHECK(stats.covered + stats.factors == intervals.size());
  CHECK(chunks.infoSize() == (intervals.size() + chunkSize - 1) / chunkSize * chunks.infoBytes());

  // The saved chunks load and answer the same.
  ByteWriter out;
  chunks.save(out);
  ByteReader in(out.bytes());
  const ValueChunks loaded = ValueChunks::load(in, chunkSize, chunks.valueCount());
  in.expectEnd();
  for (uint32_t v = 0; v < intervals.size(); ++v)
    CHECK(std::bit_cast<uint32_t>(loaded.value(v)) == std::bit_cast<uint32_t>(chunks.value(v)));
}

// Save and load through the scheme's own arrays, the way the scheme's payload holds them.
template <class F>
void roundTrip(const Dag& dag, uint32_t valueCount, F&& check) {
  ByteWriter out;
  dag.save(out);
  ByteReader in(out.bytes());
  const Dag loaded = Dag::load(in, dag.levels, dag.treelet.height, dag.skipLevel, valueCount);
  in.expectEnd();
  check(loaded);
}

Dag loadSaved(const Dag& dag, uint32_t valueCount) {
  ByteWriter out;
  dag.save(out);
  ByteReader in(out.bytes());
  return Dag::load(in, dag.levels, dag.treelet.height, dag.skipLevel, valueCount);
}

class RecordingContext final : public BuildContext {
 public:
  void phase(std::string_view name) override { phases.emplace_back(name); }
  void count(std::string_view name, uint64_t value) override {
    counters[std::string(name)] += value;
  }
  void reserve(uint64_t, std::string_view) override {}
  std::vector<std::string> phases;
  std::map<std::string, uint64_t> counters;
};

}  // namespace

TEST_CASE("dag-mh: treelet shapes follow §3.2 and §3.4", "[dag-mh]") {
  const TreeletShape four = TreeletShape::of(4);
  CHECK(four.bits == 85);
  CHECK(four.words * 4 == 12);  // "a 12 byte treelet"
  CHECK(four.subtreeBits[1] == 21);
  CHECK(four.subtreeBits[2] == 5);
  CHECK(four.subtreeBits[3] == 1);
  const TreeletShape five = TreeletShape::of(5);
  CHECK(five.bits == 341);
  CHECK(five.countBits == 16);  // 341 values need 9 bits
  CHECK(TreeletShape::of(1).words == 1);
  CHECK(TreeletShape::of(3).words == 1);

  // Depth-first index of the node at depth 3 on child path (2, 1, 3): 3 + 21·2 + 5·1 + 3.
  std::vector<uint32_t> treelet(four.words, 0);
  for (uint32_t node : {0u, 1u, 43u, 53u}) four.setValue(treelet.data(), node);
  treelet[0] |= 4;
  // Child index 2·(j bit) + (i bit): i = 0b011, j = 0b101 takes children 2, 1, 3.
  CHECK(four.lookup(treelet.data(), 0b011, 0b101, 0, 3) == 3u);  // node 53: 3 set bits before
  CHECK(four.lookup(treelet.data(), 0b010, 0b101, 0, 3) == 2u);  // 52 and 49 unset: node 43
  CHECK(four.lookup(treelet.data(), 0b111, 0b000, 0, 3) == 0u);  // only the root on its path
  // A treelet entered two levels above the texels only looks two levels down.
  CHECK(four.lookup(treelet.data(), 0b01, 0b10, 1, 3) == 2u);
}

TEST_CASE("dag-mh: treelet ranks count the set node bits one by one would", "[dag-mh]") {
  uint64_t state = 13;
  for (int height = 1; height <= kMaxTreeletHeight; ++height) {
    const TreeletShape shape = TreeletShape::of(height);
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<uint32_t> treelet(shape.words, 0);
      for (uint32_t n = 0; n < shape.bits; ++n)
        if (nextRandom(state) % 3 == 0) shape.setValue(treelet.data(), n);
      treelet[0] |= uint32_t(nextRandom(state)) & ((1u << shape.countBits) - 1);  // count bits
      const TreeletRanks ranks(shape, treelet.data());
      std::vector<uint32_t> before(shape.bits + 1, 0);
      for (uint32_t n = 0; n < shape.bits; ++n)
        before[n + 1] = before[n] + (shape.hasValue(treelet.data(), n) ? 1 : 0);
      for (uint32_t first = 0; first <= shape.bits; ++first) {
        REQUIRE(ranks.valuesBefore(first) == before[first]);
        for (uint32_t end = first; end <= shape.bits; end += 7)
          REQUIRE(ranks.valuesIn(first, end) == before[end] - before[first]);
      }
    }
  }
}

TEST_CASE("dag-mh: every value of the chunked list lies in its interval", "[dag-mh]") {
  for (const uint32_t chunkSize : {16u, 32u, 64u, 128u})
    for (const size_t count : {size_t(1), size_t(15), size_t(129), size_t(5000)})
      for (uint64_t seed = 1; seed <= 6; ++seed) {
        INFO("chunk size " << chunkSize << ", " << count << " values, seed " << seed);
        checkChunks(randomIntervals(count, seed * 7919 + count), chunkSize);
      }
}

TEST_CASE("dag-mh: value chunks use the fewest factor bits that hold every interval", "[dag-mh]") {
  // Wide intervals: 8-bit factors always fit.
  std::vector<KeyInterval> wide;
  for (int v = 0; v < 32; ++v) wide.push_back(interval(0.02f * float(v), 0.02f * float(v) + 0.01f));
  ValueChunkStats stats;
  ValueChunks chunks(wide, 32, &stats);
  CHECK(stats.covered == 1);
  CHECK(stats.factorBits == 31 * 8);
  CHECK(chunks.factorSize() == 31);

  // Points that share one depth are all the representative: no factors.
  std::vector<KeyInterval> same(32, interval(0.5f, 0.5f));
  stats = {};
  chunks = ValueChunks(same, 32, &stats);
  CHECK(stats.covered == 32);
  CHECK(chunks.factorSize() == 0);

  // Points that even 2^24 steps over [0.001, 0.9] miss (the grid is coarser than the floats
  // near 0.001) are stored raw.
  std::vector<KeyInterval> points;
  for (const float point : {0.5f, 0.5f, 0.5f, 0.001f, 0.9f, 0.0012345f, 0.0031f})
    points.push_back(interval(point, point));
  stats = {};
  chunks = ValueChunks(points, 16, &stats);
  CHECK(stats.covered == 3);
  CHECK(stats.factorBits == 4 * 32);
  CHECK(chunks.value(5) == 0.0012345f);
  checkChunks(points, 16);

  // Open-ended intervals give a finite factor range: [lo, max(lo, 1)].
  std::vector<KeyInterval> sky{interval(0.1f, 0.1f), interval(0.2f, kInfinity),
                               interval(1.0f, kInfinity), interval(0.7f, 0.8f)};
  checkChunks(sky, 16);
}

TEST_CASE("dag-mh: a map of 2^24 distinct values fills the root's 24-bit count exactly",
          "[dag-mh]") {
  // 4096² texels, each its own point interval: the root holds one value and counts the other
  // 2^24 − 1, the most its 24-bit count holds. Regression: 24-bit skip-list fields and a 2^24
  // cap on the value list refused the 64K² city, which holds more.
  const uint32_t r = 4096;
  SyntheticMap map{r, DepthMode::Open, std::vector<float>(size_t(r) * r), {}};
  for (size_t t = 0; t < map.lo.size(); ++t) map.lo[t] = float(t + 1) * 0x1p-26f;
  map.hi = map.lo;
  const MultiresHierarchy hierarchy = hierarchyOf(map, 512);
  for (int skipLevel : {0, 1}) {
    const DagBuild built = buildDag(hierarchy, 4, skipLevel);
    CHECK(built.values.size() == kMaxInnerCount + 1);
    uint64_t wrong = 0;
    for (uint32_t j = 0; j < r; j += 17)
      for (uint32_t i = 0; i < r; i += 13)
        wrong += built.values[built.dag.valueIndex(i, j)].lo != hierarchy.texelInterval(i, j).lo;
    CHECK(wrong == 0);
  }
}

TEST_CASE("dag-mh: DAG lookups reach the deepest node with a value on every texel's path",
          "[dag-mh]") {
  for (const uint32_t resolution : {8u, 32u, 128u})
    for (const DepthMode mode : {DepthMode::Open, DepthMode::Closed})
      for (uint64_t seed : {3u, 11u}) {
        const SyntheticMap map = SyntheticMap::random(resolution, mode, seed);
        const MultiresHierarchy hierarchy = hierarchyOf(map, std::min(resolution, 32u));
        for (int treeletHeight = 1; treeletHeight <= kMaxTreeletHeight; ++treeletHeight)
          for (int skipLevel : {0, 1, 3, 6, 10}) {
            INFO(resolution << "² " << toString(mode) << " seed " << seed << ", treelet height "
                            << treeletHeight << ", skip level " << skipLevel);
            const DagBuild built = buildDag(hierarchy, treeletHeight, skipLevel);
            CHECK(built.dag.skipLevel == std::min(skipLevel, hierarchy.levels));
            const auto check = [&](const Dag& dag) {
              size_t wrong = 0;
              for (uint32_t j = 0; j < resolution; ++j)
                for (uint32_t i = 0; i < resolution; ++i) {
                  const uint32_t index = dag.valueIndex(i, j);
                  const KeyInterval expected = hierarchy.texelInterval(i, j);
                  wrong += index >= built.values.size() || built.values[index].lo != expected.lo ||
                           built.values[index].hi != expected.hi;
                }
              CHECK(wrong == 0);
            };
            check(built.dag);
            roundTrip(built.dag, uint32_t(built.values.size()), check);
          }
      }
}

TEST_CASE("dag-mh: full and empty nodes with equal descendants are one DAG node", "[dag-mh]") {
  // Four quadrants with the same pattern scaled by powers of two (exact: every equality and
  // order of depths stays), so the same topology four times: whether the root keeps a
  // quadrant's value (an empty child) or stores it (a full child), all four point to one node.
  const SyntheticMap quadrant = SyntheticMap::random(32, DepthMode::Open, 5);
  SyntheticMap map{64, DepthMode::Open, std::vector<float>(64 * 64), std::vector<float>(64 * 64)};
  for (uint32_t j = 0; j < 64; ++j)
    for (uint32_t i = 0; i < 64; ++i) {
      const int scale = -1 - int((j / 32) * 2 + i / 32);
      const float lo = quadrant.lo[(j % 32) * 32 + i % 32];
      map.lo[j * 64 + i] = map.hi[j * 64 + i] = lo < 1.0f ? std::ldexp(lo, scale) : 1.0f;
      if (lo == 1.0f) map.hi[j * 64 + i] = kInfinity;
    }
  const DagBuild whole = buildDag(hierarchyOf(map, 32), 4, 0);
  const DagBuild part = buildDag(hierarchyOf(quadrant, 32), 4, 0);
  CHECK(whole.dag.innerNodeCount() == part.dag.innerNodeCount() + 1);
  CHECK(whole.dag.treeletCount() == part.dag.treeletCount());
  const uint32_t rootWord = whole.dag.skipList[0];
  const uint32_t header = whole.dag.innerNodes[rootWord];
  CHECK((header & 0xff) != 0);
  for (int k = 1; k < 4; ++k)
    CHECK(whole.dag.innerNodes[rootWord + 1 + k] == whole.dag.innerNodes[rootWord + 1]);
}

TEST_CASE("dag-mh: the skip list replaces the nodes above it", "[dag-mh]") {
  const SyntheticMap map = SyntheticMap::random(128, DepthMode::Closed, 9);
  const MultiresHierarchy hierarchy = hierarchyOf(map, 32);
  const DagBuild full = buildDag(hierarchy, 3, 0);
  const DagBuild skipped = buildDag(hierarchy, 3, 3);
  CHECK(full.dag.skipList.size() == Dag::kSkipEntryWords);
  CHECK(skipped.dag.skipList.size() == Dag::kSkipEntryWords * 64);
  CHECK(skipped.dag.innerNodeCount() < full.dag.innerNodeCount());
  CHECK(skipped.values.size() == full.values.size());
}

TEST_CASE("dag-mh: the loader rejects every inconsistent pointer, count and skip entry",
          "[dag-mh]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 21);
  const DagBuild built = buildDag(hierarchyOf(map, 32), 2, 2);
  const Dag& dag = built.dag;
  const uint32_t values = uint32_t(built.values.size());
  REQUIRE(dag.innerNodeCount() > 4);
  REQUIRE_NOTHROW(loadSaved(dag, values));

  auto rejected = [&](auto&& corrupt, const char* field) {
    Dag copy = dag;
    corrupt(copy);
    CHECK_THROWS_WITH(loadSaved(copy, values), Catch::Contains("dag-mh") && Catch::Contains(field));
  };
  // The last inner node: a parent, whose pointers and count are the ones to corrupt.
  uint32_t last = 0;
  for (uint32_t w = 0; w < dag.innerNodes.size();) {
    last = w;
    const uint32_t flags = dag.innerNodes[w] & 0xff;
    w += 1 + uint32_t(std::popcount((flags | flags >> 1) & 0x55u));
  }
  const uint32_t header = dag.innerNodes[last];
  int innerSlot = -1, treeletSlot = -1;
  for (int k = 0, slot = 1; k < 4; ++k) {
    const uint32_t flag = (header >> (2 * k)) & 3;
    if (flag == kNoChild) continue;
    (flag == kTreeletChild ? treeletSlot : innerSlot) = slot++;
  }
  if (innerSlot > 0) {
    rejected([&](Dag& d) { d.innerNodes[last + innerSlot] = last; }, "earlier inner node");
    rejected([&](Dag& d) { d.innerNodes[last + innerSlot] += 1; }, "earlier inner node");
  }
  if (treeletSlot > 0)
    rejected([&](Dag& d) { d.innerNodes[last + treeletSlot] = uint32_t(d.treeletCount()); },
             "treelet");
  rejected([&](Dag& d) { d.innerNodes[last] += 1 << 8; }, "counts");
  rejected([&](Dag& d) { d.innerNodes[last] &= ~0xffu; }, "no children");
  rejected([&](Dag& d) { d.innerNodes.pop_back(); }, "overruns");
  rejected([&](Dag& d) { d.treelets[0] += 1; }, "treelet 0");
  rejected([&](Dag& d) { d.treelets.push_back(1); }, "treelet");
  // Skip entries: kind, level, node and value ranges.
  for (size_t e = 0; e < dag.skipList.size(); e += Dag::kSkipEntryWords) {
    const uint32_t kind = dag.skipList[e + 3] & 3;
    rejected([&](Dag& d) { d.skipList[e + 2] = values; }, "last value");
    rejected([&](Dag& d) { d.skipList[e + 3] |= 3u; }, "skip list");
    rejected([&](Dag& d) { d.skipList[e + 3] += 1u << 10; }, "below the skip level");
    if (kind == Traversal::kInner) {
      rejected([&](Dag& d) { d.skipList[e] += 1; }, "no inner node");
      rejected([&](Dag& d) { d.skipList[e + 3] -= 1u << 2; }, "skip level");
      rejected([&](Dag& d) { d.skipList[e + 1] += values; }, "value");
    }
    if (kind == Traversal::kTreelet)
      rejected([&](Dag& d) { d.skipList[e] = uint32_t(d.treeletCount()); }, "treelet index");
  }

  // Value chunks: factor offsets, bitmask bits past the last value, stored floats.
  const ValueChunks chunks(built.values, 16, nullptr);
  ByteWriter out;
  chunks.save(out);
  const std::vector<uint8_t> bytes = out.bytes();
  const size_t infos = 8;  // after the infos' u64 count
  auto chunkRejected = [&](size_t at, uint8_t flip, const char* field) {
    std::vector<uint8_t> corrupted = bytes;
    corrupted[at] ^= flip;
    ByteReader in(corrupted);
    CHECK_THROWS_WITH(ValueChunks::load(in, 16, values),
                      Catch::Contains("dag-mh") && Catch::Contains(field));
  };
  chunkRejected(infos + 18 + 12, 1, "factor offset");  // chunk 1's offset
  chunkRejected(infos + 3, 0x80, "representative");    // sign bit: a negative depth
  const uint32_t lastValues = values % 16;
  if (lastValues != 0) {
    const size_t lastInfo = infos + (values / 16) * 18;
    chunkRejected(lastInfo + 16 + lastValues / 8, uint8_t(1u << (lastValues % 8)), "covers");
  }
  for (size_t length = 0; length < bytes.size(); ++length) {
    ByteReader in{std::span(bytes).first(length)};
    CHECK_THROWS_AS(ValueChunks::load(in, 16, values), FormatError);
  }
}

TEST_CASE("dag-mh: corrupted DAG words never yield a value index outside the list", "[dag-mh]") {
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 4);
  const DagBuild built = buildDag(hierarchyOf(map, 32), 3, 1);
  const uint32_t values = uint32_t(built.values.size());
  ByteWriter out;
  built.dag.save(out);
  const std::vector<uint8_t> bytes = out.bytes();
  for (size_t length = 0; length < bytes.size(); ++length) {
    ByteReader in{std::span(bytes).first(length)};
    CHECK_THROWS_AS(Dag::load(in, 5, 3, 1, values), FormatError);
  }
  for (size_t word = 0; word + 4 <= bytes.size(); word += 4)
    for (const uint32_t change : {1u, 0x100u, 0x80000000u, 0xffffffffu}) {
      std::vector<uint8_t> corrupted = bytes;
      uint32_t value;
      std::memcpy(&value, &corrupted[word], 4);
      value = change == 0xffffffffu ? 0 : value ^ change;
      std::memcpy(&corrupted[word], &value, 4);
      try {
        ByteReader in(corrupted);
        const Dag dag = Dag::load(in, 5, 3, 1, values);
        size_t outside = 0;
        for (uint32_t j = 0; j < 32; ++j)
          for (uint32_t i = 0; i < 32; ++i) outside += dag.valueIndex(i, j) >= values;
        CHECK(outside == 0);
      } catch (const FormatError&) {
      }
    }
}

TEST_CASE("dag-mh: the scheme answers inside the intervals for every parameter", "[dag-mh]") {
  const SchemeInfo& scheme = findScheme("dag-mh");
  for (const DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static}) {
    const SyntheticMap map = SyntheticMap::random(64, mode, 17);
    std::vector<Query> queries;
    std::vector<float> expected;
    for (uint32_t j = 0; j < 64; ++j)
      for (uint32_t i = 0; i < 64; ++i) {
        const float lo = map.lo[j * 64 + i], hi = map.hi[j * 64 + i];
        queries.push_back({(i + 0.5f) / 64, (j + 0.5f) / 64, lo});
        expected.push_back(1.0f);
        if (hi != kInfinity) {
          queries.push_back({(i + 0.5f) / 64, (j + 0.5f) / 64, std::nextafter(hi, 2.0f)});
          expected.push_back(0.0f);
        }
      }
    for (const char* treelet : {"1", "2", "3", "4", "5"})
      for (const char* chunk : {"16", "32", "64", "128"})
        for (const char* skip : {"0", "6"}) {
          INFO(toString(mode) << " treelet-height " << treelet << " chunk-size " << chunk
                              << " skip-level " << skip);
          const auto decoder = map.build(
              scheme, {{"treelet-height", treelet}, {"chunk-size", chunk}, {"skip-level", skip}},
              16);
          std::vector<float> got(queries.size());
          decoder->lookup(queries, 1, got);
          CHECK(got == expected);
        }
  }
}

// Issue 12: the merge of parts never holds the whole hierarchy (dag_parts.h); it must still store
// every inner node, treelet, chunk and skip entry the whole build stores, and answer as it does.
// Blocky maps make parts whose trees are treelets below the levels above (grafted at the end).
TEST_CASE("dag-mh: a merge of parts stores what the whole build stores and answers alike",
          "[dag-mh][parts]") {
  const SchemeInfo& scheme = findScheme("dag-mh");
  const SyntheticMap blocky = SyntheticMap::blocky(64, DepthMode::Closed, 3, 8);
  for (const SyntheticMap& map : {SyntheticMap::random(64, DepthMode::Open, 31),
                                  SyntheticMap::random(64, DepthMode::Static, 32), blocky}) {
    std::vector<Query> queries;
    for (uint32_t j = 0; j < 64; ++j)
      for (uint32_t i = 0; i < 64; ++i)
        for (const float z : {map.lo[j * 64 + i], std::nextafter(map.hi[j * 64 + i], 2.0f)})
          queries.push_back({(i + 0.5f) / 64, (j + 0.5f) / 64, std::min(z, 1.0f)});
    for (const char* treelet : {"2", "4", "5"})
      for (const char* skip : {"0", "2", "6"})
        for (const uint32_t partSize : {8u, 16u, 32u}) {
          INFO(toString(map.mode) << " treelet-height " << treelet << " skip-level " << skip
                                  << " parts of " << partSize);
          const Params params{{"treelet-height", treelet}, {"skip-level", skip}};
          const auto whole = map.build(scheme, params, 8);
          const auto merged = map.buildInParts(scheme, params, 8, partSize);
          CHECK(merged->size() == whole->size());
          std::vector<float> expected(queries.size()), got(queries.size());
          whole->lookup(queries, 1, expected);
          merged->lookup(queries, 1, got);
          CHECK(got == expected);
          // The merged structure is one the loader accepts.
          ByteWriter saved;
          merged->save(saved);
          ByteReader in(saved.bytes());
          const auto loaded = scheme.load(in, map.info(scheme.kind), scheme.resolve(params));
          in.expectEnd();
        }
  }
}

TEST_CASE("dag-mh: the encoder names its phases and counts its parts", "[dag-mh]") {
  const SchemeInfo& scheme = findScheme("dag-mh");
  CHECK(scheme.kind == SchemeKind::Depth);
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 2);
  RecordingContext context;
  auto encoder = scheme.makeEncoder(map.info(SchemeKind::Depth),
                                    scheme.resolve({{"skip-level", "2"}}), BuildShape{16});
  map.stream(16, [&](const DualDepthTile& tile) { encoder->consume(tile, context); });
  const auto decoder = encoder->finish(context);
  CHECK(context.phases == std::vector<std::string>{"mh", "dag", "values"});
  auto& counters = context.counters;
  CHECK(counters.at("values") ==
        counters.at("values covered by representative") + counters.at("factor values"));
  CHECK(counters.at("chunks") == (counters.at("values") + 31) / 32);
  CHECK(counters.at("factor bits") >= 8 * counters.at("factor values"));
  CHECK(counters.at("inner nodes") > 0);
  CHECK(counters.at("treelets") > 0);
  const SizeBreakdown size = decoder->size();
  REQUIRE(size.size() == 5);
  CHECK(size[0].first == "inner nodes");
  CHECK(size[2].second == counters.at("chunks") * (16 + 32 / 8));
  CHECK(size[4].second == 16 * 16);  // skip level 2: 4^2 entries of 16 bytes
}

TEST_CASE("dag-mh: a map of one depth is the root alone, a one-node treelet", "[dag-mh]") {
  SyntheticMap map{32, DepthMode::Closed, std::vector<float>(32 * 32, 0.25f),
                   std::vector<float>(32 * 32, 0.5f)};
  for (int treeletHeight : {1, 4})
    for (int skipLevel : {0, 6}) {
      const DagBuild built = buildDag(hierarchyOf(map, 16), treeletHeight, skipLevel);
      CHECK(built.values.size() == 1);
      CHECK(built.dag.innerNodes.empty());
      CHECK(built.dag.treeletCount() == 1);
      for (uint32_t j = 0; j < 32; ++j)
        for (uint32_t i = 0; i < 32; ++i) CHECK(built.dag.valueIndex(i, j) == 0);
      roundTrip(built.dag, 1, [](const Dag& dag) { CHECK(dag.valueIndex(31, 31) == 0); });
    }
}
