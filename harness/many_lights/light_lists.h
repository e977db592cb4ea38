// Many local lights (Kämpe 2015 §4): a spot light with its structure, the light-space query
// of a view sample, and Tiled Shading light lists (Olsson & Assarsson 2011): per screen tile,
// the lights that may reach it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

#include "harness/light.h"
#include "harness/query_sets.h"
#include "schemes/interface/scheme.h"

namespace sb {

// A spot light with its structure, as the shadow evaluation sees it.
struct ShadowedLight {
  ShadowedLight(Light light, const Decoder& decoder, uint32_t resolution);
  Light light;
  const Decoder* decoder;
  uint32_t resolution;
  double tanHalfFov, near, far;  // the fitted frustum, in world units
};

// The light-space query of a view sample for a k×k PCF lookup: the sample moved along its normal
// by half the filter width at its distance from the light (Kämpe §4, "Perspective Lights"), so
// the bias is minimal everywhere in a wide frustum. nullopt when it lies outside the light's
// cone or depth range: the light does not reach it.
std::optional<Query> lightSpaceQuery(const ShadowedLight& light, const glm::dvec3& position,
                                     const glm::dvec3& normal, int k);

// Tiled Shading: per screen tile of tilePixels² pixels, the lights whose frustum (widened by
// the largest normal offset) may contain a lookup of the tile, in increasing light order.
struct TileLightLists {
  uint32_t tilePixels = 8, tilesX = 0, tilesY = 0;
  std::vector<std::vector<uint32_t>> lights;  // per tile, row-major
};
TileLightLists buildLightLists(const ViewSurface& view, std::span<const ShadowedLight> lights,
                               uint32_t tilePixels, int k, bool parallel);
// Every light in every tile: the brute-force reference of the light lists.
TileLightLists allLightsEverywhere(const ViewSurface& view, size_t lightCount, uint32_t tilePixels);

// Calls body(firstTile, endTile) over all tiles: on this thread, or split over all threads.
template <class Body>
void forTiles(size_t tiles, bool parallel, Body&& body) {
  if (!parallel) return body(size_t(0), tiles);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles),
                    [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

// Calls f(pixel) for every covered pixel of tile `tile`.
template <class F>
void forCoveredPixels(const ViewSurface& view, const TileLightLists& lists, size_t tile, F&& f) {
  const uint32_t x0 = uint32_t(tile % lists.tilesX) * lists.tilePixels;
  const uint32_t y0 = uint32_t(tile / lists.tilesX) * lists.tilePixels;
  for (uint32_t y = y0; y < std::min(y0 + lists.tilePixels, view.height); ++y)
    for (uint32_t x = x0; x < std::min(x0 + lists.tilePixels, view.width); ++x)
      if (view.covered[view.pixel(x, y)]) f(view.pixel(x, y));
}

}  // namespace sb
