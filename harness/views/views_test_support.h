// What the views tests share: a scene whose shadows have a closed form — a closed box floating
// over a large open ground quad.
#pragma once

#include <string>

#include "scenes/scene.h"

namespace sb::testing {

inline constexpr float kGroundHalf = 20;  // the ground quad spans [-20, 20]² at z = 0
inline const glm::vec3 kBoxMin{-1, -1, 1}, kBoxMax{1, 1, 2};

// An axis-aligned box as a closed mesh, each face counter-clockwise seen from outside.
inline Mesh boxMesh(const std::string& name, glm::vec3 lo, glm::vec3 hi) {
  Mesh mesh;
  mesh.name = name;
  mesh.closed = true;
  for (int corner = 0; corner < 8; ++corner)
    mesh.vertices.push_back(
        {corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z});
  // Corners are numbered x + 2y + 4z; each quad is listed counter-clockwise from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

inline Scene boxOverGround() {
  Scene scene;
  scene.name = "box-over-ground";
  Mesh ground;
  ground.name = "ground";
  ground.vertices = {{-kGroundHalf, -kGroundHalf, 0},
                     {kGroundHalf, -kGroundHalf, 0},
                     {kGroundHalf, kGroundHalf, 0},
                     {-kGroundHalf, kGroundHalf, 0}};
  ground.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.meshes.push_back(std::move(ground));
  scene.meshes.push_back(boxMesh("box", kBoxMin, kBoxMax));
  scene.lights = {defaultLight()};
  return scene;
}

}  // namespace sb::testing
