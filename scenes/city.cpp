// `city`: a closed city (a stand-in for the papers' ClosedCity): blocks of box buildings, some
// with stacked setbacks and spires, on a closed ground slab, or with `relief` on fractal hills.
//
// All coordinates of the buildings are whole metres, so they are exact in float and involve no
// rounding at all. Pieces of one building overlap (each tier starts a metre inside the one below,
// each building a metre inside the slab) instead of touching: coplanar faces make the front/back
// crossing count of closed-mode ray casting depend on the order of equal-depth hits.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "scenes/det_math.h"
#include "scenes/detail.h"
#include "scenes/heightfield.h"
#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 1, kMaxSize = 200;
constexpr uint32_t kMaxRelief = 1000;
constexpr int kBlockLand = 84;  // metres of building land per block side (divisible by 2, 3, 4)
constexpr int kStreet = 12;
constexpr int kPitch = kBlockLand + kStreet;
constexpr int kSlabThickness = 2;  // the slab spans z ∈ [-2, 0]
constexpr int kFoundation = 1;     // buildings start at z = -1, inside the slab
constexpr int kMinWidth = 6;       // no tier narrower than this
constexpr int kMaxLotsPerSide = 4;
constexpr int kMaxTiers = 3;           // set-back tiers above the base
constexpr int kRooftopQuarters = 4;    // at most one rooftop unit per quarter of the roof
constexpr int kHillCellsPerMetre = 2;  // the hills' grid

// The style knobs, in the order of cityStyleKnobs().
enum StyleKnobIndex { kRelief, kTurn };

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

// The ground the buildings stand on: flat at z = 0, or the top of the hills' heightfield, whose
// vertices lie every 1 / kHillCellsPerMetre metres from the city's corner.
class Ground {
 public:
  Ground(int half, std::vector<float> heights)
      : half_(half), cells_(2 * half * kHillCellsPerMetre), heights_(std::move(heights)) {}

  // The whole metres below and above the ground under `f`: the surface over a cell lies between
  // its corners' heights.
  std::pair<int, int> range(Footprint f) const {
    if (heights_.empty()) return {0, 0};
    float lo = heights_[0], hi = heights_[0];
    for (int j = (f.y0 + half_) * kHillCellsPerMetre; j <= (f.y1 + half_) * kHillCellsPerMetre; ++j)
      for (int i = (f.x0 + half_) * kHillCellsPerMetre; i <= (f.x1 + half_) * kHillCellsPerMetre;
           ++i) {
        const float h = heights_[size_t(j) * (cells_ + 1) + i];
        lo = std::min(lo, h), hi = std::max(hi, h);
      }
    return {static_cast<int>(std::floor(lo)), static_cast<int>(std::ceil(hi))};
  }

 private:
  int half_, cells_;
  std::vector<float> heights_;  // as the mesh stores them; empty when flat
};

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

// Turns the vertices from `first` on by `radians` about the centre of `lot`, shrunk so that any
// footprint inside the lot with a metre to spare stays so: a point at most d from the centre in
// x and y is, turned, at most d (|cos| + |sin|) from it.
void turnAboutCentre(Mesh& mesh, size_t first, Footprint lot, double radians) {
  const glm::dvec2 sinCos = portableSinCos(radians);
  const double shrink = 1.0 / (std::abs(sinCos.x) + std::abs(sinCos.y));
  const double cx = 0.5 * (lot.x0 + lot.x1), cy = 0.5 * (lot.y0 + lot.y1);
  for (size_t v = first; v < mesh.vertices.size(); ++v) {
    const double x = (mesh.vertices[v].x - cx) * shrink, y = (mesh.vertices[v].y - cy) * shrink;
    mesh.vertices[v].x = static_cast<float>(cx + sinCos.y * x - sinCos.x * y);
    mesh.vertices[v].y = static_cast<float>(cy + sinCos.x * x + sinCos.y * y);
  }
}

