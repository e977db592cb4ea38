// One build: the dual depth map streamed from a DepthSource into a scheme's encoder, with the
// harness timing each phase the scheme names and recording peak memory (DESIGN §5, §6).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

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
};

// The map a scheme builds at a resolution and mode (Rz = R for voxel schemes).
MapInfo mapFor(const SchemeInfo& scheme, DepthMode mode, uint32_t resolution);

// Throws std::runtime_error naming the bytes needed and available when the scheme's declared
// build memory does not fit in what the machine has free now.
void checkBuildFits(const SchemeInfo& scheme, const MapInfo& map, const ParamValues& params,
                    const BuildShape& shape);

// `params` come resolved from the caller (SchemeInfo::resolve), once per build.
BuildOutcome buildStructure(const DepthSource& source, const SchemeInfo& scheme,
                            const ParamValues& params, const BuildShape& shape,
                            const std::function<void(uint64_t texelsDone)>& progress = {});

}  // namespace sb
