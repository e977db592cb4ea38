#include "harness/build.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "harness/machine.h"
#include "harness/record.h"

namespace sb {

using Clock = std::chrono::steady_clock;

void TimedBuildContext::phase(std::string_view name) {
  credit();
  current_ = std::string(name);
}

void TimedBuildContext::count(std::string_view name, uint64_t value) {
  counters[std::string(name)] += value;
}

void TimedBuildContext::reserve(uint64_t bytes, std::string_view what) {
  const uint64_t available = availableMemoryBytes();
  if (bytes > available)
    throw std::runtime_error(
        fmt::format("{} needs {:.2f} GiB more but only {:.2f} GiB is available", what,
                    bytes / double(1ull << 30), available / double(1ull << 30)));
  reservedRss_ = std::max(reservedRss_, currentRssBytes() + bytes);
}

void TimedBuildContext::enter() {
  since_ = Clock::now();
}

void TimedBuildContext::leave() {
  credit();
}

void TimedBuildContext::close() {
  if (current_.empty()) add(unnamedPhase_, unnamed_);
}

void TimedBuildContext::credit() {
  const auto now = Clock::now();
  const double seconds = std::chrono::duration<double>(now - since_).count();
  since_ = now;
  if (current_.empty())
    unnamed_ += seconds;
  else
    add(current_, seconds + std::exchange(unnamed_, 0.0));
}

void TimedBuildContext::add(const std::string& phase, double seconds) {
  for (auto& [name, total] : phases)
    if (name == phase) {
      total += seconds;
      return;
    }
  phases.emplace_back(phase, seconds);
}

MapInfo mapFor(const SchemeInfo& scheme, DepthMode mode, uint32_t resolution) {
  return {resolution, scheme.kind == SchemeKind::Voxel ? resolution : 0u, mode};
}

uint64_t checkBuildFits(const SchemeInfo& scheme, const MapInfo& map, const ParamValues& params,
                        const BuildShape& shape) {
  const uint64_t needed = scheme.buildBytes ? scheme.buildBytes(map, params, shape) : 0;
  const uint64_t available = availableMemoryBytes();
  if (needed > available)
    throw std::runtime_error(fmt::format(
        "{} at {}² needs at least {:.2f} GiB to build but only {:.2f} GiB is available; choose a "
        "smaller resolution",
        scheme.name, map.resolution, needed / double(1ull << 30), available / double(1ull << 30)));
  return needed;
}

std::vector<BuildOutcome> buildStructures(const DepthSource& source,
                                          std::span<const SchemeBuild> builds,
                                          const BuildShape& shape,
                                          const std::function<void(uint64_t)>& progress) {
  std::vector<BuildOutcome> outcomes(builds.size());
  for (size_t b = 0; b < builds.size(); ++b) {
    outcomes[b].params = builds[b].params;
    outcomes[b].map = mapFor(*builds[b].scheme, source.mode(), source.resolution());
    outcomes[b].shape = shape;
    outcomes[b].estimatedBytes =
        checkBuildFits(*builds[b].scheme, outcomes[b].map, builds[b].params, shape);
    for (size_t other = 0; other < builds.size(); ++other)
      if (other != b) outcomes[b].depthSharedWith.push_back(builds[other].scheme->name);
  }

  resetPeakRss();
  const uint64_t baselineRss = currentRssBytes();
  const uint64_t fallbacksBefore = source.closedFallbacks();
  const auto start = Clock::now();
  std::vector<TimedBuildContext> contexts(builds.size());
  std::vector<std::unique_ptr<Encoder>> encoders;
  for (size_t b = 0; b < builds.size(); ++b)
    encoders.push_back(builds[b].scheme->makeEncoder(outcomes[b].map, builds[b].params, shape));
  const StreamStats stream = streamDualDepth(
      source, shape.tileSize,
      [&](const DualDepthTile& tile) { consumeSideBySide<Encoder>(tile, encoders, contexts); },
      progress);
  for (size_t b = 0; b < builds.size(); ++b) {
    contexts[b].enter();
    outcomes[b].decoder = encoders[b]->finish(contexts[b]);
    contexts[b].leave();
    contexts[b].close();
    encoders[b].reset();
  }
  const double totalSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  for (size_t b = 0; b < builds.size(); ++b) {
    BuildOutcome& outcome = outcomes[b];
    outcome.totalSeconds = totalSeconds;
    outcome.texels = outcome.map.texelCount();
    outcome.depthSeconds = stream.traceThreadSeconds / tbb::this_task_arena::max_concurrency();
    outcome.phaseSeconds = std::move(contexts[b].phases);
    outcome.counters = std::move(contexts[b].counters);
    outcome.closedFallbacks = source.closedFallbacks() - fallbacksBefore;
    outcome.baselineRssBytes = baselineRss;
    outcome.peakRssBytes = peakRssBytes();
    outcome.estimatedBytes =
        std::max(outcome.estimatedBytes, contexts[b].reservedAbove(baselineRss));
  }
  return outcomes;
}

BuildOutcome buildStructure(const DepthSource& source, const SchemeInfo& scheme,
                            const ParamValues& params, const BuildShape& shape,
                            const std::function<void(uint64_t)>& progress) {
  const SchemeBuild build{&scheme, params};
  return std::move(buildStructures(source, std::span(&build, 1), shape, progress).front());
}

}  // namespace sb
