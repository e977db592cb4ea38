#include "harness/views/scene_rays.h"

#include <embree3/rtcore.h>

#include "harness/embree_scene.h"

namespace sb {

struct SceneRays::Embree {
  explicit Embree(const Scene& scene)
      : rays(
            scene, [](const glm::vec3& v) { return v; }, RTC_SCENE_FLAG_NONE,
            RTC_BUILD_QUALITY_MEDIUM) {}
  EmbreeScene rays;
};

namespace {

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

SceneRays::SceneRays(const Scene& scene) : embree_(std::make_unique<Embree>(scene)) {}

SceneRays::~SceneRays() = default;

SceneRays::Hit SceneRays::intersect(const glm::dvec3& origin, const glm::dvec3& direction,
                                    double tnear, double tfar) const {
  RTCRayHit ray{};
  ray.ray = makeRay(origin, direction, tnear, tfar);
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(embree_->rays.scene(), &context, &ray);
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return {ray.ray.tfar, glm::normalize(glm::dvec3(ray.hit.Ng_x, ray.hit.Ng_y, ray.hit.Ng_z)),
          embree_->rays.meshOfGeometry()[ray.hit.geomID], ray.hit.primID};
}

bool SceneRays::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tnear,
                         double tfar) const {
  RTCRay ray = makeRay(origin, direction, tnear, tfar);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(embree_->rays.scene(), &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0;
}

}  // namespace sb
