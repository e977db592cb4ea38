// The CPVS part payload as a file format (voxel_dag_parts.h): pinned by golden files, and every
// truncated, corrupted or crafted payload is refused with a FormatError naming the part, or
// merges into a structure whose lookups stay in bounds (the sanitizers watch them). A refused
// part leaves the merge as it was.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include "schemes/interface/lightspace.h"
#include "schemes/shared/voxel_dag_parts.h"
#include "schemes/shared/voxel_parts_test_support.h"

namespace sb {
namespace {

using testing::SyntheticMap;

// A 32² closed map in parts of 16², tiles of 8: four parts of four tiles each.
constexpr uint32_t kResolution = 32, kPartSize = 16, kTileSize = 8;
constexpr uint64_t kGoldenSeed = 42;

SyntheticMap goldenMap() {
  return SyntheticMap::random(kResolution, DepthMode::Closed, kGoldenSeed);
}

// Every voxel's point answer and a 3×3 kernel around it.
std::vector<float> everyVoxel(const Decoder& decoder) {
  std::vector<Query> queries;
  for (uint32_t k = 0; k < kResolution; ++k)
    for (uint32_t j = 0; j < kResolution; ++j)
      for (uint32_t i = 0; i < kResolution; ++i)
        queries.push_back({(float(i) + 0.5f) / float(kResolution),
                           (float(j) + 0.5f) / float(kResolution), voxelCentre(k, kResolution)});
  std::vector<float> answers(2 * queries.size());
  decoder.lookup(queries, 1, std::span(answers).first(queries.size()));
  decoder.lookup(queries, 3, std::span(answers).last(queries.size()));
  return answers;
}

// A payload taken apart along its documented layout, to craft payloads the encoder never writes.
struct PayloadParts {
  std::vector<uint64_t> leafmasks;
  std::vector<std::vector<uint32_t>> nodes;  // the leaf parents first
  std::vector<uint32_t> column;

