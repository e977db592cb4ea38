// One build: the dual depth map streamed from a DepthSource into a scheme's encoder, with the
// harness timing each phase the scheme names and recording peak memory (DESIGN §5, §6).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "harness/depth_source.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct BuildOutcome {
  std::unique_ptr<Decoder> decoder;
  MapInfo map;
  ParamValues params;  // every parameter with its value
  BuildShape shape;
  uint64_t texels = 0;
  double depthSeconds = 0;  // tracing time, thread-seconds divided by the threads available
  double totalSeconds = 0;  // wall time of the whole build
  std::vector<std::pair<std::string, double>> phaseSeconds;  // encoder phases, in order
  std::map<std::string, uint64_t> counters;
  uint64_t closedFallbacks = 0;
  uint64_t baselineRssBytes = 0, peakRssBytes = 0;
  uint64_t estimatedBytes = 0;  // the scheme's declared build memory, checked before the build
  // A build in parts: the declared memory and the peak of its part encoding (the largest part's
  // depth pass, every encoder of it) and of its merge, apart.
  uint64_t partsEstimatedBytes = 0, partsPeakRssBytes = 0;
  uint64_t mergeEstimatedBytes = 0, mergePeakRssBytes = 0;
  std::vector<std::string> depthSharedWith;    // the other schemes its depth pass fed
  std::vector<std::string> encoderSharedWith;  // those whose part payloads its encoder wrote
};

// The map a scheme builds at a resolution and mode (Rz = R for voxel schemes).
MapInfo mapFor(const SchemeInfo& scheme, DepthMode mode, uint32_t resolution);

// The scheme's declared build memory (SchemeInfo::buildBytes) for this shape. Throws
// std::runtime_error naming the bytes needed and available when it does not fit in what the
// machine has free now.
uint64_t checkBuildFits(const SchemeInfo& scheme, const MapInfo& map, const ParamValues& params,
                        const BuildShape& shape);

// A scheme with its parameters, resolved by the caller (SchemeInfo::resolve) once per build.
struct SchemeBuild {
  const SchemeInfo* scheme = nullptr;
  ParamValues params;
};

// Builds every scheme of `builds` whole from one depth pass: each tile is traced once and handed
// to every encoder in turn (issue 12). The outcomes share the depth time, the texels and the peak
// memory; their phases and counters are each scheme's own.
std::vector<BuildOutcome> buildStructures(
    const DepthSource& source, std::span<const SchemeBuild> builds, const BuildShape& shape,
    const std::function<void(uint64_t texelsDone)>& progress = {});
BuildOutcome buildStructure(const DepthSource& source, const SchemeInfo& scheme,
                            const ParamValues& params, const BuildShape& shape,
                            const std::function<void(uint64_t texelsDone)>& progress = {});

// Times the scheme's calls inside a build, credited to the phase the scheme named last: time
// before the first name goes to the first phase, or to `unnamed` ("encode"; "merge" for a
// merger) for a scheme that names none, so that a record lists only phases that ran.
class TimedBuildContext final : public BuildContext {
 public:
  explicit TimedBuildContext(std::string unnamed = "encode") : unnamedPhase_(std::move(unnamed)) {}
  void phase(std::string_view name) override;
  void count(std::string_view name, uint64_t value) override;
  void reserve(uint64_t bytes, std::string_view what) override;

  void enter();  // the scheme is called now
  void leave();  // and has returned
  // After the scheme's last call: a scheme that named no phase spent it in the unnamed phase.
  void close();

  std::vector<std::pair<std::string, double>> phases;
  std::map<std::string, uint64_t> counters;
  // The scheme's reserve() calls as declared memory above `baselineRss`: the most the process
  // held plus what it reserved at one call, less the baseline (0 without a call).
  uint64_t reservedAbove(uint64_t baselineRss) const {
    return reservedRss_ > baselineRss ? reservedRss_ - baselineRss : 0;
  }

 private:
  void credit();
  void add(const std::string& phase, double seconds);

  std::string unnamedPhase_;
  uint64_t reservedRss_ = 0;
  std::string current_;  // empty until the scheme names a phase
  double unnamed_ = 0;   // time before the scheme named one
  std::chrono::steady_clock::time_point since_ = std::chrono::steady_clock::now();
};

// Hands `tile` to every encoder of a shared depth pass side by side: the schemes' encoders are
// independent, so they run in parallel, each still seeing the tiles in order and one at a time.
// Each scheme's phases are then wall time while the others run beside it.
template <class AnyEncoder>
void consumeSideBySide(const DualDepthTile& tile,
                       std::span<const std::unique_ptr<AnyEncoder>> encoders,
                       std::span<TimedBuildContext> contexts) {
  tbb::parallel_for(size_t(0), encoders.size(), [&](size_t e) {
    contexts[e].enter();
    encoders[e]->consume(tile, contexts[e]);
    contexts[e].leave();
  });
}

}  // namespace sb
