// The voxel schemes (every registered SchemeKind::Voxel scheme: cpvs, cpvs-fast, openvdb) against
// the DESIGN §4 voxel rule computed here from the map, on seeded random maps under every parameter
// combination and on the awkward maps: undefined columns, boundaries on tile borders, a light
// that sees nothing, the deepest level of a 64K structure.
#include <algorithm>
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "schemes/interface/capabilities.h"
#include "schemes/interface/lightspace.h"
#include "schemes/shared/slice_interval.h"
#include "schemes/shared/svo.h"
#include "schemes/shared/voxel_dag.h"
#include "schemes/shared/voxel_parts_test_support.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using testing::SyntheticMap;
constexpr float kInf = std::numeric_limits<float>::infinity();

enum class Voxel { Lit, Shadowed, Undefined };

// DESIGN §4, written out independently of the schemes' slice intervals.
Voxel referenceVoxel(const SyntheticMap& map, uint32_t i, uint32_t j, uint32_t k) {
  const size_t at = size_t(j) * map.resolution + i;
  const float centre = voxelCentre(k, map.resolution);
  if (centre <= map.lo[at]) return Voxel::Lit;
  if (centre > map.hi[at]) return Voxel::Shadowed;
  return Voxel::Undefined;
}

Query centreQuery(uint32_t i, uint32_t j, uint32_t k, uint32_t resolution) {
  return {(float(i) + 0.5f) / float(resolution), (float(j) + 0.5f) / float(resolution),
          voxelCentre(k, resolution)};
}

// Every voxel by point lookup, and PCF of every odd size on a sample of voxels including the
// map's corners; returns the number of wrong answers.
uint64_t mismatches(const SyntheticMap& map, const Decoder& decoder, uint64_t seed) {
  const uint32_t r = map.resolution;
  uint64_t wrong = 0;
  std::vector<Query> queries;
  std::vector<float> answers(size_t(r) * r);
  for (uint32_t k = 0; k < r; ++k) {
    queries.clear();
    for (uint32_t j = 0; j < r; ++j)
      for (uint32_t i = 0; i < r; ++i) queries.push_back(centreQuery(i, j, k, r));
    decoder.lookup(queries, 1, answers);
    for (uint32_t j = 0; j < r; ++j)
      for (uint32_t i = 0; i < r; ++i) {
        const Voxel expected = referenceVoxel(map, i, j, k);
        const float got = answers[size_t(j) * r + i];
        wrong += (expected == Voxel::Lit && got != 1.0f) ||
                 (expected == Voxel::Shadowed && got != 0.0f) || (got != 0.0f && got != 1.0f);
      }
  }
  uint64_t state = seed;
  for (int k : {3, 5, 9, 17})
    for (int s = 0; s < 400; ++s) {
      const uint32_t i = s < 4 ? (s & 1) * (r - 1) : uint32_t(nextRandom(state) % r);
      const uint32_t j = s < 4 ? (s >> 1) * (r - 1) : uint32_t(nextRandom(state) % r);
      const uint32_t z = uint32_t(nextRandom(state) % r);
      int lit = 0, undefined = 0;
      for (int64_t y = int64_t(j) - k / 2; y <= int64_t(j) + k / 2; ++y)
        for (int64_t x = int64_t(i) - k / 2; x <= int64_t(i) + k / 2; ++x) {
          if (!insideMap(x, y, r)) {
            ++lit;
            continue;
          }
          const Voxel v = referenceVoxel(map, uint32_t(x), uint32_t(y), z);
          lit += v == Voxel::Lit, undefined += v == Voxel::Undefined;
        }
      float got = -1;
      const Query query = centreQuery(i, j, z, r);
      decoder.lookup({&query, 1}, k, {&got, 1});
      const float taps = float(k * k);
      wrong += !(got >= float(lit) / taps && got <= float(lit + undefined) / taps);
    }
  return wrong;
}

std::vector<const SchemeInfo*> voxelSchemes() {
  std::vector<const SchemeInfo*> found;
  for (const SchemeInfo& scheme : schemes())
    if (scheme.kind == SchemeKind::Voxel) found.push_back(&scheme);
  return found;
}

