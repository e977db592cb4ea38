#include "harness/cell.h"

#include <chrono>
#include <ctime>

#include <fmt/format.h>

#include "harness/lookup_timing.h"
#include "harness/progress.h"
#include "harness/query_sets.h"
#include "harness/record.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"

namespace sb {

namespace {

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

Light sceneLight(const Scene& scene, uint32_t index) {
  if (index >= scene.lights.size())
    throw std::invalid_argument(fmt::format("scene '{}' has {} light(s); light {} does not exist",
                                            scene.name, scene.lights.size(), index));
  return Light::fit(scene.lights[index], scene);
}

nlohmann::json cellIdentity(const CellSpec& cell, const Scene& scene) {
  const SchemeInfo& scheme = findScheme(cell.scheme);
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : scheme.resolve(cell.params)) params[name] = value;
  return {{"format", "shadowbench-record/1"},
          {"scene",
           {{"name", scene.name},
            {"spec", cell.sceneSpec},
            {"triangles", scene.triangleCount()},
            {"hash", scene.hash()}}},
          {"light_index", cell.lightIndex},
          {"mode", toString(cell.mode)},
          {"scheme",
           {{"name", scheme.name},
            {"kind", toString(scheme.kind)},
            {"params", params},
            {"paper", scheme.paper}}},
          {"resolution", cell.resolution}};
}

nlohmann::json runCell(const CellSpec& cell, const Scene& scene, const CellOptions& options) {
  const SchemeInfo& scheme = findScheme(cell.scheme);
  nlohmann::json record = cellIdentity(cell, scene);
  const Light light = sceneLight(scene, cell.lightIndex);
  const uint32_t tileSize = cell.tileSize ? cell.tileSize : defaultTileSize(cell.resolution);
  // Refuse before the depth source spends time on the scene (buildStructure checks again).
  checkBuildFits(scheme, mapFor(scheme, cell.mode, cell.resolution), scheme.resolve(cell.params));
  const DepthSource source(scene, light, cell.mode, cell.resolution);

  const std::string label = fmt::format("{} {} {} {}", scheme.name, scene.name, toString(cell.mode),
                                        resolutionLabel(cell.resolution));
  Progress building("build " + label, uint64_t(cell.resolution) * cell.resolution, "texels");
  BuildOutcome built = buildStructure(source, scheme, cell.params, tileSize,
                                      [&](uint64_t done) { building.set(done); });
  building.finish();

  nlohmann::json components = nlohmann::json::object();
  const SizeBreakdown sizes = built.decoder->size();
  for (const auto& [component, bytes] : sizes) components[component] = bytes;
  nlohmann::json phases = nlohmann::json::object();
  for (const auto& [phase, seconds] : built.phaseSeconds) phases[phase] = seconds;
  record["light"] = light.describe();
  record["depth_resolution"] = built.map.depthResolution;
  record["tile_size"] = tileSize;
  record["size_bytes"] = {{"total", totalBytes(sizes)}, {"components", components}};
  record["time_s"] = {
      {"total", built.totalSeconds}, {"depth", built.depthSeconds}, {"phases", phases}};
  record["depth"] = {
      {"texels", built.texels},
      {"mtexels_per_s", double(built.texels) / std::max(built.depthSeconds, 1e-9) * 1e-6},
      {"closed_fallbacks", built.closedFallbacks},
      {"method", toString(source.method())}};
  record["counters"] = built.counters;
  record["memory"] = {{"peak_rss_bytes", built.peakRssBytes},
                      {"baseline_rss_bytes", built.baselineRssBytes}};

  if (options.saveStructureTo)
    saveStructure(*options.saveStructureTo, {scheme.name, built.params, built.map}, *built.decoder);

  if (options.verify) {
    const uint64_t expected = cell.resolution <= options.verifyOptions.exhaustiveUpTo
                                  ? built.texels * 7
                                  : options.verifyOptions.sampledQueries;
    Progress checking("verify " + label, expected, "queries");
    const VerifyReport report =
        verify(*built.decoder, scheme.kind, built.map, source, options.verifyOptions,
               [&](uint64_t done) { checking.set(done); });
    checking.finish();
    record["verification"] = report.toJson();
  }

  if (options.benchLookups) {
    nlohmann::json timings = nlohmann::json::array();
    const QuerySet sets[] = {uniformQueries(1 << 22, 7), viewSamples(scene, source, 1920, 1080, 2)};
    for (const QuerySet& set : sets)
      for (int k : options.filters) timings.push_back(timeLookups(*built.decoder, set, k).toJson());
    record["lookup"] = timings;
  }

  record["machine"] = machineInfo();
  record["commit"] = sourceCommit(SHADOWBENCH_SOURCE_DIR);
  record["created"] = utcNow();
  record["complete"] = true;
  return record;
}

}  // namespace sb
