#include "harness/cell.h"

#include <algorithm>
#include <chrono>
#include <ctime>

#include <fmt/format.h>

#include "harness/cell_key.h"
#include "harness/lookup_timing.h"
#include "harness/machine.h"
#include "harness/progress.h"
#include "harness/query_sets.h"
#include "harness/source_commit.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"

namespace sb {

uint32_t CellSpec::effectiveTileSize() const {
  if (tileSize) return tileSize;
  const uint32_t tile = defaultTileSize(resolution);
  return partSize ? std::min(tile, partSize) : tile;
}

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
  record.tileSize = cell.effectiveTileSize();
  record.partSize = cell.partSize;
  return record;
}

}  // namespace

Record cellIdentity(const CellSpec& cell, const Scene& scene) {
  const SchemeInfo& scheme = findScheme(cell.scheme);
  return identityOf(cell, scene, scheme, scheme.resolve(cell.params));
}

namespace {

// A cell resolved: its scheme row, typed parameters and identifying record.
struct ResolvedCell {
  const SchemeInfo* scheme;
  ParamValues params;
  Record record;
};

std::vector<ResolvedCell> resolveCells(std::span<const CellSpec> cells, const Scene& scene) {
  std::vector<ResolvedCell> resolved;
  for (const CellSpec& cell : cells) {
    const CellSpec& first = cells.front();
    if (cell.sceneSpec != first.sceneSpec || cell.lightIndex != first.lightIndex ||
        cell.mode != first.mode || cell.resolution != first.resolution ||
        cell.tileSize != first.tileSize || cell.partSize != first.partSize)
      throw std::invalid_argument(
          "cells built from one depth pass must share scene, light, mode, resolution, tile and "
          "part size");
    const SchemeInfo& scheme = findScheme(cell.scheme);
    // Resolved once, here where the build starts; the scheme receives them typed.
    ParamValues params = scheme.resolve(cell.params);
    Record record = identityOf(cell, scene, scheme, params);
    resolved.push_back({&scheme, std::move(params), std::move(record)});
  }
  return resolved;
}

std::string labelOf(const CellSpec& cell, const Scene& scene, std::string_view schemes) {
  return fmt::format("{} {} {} {}", schemes, scene.name, toString(cell.mode),
                     resolutionLabel(cell.resolution));
}

std::string schemeNames(std::span<const ResolvedCell> cells) {
  std::string names;
  for (const ResolvedCell& cell : cells) names += (names.empty() ? "" : ",") + cell.scheme->name;
  return names;
}

// Everything measured after the build: size, times, memory, the saved structure, verification
// and lookup timings.
Record finishRecord(Record record, const SchemeInfo& scheme, const BuildOutcome& built,
                    const Scene& scene, const DepthSource& source, const CellOptions& options,
                    const std::string& label) {
  const SizeBreakdown sizes = built.decoder->size();
  for (const auto& [component, bytes] : sizes) record.sizeComponents[component] = bytes;
  record.sizeBytes = totalBytes(sizes);
  RecordTimes times{
      built.totalSeconds, built.depthSeconds, {}, built.depthSharedWith, built.encoderSharedWith};
  for (const auto& [phase, seconds] : built.phaseSeconds) times.phases[phase] = seconds;
  record.time = std::move(times);
  record.depthResolution = built.map.depthResolution;
  record.depth =
      RecordDepth{built.texels, double(built.texels) / std::max(built.depthSeconds, 1e-9) * 1e-6,
                  built.closedFallbacks, std::string(toString(source.method()))};
  record.counters = {built.counters.begin(), built.counters.end()};
  record.memory.emplace();
  record.memory->peakRssBytes = built.peakRssBytes;
  record.memory->baselineRssBytes = built.baselineRssBytes;
  record.memory->estimatedBytes = built.estimatedBytes;
  if (built.shape.inParts(built.map)) {
    record.memory->parts = {built.partsEstimatedBytes, built.partsPeakRssBytes};
    record.memory->merge = {built.mergeEstimatedBytes, built.mergePeakRssBytes};
  }

  if (options.saveStructureTo)
    saveStructure(*options.saveStructureTo,
                  {scheme.name, built.params.text(), built.map, scene.hash()}, *built.decoder);

  if (options.verify) {
    const uint64_t expected = built.map.resolution <= options.verifyOptions.exhaustiveUpTo
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
                                  t.mqueriesPerSecondAllThreads, uint64_t(t.threads),
                                  t.cacheHitRate});
      }
  }

  record.machine = machineInfo();
  record.commit = sourceCommit(SHADOWBENCH_SOURCE_DIR);
  record.created = utcNow();
  record.complete = true;
  return record;
}

