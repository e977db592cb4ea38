// Sintorn §5 distant filters: the error figures are what they say, VOAA depths follow the node
// sides, MRAA level 0 is the exact point lookup, and a small city gives finite errors in [0, 1]
// that repeat exactly.
#include <catch2/catch.hpp>

#include <cmath>

#include "harness/cell.h"
#include "harness/distant_filters.h"
#include "schemes/interface/capabilities.h"

using namespace sb;

namespace {

constexpr const char* kScene = "city:size=2,seed=1";
constexpr uint32_t kResolution = 128;

// The structure at kResolution, its MRAA levels and the report on a small view.
DistantFiltersReport evaluate(const Scene& scene, const std::string& schemeName) {
  const SchemeInfo& scheme = findScheme(schemeName);
  const Light light = sceneLight(scene, 0);
  const DepthSource source(scene, light, DepthMode::Closed, kResolution);
  const ParamValues params = scheme.resolve({});
  const BuildOutcome full =
      buildStructure(source, scheme, params, BuildShape{defaultTileSize(kResolution)});
  const auto mraa =
      buildMraaLevels(scene, light, DepthMode::Closed, scheme, params, kResolution, 4);
  DistantFiltersOptions options;
  options.time = false;
  return evaluateDistantFilters(full, mraa, viewSamples(scene, source, 96, 64, 2), options);
}

}  // namespace

TEST_CASE("filter errors are the mean, RMS and largest difference and the share over 0.1",
          "[distant]") {
  const std::vector<float> approximate{0.0f, 0.5f, 1.0f, 0.25f}, exact{0.0f, 0.25f, 0.5f, 0.3f};
  const FilterError e = filterError(approximate, exact);
  CHECK(e.meanAbs == Approx((0 + 0.25 + 0.5 + 0.05) / 4));
  CHECK(e.rms == Approx(std::sqrt((0.0625 + 0.25 + 0.0025) / 4)));
  CHECK(e.max == Approx(0.5));
  CHECK(e.overTenth == Approx(0.5));
  CHECK(filterError(exact, exact).max == 0);
  CHECK_THROWS_AS(filterError(std::span(approximate).first(2), exact), std::invalid_argument);
}

namespace {

// The occupancy a VOAA row reads, of a structure built at 128² (7 levels) with `params`.
std::unique_ptr<Decoder> built128(const std::string& schemeName, const Params& params) {
  const Scene scene = openScene(kScene);
  const SchemeInfo& scheme = findScheme(schemeName);
  const DepthSource source(scene, sceneLight(scene, 0), DepthMode::Closed, kResolution);
  return buildStructure(source, scheme, scheme.resolve(params), BuildShape{64}).decoder;
}

}  // namespace

TEST_CASE("VOAA depths follow the node side", "[distant]") {
  const auto cpvs = built128("cpvs-fast", {});
  const VoxelOccupancy* occupancy = cpvs->voxelOccupancy();
  REQUIRE(occupancy);
  CHECK(occupancy->depthOfSide(8) == 4);  // the leaf parents
  CHECK(occupancy->depthOfSide(16) == 3);
  CHECK(occupancy->depthOfSide(128) == 0);
  for (uint32_t side : {0u, 4u, 12u, 256u})
    CHECK_THROWS_AS(occupancy->depthOfSide(side), std::invalid_argument);
  // The grid replaces depths 0–3, which then hold no occupancy.
  const auto gridded = built128("cpvs-fast", {{"grid-levels", "4"}});
  CHECK(gridded->voxelOccupancy()->depthOfSide(8) == 4);
  CHECK_THROWS_AS(gridded->voxelOccupancy()->depthOfSide(16), std::invalid_argument);
  // Only CPVS-format structures keep occupancies; the MH family keeps coarser levels instead.
  CHECK(built128("sm32", {})->voxelOccupancy() == nullptr);
  CHECK(built128("openvdb", {})->voxelOccupancy() == nullptr);
  CHECK(built128("mh", {})->hierarchicalLookup() != nullptr);
  CHECK(built128("cpvs", {})->hierarchicalLookup() == nullptr);
}

TEST_CASE("MRAA levels stop at 4 and at the smallest map", "[distant]") {
  const Scene scene = openScene(kScene);
  const SchemeInfo& sm32 = findScheme("sm32");
  const Light light = sceneLight(scene, 0);
  CHECK_THROWS_AS(buildMraaLevels(scene, light, DepthMode::Closed, sm32, {}, 256, 5),
                  std::invalid_argument);
  CHECK_THROWS_AS(buildMraaLevels(scene, light, DepthMode::Closed, sm32, {}, 64, 4),
                  std::invalid_argument);
  const auto levels = buildMraaLevels(scene, light, DepthMode::Closed, sm32, {}, 64, 3);
  REQUIRE(levels.size() == 3);
  CHECK(levels[2].map.resolution == 8);
  CHECK(mraaReferenceK(0) == 1);
  CHECK(mraaReferenceK(3) == 9);
  CHECK(mraaReferenceK(4) == 17);
}

TEST_CASE("distant filters on a small city: MRAA level 0 is exact, errors in [0, 1] repeat",
          "[distant]") {
  const Scene scene = openScene(kScene);
  for (const char* name : {"cpvs-fast", "sm32"}) {
    INFO(name);
    const DistantFiltersReport report = evaluate(scene, name);
    const bool voxel = findScheme(name).kind == SchemeKind::Voxel;
    REQUIRE(report.queries > 1000);
    REQUIRE(report.rows.size() == (voxel ? 3u : 0u) + 10u);
    REQUIRE(report.mraaBytes.size() == 4);
    CHECK(report.mraaExtra() > 0);

    for (const DistantFilterRow& row : report.rows) {
      INFO(row.filter << " " << row.answer);
      CHECK(std::isfinite(row.error.rms));
      CHECK(row.error.meanAbs >= 0);
      CHECK(row.error.meanAbs <= row.error.rms);
      CHECK(row.error.rms <= row.error.max);
      CHECK(row.error.max <= 1);
      CHECK(row.error.overTenth <= 1);
      CHECK(row.nsPerQuery == 0);  // not timed
    }
    const size_t mraa0 = voxel ? 3 : 0;
    const DistantFilterRow& point = report.rows[mraa0];
    CHECK(point.answer == "L = 0 (128²), 1×1");
    CHECK(point.referenceK == 1);
    CHECK(point.error.max == 0);  // the full structure's point lookups are the exact ones
    CHECK(point.bytes == report.fullBytes);
    CHECK(report.rows[mraa0 + 1].error.max > 0);  // 3×3 blurs shadow edges the points keep
    CHECK(report.rows.back().referenceK == 17);
    if (voxel) {
      CHECK(report.rows[0].answer == "s = 8 (depth 4)");
      CHECK(report.rows[0].referenceK == 9);
      CHECK(report.rows[2].referenceK == 17);  // s = 32: the largest exact kernel
      CHECK(report.rows[0].bytes == report.fullBytes);
    }

    const DistantFiltersReport again = evaluate(scene, name);
    CHECK(again.toJson() == report.toJson());
  }
}
