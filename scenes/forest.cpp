// `forest`: thin open geometry (a stand-in for the papers' tree and foliage scenes): trees
// with open tube trunks and branches and many single-sided leaf cards, over an open ground
// quad. Nothing here is closed, so closed-mode optimisations cannot help: the interval of a
// texel is a single depth.
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "scenes/detail.h"
#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 1, kMaxSize = 200;
constexpr float kSpacing = 8.0f;  // metres between neighbouring trees (before jitter)
constexpr int kTrunkSides = 6, kTrunkRings = 5;
constexpr int kBranchSides = 4, kBranchesPerTree = 3, kBranchRings = 3;
constexpr int kMaxLeavesPerTree = 220;

// An upward open tube whose axis leans away from `base` along `lean`, more at the top.
void addTrunk(Mesh& mesh, glm::vec3 base, float height, float radius, glm::vec2 lean) {
  std::vector<glm::vec3> centres;
  std::vector<float> radii;
  for (int r = 0; r < kTrunkRings; ++r) {
    const float t = static_cast<float>(r) / (kTrunkRings - 1);
    centres.push_back(base + glm::vec3{lean * (t * t), height * t});
    radii.push_back(radius * (1.0f - 0.6f * t));  // tapering
  }
  addTube(mesh, centres, radii, kTrunkSides, /*capped=*/false);
}

// A square single-sided card of half-width `half` centred on `centre`, facing a random way.
void addLeaf(Mesh& mesh, glm::vec3 centre, float half, Rng& rng) {
  const glm::vec3 normal = rng.direction();
  glm::vec3 side;
  do side = glm::cross(normal, rng.direction());
  while (glm::dot(side, side) < 0.01f);
  const glm::vec3 u = glm::normalize(side) * half, v = glm::cross(normal, u);
  addQuad(mesh, centre - u - v, centre + u - v, centre + u + v, centre - u + v);
}

void addTree(Mesh& mesh, glm::vec2 position, Rng& rng) {
  const float height = rng.uniform(8.0f, 16.0f);
  const float radius = rng.uniform(0.15f, 0.35f);
  const glm::vec2 lean{rng.uniform(-0.6f, 0.6f), rng.uniform(-0.6f, 0.6f)};
  const glm::vec3 base{position, -0.2f};  // a little below the ground: no gap at the foot
  const float trunkHeight = 0.75f * height;
  addTrunk(mesh, base, trunkHeight, radius, lean);

  // The crown: an ellipsoid around the upper trunk, filled with leaf cards and a few branches.
  const glm::vec3 crown = base + glm::vec3{lean, 0.65f * height};
  const glm::vec3 crownRadii{rng.uniform(2.0f, 3.5f), rng.uniform(2.0f, 3.5f), 0.3f * height};
  for (int b = 0; b < kBranchesPerTree; ++b) {
    const float along = rng.uniform(0.45f, 0.7f);
    const glm::vec3 start = base + glm::vec3{lean * (along * along), trunkHeight * along};
    const glm::vec3 reach =
        crownRadii *
        glm::vec3{rng.uniform(-0.8f, 0.8f), rng.uniform(-0.8f, 0.8f), rng.uniform(0.1f, 0.5f)};
    const glm::vec3 centres[kBranchRings] = {start, start + 0.5f * reach + glm::vec3{0, 0, 0.3f},
                                             start + reach};
    const float r = 0.4f * radius;
    const float radii[kBranchRings] = {r, 0.7f * r, 0.4f * r};
    addTube(mesh, centres, radii, kBranchSides, /*capped=*/false);
  }
  const int leaves = static_cast<int>(rng.between(180, kMaxLeavesPerTree));
  for (int l = 0; l < leaves; ++l) {
    // Separate statements: the order of evaluation of function arguments is unspecified, and
    // the draws must come in the same order with every compiler.
    const glm::vec3 centre = crown + crownRadii * rng.inUnitBall();
    const float halfWidth = rng.uniform(0.15f, 0.3f);
    addLeaf(mesh, centre, halfWidth, rng);
  }
}

}  // namespace

SceneFootprint forestFootprint(uint32_t size) {
  checkSize("forest", size, kMinSize, kMaxSize);
  // Per tree: an open trunk and branches (rings of sides vertices, two triangles per side
  // between successive rings) and leaf cards of 4 vertices and 2 triangles; one ground quad.
  constexpr uint64_t kTreeVertices = kTrunkRings * kTrunkSides +
                                     kBranchesPerTree * kBranchRings * kBranchSides +
                                     kMaxLeavesPerTree * 4;
  constexpr uint64_t kTreeTriangles = (kTrunkRings - 1) * kTrunkSides * 2 +
                                      kBranchesPerTree * (kBranchRings - 1) * kBranchSides * 2 +
                                      kMaxLeavesPerTree * 2;
  const uint64_t trees = uint64_t{size} * size;
  return {trees * kTreeVertices + 4, trees * kTreeTriangles + 2,
          grownMeshBytes(trees * kTreeVertices + 4, trees * kTreeTriangles + 2) +
              (size + 1) * sizeof(Mesh) * 2};
}

Scene generateForest(uint32_t size, uint64_t seed) {
  checkSize("forest", size, kMinSize, kMaxSize);
  const int n = static_cast<int>(size);
  const float half = 0.5f * kSpacing * n;
  Scene scene;
  scene.name = generatedSceneName("forest", {size, seed});

  Mesh ground;
  ground.name = "ground";
  const float edge = half + kSpacing;  // room for crowns that overhang the outermost trees
  addQuad(ground, {-edge, -edge, 0}, {edge, -edge, 0}, {edge, edge, 0}, {-edge, edge, 0});
  scene.meshes.push_back(std::move(ground));

  // A jittered grid of trees, one mesh per row.
  for (int row = 0; row < n; ++row) {
    Mesh trees;
    trees.name = fmt::format("trees_{:03}", row);
    for (int column = 0; column < n; ++column) {
      Rng rng(streamSeed(seed, static_cast<uint64_t>(row) * n + column));
      const glm::vec2 cell{(column + 0.5f) * kSpacing - half, (row + 0.5f) * kSpacing - half};
      const glm::vec2 jitter{rng.uniform(-0.35f, 0.35f), rng.uniform(-0.35f, 0.35f)};
      addTree(trees, cell + kSpacing * jitter, rng);
    }
    scene.meshes.push_back(std::move(trees));
  }
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
