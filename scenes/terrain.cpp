// `terrain`: a closed fractal landscape (a stand-in for the papers' terrain scenes): a
// heightfield of fractal value noise as the top surface, closed by four vertical walls and a
// flat bottom into one watertight solid (scenes/heightfield.h).
#include <cstdint>

#include "scenes/detail.h"
#include "scenes/heightfield.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 2, kMaxSize = 4096;
constexpr double kExtent = 1000.0;  // metres per side, centred on the origin
constexpr double kRelief = 200.0;   // height of the highest peak above the lowest valley
constexpr float kBottom = -50.0f;   // the flat underside

}  // namespace

SceneFootprint terrainFootprint(uint32_t size) {
  checkSize("terrain", size, kMinSize, kMaxSize);
  return heightfieldFootprint(size);
}

Scene generateTerrain(uint32_t size, uint64_t seed) {
  checkSize("terrain", size, kMinSize, kMaxSize);
  Mesh mesh;
  mesh.name = "terrain";
  mesh.closed = true;
  addHeightfieldSolid(mesh, size, kExtent, fractalHeights(size, seed), kRelief, kBottom);

  Scene scene;
  scene.name = generatedSceneName("terrain", {size, seed});
  scene.meshes.push_back(std::move(mesh));
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
