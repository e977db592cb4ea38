#include "harness/views/scene_rays.h"

#include <algorithm>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <fmt/format.h>

namespace sb {

struct SceneRays::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<uint32_t> meshOfGeometry;  // empty meshes get no geometry, so ids skip them

  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void throwOnEmbreeError(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(fmt::format("Embree failed while {} (error {})", what, int(error)));
}

RTCRay makeRay(const glm::dvec3& origin, const glm::dvec3& direction, double tnear, double tfar) {
  RTCRay ray{};
  ray.org_x = float(origin.x), ray.org_y = float(origin.y), ray.org_z = float(origin.z);
  ray.dir_x = float(direction.x), ray.dir_y = float(direction.y), ray.dir_z = float(direction.z);
  ray.tnear = float(tnear);
  ray.tfar = float(tfar);
  ray.mask = ~0u;
  return ray;
}

}  // namespace

SceneRays::SceneRays(const Scene& scene) : embree_(std::make_unique<Embree>()) {
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device) throw std::runtime_error("Embree: cannot create a device");
  embree_->scene = rtcNewScene(embree_->device);
  // Robust traversal closes the cracks between triangles sharing an edge: a shadow ray must not
  // slip through a closed mesh along one of its seams.
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.triangles.empty()) continue;
    RTCGeometry geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.vertices.size()));
    std::copy_n(&mesh.vertices[0].x, 3 * mesh.vertices.size(), vertices);
    auto* indices = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), mesh.triangles.size()));
    std::copy_n(&mesh.triangles[0].x, 3 * mesh.triangles.size(), indices);
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(embree_->scene, geometry);
    rtcReleaseGeometry(geometry);
    embree_->meshOfGeometry.resize(std::max<size_t>(embree_->meshOfGeometry.size(), id + 1));
    embree_->meshOfGeometry[id] = m;
  }
  rtcCommitScene(embree_->scene);
  throwOnEmbreeError(embree_->device, "building the scene");
}

SceneRays::~SceneRays() = default;

SceneRays::Hit SceneRays::intersect(const glm::dvec3& origin, const glm::dvec3& direction,
                                    double tnear, double tfar) const {
  RTCRayHit ray{};
  ray.ray = makeRay(origin, direction, tnear, tfar);
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(embree_->scene, &context, &ray);
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return {ray.ray.tfar, glm::normalize(glm::dvec3(ray.hit.Ng_x, ray.hit.Ng_y, ray.hit.Ng_z)),
          embree_->meshOfGeometry[ray.hit.geomID], ray.hit.primID};
}

bool SceneRays::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tnear,
                         double tfar) const {
  RTCRay ray = makeRay(origin, direction, tnear, tfar);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(embree_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0;
}

}  // namespace sb
