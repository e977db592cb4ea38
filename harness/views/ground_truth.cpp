#include "harness/views/ground_truth.h"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sb {

double defaultNormalOffset(const Scene& scene) {
  const Bounds bounds = scene.bounds();
  return 1e-5 * glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min));
}

namespace {

// Whether nothing lies between `origin` and the light (and, for a spot light, whether `point`
// lies inside its cone).
bool reachesLight(const SceneRays& rays, const LightSpec& light, const glm::dvec3& point,
                  const glm::dvec3& origin) {
  const glm::dvec3 travel = glm::normalize(glm::dvec3(light.direction));
  if (light.kind == LightKind::Directional)
    return !rays.occluded(origin, -travel, 0, std::numeric_limits<double>::infinity());
  const glm::dvec3 position(light.position);
  const double cosHalfFov = std::cos(glm::radians(double(light.fovDegrees)) / 2);
  if (glm::dot(glm::normalize(point - position), travel) < cosHalfFov) return false;
  const glm::dvec3 toLight = position - origin;
  const double distance = glm::length(toLight);
  return !rays.occluded(origin, toLight / distance, 0, distance);
}

}  // namespace

GroundTruth traceGroundTruth(const SceneRays& rays, const LightSpec& light, const Camera& camera,
                             uint32_t width, uint32_t height, double normalOffset) {
  GroundTruth truth;
  truth.width = width, truth.height = height;
  truth.normalOffset = normalOffset;
  const size_t pixels = size_t(width) * height;
  truth.covered.assign(pixels, 0);
  truth.position.assign(pixels, glm::vec3(0));
  truth.normal.assign(pixels, glm::vec3(0));
  truth.viewDepth.assign(pixels, 0);
  truth.lit.assign(pixels, 0);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height), [&](const auto& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const CameraRay ray = pixelRay(camera, width, height, x, y);
        const SceneRays::Hit hit = rays.intersect(ray.origin, ray.direction);
        if (!hit.valid()) continue;
        const glm::dvec3 point = ray.origin + hit.t * ray.direction;
        const glm::dvec3 normal =
            glm::dot(hit.normal, ray.direction) > 0 ? -hit.normal : hit.normal;
        const size_t p = truth.pixel(x, y);
        truth.covered[p] = 1;
        truth.position[p] = glm::vec3(point);
        truth.normal[p] = glm::vec3(normal);
        truth.viewDepth[p] = float(viewDepth(camera, point));
        truth.lit[p] = reachesLight(rays, light, point, point + normalOffset * normal);
      }
  });
  return truth;
}

}  // namespace sb
