// A shadow map over a light window against the whole map (DESIGN §3): the window [0, 1]² is the
// plain shadow map bit for bit; a sub-window holds the same depths as the matching texels of a
// finer whole map; clipping keeps closed meshes watertight; the depth bias is the closed form.
#include <catch2/catch.hpp>

#include <cmath>

#include "harness/depth_source.h"
#include "harness/light.h"
#include "harness/light_space_rasterizer.h"
#include "harness/views/ortho_shadow_map.h"

using namespace sb;

namespace {

std::vector<float> wholeMap(const Scene& scene, const Light& light, uint32_t r) {
  const DepthSource source(scene, light, DepthMode::Open, r);
  DualDepthTile tile;
  source.trace(0, 0, r, r, tile);
  return tile.lo;
}

}  // namespace

TEST_CASE("the window [0, 1]² is the plain shadow map", "[views][window]") {
  const Scene scene = openScene("city:size=2");
  const Light light = Light::fit(scene.lights[0], scene);
  const OrthoShadowMap map(scene, light, glm::dvec2(0), 1.0, 0.0, 1.0, 256);
  CHECK(map.depth() == wholeMap(scene, light, 256));
  CHECK(map.bytes() == 256u * 256u * 4u);
}

TEST_CASE("a sub-window holds the depths of the matching texels of a finer map",
          "[views][window]") {
  const Scene scene = openScene("city:size=2");
  const Light light = Light::fit(scene.lights[0], scene);
  // Window texel (i, j) at 64² is whole-map texel (160 + i, 256 + j) at 512²: the same centre.
  const OrthoShadowMap map(scene, light, glm::dvec2(160.0 / 512, 256.0 / 512), 0.125, 0.0, 1.0, 64);
  const std::vector<float> whole = wholeMap(scene, light, 512);
  uint32_t differ = 0;
  for (uint32_t j = 0; j < 64; ++j)
    for (uint32_t i = 0; i < 64; ++i) {
      const float a = map.depth()[j * 64 + i], b = whole[(256 + j) * 512 + 160 + i];
      // The window's transform rounds differently: equal depths up to float rounding, and a
      // texel centre exactly on an edge may change owner.
      differ += std::abs(a - b) > 1e-5f;
    }
  CHECK(differ <= 8);
}

TEST_CASE("clipping to a window keeps closed meshes watertight", "[views][window]") {
  const Scene scene = openScene("city:size=2");
  const Light parent = Light::fit(scene.lights[0], scene);
  // Windows that cut through buildings and the ground slab on every side.
  for (const glm::dvec2 corner :
       {glm::dvec2(0.31, 0.27), glm::dvec2(-0.2, 0.6), glm::dvec2(0.7, 0.7)}) {
    const LightSpaceRasterizer rasterizer(scene, parent.window(corner, 0.2, 0.0, 1.0), 128);
    std::vector<float> lo(128 * 128), hi(128 * 128);
    CHECK(rasterizer.rasterize(0, 0, 128, 128, DepthMode::Closed, lo.data(), hi.data(), 128) == 0);
    for (size_t t = 0; t < lo.size(); ++t) CHECK(lo[t] <= hi[t]);
  }
}

TEST_CASE("the depth bias grows with the texel and the receiver's slope", "[views][window]") {
  // A floor under a straight-down light: the test at height h answers lit exactly when h lies
  // above the floor minus the bias, whose closed form is texel·(constant + slope·tan θ).
  Mesh floor{
      "floor", false, {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}};
  Mesh post{"post", false, {{0, 0, -1}, {0.1f, 0, -1}, {0, 0, 1}}, {{0, 1, 2}}};
  Scene scene{"floor", {floor, post}, {}};
  LightSpec down;
  down.direction = {0, 0, -1};
  scene.lights.push_back(down);
  const Light light = Light::fit(down, scene);
  const OrthoShadowMap map(scene, light, glm::dvec2(0), 1.0, 0.0, 1.0, 64);
  const double texel = light.worldPerUnitWidth() / 64;
  const DepthBias bias{0.5, 1.0, 10.0};
  const glm::dvec3 up(0, 0, 1), tilted = glm::normalize(glm::dvec3(1, 0, 1));  // tan θ = 1
  const glm::dvec3 at(-0.5, -0.5, 0);
  CHECK(map.lit(at + glm::dvec3(0, 0, -0.49 * texel), up, bias));
  CHECK_FALSE(map.lit(at + glm::dvec3(0, 0, -0.51 * texel), up, bias));
  CHECK(map.lit(at + glm::dvec3(0, 0, -1.49 * texel), tilted, bias));
  CHECK_FALSE(map.lit(at + glm::dvec3(0, 0, -1.51 * texel), tilted, bias));
  CHECK(map.covers(light.toLightSpace(at)));
  CHECK_FALSE(map.covers(glm::dvec3(1.0, 0.5, 0.5)));
}
