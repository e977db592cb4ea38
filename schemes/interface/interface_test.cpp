// The scheme interface's promises, checked for every registered scheme: parameters are
// validated by name, structures answer within the synthetic intervals, save/load round-trips,
// the file format is pinned by a golden file, and every truncated or corrupted file is a
// FormatError, never a crash (run under the sanitizers in CI).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

using namespace sb;
using sb::testing::SyntheticMap;

namespace {

constexpr uint32_t kGoldenResolution = 8;
constexpr uint64_t kGoldenSeed = 42;

// Answers of a structure at every texel centre and a spread of depths, for comparing two
// structures (a saved one and its reload).
std::vector<float> answersOnGrid(const Decoder& decoder, uint32_t resolution) {
  std::vector<Query> queries;
  for (uint32_t j = 0; j < resolution; ++j)
    for (uint32_t i = 0; i < resolution; ++i)
      for (float z : {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 0.9f, 1.0f})
        queries.push_back({(i + 0.5f) / resolution, (j + 0.5f) / resolution, z});
  std::vector<float> answers(queries.size());
  for (int k : {1, 3}) decoder.lookup(queries, k, std::span(answers));
  return answers;
}

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("the registry lists schemes sorted and names them in errors", "[interface]") {
  REQUIRE(!schemes().empty());
  for (size_t s = 1; s < schemes().size(); ++s) CHECK(schemes()[s - 1].name < schemes()[s].name);
  CHECK_THROWS_WITH(findScheme("nope"), Catch::Contains("sm32"));
  CHECK(findScheme("sm32").kind == SchemeKind::Depth);
}

TEST_CASE("texel and voxel addressing follow DESIGN §2 and §4", "[interface]") {
  CHECK(texelOf(0.0f, 8) == 0);
  CHECK(texelOf(0.124999f, 8) == 0);
  CHECK(texelOf(0.125f, 8) == 1);
  CHECK(texelOf(std::nextafter(1.0f, 0.0f), 8) == 7);
  CHECK(!insideMap(texelOf(1.0f, 8), 0, 8));
  CHECK(!insideMap(texelOf(-0.001f, 8), 0, 8));
  CHECK(!insideMap(texelOf(std::nanf(""), 8), 0, 8));
  CHECK(voxelOf(0.0f, 4) == 0);
  CHECK(voxelOf(1.0f, 4) == 3);
  CHECK(voxelOf(-2.0f, 4) == 0);
  CHECK(voxelOf(0.25f, 4) == 1);
  CHECK(voxelCentre(1, 4) == 0.375f);
}

TEST_CASE("every scheme answers inside the intervals of a synthetic map", "[interface]") {
  for (const SchemeInfo& scheme : schemes())
    for (DepthMode mode : {DepthMode::Open, DepthMode::Closed}) {
      INFO(scheme.name << " " << toString(mode));
      const SyntheticMap map = SyntheticMap::random(32, mode, 7);
      const auto decoder = map.build(scheme, {}, 16);
      const MapInfo info = map.info(scheme.kind);
      std::vector<Query> queries;
      std::vector<int> expected;  // 1 lit, 0 shadowed
      for (uint32_t j = 0; j < 32; ++j)
        for (uint32_t i = 0; i < 32; ++i) {
          const float lo = map.lo[j * 32 + i], hi = map.hi[j * 32 + i];
          for (float z : {lo, std::nextafter(lo, -1.0f), std::nextafter(hi, 2.0f), 0.0f}) {
            const float tested =
                scheme.kind == SchemeKind::Voxel
                    ? voxelCentre(voxelOf(z, info.depthResolution), info.depthResolution)
                    : z;
            if (tested <= lo || tested > hi) {
              queries.push_back({(i + 0.25f) / 32, (j + 0.75f) / 32, z});
              expected.push_back(tested <= lo);
            }
          }
        }
      std::vector<float> got(queries.size());
      decoder->lookup(queries, 1, got);
      size_t wrong = 0;
      for (size_t q = 0; q < got.size(); ++q) wrong += got[q] != float(expected[q]);
      CHECK(wrong == 0);
    }
}

TEST_CASE("lookups reject invalid filter sizes and count outside taps as lit", "[interface]") {
  for (const SchemeInfo& scheme : schemes()) {
    INFO(scheme.name);
    const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 3);
    const auto decoder = map.build(scheme, {}, 16);
    std::vector<Query> q{{-0.5f, 0.5f, 1.0f}, {0.5f, 1.5f, 1.0f}};
    std::vector<float> out(2);
    for (int bad : {0, 2, 19, -1})
      CHECK_THROWS_AS(decoder->lookup(q, bad, out), std::invalid_argument);
    decoder->lookup(q, 1, out);
    CHECK(out[0] == 1.0f);
    CHECK(out[1] == 1.0f);
  }
}