// Every combination of the sweep values of a scheme's parameters.
std::vector<Params> sweepCombinations(const SchemeInfo& scheme) {
  std::vector<Params> combinations{{}};
  for (const ParamSpec& spec : scheme.params) {
    std::vector<Params> next;
    for (const Params& partial : combinations)
      for (const std::string& value : spec.sweep) {
        Params extended = partial;
        extended[spec.name] = value;
        next.push_back(extended);
      }
    combinations = std::move(next);
  }
  return combinations;
}

TEST_CASE("slice intervals count the voxel centres at or before a depth", "[voxel]") {
  uint64_t state = 7;
  for (uint32_t rz : {8u, 64u, 1024u, 65536u}) {
    std::vector<float> depths{0.0f, 1.0f, kInf, -0.5f, voxelCentre(0, rz), voxelCentre(rz - 1, rz)};
    for (int s = 0; s < 200; ++s) {
      const float centre = voxelCentre(uint32_t(nextRandom(state) % rz), rz);
      depths.push_back(centre);
      depths.push_back(std::nextafter(centre, 0.0f));
      depths.push_back(std::nextafter(centre, 2.0f));
      depths.push_back(unitFloat(nextRandom(state)));
    }
    for (const float depth : depths) {
      uint32_t expected = 0;
      while (expected < rz && voxelCentre(expected, rz) <= depth) ++expected;
      INFO("Rz " << rz << ", depth " << depth);
      CHECK(firstSliceBeyond(depth, rz) == expected);
    }
  }
}

TEST_CASE("voxel schemes are lossless under every parameter combination", "[voxel]") {
  const std::vector<const SchemeInfo*> found = voxelSchemes();
  REQUIRE(found.size() >= 2);
  for (const SchemeInfo* scheme : found)
    for (const Params& params : sweepCombinations(*scheme))
      for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static}) {
        const SyntheticMap map = SyntheticMap::random(32, mode, 11 + int(mode));
        INFO(scheme->name << " " << toString(mode));
        for (const auto& [name, value] : params) INFO(name << "=" << value);
        CHECK(mismatches(map, *map.build(*scheme, params, 8), 3) == 0);
      }
}

TEST_CASE("voxel schemes are lossless on random 64² maps with one tile and many", "[voxel]") {
  for (const SchemeInfo* scheme : voxelSchemes())
    for (uint32_t tile : {8u, 16u, 64u})
      for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static}) {
        const SyntheticMap map = SyntheticMap::random(64, mode, 5 * tile + int(mode));
        INFO(scheme->name << " " << toString(mode) << ", tile " << tile);
        CHECK(mismatches(map, *map.build(*scheme, {}, tile), 9) == 0);
      }
}

TEST_CASE("awkward maps: undefined columns, tile-border boundaries, an empty light", "[voxel]") {
  const uint32_t r = 64, tile = 16;
  SyntheticMap undefinedColumns = SyntheticMap::random(r, DepthMode::Closed, 21);
  for (uint32_t j = 8; j < 24; ++j)
    for (uint32_t i = 30; i < 34; ++i) {
      // Every slice of these columns is undefined: lo before the first centre, hi at the far plane.
      undefinedColumns.lo[size_t(j) * r + i] = 0.0f;
      undefinedColumns.hi[size_t(j) * r + i] = 1.0f;
    }
  SyntheticMap tileBorders = SyntheticMap::uniform(r, 0.25f, 0.25f);
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i)
      if ((i / tile + j / tile) % 2)
        tileBorders.lo[size_t(j) * r + i] = tileBorders.hi[size_t(j) * r + i] = 0.75f;
  const SyntheticMap empty = SyntheticMap::uniform(r, 1.0f, kInf);
  const SyntheticMap solid = SyntheticMap::uniform(r, 0.0f, 0.0f);

  for (const SchemeInfo* scheme : voxelSchemes()) {
    INFO(scheme->name);
    CHECK(mismatches(undefinedColumns, *undefinedColumns.build(*scheme, {}, tile), 1) == 0);
    CHECK(mismatches(tileBorders, *tileBorders.build(*scheme, {}, tile), 2) == 0);
    for (const SyntheticMap* uniform : {&empty, &solid}) {
      const auto decoder = uniform->build(*scheme, {}, tile);
      CHECK(mismatches(*uniform, *decoder, 3) == 0);
      // A homogeneous map needs no node, whatever its resolution; in CPVS it is one reference
      // in the grid.
      const SyntheticMap larger = SyntheticMap::uniform(4 * r, uniform->lo[0], uniform->hi[0]);
      CHECK(totalBytes(decoder->size()) == totalBytes(larger.build(*scheme, {}, tile)->size()));
      if (decoder->voxelOccupancy()) CHECK(totalBytes(decoder->size()) == sizeof(DagRef));
    }
  }
}

