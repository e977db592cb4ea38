#include "harness/cell.h"

#include <chrono>
#include <ctime>

#include <fmt/format.h>

#include "harness/lookup_timing.h"
#include "harness/machine.h"
#include "harness/progress.h"
#include "harness/query_sets.h"
#include "harness/source_commit.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"

namespace sb {

Light sceneLight(const Scene& scene, uint32_t index) {
  if (index >= scene.lights.size())
    throw std::invalid_argument(fmt::format("scene '{}' has {} light(s); light {} does not exist",
                                            scene.name, scene.lights.size(), index));
  return Light::fit(scene.lights[index], scene);
}

namespace {

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// The identity of a cell whose parameters are already resolved.
Record identityOf(const CellSpec& cell, const Scene& scene, const SchemeInfo& scheme,
                  const ParamValues& values) {
  Record record;
  record.scene = {scene.name, cell.sceneSpec, scene.triangleCount(), scene.hash()};
  record.lightIndex = cell.lightIndex;
  record.light = sceneLight(scene, cell.lightIndex).describe();
  record.mode = toString(cell.mode);
  record.scheme.name = scheme.name;
  record.scheme.kind = toString(scheme.kind);
  for (const auto& [name, value] : values.text()) record.scheme.params[name] = value;
  record.scheme.paper = scheme.paper;
  record.resolution = cell.resolution;
  record.tileSize = cell.tileSize ? cell.tileSize : defaultTileSize(cell.resolution);
  return record;
}

}  // namespace

Record cellIdentity(const CellSpec& cell, const Scene& scene) {
  const SchemeInfo& scheme = findScheme(cell.scheme);
  return identityOf(cell, scene, scheme, scheme.resolve(cell.params));
}

Record runCell(const CellSpec& cell, const Scene& scene, const CellOptions& options) {
  const SchemeInfo& scheme = findScheme(cell.scheme);
  // Resolved once, here where the build starts; the scheme receives them typed.
  const ParamValues params = scheme.resolve(cell.params);
  Record record = identityOf(cell, scene, scheme, params);
  const Light light = sceneLight(scene, cell.lightIndex);
  const BuildShape shape{record.tileSize};
  // Refuse before the depth source spends time on the scene (buildStructure checks again).
  checkBuildFits(scheme, mapFor(scheme, cell.mode, cell.resolution), params, shape);
  const DepthSource source(scene, light, cell.mode, cell.resolution);

  const std::string label = fmt::format("{} {} {} {}", scheme.name, scene.name, toString(cell.mode),
                                        resolutionLabel(cell.resolution));
  Progress building("build " + label, uint64_t(cell.resolution) * cell.resolution, "texels");
  BuildOutcome built =
      buildStructure(source, scheme, params, shape, [&](uint64_t done) { building.set(done); });
  building.finish();

  const SizeBreakdown sizes = built.decoder->size();
  for (const auto& [component, bytes] : sizes) record.sizeComponents[component] = bytes;
  record.sizeBytes = totalBytes(sizes);
  RecordTimes times{built.totalSeconds, built.depthSeconds, {}};
  for (const auto& [phase, seconds] : built.phaseSeconds) times.phases[phase] = seconds;
  record.time = std::move(times);
  record.depthResolution = built.map.depthResolution;
  record.depth =
      RecordDepth{built.texels, double(built.texels) / std::max(built.depthSeconds, 1e-9) * 1e-6,
                  built.closedFallbacks, std::string(toString(source.method()))};
  record.counters = {built.counters.begin(), built.counters.end()};
  record.memory = RecordMemory{built.peakRssBytes, built.baselineRssBytes};

  if (options.saveStructureTo)
    saveStructure(*options.saveStructureTo,
                  {scheme.name, built.params.text(), built.map, scene.hash()}, *built.decoder);

  if (options.verify) {
    const uint64_t expected = cell.resolution <= options.verifyOptions.exhaustiveUpTo
                                  ? built.texels * 7
                                  : options.verifyOptions.sampledQueries;
    Progress checking("verify " + label, expected, "queries");
    const VerifyReport report =
        verify(*built.decoder, scheme.kind, built.map, source, options.verifyOptions,
               [&](uint64_t done) { checking.set(done); });
    checking.finish();
    record.verification = RecordVerification{report.method, report.queries, report.mismatches,
                                             report.toJson().at("examples")};
  }

  if (options.benchLookups) {
    record.lookup.emplace();
    const QuerySet sets[] = {standardUniformQueries(), standardViewQueries(scene, source)};
    for (const QuerySet& set : sets)
      for (int k : options.filters) {
        const LookupTiming t = timeLookups(*built.decoder, set, k);
        record.lookup->push_back({t.querySet, t.filter, t.queries, t.nsPerQuerySingleThread,
                                  t.mqueriesPerSecondAllThreads, uint64_t(t.threads)});
      }
  }

  record.machine = machineInfo();
  record.commit = sourceCommit(SHADOWBENCH_SOURCE_DIR);
  record.created = utcNow();
  record.complete = true;
  return record;
}

}  // namespace sb
