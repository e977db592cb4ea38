// sm-zstd beside the code: blocks larger and smaller than a tile, and tiles in any order, assemble
// the same map as sm32, lookups from several threads share no cache entries, the cache holds
// what its size says with the least recently used block out, and a payload whose block offsets,
// frames or depths are damaged (behind a valid checksum) does not load.
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include <catch2/catch.hpp>

#include "schemes/interface/capabilities.h"
#include "schemes/interface/morton.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using testing::SyntheticMap;

std::vector<Query> queriesOver(uint32_t count, uint64_t seed) {
  std::vector<Query> queries;
  uint64_t state = seed;
  auto next = [&] {  // xorshift: any spread of points and depths will do
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return float(state % 1000003) / 1000003.0f;
  };
  for (uint32_t q = 0; q < count; ++q) queries.push_back({next(), next(), next()});
  return queries;
}

std::vector<float> answers(const Decoder& decoder, std::span<const Query> queries, int k) {
  std::vector<float> visibility(queries.size());
  decoder.lookup(queries, k, visibility);
  return visibility;
}

TEST_CASE("sm-zstd answers as sm32 whether blocks are larger or smaller than tiles", "[sm-zstd]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 7);
  const auto reference = map.build(findScheme("sm32"), {}, 16);
  const std::vector<Query> queries = queriesOver(2000, 3);
  for (const char* block : {"8", "16", "32", "64", "1024"})
    for (uint32_t tile : {8u, 16u, 32u}) {
      CAPTURE(block, tile);
      const auto decoder =
          map.build(findScheme("sm-zstd"), {{"block", block}, {"level", "1"}}, tile);
      for (int k : {1, 5, 17})
        CHECK(answers(*decoder, queries, k) == answers(*reference, queries, k));
    }
}

TEST_CASE("sm-zstd lays out blocks completed in any tile order", "[sm-zstd]") {
  // Tiles in reverse Morton order complete the blocks last first: each waits, compressed, until
  // the blocks before it in the layout are written.
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 9);
  const auto reference = map.build(findScheme("sm32"), {}, 16);
  const SchemeInfo& scheme = findScheme("sm-zstd");
  for (const char* block : {"8", "32"}) {
    CAPTURE(block);
    auto encoder = scheme.makeEncoder(map.info(scheme.kind), scheme.resolve({{"block", block}}),
                                      BuildShape{16});
    testing::NullBuildContext context;
    std::vector<DualDepthTile> tiles;
    map.stream(16, [&](const DualDepthTile& tile) { tiles.push_back(tile); });
    for (auto tile = tiles.rbegin(); tile != tiles.rend(); ++tile) encoder->consume(*tile, context);
    const auto decoder = encoder->finish(context);
    const std::vector<Query> queries = queriesOver(2000, 13);
    CHECK(answers(*decoder, queries, 3) == answers(*reference, queries, 3));
  }
}

TEST_CASE("sm-zstd lookups from several threads agree with one thread", "[sm-zstd]") {
  const SyntheticMap map = SyntheticMap::random(128, DepthMode::Open, 11);
  const auto a = map.build(findScheme("sm-zstd"), {{"block", "16"}}, 32);
  const auto b = map.build(findScheme("sm-zstd"), {{"block", "32"}}, 32);
  const std::vector<Query> queries = queriesOver(4000, 5);
  const std::vector<float> expectedA = answers(*a, queries, 3), expectedB = answers(*b, queries, 3);
  std::vector<std::vector<float>> got(8);
  std::vector<std::thread> threads;
  // Two decoders interleaved per thread: each thread's cache must tell their blocks apart.
  for (size_t t = 0; t < got.size(); ++t)
    threads.emplace_back([&, t] {
      const Decoder& decoder = t % 2 ? *a : *b;
      for (int round = 0; round < 3; ++round) got[t] = answers(decoder, queries, 3);
    });
  for (std::thread& thread : threads) thread.join();
  for (size_t t = 0; t < got.size(); ++t) CHECK(got[t] == (t % 2 ? expectedA : expectedB));
}