// Over the masks, culling never changes the structure. With the depth hierarchy the paper's
// reuse may keep the node in front where a fresh build would classify the volume behind
// differently (only its undefined voxels differ): there both builds must answer every defined
// voxel as the map says.
TEST_CASE("culling changes the work of cpvs-fast, never its answers", "[voxel]") {
  const SchemeInfo& fast = findScheme("cpvs-fast");
  for (const char* classification : {"masks", "depth-hierarchy"})
    for (const char* transitions : {"aligned", "nearest-exit"})
      for (const char* layout : {"slab8", "cube4"})
        for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
          for (uint64_t seed : {33u, 34u}) {
            INFO(classification << " " << transitions << " " << layout << " " << toString(mode)
                                << " seed " << seed);
            const SyntheticMap map = SyntheticMap::random(128, mode, seed);
            const Params params{{"coarse-classification", classification},
                                {"transitions", transitions},
                                {"leaf-layout", layout}};
            Params on = params, off = params;
            on["culling"] = "on", off["culling"] = "off";
            testing::CountingContext culledCounts, builtCounts;
            const auto culled = testing::buildWhole(map, fast, on, 32, culledCounts);
            const auto built = testing::buildWhole(map, fast, off, 32, builtCounts);
            CHECK(culledCounts.counts.at("nodes culled") > 0);
            CHECK(mismatches(map, *culled, 4) == 0);
            CHECK(mismatches(map, *built, 4) == 0);
            if (std::string(classification) == "masks") {
              CHECK(culled->size() == built->size());
              CHECK(culledCounts.counts.at("dag nodes") == builtCounts.counts.at("dag nodes"));
              CHECK(culledCounts.counts.at("dag leafmasks") ==
                    builtCounts.counts.at("dag leafmasks"));
            }
          }
}

// Builds in parts (voxel_dag_parts.h): hash-consing across parts and joining the parts' columns
// as the tiles' columns are joined reproduces the whole build's DAG exactly, so a part border
// costs nothing; every voxel answers as the map says.
TEST_CASE("a CPVS merged from parts is the whole build's DAG", "[voxel][parts]") {
  struct Case {
    uint32_t resolution, tile;
    std::vector<uint32_t> partSizes;
  };
  // cpvs-fast also with its coarse volumes classified by the depth hierarchy.
  const std::pair<const char*, Params> variants[] = {
      {"cpvs", {}},
      {"cpvs-fast", {}},
      {"cpvs-fast", {{"coarse-classification", "depth-hierarchy"}}}};
  for (const auto& [name, variant] : variants)
    for (const Case& shape : {Case{64, 8, {8, 16, 32}}, Case{128, 16, {16, 64}}})
      for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
        for (const char* layout : {"cube4", "slab8"})
          for (const char* grid : {"0", "2"}) {
            const SchemeInfo& scheme = findScheme(name);
            Params params = variant;
            params["leaf-layout"] = layout, params["grid-levels"] = grid;
            const SyntheticMap map =
                SyntheticMap::random(shape.resolution, mode, shape.resolution + 3 * int(mode));
            testing::CountingContext wholeCounts;
            const auto whole = testing::buildWhole(map, scheme, params, shape.tile, wholeCounts);
            for (uint32_t partSize : shape.partSizes) {
              INFO(name << (variant.empty() ? "" : " depth-hierarchy") << " " << toString(mode)
                        << " " << layout << " grid " << grid << ", " << shape.resolution
                        << "² in parts of " << partSize << "², tile " << shape.tile);
              testing::CountingContext mergedCounts;
              const auto merged = testing::mergeParts(
                  map, scheme, params, shape.tile, partSize,
                  map.partPayloads(scheme, params, shape.tile, partSize), mergedCounts);
              CHECK(mergedCounts.counts.at("dag nodes") == wholeCounts.counts.at("dag nodes"));
              CHECK(mergedCounts.counts.at("dag leafmasks") ==
                    wholeCounts.counts.at("dag leafmasks"));
              CHECK(merged->size() == whole->size());
              if (shape.resolution == 64) CHECK(mismatches(map, *merged, partSize) == 0);
            }
          }
}

