// `city`: a closed city (a stand-in for the papers' ClosedCity): blocks of box buildings, some
// with stacked setbacks and spires, on a closed ground slab.
//
// All coordinates are whole metres, so the geometry is exact in float and involves no rounding
// at all. Pieces of one building overlap (each tier starts a metre inside the one below, each
// building a metre inside the slab) instead of touching: coplanar faces make the front/back
// crossing count of closed-mode ray casting depend on the order of equal-depth hits.
#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include <fmt/format.h>

#include "scenes/detail.h"
#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 1, kMaxSize = 200;
constexpr int kBlockLand = 84;  // metres of building land per block side (divisible by 2, 3, 4)
constexpr int kStreet = 12;
constexpr int kPitch = kBlockLand + kStreet;
constexpr int kSlabThickness = 2;  // the slab spans z ∈ [-2, 0]
constexpr int kFoundation = 1;     // buildings start at z = -1, inside the slab
constexpr int kMinWidth = 6;       // no tier narrower than this
constexpr int kMaxLotsPerSide = 4;
constexpr int kMaxTiers = 3;         // set-back tiers above the base
constexpr int kRooftopQuarters = 4;  // at most one rooftop unit per quarter of the roof

struct Footprint {
  int x0, y0, x1, y1;
  int width() const { return std::min(x1 - x0, y1 - y0); }
};

// Shrinks each side independently by a random amount in [lo, hi] metres.
Footprint inset(Footprint f, int lo, int hi, Rng& rng) {
  f.x0 += static_cast<int>(rng.between(lo, hi));
  f.y0 += static_cast<int>(rng.between(lo, hi));
  f.x1 -= static_cast<int>(rng.between(lo, hi));
  f.y1 -= static_cast<int>(rng.between(lo, hi));
  return f;
}

void addBlock(Mesh& mesh, Footprint f, int z0, int z1) {
  addBox(mesh, {f.x0, f.y0, z0}, {f.x1, f.y1, z1});
}

// Downtown is tall, the outskirts low: the tallest height allowed for a block falls off
// quadratically with its (Chebyshev) distance from the centre of the city.
int heightLimit(int bx, int by, int blocksPerSide) {
  const int d =
      std::max(std::abs(2 * bx + 1 - blocksPerSide), std::abs(2 * by + 1 - blocksPerSide)) / 2;
  const int64_t reach = (blocksPerSide + 1) / 2;
  const int64_t closeness = reach - d;  // 1 at the edge … reach at the centre
  return static_cast<int>(24 + 176 * closeness * closeness / (reach * reach));
}

// Small rooftop structures (plant rooms, stair houses), at most one per quarter of the roof and
// strictly inside it, so that no two boxes of a building share a corner.
void addRooftopUnits(Mesh& mesh, Footprint roof, int top, Rng& rng) {
  const int midX = (roof.x0 + roof.x1) / 2, midY = (roof.y0 + roof.y1) / 2;
  const Footprint quarters[kRooftopQuarters] = {{roof.x0, roof.y0, midX, midY},
                                                {midX, roof.y0, roof.x1, midY},
                                                {roof.x0, midY, midX, roof.y1},
                                                {midX, midY, roof.x1, roof.y1}};
  for (const Footprint& quarter : quarters) {
    if (quarter.width() < 3 || !rng.percent(55)) continue;
    const Footprint unit = inset(quarter, 1, std::max(1, quarter.width() / 2 - 1), rng);
    addBlock(mesh, unit, top - 1, top + static_cast<int>(rng.between(2, 5)));
  }
}