// The cache's hits and misses over `rounds` passes of a point lookup in each block of
// `blocks` (Morton indices of 64² blocks of a 1024² map), in the calling thread.
BlockCacheStatistics::Counts cacheCounts(const Decoder& decoder,
                                         std::initializer_list<uint64_t> blocks, int rounds) {
  const BlockCacheStatistics* cache = decoder.blockCacheStatistics();
  REQUIRE(cache != nullptr);
  const BlockCacheStatistics::Counts before = cache->threadCounts();
  for (int round = 0; round < rounds; ++round)
    for (uint64_t block : blocks) {
      const Query query{(float(mortonX(block)) * 64 + 0.5f) / 1024,
                        (float(mortonY(block)) * 64 + 0.5f) / 1024, 0.5f};
      float visibility;
      decoder.lookup({&query, 1}, 1, {&visibility, 1});
    }
  const BlockCacheStatistics::Counts after = cache->threadCounts();
  return {after.hits - before.hits, after.misses - before.misses};
}

TEST_CASE("sm-zstd keeps the cache's MiB of blocks per thread, least recently used out",
          "[sm-zstd]") {
  const SyntheticMap map = SyntheticMap::random(1024, DepthMode::Closed, 21);
  // 16 KiB blocks: 1 MiB holds 64 of them, 16 sets of four ways, and the blocks whose Morton
  // indices agree modulo 16 share a set.
  const auto small = map.build(findScheme("sm-zstd"), {{"block", "64"}, {"cache", "1"}}, 512);
  const auto large = map.build(findScheme("sm-zstd"), {{"block", "64"}, {"cache", "4"}}, 512);
  const auto fourWays = cacheCounts(*small, {0, 16, 32, 48}, 3);
  CHECK(fourWays.misses == 4);
  CHECK(fourWays.hits == 8);
  // A fifth block in the set evicts the least recently used: after the four still cached, every
  // read of the cycle misses.
  const auto fiveWays = cacheCounts(*small, {0, 16, 32, 48, 64}, 3);
  CHECK(fiveWays.hits == 4);
  CHECK(fiveWays.misses == 11);
  // Least recently used, not first in: the set holds 16, 32, 48, 64 (16 the oldest); read again,
  // 16 outlives 32 when 80 comes in.
  CHECK(cacheCounts(*small, {16, 80, 16}, 1).hits == 2);
  CHECK(cacheCounts(*small, {32}, 1).misses == 1);
  // 4 MiB: 64 sets, the five blocks in five of them.
  const auto roomy = cacheCounts(*large, {0, 16, 32, 48, 64}, 3);
  CHECK(roomy.misses == 5);
  CHECK(roomy.hits == 10);
}