  static PayloadParts of(const std::vector<uint8_t>& payload) {
    const uint32_t depths = std::countr_zero(kPartSize) - 2;  // leaf parents up to the column
    ByteReader in(payload);
    PayloadParts parts;
    parts.leafmasks = in.getArray<uint64_t>("leafmasks");
    for (uint32_t d = 0; d < depths; ++d) parts.nodes.push_back(in.getArray<uint32_t>("nodes"));
    parts.column = in.getArray<uint32_t>("column");
    in.expectEnd();
    return parts;
  }
  std::vector<uint8_t> join() const {
    ByteWriter out;
    out.putArray<uint64_t>(leafmasks);
    for (const auto& words : nodes) out.putArray<uint32_t>(words);
    out.putArray<uint32_t>(column);
    return out.release();
  }
};

// The golden file: each part's payload length (u64) and bytes, part after part.
std::vector<uint8_t> goldenBytes(const std::vector<std::vector<uint8_t>>& payloads) {
  ByteWriter out;
  for (const auto& payload : payloads) out.putArray<uint8_t>(payload);
  return out.release();
}

std::vector<uint8_t> readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Each part payload format is pinned by tests/golden/<scheme>.part; regenerate deliberately with
// SHADOWBENCH_UPDATE_GOLDEN=1 when the format changes.
TEST_CASE("CPVS part payloads match their golden files", "[voxel][parts][format]") {
  const SyntheticMap map = goldenMap();
  for (const char* name : {"cpvs", "cpvs-fast"}) {
    const SchemeInfo& scheme = findScheme(name);
    const std::string path = fmt::format("tests/golden/{}.part", name);
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    const auto payloads = map.partPayloads(scheme, {}, kTileSize, kPartSize);
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) {
      const std::vector<uint8_t> bytes = goldenBytes(payloads);
      std::ofstream(path, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    const std::vector<uint8_t> golden = readFile(path);
    REQUIRE(golden == goldenBytes(payloads));
    std::vector<std::vector<uint8_t>> read;
    ByteReader in(golden);
    for (size_t p = 0; p < payloads.size(); ++p) read.push_back(in.getArray<uint8_t>("payload"));
    testing::NullBuildContext context;
    CHECK(everyVoxel(*testing::mergeParts(map, scheme, {}, kTileSize, kPartSize, read, context)) ==
          everyVoxel(*map.build(scheme, {}, 8)));
  }
}

TEST_CASE("truncated and corrupted part payloads are refused or merge safely",
          "[voxel][parts][format]") {
  const SyntheticMap map = goldenMap();
  testing::NullBuildContext context;
  for (const char* name : {"cpvs", "cpvs-fast"}) {
    const SchemeInfo& scheme = findScheme(name);
    const MapInfo info = map.info(scheme.kind);
    const ParamValues params = scheme.resolve({});
    const auto payloads = map.partPayloads(scheme, {}, kTileSize, kPartSize);
    const std::vector<float> expected = everyVoxel(*map.build(scheme, {}, kTileSize));
    for (size_t part = 0; part < payloads.size(); ++part) {
      INFO(name << " part " << part);
      // Every truncation into one merger: each is refused and leaves the merge as it was.
      auto merger = scheme.makePartMerger(info, params, {kTileSize, kPartSize});
      testing::addParts(*merger, payloads, kPartSize, context, 0, part);
      for (size_t length = 0; length < payloads[part].size(); ++length) {
        ByteReader in(std::span(payloads[part]).first(length));
        CHECK_THROWS_WITH(merger->add(MapPart::of(part, kPartSize), in, context),
                          Catch::Contains(fmt::format("part {}:", part)));
      }
      testing::addParts(*merger, payloads, kPartSize, context, part);
      CHECK(everyVoxel(*merger->finish(context)) == expected);

      // Every byte with one bit flipped: refused, or merged into a structure that stays in
      // bounds (a flipped leafmask bit is a valid, different part).
      size_t refused = 0;
      for (size_t at = 0; at < payloads[part].size(); ++at) {
        std::vector<std::vector<uint8_t>> corrupted = payloads;
        corrupted[part][at] ^= uint8_t(1u << (at % 8));
        try {
          everyVoxel(
              *testing::mergeParts(map, scheme, {}, kTileSize, kPartSize, corrupted, context));
        } catch (const FormatError& error) {
          CHECK_THAT(error.what(), Catch::Contains(fmt::format("part {}:", part)));
          ++refused;
        }
      }
      CHECK(refused > 0);
    }
  }
}

TEST_CASE("crafted part payloads are refused, naming the part and the problem",
          "[voxel][parts][format]") {
  const SyntheticMap map = goldenMap();
  testing::NullBuildContext context;
  const SchemeInfo& scheme = findScheme("cpvs");
  const auto payloads = map.partPayloads(scheme, {}, kTileSize, kPartSize);
  // The part with the most nodes, so that every kind of entry is there to break.
  size_t part = 0;
  for (size_t p = 1; p < payloads.size(); ++p)
    if (payloads[p].size() > payloads[part].size()) part = p;
  const PayloadParts genuine = PayloadParts::of(payloads[part]);
  REQUIRE(!genuine.leafmasks.empty());
  REQUIRE(!genuine.nodes[0].empty());
  REQUIRE(!genuine.nodes[1].empty());
  REQUIRE(genuine.join() == payloads[part]);

  struct Craft {
    const char* problem;
    std::function<void(PayloadParts&)> edit;
  };
  // The first leaf parent's first pointer is its word 1 when child 0 is partial; find one.
  auto firstPointer = [](const std::vector<uint32_t>& words) {
    return size_t(partialBits(words[0]) != 0 ? 1 : 0);
  };
  const std::vector<Craft> crafts{
      {"homogeneous", [](PayloadParts& p) { p.leafmasks[0] = 0; }},
      {"homogeneous", [](PayloadParts& p) { p.leafmasks[0] = ~uint64_t(0); }},
      {"referenced by nothing", [](PayloadParts& p) { p.leafmasks.push_back(0x1234); }},
      {"names child",
       [&](PayloadParts& p) {
         p.nodes[0][firstPointer(p.nodes[0])] = uint32_t(p.leafmasks.size());
       }},
      {"node header", [](PayloadParts& p) { p.nodes[0][0] |= 0x10000; }},
      {"node header", [](PayloadParts& p) { p.nodes[1].insert(p.nodes[1].end(), {0u}); }},
      {"node header",
       [](PayloadParts& p) { p.nodes[1].insert(p.nodes[1].end(), {kAllShadowedChildmask}); }},
      {"invalid child code", [](PayloadParts& p) { p.nodes[0][0] |= 3; }},
      {"overruns", [](PayloadParts& p) { p.nodes[1].push_back(0x2); }},
      {"referenced by nothing",
       [](PayloadParts& p) {
         p.nodes[1].insert(p.nodes[1].end(), {0x2u, 0u});
       }},
      {"column cube", [](PayloadParts& p) { p.column[0] = 0xfffffff0u; }},
      {"CPVS part column", [](PayloadParts& p) { p.column.pop_back(); }},
  };
  for (const Craft& craft : crafts) {
    PayloadParts crafted = genuine;
    craft.edit(crafted);
    const std::vector<uint8_t> bytes = crafted.join();
    INFO(craft.problem);
    auto merger =
        scheme.makePartMerger(map.info(scheme.kind), scheme.resolve({}), {kTileSize, kPartSize});
    testing::addParts(*merger, payloads, kPartSize, context, 0, part);
    ByteReader in(bytes);
    CHECK_THROWS_WITH(
        merger->add(MapPart::of(part, kPartSize), in, context),
        Catch::Contains(fmt::format("part {}:", part)) && Catch::Contains(craft.problem));
    // The refused part left the merge as it was: the genuine parts give the whole build.
    testing::addParts(*merger, payloads, kPartSize, context, part);
    CHECK(merger->finish(context)->size() == map.build(scheme, {}, kTileSize)->size());
  }
}

TEST_CASE("parts out of order or of another size are a harness error", "[voxel][parts]") {
  const SyntheticMap map = goldenMap();
  testing::NullBuildContext context;
  const SchemeInfo& scheme = findScheme("cpvs-fast");
  const auto payloads = map.partPayloads(scheme, {}, kTileSize, kPartSize);
  auto merger =
      scheme.makePartMerger(map.info(scheme.kind), scheme.resolve({}), {kTileSize, kPartSize});
  ByteReader second(payloads[1]);
  CHECK_THROWS_AS(merger->add(MapPart::of(1, kPartSize), second, context), std::invalid_argument);
  ByteReader first(payloads[0]);
  CHECK_THROWS_AS(merger->add(MapPart::of(0, 2 * kPartSize), first, context),
                  std::invalid_argument);
  MapPart elsewhere = MapPart::of(0, kPartSize);
  elsewhere.x0 = kPartSize;
  CHECK_THROWS_AS(merger->add(elsewhere, first, context), std::invalid_argument);
  CHECK_THROWS_AS(merger->finish(context), std::logic_error);
}

}  // namespace
}  // namespace sb
