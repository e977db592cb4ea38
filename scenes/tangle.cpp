// `tangle`: a dense knot of closed tubes inside a ball (a stand-in for the papers' hairball).
// Each strand is a capped tube along a smooth random walk that turns back at the edge of the
// ball; strands pass through one another freely, which closed-mode ray casting handles as a
// union of closed objects.
#include <cmath>
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "scenes/detail.h"
#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 1, kMaxSize = 20000;
constexpr float kBallRadius = 10.0f;
constexpr float kTubeRadius = 0.08f;
// The `radius` style knob, in thousandths of a unit. At most 0.3: the bending radius below
// stays above it.
constexpr uint32_t kMaxRadiusKnob = 300;
constexpr float kStep = 0.15f;  // distance between successive rings
constexpr int kSides = 6, kRings = 256;
// The largest change of direction per step: |Δd| ≤ 0.4, so turns stay below asin(0.4) per
// step, a bending radius ≥ 0.37 — well above the tube radius, so tubes never fold.
constexpr float kMaxTurn = 0.4f;

glm::vec3 clampLength(glm::vec3 v, float maxLength) {
  const float length2 = glm::dot(v, v);
  return length2 > maxLength * maxLength ? v * (maxLength / std::sqrt(length2)) : v;
}

// The centre line of one strand: a random walk with momentum, steered inwards once it leaves
// the inner part of the ball.
std::vector<glm::vec3> strandPath(Rng& rng) {
  std::vector<glm::vec3> path;
  path.reserve(kRings);
  glm::vec3 p = 0.8f * kBallRadius * rng.inUnitBall();
  glm::vec3 d = rng.direction();
  for (int i = 0; i < kRings; ++i) {
    path.push_back(p);
    glm::vec3 turn = 0.25f * rng.inUnitBall();
    const float distance = glm::length(p);
    if (distance > 0.75f * kBallRadius && glm::dot(d, p) > 0.0f) turn -= 0.25f * (p / distance);
    d = glm::normalize(d + clampLength(turn, kMaxTurn));
    p += kStep * d;
  }
  return path;
}

}  // namespace

std::vector<StyleKnob> tangleStyleKnobs() {
  return {{"radius", "tube radius in thousandths of a unit, in a ball of radius 10 (0: 80)",
           kMaxRadiusKnob}};
}

std::vector<GeneratorPreset> tanglePresets() {
  // Fitted on `cpvs` closed (README, "Calibrated stand-ins"): more strands leave the size as it
  // is (a map sees the ball's outer layer), a thinner tube doubles it; half the default radius
  // of four settings tried.
  return {{"hairball",
           650,
           1,
           {40},
           "Scandolo & Eisemann 2021 Table 1, Hairball, DAG: cpvs closed, 4K² to 16K²"}};
}

SceneFootprint tangleFootprint(const GeneratorKnobs& knobs) {
  checkSize("tangle", knobs.size, kMinSize, kMaxSize);
  checkStyleKnobs("tangle", knobs, tangleStyleKnobs());
  const uint64_t size = knobs.size;
  // Per strand: kRings rings of kSides vertices and two cap centres; kSides quads between
  // successive rings and a fan of kSides triangles at each end.
  constexpr uint64_t kVertices = kRings * kSides + 2,
                     kTriangles = (kRings - 1) * kSides * 2 + 2 * kSides;
  const uint64_t strandBytes = grownMeshBytes(kVertices, kTriangles) + sizeof(Mesh) * 2;
  return {size * kVertices, size * kTriangles, size * strandBytes};
}

Scene generateTangle(const GeneratorKnobs& knobs) {
  checkSize("tangle", knobs.size, kMinSize, kMaxSize);
  checkStyleKnobs("tangle", knobs, tangleStyleKnobs());
  Scene scene;
  scene.name = generatedSceneName("tangle", knobs, tangleStyleKnobs());
  const uint32_t radius = knobs.styleKnob(0);
  const std::vector<float> radii(kRings, radius == 0 ? kTubeRadius : float(radius) / 1000.0f);
  for (uint32_t s = 0; s < knobs.size; ++s) {
    Rng rng(streamSeed(knobs.seed, s));
    Mesh strand;
    strand.name = fmt::format("strand_{:04}", s);
    strand.closed = true;
    addTube(strand, strandPath(rng), radii, kSides, /*capped=*/true);
    scene.meshes.push_back(std::move(strand));
  }
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
