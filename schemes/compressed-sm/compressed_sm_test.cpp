// compressed-sm beside the shared matrix: exact lines become one segment per scanline, every
// fitted depth lies in its interval in every mode, float rounding splits segments rather than
// leaving a texel outside its interval, fitting a scanline piece by piece as tiles deliver it
// gives the segments of the whole scanline, and the loader rejects an inconsistent row index.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "schemes/compressed-sm/compressed_sm.h"
#include "schemes/interface/parts.h"
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

std::vector<uint8_t> saved(const Decoder& decoder) {
  ByteWriter out;
  decoder.save(out);
  return out.release();
}

// The payloads of every part of `map` in parts of `partSize`, in part order.
std::vector<std::vector<uint8_t>> partPayloads(const SyntheticMap& map, const Params& params,
                                               uint32_t tileSize, uint32_t partSize) {
  return map.partPayloads(findScheme("compressed-sm"), params, tileSize, partSize);
}

// Merges part payloads of parts of `partSize` given one after another in `bytes`.
std::unique_ptr<Decoder> mergeAll(const SyntheticMap& map, const Params& params, uint32_t partSize,
                                  std::span<const uint8_t> bytes) {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  testing::NullBuildContext context;
  const MapInfo info = map.info(scheme.kind);
  auto merger = scheme.makePartMerger(info, scheme.resolve(params), BuildShape{partSize, partSize});
  ByteReader in(bytes);
  for (uint64_t index = 0; index < MapPart::countFor(info, partSize); ++index)
    merger->add(MapPart::of(index, partSize), in, context);
  in.expectEnd();
  return merger->finish(context);
}

std::vector<uint8_t> concatenated(const std::vector<std::vector<uint8_t>>& payloads) {
  std::vector<uint8_t> all;
  for (const auto& payload : payloads) all.insert(all.end(), payload.begin(), payload.end());
  return all;
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

TEST_CASE("compressed-sm: segments close at every multiple of the span", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const uint32_t r = 64;
  SyntheticMap map{r, DepthMode::Open, {}, {}};
  map.lo.resize(size_t(r) * r);
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i)  // one exact line per scanline, as in the test above
      map.lo[size_t(j) * r + i] = 0.25f + float(j) / 256.0f + float(i) / 4096.0f;
  map.hi = map.lo;
  for (uint32_t span : {16u, 32u}) {
    INFO("span " << span);
    const auto decoder = map.build(scheme, {{"segment-span", std::to_string(span)}}, 16);
    CHECK(bytesOf(decoder->size(), "segments") == r * (r / span) * 12);
    CHECK(texelsOutsideIntervals(*decoder, map) == 0);
  }
  // The default span reaches past this map: whole scanlines, one segment each.
  CHECK(bytesOf(map.build(scheme, {}, 16)->size(), "segments") == r * 12);
}

TEST_CASE("compressed-sm: the span is a power of two of at least 16", "[compressed-sm]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  for (const char* bad : {"100", "8", "0"})
    CHECK_THROWS_WITH(scheme.resolve({{"segment-span", bad}}),
                      Catch::Contains("compressed-sm") && Catch::Contains("segment-span"));
  CHECK(scheme.resolve({}).integer("segment-span") == 16384);
}

TEST_CASE("compressed-sm: a build in parts saves the whole build's bytes",
          "[compressed-sm][parts]") {
  // Parts whose side is a multiple of the span fit their rows on their own; smaller ones hand
  // their texels to the merger. Both give the whole build's structure, byte for byte.
  const SchemeInfo& scheme = findScheme("compressed-sm");
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    for (const char* span : {"16", "32", "16384"})
      for (uint32_t partSize : {16u, 32u, 64u}) {
        INFO(toString(mode) << " span " << span << " parts of " << partSize);
        const SyntheticMap map = SyntheticMap::random(128, mode, 0xc5 + int(mode) + partSize);
        const Params params{{"segment-span", span}};
        const std::vector<uint8_t> whole = saved(*map.build(scheme, params, 16));
        CHECK(saved(*map.buildInParts(scheme, params, 16, partSize)) == whole);
        CHECK(saved(*map.buildInParts(scheme, params, 8, partSize)) == whole);
      }
}

TEST_CASE("compressed-sm: parts smaller than the span carry their texels",
          "[compressed-sm][parts]") {
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 9);
  const size_t texelPayload = 2 * (sizeof(uint64_t) + 16 * 16 * sizeof(float));
  for (const auto& payload : partPayloads(map, {}, 8, 16)) CHECK(payload.size() == texelPayload);
  for (const auto& payload : partPayloads(map, {{"segment-span", "16"}}, 8, 16))
    CHECK(payload.size() < texelPayload);
}

TEST_CASE("compressed-sm: the merger takes parts in order only", "[compressed-sm][parts]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 4);
  const auto payloads = partPayloads(map, {}, 16, 16);
  testing::NullBuildContext context;
  auto merger =
      scheme.makePartMerger(map.info(scheme.kind), scheme.resolve({}), BuildShape{16, 16});
  ByteReader in(payloads[1]);
  CHECK_THROWS_WITH(merger->add(MapPart::of(1, 16), in, context),
                    Catch::Contains("part 1") && Catch::Contains("part 0"));
  CHECK_THROWS_WITH(merger->finish(context), Catch::Contains("0 of 4 parts"));
}

