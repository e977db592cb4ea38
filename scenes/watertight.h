// Whether a mesh is a closed surface: the promise a closed mesh makes (Mesh::closed) and the
// precondition of the closed-object optimisation (Sintorn §6.1, Kämpe §3.3), checked for the
// meshes a user declares closed and reported by `scene info`.
#pragma once

#include <cstdint>
#include <string>

#include "scenes/scene.h"

namespace sb {

// Edges are taken between vertex *positions* (vertices at the same position are one, -0 = +0),
// since a model file may repeat a vertex per face. A triangle with two corners at one position
// has no area, so no ray crosses it: it is counted and otherwise ignored.
struct Watertightness {
  uint64_t edges = 0;                // distinct edges of the non-degenerate triangles
  uint64_t boundaryEdges = 0;        // in one triangle only: the rim of a hole
  uint64_t misorientedEdges = 0;     // in two triangles that run it the same way: a flipped face
  uint64_t nonManifoldEdges = 0;     // in more than two triangles
  uint64_t degenerateTriangles = 0;  // two corners at one position

  // Edges not shared by exactly two triangles of opposite orientation.
  uint64_t openEdges() const { return boundaryEdges + misorientedEdges + nonManifoldEdges; }
  bool watertight() const { return openEdges() == 0; }
  // "watertight" or "not watertight: 12 open edges (10 on holes, 2 between faces wound
  // against each other)".
  std::string describe() const;
};

Watertightness checkWatertight(const Mesh& mesh);

// The signed volume enclosed by the mesh (divergence theorem): positive when a watertight mesh
// is wound counter-clockwise seen from outside, negative when it is inside out.
double enclosedVolume(const Mesh& mesh);

}  // namespace sb
