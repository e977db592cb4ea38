// Many local lights (Kämpe 2015 §5.3): the shadows of every light evaluated for camera views
// with the tiled light lists and k×k PCF, timed beside the paper's 3.2 ms.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/many_lights/builds.h"
#include "harness/many_lights/light_lists.h"
#include "harness/table.h"

namespace sb {

// Per pixel, the sum over the lights of its tile's list of the k×k PCF visibility of the light
// (0 where the light does not reach), looked up in one batch per tile and light. Returns the
// number of lookups.
uint64_t evaluateShadows(const ViewSurface& view, std::span<const ShadowedLight> lights,
                         const TileLightLists& lists, int k, bool parallel,
                         std::vector<float>& visibility);

// The views of the evaluation: frames along the camera orbit, each timed `repeats` times.
struct ViewOptions {
  uint32_t width = 1920, height = 1080;  // Kämpe §5.3
  uint32_t tilePixels = 8, frames = 1, repeats = 3;
  int filter = 9;  // k of the k×k PCF
};

// The view evaluation of Kämpe §5.3 for each frame of the orbit, loading the structures that
// buildManyLights saved under `out`: one table row per frame and the paper's.
Table evaluateViews(const Scene& litScene, const std::vector<nlohmann::json>& records,
                    const ManyLightsConfig& config, const ViewOptions& view,
                    const std::filesystem::path& out);

// What the evaluation of one view holds at least besides the structures: per pixel its
// sample (position, normal, coverage) and visibility, per tile a light list; checked before
// any build, since a view too large would otherwise fail only after every light is built.
uint64_t viewEvaluationBytes(const ViewOptions& view);

}  // namespace sb