TEST_CASE("structures round-trip through their files and reject every corruption",
          "[interface][format]") {
  for (const SchemeInfo& scheme : schemes()) {
    INFO(scheme.name);
    const SyntheticMap map =
        SyntheticMap::random(kGoldenResolution, DepthMode::Closed, kGoldenSeed);
    const auto decoder = map.build(scheme, {}, kGoldenResolution);
    const StructureHeader header{scheme.name, scheme.resolve({}).text(), map.info(scheme.kind)};
    const std::vector<uint8_t> file = encodeStructureFile(header, *decoder);

    StructureHeader loadedHeader;
    const auto loaded = decodeStructureFile(file, &loadedHeader);
    CHECK(loadedHeader.scheme == scheme.name);
    CHECK(loadedHeader.map.resolution == kGoldenResolution);
    CHECK(answersOnGrid(*loaded, kGoldenResolution) == answersOnGrid(*decoder, kGoldenResolution));
    CHECK(totalBytes(loaded->size()) == totalBytes(decoder->size()));

    for (size_t length = 0; length < file.size(); ++length)
      CHECK_THROWS_AS(decodeStructureFile(std::span(file).first(length), nullptr), FormatError);
    for (size_t at = 0; at < file.size(); ++at) {
      std::vector<uint8_t> corrupted = file;
      corrupted[at] ^= uint8_t(1u << (at % 8));
      CHECK_THROWS_AS(decodeStructureFile(corrupted, nullptr), FormatError);
    }
  }
}

TEST_CASE("a valid checksum does not make an inconsistent header acceptable",
          "[interface][format]") {
  const SchemeInfo& scheme = findScheme("sm32");
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 1);
  const auto decoder = map.build(scheme, {}, 16);
  for (uint32_t claimed : {8u, 32u, 12u}) {
    // The header claims another resolution than the payload holds, checksum recomputed.
    const StructureHeader header{scheme.name, {}, {claimed, 0, DepthMode::Open}};
    CHECK_THROWS_AS(decodeStructureFile(encodeStructureFile(header, *decoder), nullptr),
                    FormatError);
  }
  const StructureHeader unknown{"no-such-scheme", {}, {16, 0, DepthMode::Open}};
  CHECK_THROWS_WITH(decodeStructureFile(encodeStructureFile(unknown, *decoder), nullptr),
                    Catch::Contains("no-such-scheme"));
}

// Each scheme's file format is pinned by tests/golden/<scheme>.sb; regenerate deliberately
// with SHADOWBENCH_UPDATE_GOLDEN=1 when a format version changes.
TEST_CASE("file formats match their golden files", "[interface][format]") {
  for (const SchemeInfo& scheme : schemes()) {
    INFO(scheme.name);
    const SyntheticMap map =
        SyntheticMap::random(kGoldenResolution, DepthMode::Closed, kGoldenSeed);
    const auto decoder = map.build(scheme, {}, kGoldenResolution);
    const std::vector<uint8_t> file = encodeStructureFile(
        {scheme.name, scheme.resolve({}).text(), map.info(scheme.kind)}, *decoder);
    const std::string path = "tests/golden/" + scheme.name + ".sb";
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) {
      std::ofstream(path, std::ios::binary)
          .write(reinterpret_cast<const char*>(file.data()), file.size());
    }
    const std::vector<uint8_t> golden = readFile(path);
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    REQUIRE(!golden.empty());
    CHECK(golden == file);
    CHECK(answersOnGrid(*decodeStructureFile(golden, nullptr), kGoldenResolution) ==
          answersOnGrid(*decoder, kGoldenResolution));
  }
}