// Issue 12 item 3: the estimate a build in parts is checked against follows the part size, and
// the merge holds the whole DAG as a whole build does at its end.
TEST_CASE("the CPVS memory estimate in parts follows the part size", "[voxel][parts]") {
  for (const char* name : {"cpvs", "cpvs-fast"}) {
    const SchemeInfo& scheme = findScheme(name);
    const ParamValues params = scheme.resolve({});
    const MapInfo map{262144, 262144, DepthMode::Closed};
    const uint64_t whole = scheme.buildBytes(map, params, {512});
    uint64_t previous = 0;
    for (uint32_t partSize : {512u, 4096u, 16384u, 65536u}) {
      INFO(name << " parts of " << partSize);
      const uint64_t inParts = scheme.buildBytes(map, params, {512, partSize});
      CHECK(inParts > previous);
      CHECK(inParts >= whole - uint64_t(512) * 512 * 24);
      previous = inParts;
    }
  }
}

TEST_CASE("the deepest level of a 64K structure is addressed exactly", "[voxel]") {
  // One shadowed voxel at the far corner of a 65536³ volume, built node by node down its path.
  for (LeafLayout layout : {LeafLayout::Slab8, LeafLayout::Cube4}) {
    const VoxelDagShape shape{16, layout};
    const uint32_t last = 65535;
    VoxelDagBuilder builder(shape);
    DagRef ref = builder.leafmask(~(uint64_t(1) << shape.leafBit(last, last, last)));
    for (uint32_t depth = shape.leafParentDepth() + 1; depth-- > 0;) {
      std::array<DagRef, 8> children;
      children.fill(kLitRef);
      children[shape.childIndex(last, last, last, depth)] = ref;
      ref = builder.node(depth, children);
    }
    for (uint32_t grid : {0u, 4u}) {
      const auto decoder = makeVoxelDagDecoder(builder.finish(ref, grid));
      const float far = voxelCentre(last, 65536), near = voxelCentre(last - 1, 65536);
      const float edge = (float(last) + 0.5f) / 65536.0f, inside = (float(last) - 0.5f) / 65536.0f;
      const std::vector<Query> queries{{edge, edge, far},
                                       {inside, edge, far},
                                       {edge, inside, far},
                                       {edge, edge, near},
                                       {edge, edge, far}};
      std::vector<float> answers(queries.size());
      decoder->lookup(queries, 1, answers);
      CHECK(answers == std::vector<float>{0, 1, 1, 1, 0});
      // 3×3 around the corner voxel: 4 taps on the map, one of them shadowed, 5 off the map.
      decoder->lookup({&queries[0], 1}, 3, answers);
      CHECK(answers[0] == Approx(8.0f / 9.0f));
    }
  }
}

TEST_CASE("VOAA occupancy is the lit fraction of the node's voxels", "[voxel]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Open, 41);
  for (const char* name : {"cpvs", "cpvs-fast"}) {  // the CPVS-format schemes
    const SchemeInfo* scheme = &findScheme(name);
    const auto decoder = map.build(*scheme, {}, 16);
    REQUIRE(decoder->voxelOccupancy());
    // Depth 3 holds 8³ cubes (the leaf parents at 64³); depth 0 the whole volume.
    for (uint32_t depth : {0u, 1u, 3u}) {
      const uint32_t side = 64u >> depth;
      for (uint32_t cube = 0; cube < 8; ++cube) {
        const uint32_t x0 = (cube * 37 % 64) / side * side, y0 = (cube * 11 % 64) / side * side,
                       z0 = (cube * 23 % 64) / side * side;
        uint64_t lit = 0;
        std::vector<Query> queries;
        for (uint32_t k = z0; k < z0 + side; ++k)
          for (uint32_t j = y0; j < y0 + side; ++j)
            for (uint32_t i = x0; i < x0 + side; ++i) queries.push_back(centreQuery(i, j, k, 64));
        std::vector<float> answers(queries.size()), occupancy(1);
        decoder->lookup(queries, 1, answers);
        for (float a : answers) lit += a == 1.0f;
        decoder->voxelOccupancy()->litFraction({&queries[0], 1}, depth, occupancy);
        INFO(scheme->name << " depth " << depth << " cube " << cube);
        CHECK(occupancy[0] == Approx(double(lit) / double(queries.size())).margin(1.0 / 65535));
      }
    }
  }
}

}  // namespace
}  // namespace sb
