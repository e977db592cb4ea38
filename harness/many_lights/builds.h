// Many local lights (Kämpe 2015 §5.3): one structure per spot light, built through runCell,
// with a record per light so that an interrupted run resumes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/depth_source.h"
#include "harness/many_lights/placement.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace sb {

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

}  // namespace sb
