#include "harness/parts_build.h"

#include <algorithm>
#include <bit>
#include <chrono>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "harness/machine.h"

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Whether `path` holds this part already. A file that cannot be read as a part file is damaged
// (a killed build never leaves one half-written: part files are written atomically) and is encoded
// again; another build's file is an error, not something to overwrite.
bool hasValidPart(const std::filesystem::path& path, const PartIdentity& expected) {
  if (!std::filesystem::exists(path)) return false;
  try {
    loadPartFile(path, expected);
    return true;
  } catch (const FormatError& damaged) {
    fmt::print(stderr, "shadowbench: {}; encoding that part again\n", damaged.what());
    return false;
  }
}

PartIdentity identityOfPart(const PartsTarget& target, uint64_t index) {
  PartIdentity identity = target.identity;
  identity.part = index;
  return identity;
}

// The build whose part encoder writes build b's payload: the first that writes the same
// (SchemeInfo::partPayload), b itself when none before it does.
size_t encoderOwner(std::span<const SchemeBuild> builds, size_t b) {
  const std::string& payload = builds[b].scheme->partPayload;
  if (payload.empty()) return b;
  return size_t(
      std::find_if(builds.begin(), builds.end(),
                   [&](const SchemeBuild& other) { return other.scheme->partPayload == payload; }) -
      builds.begin());
}

}  // namespace

uint64_t partPassBytes(std::span<const SchemeBuild> builds, DepthMode mode, uint32_t resolution,
                       const BuildShape& shape) {
  BuildShape part = shape;
  part.step = BuildShape::Step::EncodePart;
  uint64_t bytes = 0;
  for (size_t b = 0; b < builds.size(); ++b)
    if (encoderOwner(builds, b) == b && builds[b].scheme->buildBytes)
      bytes += builds[b].scheme->buildBytes(mapFor(*builds[b].scheme, mode, resolution),
                                            builds[b].params, part);
  return bytes;
}

void checkPartShape(const SchemeInfo& scheme, const MapInfo& map, const BuildShape& shape) {
  if (!std::has_single_bit(shape.partSize) || shape.partSize < shape.tileSize ||
      shape.partSize >= map.resolution)
    throw std::invalid_argument(fmt::format(
        "part size {} must be a power of two from the tile size {} to below the resolution {}",
        shape.partSize, shape.tileSize, map.resolution));
  if (!scheme.buildsInParts())
    throw std::invalid_argument(fmt::format(
        "scheme '{}' does not build in parts; build it whole (no --part-size)", scheme.name));
}

