#include "harness/query_sets.h"

#include <cmath>

#include <tbb/parallel_for.h>

#include <glm/gtc/constants.hpp>
#include "schemes/interface/splitmix.h"

namespace sb {

QuerySet uniformQueries(uint64_t count, uint64_t seed) {
  QuerySet set{"uniform", std::vector<Query>(count)};
  uint64_t state = seed;
  for (Query& q : set.queries)
    q = {unitFloat(nextRandom(state)), unitFloat(nextRandom(state)), unitFloat(nextRandom(state))};
  return set;
}

QuerySet viewSamples(const Scene& scene, const DepthSource& source, uint32_t width, uint32_t height,
                     uint32_t frames) {
  const Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double radius = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5;
  const Light& light = source.light();
  // The offset along the normal, in world units: a small fraction of the scene.
  const double offset = radius * 1e-4;
  std::vector<std::vector<Query>> rows(size_t(frames) * height);

  for (uint32_t frame = 0; frame < frames; ++frame) {
    // A camera circling the scene at 60% of its radius above the centre, looking at it.
    const double angle = 2 * glm::pi<double>() * (frame + 0.125) / frames;
    const glm::dvec3 eye = centre + glm::dvec3(std::cos(angle) * radius * 0.8,
                                               std::sin(angle) * radius * 0.8, radius * 0.6);
    const glm::dvec3 forward = glm::normalize(centre - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tanHalf = std::tan(glm::radians(30.0));
    const double aspect = double(width) / height;
    const glm::dvec3 viewEye = light.toView(eye);

    tbb::parallel_for(uint32_t(0), height, [&](uint32_t y) {
      std::vector<Query>& out = rows[size_t(frame) * height + y];
      for (uint32_t x = 0; x < width; ++x) {
        const double u = (2 * (x + 0.5) / width - 1) * tanHalf * aspect;
        const double v = (1 - 2 * (y + 0.5) / height) * tanHalf;
        const glm::dvec3 direction = glm::normalize(forward + u * right + v * up);
        // Light view space is an affine image of world space: the ray maps with the same t.
        const glm::dvec3 viewDirection = light.toView(eye + direction) - viewEye;
        const DepthSource::Hit hit = source.intersect(glm::vec3(viewEye), glm::vec3(viewDirection));
        if (hit.t < 0) continue;
        glm::dvec3 point = eye + double(hit.t) * direction;
        // Move along the world normal towards the camera's side of the surface.
        const glm::dvec3 worldNormal = glm::normalize(light.normalToWorld(glm::dvec3(hit.normal)));
        point += (glm::dot(worldNormal, direction) < 0 ? offset : -offset) * worldNormal;
        const glm::dvec3 p = light.toLightSpace(point);
        if (p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1 && p.z >= 0 && p.z <= 1)
          out.push_back({float(p.x), float(p.y), float(p.z)});
      }
    });
  }
  QuerySet set{"view", {}};
  for (const auto& row : rows) set.queries.insert(set.queries.end(), row.begin(), row.end());
  return set;
}

}  // namespace sb