// One building on `lot`: a base box, up to three set-back tiers, then a spire or rooftop units.
// On hills it stands on the highest ground under its lot, and its base reaches a metre below the
// lowest; `turn` radians turn it about the lot's centre.
void addBuilding(Mesh& mesh, Footprint lot, int maxHeight, const Ground& ground, double turn,
                 Rng& rng) {
  const size_t firstVertex = mesh.vertices.size();
  // Heights are heavy-tailed (cube of a uniform draw): mostly low buildings, a few towers.
  const int64_t u = rng.between(0, 1000);
  const int height = 6 + static_cast<int>((maxHeight - 6) * u * u * u / 1'000'000'000);

  const int tiers =
      height >= 20 && rng.percent(70) ? static_cast<int>(rng.between(1, kMaxTiers)) : 0;
  Footprint f = inset(lot, 1, 4, rng);
  // A turned building stays inside its lot less a metre on each side (turnAboutCentre).
  const auto [low, high] =
      ground.range(turn == 0.0 ? f : Footprint{lot.x0 + 1, lot.y0 + 1, lot.x1 - 1, lot.y1 - 1});
  int bottom = low - high - kFoundation;
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
  for (size_t v = firstVertex; v < mesh.vertices.size(); ++v) mesh.vertices[v].z += float(high);
  if (turn != 0.0) turnAboutCentre(mesh, firstVertex, lot, turn);
}

// A block is divided into 2×2 (large buildings), 3×3 or 4×4 lots; a few lots stay empty.
// With `maxTurn` degrees, each lot's building turns by an angle uniform in [0, maxTurn], drawn
// from a stream of its own so that the buildings are those of the grid city, turned.
Mesh buildBlock(int bx, int by, int blocksPerSide, const Ground& ground, uint32_t maxTurn,
                uint64_t seed) {
  const uint64_t stream = static_cast<uint64_t>(by) * blocksPerSide + bx;
  Rng rng(streamSeed(seed, stream));
  Rng turns(streamSeed(seed, stream, 1));
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
      const double turn = maxTurn == 0 ? 0.0 : turns.unit() * maxTurn * (kPi / 180.0);
      if (rng.percent(8)) continue;  // a park
      const Footprint f{x0 + lx * lot, y0 + ly * lot, x0 + (lx + 1) * lot, y0 + (ly + 1) * lot};
      addBuilding(mesh, f, maxHeight, ground, turn, rng);
    }
  return mesh;
}

}  // namespace

std::vector<StyleKnob> cityStyleKnobs() {
  return {{"relief", "metres of fractal hills the city stands on (0: a flat slab)", kMaxRelief},
          {"turn", "degrees up to which each building turns about its lot's centre", 90}};
}

std::vector<GeneratorPreset> cityPresets() {
  // Fitted on `cpvs` closed at 4K²–64K² (README, "Calibrated stand-ins"): one block of towers,
  // turned, on a 400 m hill; seed 4 of the five tried.
  return {{"cityscape",
           1,
           4,
           {400, 90},
           "Scandolo & Eisemann 2021 Table 1, City, DAG (Scandolo et al. 2016 Table 1, "
           "CITYSCAPE, DAG): cpvs closed, 4K² to 64K²"}};
}

SceneFootprint cityFootprint(const GeneratorKnobs& knobs) {
  checkSize("city", knobs.size, kMinSize, kMaxSize);
  checkStyleKnobs("city", knobs, cityStyleKnobs());
  const uint64_t size = knobs.size;
  // Every lot built on, every building with a base, all tiers and four rooftop units (a spire
  // replaces the units): boxes of 8 vertices and 12 triangles; one ground slab, or the hills.
  constexpr uint64_t kBoxesPerBlock =
      kMaxLotsPerSide * kMaxLotsPerSide * (1 + kMaxTiers + kRooftopQuarters);
  const uint64_t boxes = size * size * kBoxesPerBlock + 1;
  SceneFootprint footprint{
      boxes * 8, boxes * 12,
      grownMeshBytes(boxes * 8, boxes * 12) + (size * size + 1) * sizeof(Mesh) * 2};
  if (knobs.styleKnob(kRelief) > 0) {
    const SceneFootprint hills = heightfieldFootprint(uint32_t(size * kPitch * kHillCellsPerMetre));
    footprint.vertices += hills.vertices, footprint.triangles += hills.triangles;
    footprint.bytes += hills.bytes + hills.vertices * sizeof(float);  // and the tops' copy
  }
  return footprint;
}

Scene generateCity(const GeneratorKnobs& knobs) {
  checkSize("city", knobs.size, kMinSize, kMaxSize);
  checkStyleKnobs("city", knobs, cityStyleKnobs());
  const int n = static_cast<int>(knobs.size);
  const uint32_t relief = knobs.styleKnob(kRelief);
  Scene scene;
  scene.name = generatedSceneName("city", knobs, cityStyleKnobs());

  Mesh ground;
  ground.name = "ground";
  ground.closed = true;
  const int half = n * kPitch / 2;
  std::vector<float> hillTops;
  if (relief == 0) {
    addBox(ground, {-half, -half, -kSlabThickness}, {half, half, 0});
  } else {
    // The hills' own stream of the seed: the blocks use streams 0 … n² - 1.
    const uint32_t cells = uint32_t(2 * half * kHillCellsPerMetre);
    addHeightfieldSolid(ground, cells, 2.0 * half,
                        fractalHeights(cells, streamSeed(knobs.seed, ~uint64_t{0})), relief,
                        -float(kSlabThickness));
    hillTops.reserve(size_t(cells + 1) * (cells + 1));
    for (size_t v = 0; v < size_t(cells + 1) * (cells + 1); ++v)
      hillTops.push_back(ground.vertices[v].z);
  }
  scene.meshes.push_back(std::move(ground));
  const Ground surface(half, std::move(hillTops));

  for (int by = 0; by < n; ++by)
    for (int bx = 0; bx < n; ++bx) {
      Mesh block = buildBlock(bx, by, n, surface, knobs.styleKnob(kTurn), knobs.seed);
      if (!block.triangles.empty()) scene.meshes.push_back(std::move(block));
    }
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
