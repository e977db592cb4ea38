// A Light maps world space to light space (DESIGN §2): x, y ∈ [0, 1) across the shadow map,
// z ∈ [0, 1] from the near to the far plane, the frustum fitted to the scene so that all
// geometry lies strictly inside.
//
// Rays are cast in the light's *view space*: for a directional light that is light space
// itself (an orthographic box scaled to the unit cube, rays along +z, t = z); for a spot light
// the light sits at the origin looking down +z, and rays have direction z = 1 so that t is the
// view depth, mapped to [0, 1] linearly or logarithmically (Kämpe eq. 1).
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "scenes/scene.h"

namespace sb {

struct PrimaryRay {
  glm::vec3 origin, direction;
  float tnear, tfar;
};

class Light {
 public:
  // Fits the light's frustum to the scene's geometry.
  static Light fit(const LightSpec& spec, const Scene& scene);

  LightKind kind() const { return spec_.kind; }
  const LightSpec& spec() const { return spec_; }

  // World → view space (affine and orientation-preserving, so windings keep their facing).
  glm::dvec3 toView(const glm::dvec3& world) const;
  // A view-space normal (as Embree reports it) back to world space, unnormalised.
  glm::dvec3 normalToWorld(const glm::dvec3& viewNormal) const;
  // World → light space; for points outside a spot light's cone x, y leave [0, 1).
  glm::dvec3 toLightSpace(const glm::dvec3& world) const;

  // Directional lights: the light whose light space is the box [corner, corner + size]² ×
  // [zNear, zFar] of this one's (all in this light's light-space units), the orthographic frustum
  // of a shadow-map cascade or tile. Geometry may lie outside it.
  Light window(glm::dvec2 corner, double size, double zNear, double zFar) const;
  // Directional lights: world units per light-space unit along x (= y) and along z.
  double worldPerUnitWidth() const { return 1.0 / scale_.x; }
  double worldPerUnitDepth() const { return 1.0 / scale_.z; }

  // The ray through the centre of texel (i, j) at resolution R, in view space.
  PrimaryRay texelRay(uint32_t i, uint32_t j, uint32_t resolution) const;
  // Light-space depth of a hit at parameter t along a texelRay.
  float depthOfHit(float t) const;

  nlohmann::json describe() const;

 private:
  double depthOfViewZ(double viewZ) const;

  LightSpec spec_;
  glm::dvec3 origin_{0.0};  // directional: the fitted box's corner in frame coordinates; spot: the
                            // light's position
  glm::dvec3 axisX_{1, 0, 0}, axisY_{0, 1, 0}, axisZ_{0, 0, 1};  // right-handed, z = forward
  glm::dvec3 scale_{1.0};  // directional: view = (world·axes − origin) · scale
  double tanHalfFov_ = 0, near_ = 0, far_ = 0;  // spot
};

}  // namespace sb