TEST_CASE("sm-zstd refuses block sizes that are not powers of two and caches under 1 MiB",
          "[sm-zstd]") {
  const SchemeInfo& scheme = findScheme("sm-zstd");
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 1);
  auto message = [&](const Params& params) {
    try {
      map.build(scheme, params, 16);
    } catch (const ParamError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(message({{"block", "48"}}),
             Catch::Contains("'sm-zstd'") && Catch::Contains("'block'"));
  CHECK_THAT(message({{"block", "4"}}), Catch::Contains("'sm-zstd'") && Catch::Contains("'block'"));
  CHECK_THAT(message({{"level", "20"}}),
             Catch::Contains("'sm-zstd'") && Catch::Contains("'level'"));
  CHECK_THAT(message({{"cache", "0"}}), Catch::Contains("'sm-zstd'") && Catch::Contains("'cache'"));
}

TEST_CASE("sm-zstd rejects damaged block offsets and frames at load", "[sm-zstd][format]") {
  const SchemeInfo& scheme = findScheme("sm-zstd");
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 4);
  const ParamValues params = scheme.resolve({{"block", "8"}});
  const auto decoder = map.build(scheme, params.text(), 16);
  ByteWriter writer;
  decoder->save(writer);
  const std::vector<uint8_t> payload = writer.bytes();
  auto load = [&](const std::vector<uint8_t>& bytes) {
    ByteReader in(bytes);
    auto loaded = scheme.load(in, map.info(scheme.kind), params);
    in.expectEnd();
    return loaded;
  };
  REQUIRE_NOTHROW(load(payload));

  const size_t blocks = (32 / 8) * (32 / 8);
  auto offsetAt = [&](size_t b) { return sizeof(uint64_t) * (1 + b); };  // after the count
  auto withOffset = [&](size_t b, uint64_t value) {
    std::vector<uint8_t> bytes = payload;
    std::memcpy(bytes.data() + offsetAt(b), &value, sizeof value);
    return bytes;
  };
  uint64_t third;
  std::memcpy(&third, payload.data() + offsetAt(3), sizeof third);
  CHECK_THROWS_AS(load(withOffset(3, third + 1)), FormatError);  // frames cut wrong
  CHECK_THROWS_AS(load(withOffset(3, third - 1)), FormatError);
  CHECK_THROWS_AS(load(withOffset(2, third + 5)), FormatError);          // offsets decrease
  CHECK_THROWS_AS(load(withOffset(0, 1)), FormatError);                  // not starting at 0
  CHECK_THROWS_AS(load(withOffset(blocks, ~uint64_t(0))), FormatError);  // past the data
  // A flipped byte inside a frame: zstd's content size or data no longer decode to one block.
  std::vector<uint8_t> frameDamaged = payload;
  const size_t dataStart = offsetAt(blocks + 1) + sizeof(uint64_t);
  for (size_t at = dataStart; at < dataStart + 8; ++at) {
    frameDamaged = payload;
    frameDamaged[at] ^= 0x40;
    CHECK_THROWS_AS(load(frameDamaged), FormatError);
  }
}

TEST_CASE("sm-zstd refuses blocks holding depths its encoder never writes", "[sm-zstd][format]") {
  // Issue 11: as in sm32, NaN, infinite or negative depths behind a valid checksum loaded.
  const SchemeInfo& scheme = findScheme("sm-zstd");
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 5);
  const ParamValues params = scheme.resolve({{"block", "8"}});
  ByteWriter writer;
  map.build(scheme, params.text(), 16)->save(writer);
  ByteReader reader(writer.bytes());
  const auto offsets = reader.getArray<uint64_t>("offsets");
  const auto blocks = reader.getArray<uint8_t>("blocks");
  // Block 0 recompressed with one texel replaced, the offsets of the others shifted.
  auto withFirstTexel = [&](float depth) {
    std::vector<float> texels(8 * 8);
    REQUIRE(ZSTD_decompress(texels.data(), texels.size() * sizeof(float), blocks.data(),
                            offsets[1]) == texels.size() * sizeof(float));
    texels[0] = depth;
    std::vector<uint8_t> frame(ZSTD_compressBound(texels.size() * sizeof(float)));
    frame.resize(
        ZSTD_compress(frame.data(), frame.size(), texels.data(), texels.size() * sizeof(float), 3));
    std::vector<uint8_t> crafted = frame;
    crafted.insert(crafted.end(), blocks.begin() + int64_t(offsets[1]), blocks.end());
    std::vector<uint64_t> shifted = offsets;
    for (size_t b = 1; b < shifted.size(); ++b) shifted[b] = shifted[b] - offsets[1] + frame.size();
    ByteWriter payload;
    payload.putArray<uint64_t>(shifted);
    payload.putArray<uint8_t>(crafted);
    return payload.release();
  };
  auto load = [&](const std::vector<uint8_t>& bytes) {
    ByteReader in(bytes);
    scheme.load(in, map.info(scheme.kind), params);
  };
  for (float good : {0.0f, 0.25f, 1.0f}) CHECK_NOTHROW(load(withFirstTexel(good)));
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (float bad : {std::nanf(""), kInf, -kInf, -0.5f, 1.5f}) {
    INFO(bad);
    CHECK_THROWS_WITH(load(withFirstTexel(bad)), Catch::Contains("outside [0, 1]"));
  }
}

}  // namespace
}  // namespace sb
