// A plain shadow map over an orthographic window of a directional light's light space: the
// depth buffer of one cascade of cascaded shadow maps or one tile of an irregular adaptive
// shadow map. It holds the first hit (float32, as Alecu 2014 §3.2's buffer) rendered by the
// light-space rasteriser, and answers the biased depth test a renderer makes.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "harness/light.h"
#include "scenes/scene.h"

namespace sb {

// The depth bias of a shadow-map lookup, in texels of the map it is applied to: a constant and
// a slope-scaled part (the receiver's tan θ to the light, clamped), so that one setting serves
// every cascade and tile size.
struct DepthBias {
  double constantTexels = 0.5;
  double slopeTexels = 1.0;
  double maxSlope = 10.0;
};

class OrthoShadowMap {
 public:
  // The window [corner, corner + size]² × [zNear, zFar] of `parent`'s light space (its units) at
  // `resolution`² texels, a power of two in [8, 2^20].
  OrthoShadowMap(const Scene& scene, const Light& parent, glm::dvec2 corner, double size,
                 double zNear, double zFar, uint32_t resolution);

  // Whether the window holds a parent light-space point (x, y only: depth is never clipped).
  bool covers(const glm::dvec3& parentPoint) const;
  // The biased test of a world point with unit normal `normal` (either facing); the point must
  // be covered.
  bool lit(const glm::dvec3& world, const glm::dvec3& normal, const DepthBias& bias) const;

  uint32_t resolution() const { return resolution_; }
  const std::vector<float>& depth() const { return depth_; }
  uint64_t bytes() const { return uint64_t(depth_.size()) * sizeof(float); }

 private:
  Light light_;
  glm::dvec2 corner_;
  double size_;
  uint32_t resolution_;
  glm::dvec3 towardsLight_;  // unit world direction to the light
  std::vector<float> depth_;
};

}  // namespace sb