namespace {

// A part payload format pinned by a golden file: a 32² closed map in parts of 16², every part's
// payload one after another, with the default span (texels) and a span of 16 (segments).
struct GoldenParts {
  Params params;
  std::string path() const {
    std::string name = "compressed-sm";
    for (const auto& [param, value] : params) name += "_" + param + "-" + value;
    return "tests/golden/" + name + ".part";
  }
};

const std::vector<GoldenParts> kGoldenParts{{{}}, {{{"segment-span", "16"}}}};
constexpr uint64_t kGoldenPartsSeed = 0x9011;

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every texel's stored depth read back at its bounds: a structure that validates must answer
// them without reading out of bounds (the sanitizers watch).
void touchEveryTexel(const Decoder& decoder, uint32_t r) {
  std::vector<Query> queries;
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i) queries.push_back({(i + 0.5f) / r, (j + 0.5f) / r, 0.5f});
  std::vector<float> answers(queries.size());
  decoder.lookup(queries, 3, answers);
}

}  // namespace

// Regenerate deliberately with SHADOWBENCH_UPDATE_GOLDEN=1 when the part format changes.
TEST_CASE("compressed-sm: part payloads match their golden files",
          "[compressed-sm][parts][format]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, kGoldenPartsSeed);
  for (const GoldenParts& golden : kGoldenParts) {
    const std::string path = golden.path();
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    const std::vector<uint8_t> payloads = concatenated(partPayloads(map, golden.params, 16, 16));
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) {
      std::ofstream out(path, std::ios::binary);
      out.write(reinterpret_cast<const char*>(payloads.data()), std::streamsize(payloads.size()));
    }
    const std::vector<uint8_t> pinned = readBytes(path);
    REQUIRE(!pinned.empty());
    CHECK(pinned == payloads);
    CHECK(saved(*mergeAll(map, golden.params, 16, pinned)) ==
          saved(*map.build(scheme, golden.params, 16)));
  }
}

TEST_CASE("compressed-sm: the merger refuses every truncated or corrupted part payload",
          "[compressed-sm][parts][format]") {
  const SchemeInfo& scheme = findScheme("compressed-sm");
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, kGoldenPartsSeed);
  const MapInfo info = map.info(scheme.kind);
  testing::NullBuildContext context;
  for (const GoldenParts& golden : kGoldenParts) {
    INFO(golden.path());
    const ParamValues params = scheme.resolve(golden.params);
    const auto payloads = partPayloads(map, golden.params, 16, 16);
    // Part 3 is merged last, after its neighbours; a refused payload leaves the merger as it was,
    // so the intact one is then accepted.
    auto merger = scheme.makePartMerger(info, params, BuildShape{16, 16});
    for (uint64_t index = 0; index < 3; ++index) {
      ByteReader in(payloads[index]);
      merger->add(MapPart::of(index, 16), in, context);
    }
    const std::vector<uint8_t>& last = payloads[3];
    for (size_t length = 0; length < last.size(); ++length) {
      ByteReader in(std::span<const uint8_t>(last).first(length));
      INFO("payload truncated to " << length << " bytes");
      CHECK_THROWS_WITH(merger->add(MapPart::of(3, 16), in, context),
                        Catch::Contains("compressed-sm part 3"));
    }
    // Every byte flipped: refused, or a structure that validates as a loaded file does and
    // answers without reading out of bounds; the counts, the row index and a value that breaks
    // the format must be refused.
    size_t refused = 0;
    for (size_t at = 0; at < last.size(); ++at) {
      std::vector<uint8_t> corrupted = last;
      corrupted[at] ^= uint8_t(1u << (at % 8));
      auto fresh = scheme.makePartMerger(info, params, BuildShape{16, 16});
      try {
        for (uint64_t index = 0; index < 4; ++index) {
          ByteReader in(index == 3 ? std::span<const uint8_t>(corrupted)
                                   : std::span<const uint8_t>(payloads[index]));
          fresh->add(MapPart::of(index, 16), in, context);
        }
        const auto merged = fresh->finish(context);
        const std::vector<uint8_t> bytes = saved(*merged);
        ByteReader reload(bytes);
        const auto loaded = scheme.load(reload, info, params);
        touchEveryTexel(*loaded, 32);
      } catch (const FormatError& error) {
        CHECK_THAT(error.what(), Catch::Contains("compressed-sm part 3"));
        ++refused;
      }
    }
    CHECK(refused > 0);
    for (size_t at : {size_t(0), size_t(7)}) {  // the first array's count
      std::vector<uint8_t> corrupted = last;
      corrupted[at] ^= 0x40;
      ByteReader in(corrupted);
      CHECK_THROWS_AS(merger->add(MapPart::of(3, 16), in, context), FormatError);
    }
    {
      std::vector<uint8_t> corrupted = last;
      const float nan = std::numeric_limits<float>::quiet_NaN();
      std::memcpy(corrupted.data() + corrupted.size() - sizeof(float), &nan, sizeof nan);
      ByteReader in(corrupted);
      CHECK_THROWS_AS(merger->add(MapPart::of(3, 16), in, context), FormatError);
    }
    ByteReader intact(last);
    merger->add(MapPart::of(3, 16), intact, context);
    intact.expectEnd();
    CHECK(saved(*merger->finish(context)) == saved(*map.build(scheme, golden.params, 16)));
  }
}