PartsEncoded encodeParts(const DepthSource& source, std::span<const PartsTarget> targets,
                         const BuildShape& shape, std::optional<uint64_t> only,
                         const std::function<void(uint64_t, uint64_t)>& progress) {
  std::vector<MapInfo> maps;
  for (const PartsTarget& target : targets) {
    maps.push_back(mapFor(*target.build.scheme, source.mode(), source.resolution()));
    checkPartShape(*target.build.scheme, maps.back(), shape);
    checkBuildFits(*target.build.scheme, maps.back(), target.build.params,
                   {shape.tileSize, shape.partSize, BuildShape::Step::EncodePart});
    std::filesystem::create_directories(target.folder);
  }
  const uint64_t count = MapPart::countFor({source.resolution(), 0, source.mode()}, shape.partSize);
  if (only && *only >= count)
    throw std::invalid_argument(fmt::format(
        "part {} does not exist: the map has {} parts (0 to {})", *only, count, count - 1));

  // Which targets lack which part, decided for every part before the first is encoded: another
  // build's file anywhere stops the build before it costs anything.
  std::vector<std::vector<size_t>> lacking(count);
  uint64_t toDo = 0;
  for (uint64_t index = only.value_or(0); index < (only ? *only + 1 : count); ++index) {
    for (size_t t = 0; t < targets.size(); ++t)
      if (!hasValidPart(partFilePath(targets[t].folder, index), identityOfPart(targets[t], index)))
        lacking[index].push_back(t);
    toDo += !lacking[index].empty();
  }

  PartsEncoded result;
  if (progress) progress(0, toDo);
  for (uint64_t index = only.value_or(0); index < (only ? *only + 1 : count); ++index) {
    if (lacking[index].empty()) {
      ++result.kept;
      continue;
    }
    const MapPart part = MapPart::of(index, shape.partSize);
    const std::vector<size_t>& lack = lacking[index];
    resetPeakRss();
    const uint64_t baselineRss = currentRssBytes();
    const uint64_t fallbacksBefore = source.closedFallbacks();
    const auto start = Clock::now();
    // One encoder per distinct part payload (SchemeInfo::partPayload); encoderOf[l] is the one
    // whose payload the l-th lacking target's part file takes.
    std::vector<SchemeBuild> builds;
    for (size_t t : lack) builds.push_back(targets[t].build);
    std::vector<std::unique_ptr<PartEncoder>> encoders;
    std::vector<size_t> encoderOf(lack.size());
    for (size_t l = 0; l < lack.size(); ++l) {
      const size_t owner = encoderOwner(builds, l);
      if (owner < l) {
        encoderOf[l] = encoderOf[owner];
        continue;
      }
      encoderOf[l] = encoders.size();
      encoders.push_back(
          builds[l].scheme->makePartEncoder(maps[lack[l]], part, builds[l].params, shape));
    }
    const uint64_t passBytes = partPassBytes(builds, source.mode(), source.resolution(), shape);
    std::vector<TimedBuildContext> contexts(encoders.size());
    const StreamStats stream =
        streamDualDepth(source, shape.tileSize, part, [&](const DualDepthTile& tile) {
          consumeSideBySide<PartEncoder>(tile, encoders, contexts);
        });
    std::vector<ByteWriter> payloads(encoders.size());
    for (size_t e = 0; e < encoders.size(); ++e) {
      contexts[e].enter();
      encoders[e]->finish(payloads[e], contexts[e]);
      contexts[e].leave();
      contexts[e].close();
      encoders[e].reset();
    }
    for (size_t l = 0; l < lack.size(); ++l) {
      const PartsTarget& target = targets[lack[l]];
      const size_t e = encoderOf[l];
      PartCosts costs;
      costs.depthSeconds = stream.traceThreadSeconds / tbb::this_task_arena::max_concurrency();
      costs.phases = contexts[e].phases;
      costs.counters = contexts[e].counters;
      costs.closedFallbacks = source.closedFallbacks() - fallbacksBefore;
      for (size_t other = 0; other < lack.size(); ++other) {
        if (other == l) continue;
        const std::string& name = targets[lack[other]].build.scheme->name;
        costs.depthSharedWith.push_back(name);
        if (encoderOf[other] == e) costs.encoderSharedWith.push_back(name);
      }
      costs.wallSeconds = secondsSince(start);
      costs.peakRssBytes = peakRssBytes();
      costs.estimatedBytes = std::max(passBytes, contexts[e].reservedAbove(baselineRss));
      savePartFile(partFilePath(target.folder, index), identityOfPart(target, index), costs,
                   payloads[e].bytes());
    }
    ++result.encoded;
    if (progress) progress(result.encoded, toDo);
  }
  return result;
}