// One building on `lot`: a base box, up to three set-back tiers, then a spire or rooftop units.
void addBuilding(Mesh& mesh, Footprint lot, int maxHeight, Rng& rng) {
  // Heights are heavy-tailed (cube of a uniform draw): mostly low buildings, a few towers.
  const int64_t u = rng.between(0, 1000);
  const int height = 6 + static_cast<int>((maxHeight - 6) * u * u * u / 1'000'000'000);

  const int tiers =
      height >= 20 && rng.percent(70) ? static_cast<int>(rng.between(1, kMaxTiers)) : 0;
  Footprint f = inset(lot, 1, 4, rng);
  int bottom = -kFoundation;
  int top = tiers == 0 ? height : height * static_cast<int>(rng.between(40, 70)) / 100;
  addBlock(mesh, f, bottom, top);
  for (int tier = 1; tier <= tiers; ++tier) {
    const Footprint inner = inset(f, 1, 3, rng);
    if (inner.width() < kMinWidth || height - top < 3) break;
    f = inner;
    bottom = top - 1;
    top =
        tier == tiers ? height : top + (height - top) * static_cast<int>(rng.between(40, 70)) / 100;
    addBlock(mesh, f, bottom, top);
  }

  if (top >= 60 && rng.percent(25)) {  // a spire, centred so that it stands strictly inside
    const int side = static_cast<int>(rng.between(2, 4));
    const int x0 = f.x0 + (f.x1 - f.x0 - side) / 2, y0 = f.y0 + (f.y1 - f.y0 - side) / 2;
    addBlock(mesh, {x0, y0, x0 + side, y0 + side}, top - 1,
             top + static_cast<int>(rng.between(5, 25)));
  } else {
    addRooftopUnits(mesh, f, top, rng);
  }
}

// A block is divided into 2×2 (large buildings), 3×3 or 4×4 lots; a few lots stay empty.
Mesh buildBlock(int bx, int by, int blocksPerSide, uint64_t seed) {
  Rng rng(streamSeed(seed, static_cast<uint64_t>(by) * blocksPerSide + bx));
  const int roll = static_cast<int>(rng.between(0, 99));
  const int lotsPerSide = roll < 15 ? 2 : roll < 50 ? 3 : kMaxLotsPerSide;
  const int lot = kBlockLand / lotsPerSide;
  const int half = blocksPerSide * kPitch / 2;
  const int x0 = bx * kPitch + kStreet / 2 - half, y0 = by * kPitch + kStreet / 2 - half;
  const int maxHeight = heightLimit(bx, by, blocksPerSide);

  Mesh mesh;
  mesh.name = fmt::format("block_{:03}_{:03}", bx, by);
  mesh.closed = true;
  for (int ly = 0; ly < lotsPerSide; ++ly)
    for (int lx = 0; lx < lotsPerSide; ++lx) {
      if (rng.percent(8)) continue;  // a park
      const Footprint f{x0 + lx * lot, y0 + ly * lot, x0 + (lx + 1) * lot, y0 + (ly + 1) * lot};
      addBuilding(mesh, f, maxHeight, rng);
    }
  return mesh;
}

}  // namespace

SceneFootprint cityFootprint(uint32_t size) {
  checkSize("city", size, kMinSize, kMaxSize);
  // Every lot built on, every building with a base, all tiers and four rooftop units (a spire
  // replaces the units): boxes of 8 vertices and 12 triangles; one ground slab.
  constexpr uint64_t kBoxesPerBlock =
      kMaxLotsPerSide * kMaxLotsPerSide * (1 + kMaxTiers + kRooftopQuarters);
  const uint64_t boxes = uint64_t{size} * size * kBoxesPerBlock + 1;
  return {boxes * 8, boxes * 12,
          grownMeshBytes(boxes * 8, boxes * 12) + (uint64_t{size} * size + 1) * sizeof(Mesh) * 2};
}

Scene generateCity(uint32_t size, uint64_t seed) {
  checkSize("city", size, kMinSize, kMaxSize);
  const int n = static_cast<int>(size);
  Scene scene;
  scene.name = generatedSceneName("city", size, seed);

  Mesh ground;
  ground.name = "ground";
  ground.closed = true;
  const int half = n * kPitch / 2;
  addBox(ground, {-half, -half, -kSlabThickness}, {half, half, 0});
  scene.meshes.push_back(std::move(ground));

  for (int by = 0; by < n; ++by)
    for (int bx = 0; bx < n; ++bx) {
      Mesh block = buildBlock(bx, by, n, seed);
      if (!block.triangles.empty()) scene.meshes.push_back(std::move(block));
    }
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
