// openvdb beside the code: the tree does not depend on how the map was tiled, homogeneous
// volumes become tiles with no nodes below them (sizes in closed form), and a payload that is
// not the listing of the tree it builds (behind a valid checksum) does not load. Losslessness
// against the voxel rule is checked for every voxel scheme in voxel_schemes_test and the matrix.
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using testing::SyntheticMap;
constexpr float kInf = std::numeric_limits<float>::infinity();

std::vector<uint8_t> payloadOf(const Decoder& decoder) {
  ByteWriter writer;
  decoder.save(writer);
  return writer.release();
}

uint64_t component(const Decoder& decoder, const std::string& name) {
  for (const auto& [part, bytes] : decoder.size())
    if (part == name) return bytes;
  FAIL("no size component " << name);
  return 0;
}

TEST_CASE("openvdb builds the same tree from any tiling", "[openvdb]") {
  const SchemeInfo& scheme = findScheme("openvdb");
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed}) {
    // 256² spans two lower nodes per side: columns complete across tiles and within them.
    const SyntheticMap map = SyntheticMap::random(256, mode, 21);
    const std::vector<uint8_t> whole = payloadOf(*map.build(scheme, {}, 256));
    for (uint32_t tile : {8u, 64u, 128u}) {
      CAPTURE(toString(mode), tile);
      CHECK(payloadOf(*map.build(scheme, {}, tile)) == whole);
    }
  }
}

TEST_CASE("openvdb stores homogeneous volumes as tiles", "[openvdb]") {
  const SchemeInfo& scheme = findScheme("openvdb");
  // OpenVDB's count of an upper node: a dense table of 32³ 8-byte entries, the child and value
  // masks (a bit per entry each) and the origin.
  constexpr uint64_t kUpperNodeBytes = 32768 * 8 + 2 * 32768 / 8 + 12;
  SECTION("lit and undefined space only: the tree is empty") {
    const auto decoder = SyntheticMap::uniform(256, 0.3f, kInf).build(scheme, {}, 64);
    CHECK(component(*decoder, "upper internal nodes") == 0);
    CHECK(component(*decoder, "leaves") == 0);
  }
  SECTION("a shadowed half: one upper node of 128³ tiles, no lower nodes or leaves") {
    // Lit below slice 77, undefined to slice 128, shadowed after: the undefined band joins the
    // lit lower volumes by the parent rule, the shadowed ones are tiles.
    const auto decoder = SyntheticMap::uniform(256, 0.3f, 0.5f).build(scheme, {}, 64);
    CHECK(component(*decoder, "upper internal nodes") == kUpperNodeBytes);
    CHECK(component(*decoder, "lower internal nodes") == 0);
    CHECK(component(*decoder, "leaves") == 0);
    const Query shadowed{0.5f, 0.5f, voxelCentre(128, 256)}, lit{0.5f, 0.5f, voxelCentre(127, 256)};
    float answers[2];
    decoder->lookup(std::vector<Query>{shadowed, lit}, 1, answers);
    CHECK(answers[0] == 0.0f);
    CHECK(answers[1] == 1.0f);
  }
  SECTION("a boundary inside a leaf's slices: one leaf per 8×8 texels") {
    const auto decoder = SyntheticMap::uniform(64, 20.3f / 64, 20.3f / 64).build(scheme, {}, 64);
    CHECK(component(*decoder, "leaves") == (64 / 8) * (64 / 8) * 80);  // 80 bytes per leaf
  }
}

TEST_CASE("openvdb rejects listings that are not the tree they build", "[openvdb][format]") {
  const SchemeInfo& scheme = findScheme("openvdb");
  const MapInfo info{256, 256, DepthMode::Closed};
  auto load = [&](const std::vector<std::vector<uint32_t>>& origins,
                  const std::vector<uint64_t>& masks) {
    ByteWriter writer;
    for (const auto& list : origins) writer.putArray<uint32_t>(list);
    writer.putArray<uint64_t>(masks);
    ByteReader in(writer.bytes());
    auto loaded = scheme.load(in, info, {});
    in.expectEnd();
    return loaded;
  };
  const std::vector<uint64_t> oneLeaf(8, 0x00ff00ff00ff00ffull), twoLeaves(16, 1);
  // root tiles, upper node tiles (128³), lower node tiles (8³), leaf origins
  REQUIRE_NOTHROW(load({{}, {128, 0, 0}, {0, 8, 0}, {8, 0, 16}}, oneLeaf));
  REQUIRE_NOTHROW(load({{}, {}, {}, {8, 0, 16, 16, 0, 16}}, twoLeaves));
  CHECK_THROWS_AS(load({{}, {}, {}, {8, 0, 16}}, twoLeaves), FormatError);   // mask count
  CHECK_THROWS_AS(load({{}, {}, {}, {8, 0, 17}}, oneLeaf), FormatError);     // off the grid
  CHECK_THROWS_AS(load({{}, {}, {}, {8, 0, 256}}, oneLeaf), FormatError);    // outside
  CHECK_THROWS_AS(load({{}, {64, 0, 0}, {}, {}}, {}), FormatError);          // off the grid
  CHECK_THROWS_AS(load({{}, {}, {}, {8, 0, 16, 8}}, oneLeaf), FormatError);  // not triples
  CHECK_THROWS_AS(load({{}, {}, {}, {16, 0, 16, 8, 0, 16}}, twoLeaves),
                  FormatError);  // out of order
  CHECK_THROWS_AS(load({{}, {}, {}, {8, 0, 16, 8, 0, 16}}, twoLeaves), FormatError);  // twice
  CHECK_THROWS_AS(load({{}, {0, 0, 0}, {}, {8, 0, 16}}, oneLeaf), FormatError);       // in a tile
  CHECK_THROWS_AS(load({{}, {}, {8, 0, 16}, {8, 0, 16}}, oneLeaf), FormatError);      // in a tile
  CHECK_THROWS_AS(load({{0, 0, 0}, {128, 0, 0}, {}, {}}, {}), FormatError);           // in a tile
}

}  // namespace
}  // namespace sb
