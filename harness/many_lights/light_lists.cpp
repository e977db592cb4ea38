#include "harness/many_lights/light_lists.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace sb {

ShadowedLight::ShadowedLight(Light l, const Decoder& d, uint32_t r)
    : light(std::move(l)), decoder(&d), resolution(r) {
  if (light.kind() != LightKind::Spot)
    throw std::invalid_argument("many lights: only spot lights are evaluated");
  // The fitted near and far planes are the Light's own; describe() is where it reports them.
  const nlohmann::json frustum = light.describe();
  tanHalfFov = std::tan(glm::radians(double(light.spec().fovDegrees)) / 2);
  near = frustum["near"].get<double>();
  far = frustum["far"].get<double>();
}

std::optional<Query> lightSpaceQuery(const ShadowedLight& s, const glm::dvec3& position,
                                     const glm::dvec3& normal, int k) {
  // A texel at view depth z is 2·tan(fov/2)·z/R wide; half of k texels along the normal.
  const double z = std::clamp(s.light.toView(position).z, 0.0, s.far);
  const double offset = k * s.tanHalfFov * z / s.resolution;
  const glm::dvec3 p = s.light.toLightSpace(position + offset * normal);
  if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1 && p.z >= 0 && p.z <= 1)) return std::nullopt;
  return Query{float(p.x), float(p.y), float(p.z)};
}

namespace {

// A light's frustum as six world-space planes dot(n, p) ≤ w (n unit), each pushed out by the
// largest normal offset of lightSpaceQuery plus rounding slack, so that every view sample whose
// query it accepts lies inside: the light's bounding volume for the light lists.
struct LightVolume {
  std::array<glm::dvec4, 6> planes;

  explicit LightVolume(const ShadowedLight& s, int k) {
    const double padding = k * s.tanHalfFov * s.far / s.resolution + 1e-6 * s.far;
    const double t = s.tanHalfFov, c = 1 / std::sqrt(1 + t * t);
    // View space: |x| ≤ t·z, |y| ≤ t·z, near ≤ z ≤ far.
    const glm::dvec4 view[6] = {{c, 0, -t * c, 0},  {-c, 0, -t * c, 0},  {0, c, -t * c, 0},
                                {0, -c, -t * c, 0}, {0, 0, -1, -s.near}, {0, 0, 1, s.far}};
    // toView is a rotation and a shift: n·view(p) = normalToWorld(n)·p + n·view(0).
    const glm::dvec3 viewOfOrigin = s.light.toView(glm::dvec3(0));
    for (size_t i = 0; i < 6; ++i) {
      const glm::dvec3 n(view[i]);
      planes[i] =
          glm::dvec4(s.light.normalToWorld(n), view[i].w + padding - glm::dot(n, viewOfOrigin));
    }
  }

  // False only when the box lies wholly outside one of the planes.
  bool mayIntersect(const glm::dvec3& lo, const glm::dvec3& hi) const {
    const glm::dvec3 centre = (lo + hi) * 0.5, half = (hi - lo) * 0.5;
    for (const glm::dvec4& plane : planes) {
      const glm::dvec3 n(plane);
      if (glm::dot(n, centre) - glm::dot(glm::abs(n), half) > plane.w) return false;
    }
    return true;
  }
};

TileLightLists emptyLists(const ViewSurface& view, uint32_t tilePixels) {
  if (tilePixels == 0) throw std::invalid_argument("many lights: tiles need at least one pixel");
  TileLightLists lists;
  lists.tilePixels = tilePixels;
  lists.tilesX = (view.width + tilePixels - 1) / tilePixels;
  lists.tilesY = (view.height + tilePixels - 1) / tilePixels;
  lists.lights.resize(size_t(lists.tilesX) * lists.tilesY);
  return lists;
}

}  // namespace

TileLightLists buildLightLists(const ViewSurface& view, std::span<const ShadowedLight> lights,
                               uint32_t tilePixels, int k, bool parallel) {
  TileLightLists lists = emptyLists(view, tilePixels);
  std::vector<LightVolume> volumes;
  for (const ShadowedLight& light : lights) volumes.emplace_back(light, k);
  forTiles(lists.lights.size(), parallel, [&](size_t begin, size_t end) {
    for (size_t tile = begin; tile < end; ++tile) {
      // The tile's three-dimensional bounds over its view samples (Olsson & Assarsson 2011).
      constexpr double inf = std::numeric_limits<double>::infinity();
      glm::dvec3 lo(inf), hi(-inf);
      forCoveredPixels(view, lists, tile, [&](size_t p) {
        lo = glm::min(lo, glm::dvec3(view.position[p]));
        hi = glm::max(hi, glm::dvec3(view.position[p]));
      });
      if (!(lo.x <= hi.x)) continue;
      for (uint32_t l = 0; l < volumes.size(); ++l)
        if (volumes[l].mayIntersect(lo, hi)) lists.lights[tile].push_back(l);
    }
  });
  return lists;
}

TileLightLists allLightsEverywhere(const ViewSurface& view, size_t lightCount,
                                   uint32_t tilePixels) {
  TileLightLists lists = emptyLists(view, tilePixels);
  std::vector<uint32_t> all(lightCount);
  for (uint32_t l = 0; l < lightCount; ++l) all[l] = l;
  std::fill(lists.lights.begin(), lists.lights.end(), all);
  return lists;
}

}  // namespace sb
