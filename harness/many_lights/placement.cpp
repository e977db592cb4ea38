#include "harness/many_lights/placement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/gtc/constants.hpp>

#include "schemes/interface/splitmix.h"

namespace sb {

namespace {

// The highest point of the triangles whose ground plan overlaps the square of half-width `half`
// around `centre`; `floor` where there are none.
double highestOver(const Scene& scene, glm::dvec2 centre, double half, double floor) {
  double top = floor;
  for (const Mesh& mesh : scene.meshes)
    for (const glm::uvec3& t : mesh.triangles) {
      const glm::vec3 &a = mesh.vertices[t.x], &b = mesh.vertices[t.y], &c = mesh.vertices[t.z];
      const glm::dvec2 lo(glm::min(glm::min(a, b), c)), hi(glm::max(glm::max(a, b), c));
      if (hi.x >= centre.x - half && lo.x <= centre.x + half && hi.y >= centre.y - half &&
          lo.y <= centre.y + half)
        top = std::max<double>(top, std::max({a.z, b.z, c.z}));
    }
  return top;
}

}  // namespace

std::vector<LightSpec> placeSpotLights(const Scene& scene, const SpotLightPlacement& placement) {
  if (placement.count == 0) throw std::invalid_argument("many lights: at least one light");
  if (!(isValidSpotFov(placement.minFovDegrees) && isValidSpotFov(placement.maxFovDegrees) &&
        placement.minFovDegrees <= placement.maxFovDegrees))
    throw std::invalid_argument(
        fmt::format("many lights: the fov range {}–{} degrees must lie within (0, {})",
                    placement.minFovDegrees, placement.maxFovDegrees, kMaxSpotFovDegrees));
  if (!(placement.maxTiltDegrees >= 0 && placement.maxTiltDegrees <= placement.minFovDegrees / 2))
    throw std::invalid_argument("many lights: the tilt must not exceed half the smallest fov");
  const Bounds bounds = scene.bounds();
  const glm::dvec2 lo(bounds.min), extent = glm::dvec2(bounds.max) - lo;
  // Lights this far apart cover the ground plan about once; each stands at least half a
  // spacing inside the plan, so that its footprint stays over the scene.
  const double spacing = std::max(extent.x, extent.y) / std::sqrt(double(placement.count));
  const glm::dvec2 margin = glm::min(glm::dvec2(spacing / 2), extent / 4.0);

  uint64_t state = placement.seed;
  const glm::dvec2 shift(unitFloat(nextRandom(state)), unitFloat(nextRandom(state)));
  std::vector<LightSpec> lights;
  for (uint32_t i = 0; i < placement.count; ++i) {
    // The R2 sequence (Roberts 2018, steps 1/g and 1/g², g the plastic number) spreads any
    // number of lights evenly; the seed shifts it.
    const glm::dvec2 u =
        glm::fract(shift + double(i + 1) * glm::dvec2(0.7548776662466927, 0.5698402909980532));
    const glm::dvec2 xy = lo + margin + u * (extent - 2.0 * margin);
    // Above everything under the light's cell, so never inside a closed object (DESIGN §3).
    const double height = highestOver(scene, xy, spacing / 2, bounds.min.z) +
                          spacing * (0.5 + 0.5 * unitFloat(nextRandom(state)));
    const double tilt =
        glm::radians(double(placement.maxTiltDegrees)) * unitFloat(nextRandom(state));
    const double azimuth = 2 * glm::pi<double>() * unitFloat(nextRandom(state));
    LightSpec light;
    light.kind = LightKind::Spot;
    light.position = glm::vec3(xy.x, xy.y, height);
    light.direction = glm::vec3(std::sin(tilt) * std::cos(azimuth),
                                std::sin(tilt) * std::sin(azimuth), -std::cos(tilt));
    light.fovDegrees =
        placement.minFovDegrees +
        (placement.maxFovDegrees - placement.minFovDegrees) * unitFloat(nextRandom(state));
    light.depth = DepthDistribution::Logarithmic;  // Kämpe eq. 1
    lights.push_back(light);
  }
  return lights;
}

Scene withSpotLights(Scene scene, const SpotLightPlacement& placement) {
  scene.lights = placeSpotLights(scene, placement);
  return scene;
}

}  // namespace sb