BuildOutcome mergeParts(
    const PartsTarget& target, DepthMode mode, uint32_t resolution, const BuildShape& shape,
    const std::function<void(uint64_t pass, uint64_t done, uint64_t total)>& progress) {
  const SchemeInfo& scheme = *target.build.scheme;
  BuildOutcome outcome;
  outcome.map = mapFor(scheme, mode, resolution);
  outcome.params = target.build.params;
  outcome.shape = shape;
  checkPartShape(scheme, outcome.map, shape);

  const uint64_t count = MapPart::countFor(outcome.map, shape.partSize);
  uint64_t missing = 0, firstMissing = 0;
  BuildShape merge{shape.tileSize, shape.partSize, BuildShape::Step::Merge};
  for (uint64_t index = count; index-- > 0;) {
    const std::filesystem::path path = partFilePath(target.folder, index);
    if (!std::filesystem::exists(path)) {
      ++missing, firstMissing = index;
      continue;
    }
    const uint64_t bytes = partPayloadBytes(path);
    merge.partFiles.totalBytes += bytes;
    merge.partFiles.largestBytes = std::max(merge.partFiles.largestBytes, bytes);
  }
  if (missing)
    throw std::runtime_error(
        fmt::format("{} of {} part files of {} are missing in '{}', the first {} (encode them with "
                    "'shadowbench part' or 'build --part-size')",
                    missing, count, scheme.name, target.folder.string(),
                    partFilePath(target.folder, firstMissing).filename().string()));
  outcome.mergeEstimatedBytes = checkBuildFits(scheme, outcome.map, outcome.params, merge);

  resetPeakRss();
  outcome.baselineRssBytes = currentRssBytes();
  const auto start = Clock::now();
  TimedBuildContext context("merge");
  std::unique_ptr<PartMerger> merger = scheme.makePartMerger(outcome.map, outcome.params, merge);
  std::map<std::string, double> partPhases;
  std::vector<std::string> partPhaseOrder;
  double partsWall = 0;
  uint64_t partsPeak = 0;
  for (uint64_t pass = 0, index = 0;; ++index) {
    if (index == count) {
      context.enter();
      const bool again = merger->anotherPass(context);
      context.leave();
      if (!again) break;
      ++pass, index = 0;
    }
    const std::filesystem::path path = partFilePath(target.folder, index);
    const PartFile file = loadPartFile(path, identityOfPart(target, index));
    ByteReader payload(file.payload);
    try {
      context.enter();
      merger->add(MapPart::of(index, shape.partSize), payload, context);
      context.leave();
      payload.expectEnd();
    } catch (const FormatError& error) {
      throw FormatError(fmt::format("part file '{}': {}", path.string(), error.what()));
    }
    if (progress) progress(pass, index + 1, count);
    if (pass > 0) continue;
    outcome.depthSeconds += file.costs.depthSeconds;
    partsWall += file.costs.wallSeconds;
    partsPeak = std::max(partsPeak, file.costs.peakRssBytes);
    outcome.partsEstimatedBytes = std::max(outcome.partsEstimatedBytes, file.costs.estimatedBytes);
    outcome.closedFallbacks += file.costs.closedFallbacks;
    for (const auto& [name, seconds] : file.costs.phases) {
      if (!partPhases.count(name)) partPhaseOrder.push_back(name);
      partPhases[name] += seconds;
    }
    for (const auto& [name, value] : file.costs.counters) outcome.counters[name] += value;
    if (index == 0) {
      outcome.depthSharedWith = file.costs.depthSharedWith;
      outcome.encoderSharedWith = file.costs.encoderSharedWith;
    }
  }
  context.enter();
  outcome.decoder = merger->finish(context);
  context.leave();
  context.close();
  merger.reset();

  for (const std::string& name : partPhaseOrder)
    outcome.phaseSeconds.emplace_back(name, partPhases[name]);
  for (const auto& [name, seconds] : context.phases) {
    auto same = std::find_if(outcome.phaseSeconds.begin(), outcome.phaseSeconds.end(),
                             [&](const auto& phase) { return phase.first == name; });
    if (same == outcome.phaseSeconds.end())
      outcome.phaseSeconds.emplace_back(name, seconds);
    else
      same->second += seconds;
  }
  for (const auto& [name, value] : context.counters) outcome.counters[name] += value;
  outcome.texels = outcome.map.texelCount();
  outcome.totalSeconds = partsWall + secondsSince(start);
  outcome.mergePeakRssBytes = peakRssBytes();
  outcome.partsPeakRssBytes = partsPeak;
  outcome.peakRssBytes = std::max(partsPeak, outcome.mergePeakRssBytes);
  outcome.mergeEstimatedBytes =
      std::max(outcome.mergeEstimatedBytes, context.reservedAbove(outcome.baselineRssBytes));
  outcome.estimatedBytes = std::max(outcome.partsEstimatedBytes, outcome.mergeEstimatedBytes);
  return outcome;
}

}  // namespace sb
