// Many lights (Kämpe §4, §5.3): the placement is deterministic and every light sees the scene;
// the tiled light lists never drop a light that reaches a pixel; the tiled shadows equal a
// brute-force loop over every light; builds resume from their records.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "harness/build.h"
#include "harness/cell.h"
#include "harness/many_lights.h"
#include "tests/support/scratch_dir.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

using sb::testing::ScratchDir;

constexpr const char* kScene = "city:size=2";

bool sameSpec(const LightSpec& a, const LightSpec& b) {
  return a.kind == b.kind && a.position == b.position && a.direction == b.direction &&
         a.fovDegrees == b.fovDegrees && a.depth == b.depth;
}

// Lights of `scene` with sm32 structures at `resolution`, built in closed mode.
struct BuiltLights {
  std::vector<std::unique_ptr<Decoder>> decoders;
  std::vector<ShadowedLight> lights;

  BuiltLights(const Scene& scene, uint32_t resolution) {
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
      const DepthSource source(scene, sceneLight(scene, i), DepthMode::Closed, resolution);
      decoders.push_back(buildStructure(source, findScheme("sm32"), findScheme("sm32").resolve({}),
                                        BuildShape{defaultTileSize(resolution)})
                             .decoder);
      lights.emplace_back(source.light(), *decoders.back(), resolution);
    }
  }
};

ViewSurface viewOf(const Scene& scene, uint32_t width, uint32_t height) {
  const DepthSource camera(scene, sceneLight(scene, 0), DepthMode::Open, 8, DepthMethod::RayCast);
  return captureView(scene, camera, width, height, 0, 1);
}

}  // namespace

TEST_CASE("the placement is deterministic and every light's cone sees the scene", "[lights]") {
  const Scene scene = openScene(kScene);
  SpotLightPlacement placement;
  placement.count = 12;
  placement.seed = 3;
  const auto lights = placeSpotLights(scene, placement);
  const auto again = placeSpotLights(scene, placement);
  REQUIRE(lights.size() == 12);
  placement.seed = 4;
  const auto other = placeSpotLights(scene, placement);
  for (size_t i = 0; i < lights.size(); ++i) {
    CHECK(sameSpec(lights[i], again[i]));
    CHECK_FALSE(sameSpec(lights[i], other[i]));
    CHECK(lights[i].kind == LightKind::Spot);
    CHECK(lights[i].depth == DepthDistribution::Logarithmic);
    CHECK(lights[i].fovDegrees >= 60);
    CHECK(lights[i].fovDegrees <= 90);
    // Some ray of an 8×8 map hits the scene.
    const DepthSource source(scene, Light::fit(lights[i], scene), DepthMode::Open, 8,
                             DepthMethod::RayCast);
    bool hits = false;
    for (uint32_t j = 0; j < 8; ++j)
      for (uint32_t t = 0; t < 8; ++t) hits = hits || source.texel(t, j).lo < 1;
    CHECK(hits);
  }
}

TEST_CASE("a light that reaches a pixel is always in its tile's list", "[lights]") {
  SpotLightPlacement placement;
  placement.count = 8;
  const Scene scene = withSpotLights(openScene(kScene), placement);
  const BuiltLights built(scene, 64);
  const ViewSurface view = viewOf(scene, 96, 60);
  for (int k : {1, 9, 17}) {
    const TileLightLists lists = buildLightLists(view, built.lights, 8, k, true);
    CHECK(lists.lights == buildLightLists(view, built.lights, 8, k, false).lights);
    uint64_t reached = 0, missing = 0, listed = 0;
    for (uint32_t y = 0; y < view.height; ++y)
      for (uint32_t x = 0; x < view.width; ++x) {
        const size_t p = view.pixel(x, y);
        if (!view.covered[p]) continue;
        const auto& list = lists.lights[(y / 8) * lists.tilesX + x / 8];
        for (uint32_t l = 0; l < built.lights.size(); ++l) {
          if (!lightSpaceQuery(built.lights[l], view.position[p], view.normal[p], k)) continue;
          ++reached;
          missing += std::find(list.begin(), list.end(), l) == list.end();
        }
      }
    for (const auto& list : lists.lights) listed += list.size();
    INFO("k = " << k);
    CHECK(reached > 0);
    CHECK(missing == 0);
    // The lists cull: fewer than every light in every tile.
    CHECK(listed < lists.lights.size() * built.lights.size());
  }
}

TEST_CASE("tiled shadows equal a brute-force loop over every light", "[lights]") {
  SpotLightPlacement placement;
  placement.count = 4;
  placement.seed = 7;
  const Scene scene = withSpotLights(openScene(kScene), placement);
  const BuiltLights built(scene, 256);
  const ViewSurface view = viewOf(scene, 100, 60);  // tiles at the edges are partial
  constexpr int k = 9;

  std::vector<float> tiled, everywhere, serial;
  const TileLightLists lists = buildLightLists(view, built.lights, 8, k, true);
  const uint64_t lookups = evaluateShadows(view, built.lights, lists, k, true, tiled);
  CHECK(evaluateShadows(view, built.lights, allLightsEverywhere(view, 4, 8), k, false,
                        everywhere) == lookups);
  CHECK(evaluateShadows(view, built.lights, lists, k, false, serial) == lookups);
  CHECK(tiled == everywhere);
  CHECK(tiled == serial);

  uint64_t bruteLookups = 0, differ = 0, partial = 0;
  for (size_t p = 0; p < tiled.size(); ++p) {
    float sum = 0;
    if (view.covered[p])
      for (const ShadowedLight& light : built.lights)
        if (const auto q = lightSpaceQuery(light, view.position[p], view.normal[p], k)) {
          float v = 0;
          light.decoder->lookup(std::span(&*q, 1), k, std::span(&v, 1));
          sum += v;
          ++bruteLookups;
          partial += v > 0 && v < 1;
        }
    differ += sum != tiled[p];
  }
  CHECK(bruteLookups == lookups);
  CHECK(differ == 0);
  CHECK(partial > 0);  // penumbrae of the 9×9 filter: the test sees shadows, not only light
}

