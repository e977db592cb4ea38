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

ViewSurface captureView(const Scene& scene, const DepthSource& source, uint32_t width,
                        uint32_t height, uint32_t frame, uint32_t frames) {
  const Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double radius = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5;
  const double angle = 2 * glm::pi<double>() * (frame + 0.125) / frames;
  const glm::dvec3 eye = centre + glm::dvec3(std::cos(angle) * radius * 0.8,
                                             std::sin(angle) * radius * 0.8, radius * 0.6);
  const glm::dvec3 forward = glm::normalize(centre - eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tanHalf = std::tan(glm::radians(30.0)), aspect = double(width) / height;
  const Light& light = source.light();
  const glm::dvec3 viewEye = light.toView(eye);

  ViewSurface view{width, height, {}, {}, {}};
  const size_t pixels = size_t(width) * height;
  view.position.resize(pixels);
  view.normal.resize(pixels);
  view.covered.assign(pixels, 0);
  tbb::parallel_for(uint32_t(0), height, [&](uint32_t y) {
    for (uint32_t x = 0; x < width; ++x) {
      const double u = (2 * (x + 0.5) / width - 1) * tanHalf * aspect;
      const double v = (1 - 2 * (y + 0.5) / height) * tanHalf;
      const glm::dvec3 direction = glm::normalize(forward + u * right + v * up);
      // The light's view space is an affine image of world space: the ray keeps its t.
      const glm::dvec3 viewDirection = light.toView(eye + direction) - viewEye;
      const DepthSource::Hit hit = source.intersect(glm::vec3(viewEye), glm::vec3(viewDirection));
      if (hit.t < 0) continue;
      glm::dvec3 normal = glm::normalize(light.normalToWorld(glm::dvec3(hit.normal)));
      if (glm::dot(normal, direction) > 0) normal = -normal;
      const size_t p = view.pixel(x, y);
      view.position[p] = glm::vec3(eye + double(hit.t) * direction);
      view.normal[p] = glm::vec3(normal);
      view.covered[p] = 1;
    }
  });
  return view;
}

QuerySet viewSamples(const Scene& scene, const DepthSource& source, uint32_t width, uint32_t height,
                     uint32_t frames) {
  const Bounds bounds = scene.bounds();
  // The offset along the normal, in world units: a small fraction of the scene.
  const double offset = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5e-4;
  QuerySet set{"view", {}};
  for (uint32_t frame = 0; frame < frames; ++frame) {
    const ViewSurface view = captureView(scene, source, width, height, frame, frames);
    for (size_t p = 0; p < view.covered.size(); ++p) {
      if (!view.covered[p]) continue;
      const glm::dvec3 point = glm::dvec3(view.position[p]) + offset * glm::dvec3(view.normal[p]);
      const glm::dvec3 q = source.light().toLightSpace(point);
      if (q.x >= 0 && q.x < 1 && q.y >= 0 && q.y < 1 && q.z >= 0 && q.z <= 1)
        set.queries.push_back({float(q.x), float(q.y), float(q.z)});
    }
  }
  return set;
}

QuerySet standardUniformQueries() {
  return uniformQueries(1 << 22, 7);
}

QuerySet standardViewQueries(const Scene& scene, const DepthSource& source) {
  return viewSamples(scene, source, 1920, 1080, 2);
}

}  // namespace sb
