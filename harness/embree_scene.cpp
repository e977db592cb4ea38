#include "harness/embree_scene.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace sb {

EmbreeScene::EmbreeScene(const Scene& scene,
                         const std::function<glm::vec3(const glm::vec3&)>& place,
                         RTCSceneFlags flags, RTCBuildQuality quality) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | flags));
  rtcSetSceneBuildQuality(scene_, quality);
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.triangles.empty()) continue;
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.vertices.size()));
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
      const glm::vec3 p = place(mesh.vertices[v]);
      vertices[3 * v + 0] = p.x, vertices[3 * v + 1] = p.y, vertices[3 * v + 2] = p.z;
    }
    auto* indices = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), mesh.triangles.size()));
    std::copy_n(&mesh.triangles[0].x, 3 * mesh.triangles.size(), indices);
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    meshOfGeometry_.resize(std::max<size_t>(meshOfGeometry_.size(), id + 1));
    meshOfGeometry_[id] = m;
  }
  rtcCommitScene(scene_);
  if (const RTCError error = rtcGetDeviceError(device_); error != RTC_ERROR_NONE) {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
    throw std::runtime_error(
        fmt::format("Embree failed while building the scene (error {})", int(error)));
  }
}

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

}  // namespace sb
