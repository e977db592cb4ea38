// Tests of the generators' style knobs and presets: a knob at 0 leaves its scene as it was, a
// preset is its knobs, and each knob changes only what it names (README, "Calibrated stand-ins").

#include <algorithm>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

#include "scenes/scene.h"
#include "scenes/scene_test_support.h"
#include "scenes/watertight.h"

using sb::Mesh;
using sb::Scene;
using namespace sb::testing;

TEST_CASE("style knobs at 0 leave the city as it was; presets are named knobs",
          "[scenes][spec][style]") {
  const Scene plain = sb::openScene("city:size=3,seed=7");
  const Scene zero = sb::openScene("city:size=3,seed=7,relief=0,turn=0");
  CHECK(zero.hash() == plain.hash());
  CHECK(zero.name == plain.name);
  const Scene styled = sb::openScene("city:turn=30,size=3,relief=40");
  CHECK(styled.name == "city:size=3,seed=1,relief=40,turn=30");
  CHECK(sb::openScene(styled.name).hash() == styled.hash());
  for (const auto& g : sb::sceneGenerators())
    for (const sb::GeneratorPreset& preset : g.presets) {
      const std::string spec = g.name + ":" + preset.name;
      INFO("preset " << spec);
      const sb::GeneratorKnobs knobs{preset.size, preset.seed, preset.style};
      CHECK(sb::openScene(spec).hash() == g.generate(knobs).hash());
      for (const char* knob : {"size", "seed"})
        CHECK_THAT(sceneErrorOf([&] { sb::openScene(spec + "," + knob + "=2"); }),
                   Catch::Contains(std::string(knob) + " given twice"));
      CHECK(!preset.fittedTo.empty());
    }
  for (const char* spec :
       {"city:relief=1001", "city:turn=91", "city:relief=-1", "city:turn=1,turn=2",
        "city:relief=99999999999", "terrain:relief=3", "tangle:turn=1"}) {
    INFO(spec);
    const std::string message = sceneErrorOf([&] { sb::openScene(spec); });
    CHECK_THAT(message, Catch::Contains(spec));
  }
  CHECK_THAT(sceneErrorOf([] { sb::openScene("city:turn=91"); }),
             Catch::Contains("turn 91 out of range [0, 90]"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene("terrain:relief=3"); }),
             Catch::Contains("unknown knob 'relief=3'"));
  CHECK_THAT(sceneErrorOf([] {
               generator("terrain").generate({3, 1, {1}});
             }),
             Catch::Contains("1 style knobs given, it has 0"));
}

TEST_CASE("a tangle's radius knob widens its tubes and nothing else",
          "[scenes][generators][style]") {
  // 80 thousandths is the default radius: the same bytes as no knob.
  CHECK(sb::openScene("tangle:size=3,radius=80").hash() == sb::openScene("tangle:size=3").hash());
  CHECK(sb::openScene("tangle:size=3,radius=40").hash() == "7cd0f4e75b069102");
  const Scene thin = sb::openScene("tangle:size=1,radius=80");
  const Scene thick = sb::openScene("tangle:size=1,radius=160");
  checkSceneInvariants(thick);
  REQUIRE(thick.meshes.size() == 1);
  CHECK(thick.meshes[0].closed);
  CHECK(sb::checkWatertight(thick.meshes[0]).watertight());
  CHECK(thick.meshes[0].triangles == thin.meshes[0].triangles);
  // The same centre line: the extreme vertex moves out by the radius's growth, 0.08, at most,
  // and at least by its projection at a hexagon's corner (cos 30°).
  for (int axis = 0; axis < 3; ++axis) {
    INFO("axis " << axis);
    const float grown = thick.bounds().max[axis] - thin.bounds().max[axis];
    CHECK(grown >= 0.08f * 0.866f - 1e-4f);
    CHECK(grown <= 0.08f + 1e-4f);
  }
  CHECK_THAT(sceneErrorOf([] { sb::openScene("tangle:radius=301"); }),
             Catch::Contains("radius 301 out of range [0, 300]"));
}

TEST_CASE("a city on hills stands on them, closed, its buildings turned inside their lots",
          "[scenes][generators][style]") {
  const Scene flat = sb::openScene("city:size=2,seed=5");
  for (const char* spec : {"city:size=2,seed=5,relief=60", "city:size=2,seed=5,turn=90",
                           "city:size=2,seed=5,relief=60,turn=90"}) {
    INFO(spec);
    const Scene scene = sb::openScene(spec);
    checkSceneInvariants(scene);
    for (const Mesh& mesh : scene.meshes) {
      INFO("mesh " << mesh.name);
      CHECK(mesh.closed);
      CHECK(sb::checkWatertight(mesh).watertight());
    }
    // The same buildings: turning and hills move vertices, they add or remove none.
    REQUIRE(scene.meshes.size() == flat.meshes.size());
    for (size_t m = 1; m < scene.meshes.size(); ++m)
      CHECK(scene.meshes[m].triangles.size() == flat.meshes[m].triangles.size());
    // Every building stays inside the city, a metre from its edge (blocks of 2 × 96 m), and its
    // base inside the slab under the hills (z ∈ [-2, 0] at the lowest).
    for (size_t m = 1; m < scene.meshes.size(); ++m)
      for (const glm::vec3& v : scene.meshes[m].vertices) {
        CHECK(std::abs(v.x) <= 95.0f);
        CHECK(std::abs(v.y) <= 95.0f);
        CHECK(v.z >= -1.0f);
      }
  }
  const Scene hills = sb::openScene("city:size=2,seed=5,relief=60");
  float groundTop = hills.meshes[0].vertices[0].z;
  for (const glm::vec3& v : hills.meshes[0].vertices) groundTop = std::max(groundTop, v.z);
  CHECK(groundTop > 30.0f);
  CHECK(groundTop <= 60.0f);
}
