// Fractal relief as a closed solid, shared by `terrain` and the hills under `city`.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "scenes/scene.h"

namespace sb::detail {

// Fractal (fBm) heights in [0, 1] on the (cells+1)² grid, row by row: octaves of value noise
// of doubling frequency and halving amplitude down to the grid spacing, stretched to [0, 1]
// and squared, which flattens the valleys and sharpens the peaks as in real relief. Exact
// rationals and + × in double: the same bytes on every machine.
std::vector<double> fractalHeights(uint32_t cells, uint64_t seed);

// A closed solid over the square of side `extent` centred on the origin: the top through the
// (cells+1)² grid at heights `relief` × `heights`, four vertical walls down to `bottom` and a flat
// underside, wound outward.
void addHeightfieldSolid(Mesh& mesh, uint32_t cells, double extent, std::span<const double> heights,
                         double relief, float bottom);

// What addHeightfieldSolid adds (it reserves exactly) and fractalHeights holds while it runs.
SceneFootprint heightfieldFootprint(uint32_t cells);

}  // namespace sb::detail
