#include "harness/many_lights/builds.h"

#include <stdexcept>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cell_key.h"
#include "harness/record.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

CellSpec cellOf(const ManyLightsConfig& config, uint32_t index) {
  return {config.sceneSpec,  index,          config.mode, config.scheme, config.params,
          config.resolution, config.tileSize};
}

std::string cellName(const Scene& litScene, const ManyLightsConfig& config, uint32_t index) {
  return cellKey(cellIdentity(cellOf(config, index), litScene));
}

}  // namespace

fs::path lightRecordPath(const fs::path& out, const Scene& litScene, const ManyLightsConfig& config,
                         uint32_t index) {
  return out / (cellName(litScene, config, index) + ".json");
}

fs::path lightStructurePath(const fs::path& out, const Scene& litScene,
                            const ManyLightsConfig& config, uint32_t index) {
  return out / "structures" / (cellName(litScene, config, index) + ".sb");
}

std::vector<nlohmann::json> buildManyLights(
    const Scene& litScene, const ManyLightsConfig& config, const fs::path& out,
    const std::function<void(uint32_t, const nlohmann::json&, bool)>& done) {
  CellOptions options;
  options.verify = config.verify;
  // One light of hundreds: sampled at every resolution, never exhaustive.
  options.verifyOptions.exhaustiveUpTo = 0;
  options.verifyOptions.sampledQueries = config.sampledQueries;
  options.benchLookups = false;
  const nlohmann::json placement = {
      {"lights", litScene.lights.size()},
      {"seed", config.placement.seed},
      {"fov_degrees", {config.placement.minFovDegrees, config.placement.maxFovDegrees}},
      {"max_tilt_degrees", config.placement.maxTiltDegrees}};

  std::vector<nlohmann::json> records;
  for (uint32_t index = 0; index < litScene.lights.size(); ++index) {
    const fs::path recordPath = lightRecordPath(out, litScene, config, index);
    const fs::path structurePath = lightStructurePath(out, litScene, config, index);
    if (const auto existing = readRecord(recordPath)) {
      if (existing->value("light", nlohmann::json()) != sceneLight(litScene, index).describe())
        throw std::runtime_error(
            fmt::format("'{}' holds a record of another light {}: the folder belongs to another "
                        "placement; choose another --out",
                        recordPath.string(), index));
      if (!config.saveStructures || fs::exists(structurePath)) {
        records.push_back(*existing);
        if (done) done(index, records.back(), false);
        continue;
      }
    }
    options.saveStructureTo = std::nullopt;
    if (config.saveStructures) {
      fs::create_directories(structurePath.parent_path());
      options.saveStructureTo = structurePath;
    }
    nlohmann::json record = runCell(cellOf(config, index), litScene, options);
    record["many_lights"] = placement;
    // The record comes last: a structure without its record is rebuilt on resuming.
    writeJsonAtomically(recordPath, record);
    records.push_back(std::move(record));
    if (done) done(index, records.back(), true);
  }
  return records;
}

}  // namespace sb
