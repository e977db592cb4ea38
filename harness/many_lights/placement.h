// Many local lights (Kämpe 2015 §5.3): the placement of the spot lights over a scene.
#pragma once

#include <cstdint>
#include <vector>

#include "scenes/scene.h"

namespace sb {

// Where the spot lights go. Positions follow a seeded R2 low-discrepancy sequence over the
// scene's ground plan, each light a random height above the geometry under it; it points down,
// tilted by at most maxTiltDegrees ≤ minFovDegrees / 2 so that the point straight below it is
// always inside its cone.
struct SpotLightPlacement {
  uint32_t count = 165;  // Kämpe §5.3
  uint64_t seed = 1;
  float minFovDegrees = 60, maxFovDegrees = 90;
  float maxTiltDegrees = 30;
};

// `count` spot lights with the logarithmic depth distribution (Kämpe eq. 1); deterministic.
std::vector<LightSpec> placeSpotLights(const Scene& scene, const SpotLightPlacement& placement);

// `scene` with its lights replaced by the placement's spot lights.
Scene withSpotLights(Scene scene, const SpotLightPlacement& placement);

}  // namespace sb
