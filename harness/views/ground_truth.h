// Ground truth for view-dependent shadow techniques (DESIGN §5b): for every pixel of a frame the
// first visible point, by a primary ray, and its exact visibility toward the light, by an
// occlusion ray — what every technique's shadow test is scored against.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "harness/views/camera_path.h"
#include "harness/views/scene_rays.h"
#include "scenes/scene.h"

namespace sb {

// One frame's visible surface and its exact visibility toward the light.
struct GroundTruth {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> covered;     // primary ray hit something
  std::vector<glm::vec3> position;  // world-space hit point
  std::vector<glm::vec3> normal;    // unit geometric normal, flipped to face the camera
  std::vector<float> viewDepth;     // w: distance along the camera's forward axis (0 where not
                                    // covered)
  std::vector<uint8_t> lit;  // 1 when the occlusion ray toward the light reaches it (0 where not
                             // covered)
  double normalOffset = 0;   // world units the occlusion ray's origin moved along `normal`
  size_t pixel(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
};

// The occlusion ray's offset when none is given: 1e-5 of the scene's bounding-box diagonal, well
// above float's rounding of a hit point anywhere in the scene (about 1e-7 of its extent), so that
// a lit surface does not shadow itself, and well below any feature of the scenes.
double defaultNormalOffset(const Scene& scene);

// Primary rays through the pixel centres (pixelRay), then from each hit, moved `normalOffset`
// along the normal facing the camera, an occlusion ray toward the light: against the travel of a
// directional light to infinity; to a spot light's position, unlit outside its cone (the angle
// to its axis above fov/2). A surface facing away from the light needs no test of its own: its
// offset origin lies on the camera's side, and the ray to the light crosses the surface itself.
GroundTruth traceGroundTruth(const SceneRays& rays, const LightSpec& light, const Camera& camera,
                             uint32_t width, uint32_t height, double normalOffset);

}  // namespace sb
