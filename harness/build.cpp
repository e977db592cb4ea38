#include "harness/build.h"

#include <chrono>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "harness/machine.h"
#include "harness/record.h"

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

// Times only what happens inside the scheme's calls, credited to the phase the scheme named
// last. Time before the first name goes to the first phase, or to "encode" for a scheme that
// names none: a record lists only phases that ran.
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
  // After the scheme's last call: a scheme that named no phase spent its time encoding.
  void close() {
    if (current_.empty()) add("encode", unnamed_);
  }

  std::vector<std::pair<std::string, double>> phases;
  std::map<std::string, uint64_t> counters;

 private:
  void credit() {
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - since_).count();
    since_ = now;
    if (current_.empty())
      unnamed_ += seconds;
    else
      add(current_, seconds + std::exchange(unnamed_, 0.0));
  }
  void add(const std::string& phase, double seconds) {
    for (auto& [name, total] : phases)
      if (name == phase) {
        total += seconds;
        return;
      }
    phases.emplace_back(phase, seconds);
  }

  std::string current_;  // empty until the scheme names a phase
  double unnamed_ = 0;   // time before the scheme named one
  Clock::time_point since_ = Clock::now();
};

}  // namespace

MapInfo mapFor(const SchemeInfo& scheme, DepthMode mode, uint32_t resolution) {
  return {resolution, scheme.kind == SchemeKind::Voxel ? resolution : 0u, mode};
}

void checkBuildFits(const SchemeInfo& scheme, const MapInfo& map, const ParamValues& params,
                    const BuildShape& shape) {
  const uint64_t needed = scheme.buildBytes ? scheme.buildBytes(map, params, shape) : 0;
  const uint64_t available = availableMemoryBytes();
  if (needed > available)
    throw std::runtime_error(fmt::format(
        "{} at {}² needs at least {:.2f} GiB to build but only {:.2f} GiB is available; choose a "
        "smaller resolution",
        scheme.name, map.resolution, needed / double(1ull << 30), available / double(1ull << 30)));
}

BuildOutcome buildStructure(const DepthSource& source, const SchemeInfo& scheme,
                            const ParamValues& params, const BuildShape& shape,
                            const std::function<void(uint64_t)>& progress) {
  BuildOutcome outcome;
  outcome.params = params;
  outcome.map = mapFor(scheme, source.mode(), source.resolution());
  outcome.shape = shape;
  checkBuildFits(scheme, outcome.map, outcome.params, shape);

  resetPeakRss();
  outcome.baselineRssBytes = currentRssBytes();
  const uint64_t fallbacksBefore = source.closedFallbacks();
  const auto start = Clock::now();
  TimedBuildContext context;
  std::unique_ptr<Encoder> encoder = scheme.makeEncoder(outcome.map, outcome.params, shape);
  const StreamStats stream = streamDualDepth(
      source, shape.tileSize,
      [&](const DualDepthTile& tile) {
        context.enter();
        encoder->consume(tile, context);
        context.leave();
      },
      progress);
  context.enter();
  outcome.decoder = encoder->finish(context);
  context.leave();
  context.close();
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
