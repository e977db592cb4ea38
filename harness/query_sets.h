// Query sets for lookup benchmarks: uniform random light-space points, and view samples —
// what a renderer actually asks — from a camera path over the scene.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "harness/depth_source.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct QuerySet {
  std::string name;
  std::vector<Query> queries;
};

QuerySet uniformQueries(uint64_t count, uint64_t seed);

// Primary rays of a width × height camera at `frames` positions orbiting the scene, cast with
// Embree; each hit is moved a little along its normal (towards the camera side) and turned
// into a light-space query. Misses and points outside the light's map are dropped.
QuerySet viewSamples(const Scene& scene, const DepthSource& source, uint32_t width, uint32_t height,
                     uint32_t frames);

}  // namespace sb
