// `terrain`: a closed fractal landscape (a stand-in for the papers' terrain scenes): a
// heightfield of fractal value noise as the top surface, closed by four vertical walls and a
// flat bottom into one watertight solid.
//
// Noise lattice coordinates are exact rationals (integer grid index × lattice cells / grid
// cells), and the rest is + and × in double, so the heights are the same on every machine.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "scenes/detail.h"
#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

constexpr uint32_t kMinSize = 2, kMaxSize = 4096;
constexpr double kExtent = 1000.0;  // metres per side, centred on the origin
constexpr double kRelief = 200.0;   // height of the highest peak above the lowest valley
constexpr float kBottom = -50.0f;   // the flat underside

// A random value in [0, 1) at an integer lattice point of one octave.
double latticeValue(uint64_t seed, int octave, int64_t ix, int64_t iy) {
  const uint64_t h = streamSeed(seed, static_cast<uint64_t>(octave),
                                static_cast<uint64_t>(ix) << 32 | static_cast<uint64_t>(iy));
  return static_cast<double>(h >> 11) * 0x1p-53;
}

// Quintic fade (Perlin 2002): lattice seams have continuous slope and curvature.
double fade(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Value noise of an octave with `cells` lattice cells across the map, at grid vertex (i, j) of
// a grid with `gridCells` cells across.
double valueNoise(uint64_t seed, int octave, int64_t cells, int64_t i, int64_t j,
                  int64_t gridCells) {
  const int64_t xi = i * cells / gridCells, yi = j * cells / gridCells;
  const double fx =
      fade(static_cast<double>(i * cells % gridCells) / static_cast<double>(gridCells));
  const double fy =
      fade(static_cast<double>(j * cells % gridCells) / static_cast<double>(gridCells));
  const double v00 = latticeValue(seed, octave, xi, yi),
               v10 = latticeValue(seed, octave, xi + 1, yi);
  const double v01 = latticeValue(seed, octave, xi, yi + 1);
  const double v11 = latticeValue(seed, octave, xi + 1, yi + 1);
  const double bottom = v00 + (v10 - v00) * fx, top = v01 + (v11 - v01) * fx;
  return bottom + (top - bottom) * fy;
}

// Fractal (fBm) heights on the (n+1)² grid: octaves of doubling frequency and halving
// amplitude, down to the grid spacing; then stretched to [0, 1] and squared, which flattens
// the valleys and sharpens the peaks as in real relief.
std::vector<double> fractalHeights(uint32_t n, uint64_t seed) {
  const int64_t cells = n;
  std::vector<double> height(static_cast<size_t>(n + 1) * (n + 1), 0.0);
  double amplitude = 1.0;
  for (int octave = 0; int64_t{2} << octave <= cells; ++octave, amplitude *= 0.5)
    for (int64_t j = 0; j <= cells; ++j)
      for (int64_t i = 0; i <= cells; ++i)
        height[j * (cells + 1) + i] +=
            amplitude * valueNoise(seed, octave, int64_t{2} << octave, i, j, cells);

  const auto [lo, hi] = std::minmax_element(height.begin(), height.end());
  const double low = *lo, range = std::max(*hi - *lo, 1e-9);
  for (double& h : height) {
    const double t = (h - low) / range;
    h = t * t;
  }
  return height;
}

// Boundary grid vertices in counter-clockwise order seen from above, starting at (0, 0).
std::vector<uint32_t> boundaryLoop(uint32_t n) {
  auto index = [n](uint32_t i, uint32_t j) { return j * (n + 1) + i; };
  std::vector<uint32_t> loop;
  loop.reserve(4 * n);
  for (uint32_t i = 0; i < n; ++i) loop.push_back(index(i, 0));
  for (uint32_t j = 0; j < n; ++j) loop.push_back(index(n, j));
  for (uint32_t i = n; i > 0; --i) loop.push_back(index(i, n));
  for (uint32_t j = n; j > 0; --j) loop.push_back(index(0, j));
  return loop;
}

}  // namespace

SceneFootprint terrainFootprint(uint32_t size) {
  checkSize("terrain", size, kMinSize, kMaxSize);
  // The grid, a bottom copy of its boundary and a centre; two triangles per cell, two per wall
  // quad and one per bottom fan segment. The mesh is reserved exactly; the heights are doubles.
  const uint64_t n = size, gridVertices = (n + 1) * (n + 1);
  const uint64_t vertices = gridVertices + 4 * n + 1, triangles = 2 * n * n + 12 * n;
  return {vertices, triangles,
          vertices * sizeof(glm::vec3) + triangles * sizeof(glm::uvec3) +
              gridVertices * sizeof(double) + 4 * n * sizeof(uint32_t)};
}

Scene generateTerrain(uint32_t size, uint64_t seed) {
  checkSize("terrain", size, kMinSize, kMaxSize);
  const uint32_t n = size;
  const std::vector<double> height = fractalHeights(n, seed);

  Mesh mesh;
  mesh.name = "terrain";
  mesh.closed = true;
  mesh.vertices.reserve(static_cast<size_t>(n + 1) * (n + 1) + 4 * n + 1);
  mesh.triangles.reserve(2 * static_cast<size_t>(n) * n + 12 * n);
  auto coordinate = [n](uint32_t i) {
    return static_cast<float>(-0.5 * kExtent + kExtent * i / n);
  };
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i)
      addVertex(mesh, {coordinate(i), coordinate(j),
                       static_cast<float>(kRelief * height[j * (n + 1) + i])});

  // Top: two triangles per cell, split along alternating diagonals so that the surface has no
  // preferred direction.
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v00 = j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        addTriangle(mesh, v00, v10, v11);
        addTriangle(mesh, v00, v11, v01);
      } else {
        addTriangle(mesh, v00, v10, v01);
        addTriangle(mesh, v10, v11, v01);
      }
    }

  // Walls: each boundary edge of the top drops to a copy of its vertices at the bottom level.
  const std::vector<uint32_t> loop = boundaryLoop(n);
  const uint32_t firstBottom = static_cast<uint32_t>(mesh.vertices.size());
  for (uint32_t top : loop) addVertex(mesh, {mesh.vertices[top].x, mesh.vertices[top].y, kBottom});
  const uint32_t loopSize = static_cast<uint32_t>(loop.size());
  for (uint32_t k = 0; k < loopSize; ++k) {
    const uint32_t next = (k + 1) % loopSize;
    addQuad(mesh, firstBottom + k, firstBottom + next, loop[next], loop[k]);
  }

  // Bottom: a fan around the centre, facing down.
  const uint32_t centre = addVertex(mesh, {0.0f, 0.0f, kBottom});
  for (uint32_t k = 0; k < loopSize; ++k)
    addTriangle(mesh, centre, firstBottom + (k + 1) % loopSize, firstBottom + k);

  Scene scene;
  scene.name = generatedSceneName("terrain", size, seed);
  scene.meshes.push_back(std::move(mesh));
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::detail
