// compressed-sm beside the shared matrix: exact lines become one segment per scanline, every
// fitted depth lies in its interval in every mode, float rounding splits segments rather than
// leaving a texel outside its interval, fitting a scanline piece by piece as tiles deliver it
// gives the segments of the whole scanline, and the loader rejects an inconsistent row index.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

#include "schemes/compressed-sm/compressed_sm.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

using namespace sb;
using sb::testing::SyntheticMap;

namespace {

uint64_t bytesOf(const SizeBreakdown& sizes, const std::string& name) {
  for (const auto& [component, bytes] : sizes)
    if (component == name) return bytes;
  FAIL("no size component " << name);
  return 0;
}

// The stored depth of every texel, read back through point lookups at two depths: d is the
// largest z that is lit, so the answer at lo must be lit and at nextafter(bound) shadowed.
size_t texelsOutsideIntervals(const Decoder& decoder, const SyntheticMap& map) {
  const uint32_t r = map.resolution;
  std::vector<Query> queries;
  std::vector<float> expected;
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i) {
      const float lo = map.lo[size_t(j) * r + i], hi = map.hi[size_t(j) * r + i];
      const float x = (i + 0.5f) / float(r), y = (j + 0.5f) / float(r);
      queries.push_back({x, y, lo});
      expected.push_back(1.0f);
      const float bound = std::isinf(hi) ? std::max(lo, 1.0f) : hi;
      queries.push_back({x, y, std::nextafter(bound, 2.0f)});
      expected.push_back(0.0f);
    }
  std::vector<float> got(queries.size());
  decoder.lookup(queries, 1, got);
  size_t wrong = 0;
  for (size_t q = 0; q < got.size(); ++q) wrong += got[q] != expected[q];
  return wrong;
}

}  // namespace

TEST_CASE("compressed-sm: a scanline of exact points on a line is one segment", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const uint32_t r = 64;
  SyntheticMap map{r, DepthMode::Open, {}, {}};
  map.lo.resize(size_t(r) * r);
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i)  // dyadic start and slope: every depth exact in float32
      map.lo[size_t(j) * r + i] = 0.25f + float(j) / 256.0f + float(i) / 4096.0f;
  map.hi = map.lo;
  const auto decoder = map.build(scheme, {}, 16);
  CHECK(bytesOf(decoder->size(), "segments") == r * 12);
  CHECK(bytesOf(decoder->size(), "row index") == (r + 1) * 4);
  CHECK(texelsOutsideIntervals(*decoder, map) == 0);
}

TEST_CASE("compressed-sm: fitted depths lie in every texel's interval in every mode",
          "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    for (uint32_t tile : {8u, 32u}) {
      INFO(toString(mode) << " tile " << tile);
      const SyntheticMap map = SyntheticMap::random(128, mode, 11 + tile);
      const auto decoder = map.build(scheme, {}, tile);
      CHECK(texelsOutsideIntervals(*decoder, map) == 0);
      // Fewer segments than texels: plateaus and slopes share segments.
      CHECK(bytesOf(decoder->size(), "segments") < 128 * 128 * 12);
    }
}

TEST_CASE("compressed-sm: the structure does not depend on the tile size", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 5);
  ByteWriter a, b;
  map.build(scheme, {}, 8)->save(a);
  map.build(scheme, {}, 64)->save(b);
  CHECK(a.bytes() == b.bytes());
}

TEST_CASE("compressed-sm: fitting a scanline piece by piece gives the whole scanline's segments",
          "[compressed-sm]") {
  // Long exact lines (terrain-like) and short noisy runs, cut into pieces of random widths, as
  // the encoder receives them from tiles.
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed})
    for (uint64_t seed : {1u, 2u, 3u}) {
      const uint32_t r = 512;
      SyntheticMap map = SyntheticMap::random(r, mode, seed);
      for (uint32_t i = 0; i < r; ++i) map.lo[i] = map.hi[i] = 0.25f + float(i) / 4096.0f;
      uint64_t state = seed;
      for (uint32_t j = 0; j < r; j += 37) {
        const std::span lo(map.lo.data() + size_t(j) * r, r), hi(map.hi.data() + size_t(j) * r, r);
        compressed_sm::Segments whole, pieces;
        compressed_sm::fitScanline(lo, hi, whole);
        std::vector<float> pendingLo, pendingHi;
        compressed_sm::OpenSegment open;
        uint32_t first = 0, arrived = 0;
        while (arrived < r) {
          const uint32_t width = std::min<uint32_t>(r - arrived, 1 + nextRandom(state) % 96);
          pendingLo.insert(pendingLo.end(), lo.begin() + arrived, lo.begin() + arrived + width);
          pendingHi.insert(pendingHi.end(), hi.begin() + arrived, hi.begin() + arrived + width);
          arrived += width;
          const size_t fitted =
              compressed_sm::fitDecided(pendingLo, pendingHi, first, arrived == r, pieces, open);
          pendingLo.erase(pendingLo.begin(), pendingLo.begin() + fitted);
          pendingHi.erase(pendingHi.begin(), pendingHi.begin() + fitted);
          first += uint32_t(fitted);
        }
        INFO(toString(mode) << " seed " << seed << " scanline " << j);
        CHECK(pendingLo.empty());
        CHECK(pieces.firstColumns == whole.firstColumns);
        CHECK(pieces.starts == whole.starts);
        CHECK(pieces.slopes == whole.slopes);
      }
    }
}