TEST_CASE("builds write one record per light and resume from them", "[lights]") {
  const ScratchDir out("sb-many-lights-test");
  ManyLightsConfig config;
  config.sceneSpec = kScene;
  config.placement.count = 3;
  config.scheme = "sm32";
  config.resolution = 64;
  config.verify = true;
  config.sampledQueries = 1000;
  const Scene scene = withSpotLights(openScene(kScene), config.placement);

  uint32_t built = 0;
  const auto count = [&](uint32_t, const nlohmann::json&, bool b) { built += b; };
  const auto records = buildManyLights(scene, config, out.path(), count);
  REQUIRE(records.size() == 3);
  CHECK(built == 3);
  for (uint32_t i = 0; i < 3; ++i) {
    CHECK(records[i]["light_index"] == i);
    CHECK(records[i]["verification"]["mismatches"] == 0);
    CHECK(fs::exists(lightRecordPath(out.path(), scene, config, i)));
    CHECK(fs::exists(lightStructurePath(out.path(), scene, config, i)));
  }

  // A resumed run rebuilds only the light whose structure went missing.
  fs::remove(lightStructurePath(out.path(), scene, config, 1));
  built = 0;
  const auto resumed = buildManyLights(scene, config, out.path(), count);
  CHECK(built == 1);
  CHECK(resumed[0] == records[0]);

  // Another placement in the same folder is refused.
  config.placement.seed = 2;
  CHECK_THROWS_WITH(
      buildManyLights(withSpotLights(openScene(kScene), config.placement), config, out.path()),
      Catch::Contains("another placement"));

  const BuildSummary summary = summariseBuilds(records, 4);
  CHECK(summary.perLight.rows.size() == 3);
  CHECK(summary.distribution.rows.front().front() == "size (MiB)");
  uint32_t binned = 0;
  for (const auto& row : summary.histograms.rows) binned += std::stoul(row.back());
  CHECK(binned == 2 * 3);
}

TEST_CASE("distribution and histogram of a few values", "[lights]") {
  const Distribution d = distributionOf({4, 1, 3, 2});
  CHECK(d.min == 1);
  CHECK(d.median == 2.5);
  CHECK(d.mean == 2.5);
  CHECK(d.max == 4);
  CHECK(d.total == 10);
  const std::vector<double> values{1, 2, 3, 4};
  const Histogram h = histogramOf(values, 2);
  CHECK(h.counts == std::vector<uint32_t>{2, 2});
  CHECK(histogramOf(std::vector<double>{5, 5}, 3).counts == std::vector<uint32_t>{2});
}

TEST_CASE("views and histograms too large for the memory are refused before any build",
          "[lights][memory]") {
  constexpr uint64_t kGiB = 1ull << 30;
  ManyLightsCommandOptions options;
  CHECK_NOTHROW(checkManyLightsFits(options, kGiB));  // the defaults: 1920×1080, 12 bins
  // 29 bytes per pixel (position, normal, coverage, visibility) of 10⁶ × 1080 pixels.
  options.view.width = 1'000'000;
  CHECK(viewEvaluationBytes(options.view) >= 29ull * 1'000'000 * 1080);
  CHECK_THROWS_WITH(checkManyLightsFits(options, 16 * kGiB),
                    Catch::Contains("a 1000000×1080 view needs at least 29.") &&
                        Catch::Contains("GiB but only 16.00 GiB is available"));
  options.noView = true;
  CHECK_NOTHROW(checkManyLightsFits(options, 16 * kGiB));

  options.bins = 4'000'000'000u;
  CHECK(summaryBytes(options.bins) > 8ull * options.bins);
  CHECK_THROWS_WITH(checkManyLightsFits(options, 16 * kGiB),
                    Catch::Contains("--bins 4000000000 needs at least"));
  CHECK_NOTHROW(checkManyLightsFits(options, 0));  // memory unknown: nothing refused
}

TEST_CASE("the many-lights command refuses a histogram too large before placing any light",
          "[lights][memory]") {
  ScratchDir out;
  CLI::App app;
  addManyLightsCommand(app);
  const std::vector<std::string> args = {
      "many-lights", "--scene",    kScene,  "--lights",         "1", "--resolution", "64",
      "--bins",      "4000000000", "--out", out.path().string()};
  std::vector<const char*> argv = {"shadowbench"};
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  CHECK_THROWS_WITH(app.parse(static_cast<int>(argv.size()), argv.data()),
                    Catch::Contains("--bins 4000000000 needs at least"));
  CHECK(fs::is_empty(out.path()));  // nothing built
}
