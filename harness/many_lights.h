// Many local lights (Kämpe 2015 §4, §5.3, Fig. 3): a scene lit by hundreds of bounded spot
// lights, one precomputed structure per light, the distribution of their sizes and build times,
// and the shadows of every light evaluated for a camera view with Tiled Shading light lists
// (Olsson & Assarsson 2011) and 9×9 PCF.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "harness/depth_source.h"
#include "harness/light.h"
#include "harness/query_sets.h"
#include "harness/table.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace CLI {
class App;
}

namespace sb {

// Where the spot lights go. Positions follow a seeded R2 low-discrepancy sequence over the
// scene's ground plan, each light a random height above the geometry under it; it points down,
// tilted by at most maxTiltDegrees ≤ minFovDegrees / 2 so that the point straight below it is
// always inside its cone.
struct SpotLightPlacement {
  uint32_t count = 165;  // Kämpe §5.3
  uint64_t seed = 1;
  float minFovDegrees = 60, maxFovDegrees = 90;
  float maxTiltDegrees = 30;
};

// `count` spot lights with the logarithmic depth distribution (Kämpe eq. 1); deterministic.
std::vector<LightSpec> placeSpotLights(const Scene& scene, const SpotLightPlacement& placement);

// One build per light: the cells of the experiment.
struct ManyLightsConfig {
  std::string sceneSpec = "city";
  SpotLightPlacement placement;
  std::string scheme = "cpvs-fast";
  Params params;
  DepthMode mode = DepthMode::Closed;
  uint32_t resolution = 8192;  // Kämpe §5.3: 8192³ per light
  uint32_t tileSize = 0;       // 0: defaultTileSize
  bool verify = false;
  uint64_t sampledQueries = 1'000'000;  // per light, when verifying
  bool saveStructures = true;           // needed by the view evaluation
};

// `scene` with its lights replaced by the placement's spot lights.
Scene withSpotLights(Scene scene, const SpotLightPlacement& placement);

// The record and structure files of light `index` under `out`.
std::filesystem::path lightRecordPath(const std::filesystem::path& out, const Scene& litScene,
                                      const ManyLightsConfig& config, uint32_t index);
std::filesystem::path lightStructurePath(const std::filesystem::path& out, const Scene& litScene,
                                         const ManyLightsConfig& config, uint32_t index);

// Builds every light of `litScene` (withSpotLights) through runCell and writes one record per
// light atomically. A light whose complete record (and, when saving, structure) is already
// under `out` is not rebuilt; a record of another light at the same index is an error, since
// the folder then holds another placement. `done(index, record, built)` follows each light.
std::vector<nlohmann::json> buildManyLights(
    const Scene& litScene, const ManyLightsConfig& config, const std::filesystem::path& out,
    const std::function<void(uint32_t index, const nlohmann::json& record, bool built)>& done = {});

// The distribution of Kämpe Fig. 3 over the records: size and build time, with the paper's
// figures beside ours, per-light rows and histograms.
struct Distribution {
  double min = 0, median = 0, mean = 0, max = 0, total = 0;
};
Distribution distributionOf(std::vector<double> values);

struct Histogram {
  double lo = 0, binWidth = 0;
  std::vector<uint32_t> counts;
};
Histogram histogramOf(std::span<const double> values, uint32_t bins);
// One line per bin: its range, a bar and its count.
std::string histogramText(const Histogram& histogram, int significantDigits = 3);

struct BuildSummary {
  Table distribution;  // min, median, mean, max, total of ours and the paper's
  Table perLight;      // one row per light
  Table histograms;    // one row per bin of size and of build time
  std::string histogramText;
};
BuildSummary summariseBuilds(const std::vector<nlohmann::json>& records, uint32_t bins = 12);

// A spot light with its structure, as the shadow evaluation sees it.
struct ShadowedLight {
  ShadowedLight(Light light, const Decoder& decoder, uint32_t resolution);
  Light light;
  const Decoder* decoder;
  uint32_t resolution;
  double tanHalfFov, near, far;  // the fitted frustum, in world units
};

// The light-space query of a view sample for a k×k PCF lookup: the sample moved along its normal
// by half the filter width at its distance from the light (Kämpe §4, "Perspective Lights"), so
// the bias is minimal everywhere in a wide frustum. nullopt when it lies outside the light's
// cone or depth range: the light does not reach it.
std::optional<Query> lightSpaceQuery(const ShadowedLight& light, const glm::dvec3& position,
                                     const glm::dvec3& normal, int k);

// Tiled Shading: per screen tile of tilePixels² pixels, the lights whose frustum (widened by
// the largest normal offset) may contain a lookup of the tile, in increasing light order.
struct TileLightLists {
  uint32_t tilePixels = 8, tilesX = 0, tilesY = 0;
  std::vector<std::vector<uint32_t>> lights;  // per tile, row-major
};
TileLightLists buildLightLists(const ViewSurface& view, std::span<const ShadowedLight> lights,
                               uint32_t tilePixels, int k, bool parallel);
// Every light in every tile: the brute-force reference of the light lists.
TileLightLists allLightsEverywhere(const ViewSurface& view, size_t lightCount, uint32_t tilePixels);

// Per pixel, the sum over the lights of its tile's list of the k×k PCF visibility of the light
// (0 where the light does not reach), looked up in one batch per tile and light. Returns the
// number of lookups.
uint64_t evaluateShadows(const ViewSurface& view, std::span<const ShadowedLight> lights,
                         const TileLightLists& lists, int k, bool parallel,
                         std::vector<float>& visibility);

// `shadowbench many-lights`: places the lights, builds them, summarises (Kämpe Fig. 3) and
// evaluates a view, writing everything under --out.
void addManyLightsCommand(CLI::App& app);

}  // namespace sb
