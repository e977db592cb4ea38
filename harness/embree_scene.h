// One Embree device and scene over a Scene's meshes, each a triangle geometry: what the depth
// source (rays in the light's view space) and the view rays (world space) both cast against.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace sb {

class EmbreeScene {
 public:
  // Every mesh with triangles, its vertices mapped by `place` into the space rays are cast in.
  // Traversal is robust (no cracks between triangles sharing an edge, which a closed mesh's
  // counter and a shadow ray along a seam both depend on), plus `flags`.
  EmbreeScene(const Scene& scene, const std::function<glm::vec3(const glm::vec3&)>& place,
              RTCSceneFlags flags, RTCBuildQuality quality);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene scene() const { return scene_; }
  // Per Embree geometry id, the index of its mesh in Scene::meshes (empty meshes get no id).
  const std::vector<uint32_t>& meshOfGeometry() const { return meshOfGeometry_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<uint32_t> meshOfGeometry_;
};

}  // namespace sb