TEST_CASE("compressed-sm: scanlines must arrive left to right", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 2);
  auto encoder = scheme.makeEncoder(map.info(scheme.kind), scheme.resolve({}), BuildShape{16});
  testing::NullBuildContext context;
  DualDepthTile tile;
  tile.resize(8, 0, 8, 8);
  CHECK_THROWS_WITH(encoder->consume(tile, context), Catch::Contains("left to right"));
}

TEST_CASE("compressed-sm: float rounding splits a segment instead of leaving a texel outside",
          "[compressed-sm]") {
  // Points of a line with an awkward slope, each rounded to float: a line through all of them
  // exists in real arithmetic up to half a float gap (the feasible range stays open), but no
  // float32 start and slope evaluated as the lookup does hit them all, so only the float32 check
  // keeps every texel exact, by splitting.
  const size_t n = 4096;
  std::vector<float> lo(n);
  for (size_t i = 0; i < n; ++i) lo[i] = float(0.3 + 1.0 / 7919.0 * double(i) / 10.0);
  compressed_sm::Segments segments;
  const size_t count = compressed_sm::fitScanline(lo, lo, segments);
  CHECK(count > 1);
  // Rounded points still share segments (about four texels each here: a point whose real
  // offset from the line is near half a float gap is where product rounding tips it out).
  CHECK(count < n / 2);
  for (size_t s = 0; s < count; ++s) {
    const uint32_t first = segments.firstColumns[s];
    const uint32_t end = s + 1 < count ? segments.firstColumns[s + 1] : uint32_t(n);
    for (uint32_t i = first; i < end; ++i)
      REQUIRE(compressed_sm::segmentDepth(segments.starts[s], segments.slopes[s], i - first) ==
              lo[i]);
  }
}

TEST_CASE("compressed-sm: open-ended intervals are fitted below max(lo, 1)", "[compressed-sm]") {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> lo{1.0f, 1.0f, 0.5f, 0.6f, 1.0f};
  const std::vector<float> hi{inf, inf, inf, 0.7f, inf};
  compressed_sm::Segments segments;
  compressed_sm::fitScanline(lo, hi, segments);
  for (size_t s = 0; s < segments.count(); ++s) {
    CHECK(std::isfinite(segments.starts[s]));
    CHECK(std::isfinite(segments.slopes[s]));
  }
}

TEST_CASE("compressed-sm: the loader rejects a row index past the segments", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(8, DepthMode::Closed, 3);
  const auto decoder = map.build(scheme, {}, 8);
  ByteWriter payload;
  decoder->save(payload);
  // The row index comes first: a u64 count, then R + 1 u32 entries. Push the last entry past
  // the segment count, and separately make a middle one run backwards.
  for (size_t entry : {size_t(8), size_t(4)}) {
    std::vector<uint8_t> bytes = payload.bytes();
    uint32_t value;
    std::memcpy(&value, bytes.data() + 8 + entry * 4, 4);
    value = entry == 8 ? value + 5 : 1000;
    std::memcpy(bytes.data() + 8 + entry * 4, &value, 4);
    ByteReader in(bytes);
    CHECK_THROWS_WITH(scheme.load(in, map.info(scheme.kind), scheme.resolve({})),
                      Catch::Contains("compressed-sm"));
  }
  ByteReader intact(payload.bytes());
  CHECK_NOTHROW(scheme.load(intact, map.info(scheme.kind), scheme.resolve({})));
}
