// Builds in parts (DESIGN §5, parts.h): for every scheme that builds in parts, the structure merged
// from parts answers every texel exactly as the whole build does, on seeded random maps of every
// mode and at every part size; each is also checked against the map itself (lossless, DESIGN §4).
// The size difference a part border costs is printed for the scheme READMEs.
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include "schemes/interface/parts.h"
#include "tests/support/synthetic_map.h"

using namespace sb;
using sb::testing::SyntheticMap;

namespace {

// Depth schemes: each texel at its bounds, just beyond them and at seeded random depths. Voxel
// schemes: every voxel centre of the column (DESIGN §4 quantises z).
std::vector<Query> texelQueries(const SyntheticMap& map, SchemeKind kind) {
  std::vector<Query> queries;
  const float r = float(map.resolution);
  uint64_t state = 0x5eed;
  for (uint32_t j = 0; j < map.resolution; ++j)
    for (uint32_t i = 0; i < map.resolution; ++i) {
      const float x = (i + 0.5f) / r, y = (j + 0.5f) / r;
      if (kind == SchemeKind::Voxel) {
        for (uint32_t k = 0; k < map.resolution; ++k) queries.push_back({x, y, (k + 0.5f) / r});
        continue;
      }
      const size_t at = size_t(j) * map.resolution + i;
      for (float z : {map.lo[at], std::nextafter(map.lo[at], 2.0f), map.hi[at],
                      std::nextafter(map.hi[at], 2.0f), unitFloat(nextRandom(state))})
        if (std::isfinite(z) && z <= 1.0f) queries.push_back({x, y, z});
    }
  return queries;
}

// The reference answer of a point query, or -1 in the undefined band.
float referenceAnswer(const SyntheticMap& map, SchemeKind kind, const Query& q) {
  const uint32_t i = uint32_t(q.x * map.resolution), j = uint32_t(q.y * map.resolution);
  const size_t at = size_t(j) * map.resolution + i;
  const float z = kind == SchemeKind::Voxel
                      ? (std::min(uint32_t(q.z * map.resolution), map.resolution - 1) + 0.5f) /
                            float(map.resolution)
                      : q.z;
  if (z <= map.lo[at]) return 1.0f;
  if (z > map.hi[at]) return 0.0f;
  return -1.0f;
}

}  // namespace

TEST_CASE("a build in parts answers every texel as the whole build", "[parts]") {
  const DepthMode mode = GENERATE(DepthMode::Open, DepthMode::Closed, DepthMode::Static);
  constexpr uint32_t kResolution = 128, kTile = 16;
  const SyntheticMap map = SyntheticMap::random(kResolution, mode, 0x9a27 + int(mode));
  for (const SchemeInfo& scheme : schemes()) {
    if (!scheme.buildsInParts()) continue;
    const auto whole = map.build(scheme, {}, kTile);
    const std::vector<Query> queries = texelQueries(map, scheme.kind);
    std::vector<float> expected(queries.size()), got(queries.size());
    for (int k : {1, 3}) {
      whole->lookup(queries, k, expected);
      for (uint32_t partSize : {16u, 32u, 64u}) {
        const auto merged = map.buildInParts(scheme, {}, kTile, partSize);
        merged->lookup(queries, k, got);
        size_t differing = 0, wrong = 0;
        for (size_t q = 0; q < queries.size(); ++q) {
          differing += got[q] != expected[q];
          if (k == 1) {
            const float reference = referenceAnswer(map, scheme.kind, queries[q]);
            wrong += reference >= 0 && got[q] != reference;
          }
        }
        INFO(fmt::format("{} {} parts of {}², k = {}", scheme.name, toString(mode), partSize, k));
        CHECK(differing == 0);
        CHECK(wrong == 0);
        if (k == 1) {
          const uint64_t wholeBytes = totalBytes(whole->size()),
                         mergedBytes = totalBytes(merged->size());
          fmt::print("parts: {} {} {}² in parts of {}²: {} bytes whole, {} merged ({:+.2f}%)\n",
                     scheme.name, toString(mode), kResolution, partSize, wholeBytes, mergedBytes,
                     100.0 * (double(mergedBytes) - double(wholeBytes)) / double(wholeBytes));
        }
      }
    }
  }
}

// Issue 12: every compressed scheme reaches 256K² through builds in parts.
TEST_CASE("every compressed scheme builds in parts", "[parts]") {
  for (const char* name : {"cpvs", "cpvs-fast", "mh", "mmh", "dag-mh", "compressed-sm"}) {
    INFO(name);
    CHECK(findScheme(name).buildsInParts());
  }
}
