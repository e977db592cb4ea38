#include "scenes/heightfield.h"

#include <algorithm>
#include <cstdint>

#include "scenes/mesh_builder.h"
#include "scenes/random.h"

namespace sb::detail {
namespace {

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

void addHeightfieldSolid(Mesh& mesh, uint32_t cells, double extent, std::span<const double> heights,
                         double relief, float bottom) {
  const uint32_t n = cells;
  mesh.vertices.reserve(mesh.vertices.size() + static_cast<size_t>(n + 1) * (n + 1) + 4 * n + 1);
  mesh.triangles.reserve(mesh.triangles.size() + 2 * static_cast<size_t>(n) * n + 12 * n);
  const uint32_t first = static_cast<uint32_t>(mesh.vertices.size());
  auto coordinate = [&](uint32_t i) { return static_cast<float>(-0.5 * extent + extent * i / n); };
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i)
      addVertex(mesh, {coordinate(i), coordinate(j),
                       static_cast<float>(relief * heights[j * (n + 1) + i])});

  // Top: two triangles per cell, split along alternating diagonals so that the surface has no
  // preferred direction.
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v00 = first + j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
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
  for (uint32_t top : loop)
    addVertex(mesh, {mesh.vertices[first + top].x, mesh.vertices[first + top].y, bottom});
  const uint32_t loopSize = static_cast<uint32_t>(loop.size());
  for (uint32_t k = 0; k < loopSize; ++k) {
    const uint32_t next = (k + 1) % loopSize;
    addQuad(mesh, firstBottom + k, firstBottom + next, first + loop[next], first + loop[k]);
  }

  // Bottom: a fan around the centre, facing down.
  const uint32_t centre = addVertex(mesh, {0.0f, 0.0f, bottom});
  for (uint32_t k = 0; k < loopSize; ++k)
    addTriangle(mesh, centre, firstBottom + (k + 1) % loopSize, firstBottom + k);
}

SceneFootprint heightfieldFootprint(uint32_t cells) {
  // The grid, a bottom copy of its boundary and a centre; two triangles per cell, two per wall
  // quad and one per bottom fan segment; the heights are doubles.
  const uint64_t n = cells, gridVertices = (n + 1) * (n + 1);
  const uint64_t vertices = gridVertices + 4 * n + 1, triangles = 2 * n * n + 12 * n;
  return {vertices, triangles,
          vertices * sizeof(glm::vec3) + triangles * sizeof(glm::uvec3) +
              gridVertices * sizeof(double) + 4 * n * sizeof(uint32_t)};
}

}  // namespace sb::detail