PartsTarget targetOf(const ResolvedCell& cell, const CellSpec& spec, const Scene& scene,
                     const CellOptions& options) {
  PartsTarget target;
  target.build = {cell.scheme, cell.params};
  target.identity.structure = {cell.scheme->name, cell.params.text(),
                               mapFor(*cell.scheme, spec.mode, spec.resolution), scene.hash()};
  target.identity.light = cell.record.light;
  target.identity.tileSize = cell.record.tileSize;
  target.identity.partSize = spec.partSize;
  target.folder = partsFolder(options.partsRoot, cell.record);
  return target;
}

// Refuses, before the depth source spends time on the scene, any cell whose build would not fit.
// Whole builds from one pass hold every encoder at once; builds in parts hold one part encoder of
// every scheme at once, then merge one scheme at a time.
void checkCellsFit(std::span<const ResolvedCell> cells, const CellSpec& spec) {
  BuildShape shape = spec.shape();
  if (shape.partSize) shape.step = BuildShape::Step::EncodePart;
  uint64_t together = 0;
  std::vector<SchemeBuild> builds;
  for (const ResolvedCell& cell : cells) {
    const MapInfo map = mapFor(*cell.scheme, spec.mode, spec.resolution);
    if (shape.partSize) {
      checkPartShape(*cell.scheme, map, shape);
      checkBuildFits(*cell.scheme, map, cell.params,
                     {shape.tileSize, shape.partSize, BuildShape::Step::Merge});
    }
    const uint64_t bytes = checkBuildFits(*cell.scheme, map, cell.params, shape);
    if (!shape.partSize) together += bytes;
    builds.push_back({cell.scheme, cell.params});
  }
  // Schemes that write one part payload share one part encoder (SchemeInfo::partPayload).
  if (shape.partSize) together = partPassBytes(builds, spec.mode, spec.resolution, shape);
  const uint64_t available = availableMemoryBytes();
  if (cells.size() > 1 && together > available)
    throw std::runtime_error(fmt::format(
        "{} together at {}² need at least {:.2f} GiB to {} from one depth pass but only {:.2f} "
        "GiB is available; build them {}one at a time",
        schemeNames(cells), spec.resolution, together / double(1ull << 30),
        shape.partSize ? "encode a part of each" : "build", available / double(1ull << 30),
        shape.partSize ? "in smaller parts or " : "in parts (--part-size) or "));
}

}  // namespace

std::filesystem::path partsFolder(const std::filesystem::path& partsRoot, const Record& identity) {
  return partsRoot / cellKey(identity);
}

PartsEncoded encodeCellParts(std::span<const CellSpec> cells, const Scene& scene,
                             const CellOptions& options, std::optional<uint64_t> only) {
  const std::vector<ResolvedCell> resolved = resolveCells(cells, scene);
  const CellSpec& spec = cells.front();
  checkCellsFit(resolved, spec);
  if (!spec.partSize) throw std::invalid_argument("cells without a part size are built whole");
  std::vector<PartsTarget> targets;
  for (size_t c = 0; c < cells.size(); ++c)
    targets.push_back(targetOf(resolved[c], cells[c], scene, options));
  const DepthSource source(scene, sceneLight(scene, spec.lightIndex), spec.mode, spec.resolution);
  std::optional<Progress> progress;
  const PartsEncoded encoded =
      encodeParts(source, targets, spec.shape(), only, [&](uint64_t done, uint64_t total) {
        if (!progress)
          progress.emplace("parts " + labelOf(spec, scene, schemeNames(resolved)), total, "parts");
        progress->set(done);
      });
  return encoded;
}

