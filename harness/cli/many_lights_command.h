// `shadowbench many-lights` (Kämpe 2015 §5.3): places the lights, builds them, summarises their
// sizes and build times and evaluates a view, writing everything under --out.
#pragma once

#include <cstdint>
#include <string>

#include "harness/many_lights/builds.h"
#include "harness/many_lights/view_evaluation.h"

namespace CLI {
class App;
}

namespace sb {

struct ManyLightsCommandOptions {
  ManyLightsConfig config;
  std::string mode = "closed", resolution = "8K", out = "results/many-lights";
  bool noView = false;
  ViewOptions view;
  uint32_t bins = 12;
};

// Refuses options whose histograms or view need more memory than `availableBytes` (0: unknown,
// nothing refused), naming the figure and the option: checked before any light is built.
void checkManyLightsFits(const ManyLightsCommandOptions& options, uint64_t availableBytes);

void addManyLightsCommand(CLI::App& app);

}  // namespace sb
