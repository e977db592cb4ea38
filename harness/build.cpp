#include "harness/build.h"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "harness/record.h"

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

// Times only what happens inside the scheme's calls, credited to the phase the scheme named
// last ("encode" until it names one).
class TimedBuildContext final : public BuildContext {
 public:
  void phase(std::string_view name) override {
    credit();
    current_ = std::string(name);
  }
  void count(std::string_view name, uint64_t value) override {
    counters[std::string(name)] += value;
  }

  void enter() { since_ = Clock::now(); }
  void leave() { credit(); }

  std::vector<std::pair<std::string, double>> phases;
  std::map<std::string, uint64_t> counters;

 private:
  void credit() {
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - since_).count();
    since_ = now;
    for (auto& [name, total] : phases)
      if (name == current_) {
        total += seconds;
        return;
      }
    phases.emplace_back(current_, seconds);
  }

  std::string current_ = "encode";
  Clock::time_point since_ = Clock::now();
};

}  // namespace

MapInfo mapFor(const SchemeInfo& scheme, DepthMode mode, uint32_t resolution) {
  return {resolution, scheme.kind == SchemeKind::Voxel ? resolution : 0u, mode};
}

void checkBuildFits(const SchemeInfo& scheme, const MapInfo& map, const Params& params) {
  const uint64_t needed = scheme.buildBytes ? scheme.buildBytes(map, params) : 0;
  const uint64_t available = availableMemoryBytes();
  if (needed > available)
    throw std::runtime_error(fmt::format(
        "{} at {}² needs at least {:.2f} GiB to build but only {:.2f} GiB is available; choose a "
        "smaller resolution",
        scheme.name, map.resolution, needed / double(1ull << 30), available / double(1ull << 30)));
}

BuildOutcome buildStructure(const DepthSource& source, const SchemeInfo& scheme,
                            const Params& given, uint32_t tileSize,
                            const std::function<void(uint64_t)>& progress) {
  BuildOutcome outcome;
  outcome.params = scheme.resolve(given);
  outcome.map = mapFor(scheme, source.mode(), source.resolution());
  outcome.tileSize = tileSize;
  checkBuildFits(scheme, outcome.map, outcome.params);

  resetPeakRss();
  outcome.baselineRssBytes = currentRssBytes();
  const uint64_t fallbacksBefore = source.closedFallbacks();
  const auto start = Clock::now();
  TimedBuildContext context;
  std::unique_ptr<Encoder> encoder = scheme.makeEncoder(outcome.map, outcome.params);
  const StreamStats stream = streamDualDepth(
      source, tileSize,
      [&](const DualDepthTile& tile) {
        context.enter();
        encoder->consume(tile, context);
        context.leave();
      },
      progress);
  context.enter();
  outcome.decoder = encoder->finish(context);
  context.leave();
  encoder.reset();
  outcome.totalSeconds = std::chrono::duration<double>(Clock::now() - start).count();

  outcome.texels = outcome.map.texelCount();
  outcome.depthSeconds = stream.traceThreadSeconds / tbb::this_task_arena::max_concurrency();
  outcome.phaseSeconds = std::move(context.phases);
  outcome.counters = std::move(context.counters);
  outcome.closedFallbacks = source.closedFallbacks() - fallbacksBefore;
  outcome.peakRssBytes = peakRssBytes();
  return outcome;
}

}  // namespace sb