Record mergeCell(const CellSpec& cell, const Scene& scene, const CellOptions& options) {
  const std::vector<ResolvedCell> resolved = resolveCells(std::span(&cell, 1), scene);
  checkCellsFit(resolved, cell);
  const DepthSource source(scene, sceneLight(scene, cell.lightIndex), cell.mode, cell.resolution);
  const PartsTarget target = targetOf(resolved[0], cell, scene, options);
  const std::string label = labelOf(cell, scene, resolved[0].scheme->name);
  std::optional<Progress> progress;
  const BuildOutcome built = mergeParts(
      target, cell.mode, cell.resolution, cell.shape(),
      [&](uint64_t pass, uint64_t done, uint64_t total) {
        if (done == 1)
          progress.emplace(fmt::format("merge {} (pass {})", label, pass + 1), total, "parts");
        progress->set(done);
      });
  progress.reset();
  return finishRecord(resolved[0].record, *resolved[0].scheme, built, scene, source, options,
                      label);
}

void mergeCells(std::span<const CellSpec> cells, const Scene& scene, const CellOptions& options,
                const std::function<void(size_t, const Record&)>& done) {
  std::vector<std::string> failed;
  for (size_t c = 0; c < cells.size(); ++c) {
    std::optional<Record> record;
    try {
      record = mergeCell(cells[c], scene, options);
    } catch (const std::runtime_error& error) {
      failed.push_back(fmt::format("{}: {}", cells[c].scheme, error.what()));
      continue;
    }
    done(c, *record);
  }
  if (!failed.empty())
    throw std::runtime_error(fmt::format("{} of {} merges failed (the others are recorded): {}",
                                         failed.size(), cells.size(), fmt::join(failed, "; ")));
}

void runCells(std::span<const CellSpec> cells, const Scene& scene, const CellOptions& options,
              const std::function<void(size_t, const Record&)>& done) {
  const std::vector<ResolvedCell> resolved = resolveCells(cells, scene);
  const CellSpec& spec = cells.front();
  checkCellsFit(resolved, spec);
  if (spec.partSize) {
    encodeCellParts(cells, scene, options, std::nullopt);
    mergeCells(cells, scene, options, done);
    return;
  }
  const DepthSource source(scene, sceneLight(scene, spec.lightIndex), spec.mode, spec.resolution);
  std::vector<SchemeBuild> builds;
  for (const ResolvedCell& cell : resolved) builds.push_back({cell.scheme, cell.params});
  const std::string label = labelOf(spec, scene, schemeNames(resolved));
  Progress building("build " + label, uint64_t(spec.resolution) * spec.resolution, "texels");
  std::vector<BuildOutcome> built =
      buildStructures(source, builds, spec.shape(), [&](uint64_t texels) { building.set(texels); });
  building.finish();
  for (size_t c = 0; c < cells.size(); ++c) {
    done(c, finishRecord(resolved[c].record, *resolved[c].scheme, built[c], scene, source, options,
                         labelOf(spec, scene, resolved[c].scheme->name)));
    built[c].decoder.reset();  // only one finished structure is kept at a time beyond the build
  }
}

Record runCell(const CellSpec& cell, const Scene& scene, const CellOptions& options) {
  Record record;
  runCells(std::span(&cell, 1), scene, options, [&](size_t, const Record& r) { record = r; });
  return record;
}

}  // namespace sb
