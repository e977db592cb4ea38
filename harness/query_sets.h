// Query sets for lookup benchmarks: uniform random light-space points, and view samples —
// what a renderer actually asks — from a camera path over the scene.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "harness/depth_source.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct QuerySet {
  std::string name;
  std::vector<Query> queries;
};

QuerySet uniformQueries(uint64_t count, uint64_t seed);

// The visible surface of one camera view (a G-buffer): per pixel the world-space position and
// the normal facing the camera, where a primary ray hit.
struct ViewSurface {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> position, normal;
  std::vector<uint8_t> covered;
  size_t pixel(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
};

// Frame `frame` of `frames` of a camera circling the scene at 60% of its radius above the
// centre, looking at it, ray cast with Embree through `source` (any light's depth source).
ViewSurface captureView(const Scene& scene, const DepthSource& source, uint32_t width,
                        uint32_t height, uint32_t frame, uint32_t frames);

// The covered pixels of captureView's `frames` frames; each hit is moved a little along its normal
// (towards the camera side) and turned into a light-space query. Misses and points outside the
// light's map are dropped.
QuerySet viewSamples(const Scene& scene, const DepthSource& source, uint32_t width, uint32_t height,
                     uint32_t frames);

// The filter sizes every lookup figure is reported for: the point test, then PCF from 3×3 to
// 17×17, the range of the papers' tables (DESIGN §4 allows k ≤ 17).
inline constexpr int kStandardFilters[] = {1, 3, 5, 9, 17};

// The query sets of every recorded lookup timing: 4 Mi uniform queries (seed 7), and the view
// samples of two 1920×1080 frames.
QuerySet standardUniformQueries();
QuerySet standardViewQueries(const Scene& scene, const DepthSource& source);

}  // namespace sb
