// Building blocks for generated meshes. Every closed piece (box, capped tube) is watertight and
// wound counter-clockwise seen from outside, so a mesh made of several of them is closed.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "scenes/det_math.h"
#include "scenes/scene.h"

namespace sb::detail {

inline uint32_t addVertex(Mesh& mesh, glm::vec3 p) {
  mesh.vertices.push_back(p);
  return static_cast<uint32_t>(mesh.vertices.size() - 1);
}

inline void addTriangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  mesh.triangles.push_back({a, b, c});
}

// A quad a-b-c-d, counter-clockwise seen from the side it faces.
inline void addQuad(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  addTriangle(mesh, a, b, c);
  addTriangle(mesh, a, c, d);
}

inline void addQuad(Mesh& mesh, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
  const uint32_t ia = addVertex(mesh, a), ib = addVertex(mesh, b);
  const uint32_t ic = addVertex(mesh, c), id = addVertex(mesh, d);
  addQuad(mesh, ia, ib, ic, id);
}

// An axis-aligned closed box: 8 vertices, 12 triangles.
inline void addBox(Mesh& mesh, glm::vec3 lo, glm::vec3 hi) {
  uint32_t corner[8];  // bit 0: x, bit 1: y, bit 2: z (0 = lo, 1 = hi)
  for (int i = 0; i < 8; ++i)
    corner[i] = addVertex(mesh, {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  addQuad(mesh, corner[0], corner[2], corner[3], corner[1]);  // -z
  addQuad(mesh, corner[4], corner[5], corner[7], corner[6]);  // +z
  addQuad(mesh, corner[0], corner[1], corner[5], corner[4]);  // -y
  addQuad(mesh, corner[2], corner[6], corner[7], corner[3]);  // +y
  addQuad(mesh, corner[0], corner[4], corner[6], corner[2]);  // -x
  addQuad(mesh, corner[1], corner[3], corner[7], corner[5]);  // +x
}

// A tube of `sides`-gon cross-sections along a polyline (at least 2 centres). Frames are
// parallel-transported, so the tube does not twist. Capped tubes are closed (a fan at each
// end); uncapped ones are open sleeves. The caller keeps the bending radius above the tube
// radius, otherwise the sleeve folds through itself.
inline void addTube(Mesh& mesh, std::span<const glm::vec3> centres, std::span<const float> radii,
                    int sides, bool capped) {
  const size_t rings = centres.size();
  std::vector<glm::vec2> circle(sides);
  for (int k = 0; k < sides; ++k) circle[k] = circlePoint(k, sides);

  auto segment = [&](size_t i) { return glm::normalize(centres[i + 1] - centres[i]); };
  glm::vec3 tangent = segment(0);
  // Any unit vector perpendicular to the first tangent starts the frame.
  const glm::vec3 axis = std::abs(tangent.x) < 0.6f ? glm::vec3{1, 0, 0} : glm::vec3{0, 1, 0};
  glm::vec3 normal = glm::normalize(glm::cross(tangent, axis));

  const uint32_t first = static_cast<uint32_t>(mesh.vertices.size());
  for (size_t i = 0; i < rings; ++i) {
    if (i > 0) {
      tangent = i + 1 < rings ? glm::normalize(segment(i - 1) + segment(i)) : segment(i - 1);
      normal = glm::normalize(normal - glm::dot(normal, tangent) * tangent);
    }
    const glm::vec3 binormal = glm::cross(tangent, normal);
    for (int k = 0; k < sides; ++k)
      addVertex(mesh, centres[i] + radii[i] * (circle[k].x * normal + circle[k].y * binormal));
  }

  auto ring = [&](size_t i, int k) { return first + static_cast<uint32_t>(i * sides + k % sides); };
  for (size_t i = 0; i + 1 < rings; ++i)
    for (int k = 0; k < sides; ++k)
      addQuad(mesh, ring(i, k), ring(i, k + 1), ring(i + 1, k + 1), ring(i + 1, k));

  if (!capped) return;
  const uint32_t start = addVertex(mesh, centres.front());
  const uint32_t end = addVertex(mesh, centres.back());
  for (int k = 0; k < sides; ++k) {
    addTriangle(mesh, start, ring(0, k + 1), ring(0, k));
    addTriangle(mesh, end, ring(rings - 1, k), ring(rings - 1, k + 1));
  }
}

}  // namespace sb::detail
