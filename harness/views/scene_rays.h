// Rays in world space against every mesh of a scene, for what a camera sees: primary rays,
// occlusion rays toward a light, and probes that keep a camera out of the geometry. (The depth
// source casts in the light's view space instead, where its texel rays are simple.)
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace sb {

class SceneRays {
 public:
  explicit SceneRays(const Scene& scene);
  ~SceneRays();
  SceneRays(const SceneRays&) = delete;
  SceneRays& operator=(const SceneRays&) = delete;

  struct Hit {
    double t = -1;
    // The unit geometric normal cross(v1 - v0, v2 - v0) of the triangle hit, not turned toward
    // the ray: outward for a closed mesh, so its sign tells a front face from a back face.
    glm::dvec3 normal{0};
    uint32_t mesh = 0;      // index into Scene::meshes
    uint32_t triangle = 0;  // index into that mesh's triangles
    bool valid() const { return t >= 0; }
  };

  // The nearest hit with t in [tnear, tfar], t in units of `direction`'s length (Embree traces in
  // float: world coordinates and t are rounded to float precision).
  Hit intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tnear = 0,
                double tfar = std::numeric_limits<double>::infinity()) const;
  // Whether anything lies on the ray with t in [tnear, tfar].
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tnear,
                double tfar) const;

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
};

}  // namespace sb
