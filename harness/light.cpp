#include "harness/light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace sb {

namespace {

// A right-handed frame (x, y, z) with z along `forward`.
void frameAlong(glm::dvec3 forward, glm::dvec3& x, glm::dvec3& y, glm::dvec3& z) {
  if (!(glm::length(forward) > 0.0) || !std::isfinite(glm::length(forward)))
    throw std::invalid_argument("light direction must be a finite non-zero vector");
  z = glm::normalize(forward);
  const glm::dvec3 helper = std::abs(z.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  x = glm::normalize(glm::cross(z, helper));
  y = glm::cross(z, x);
}

template <class F>
void forEachVertex(const Scene& scene, F&& f) {
  for (const Mesh& mesh : scene.meshes)
    for (const glm::vec3& v : mesh.vertices) f(glm::dvec3(v));
}

}  // namespace

Light Light::fit(const LightSpec& spec, const Scene& scene) {
  Light light;
  light.spec_ = spec;
  frameAlong(glm::dvec3(spec.direction), light.axisX_, light.axisY_, light.axisZ_);
  constexpr double inf = std::numeric_limits<double>::infinity();
  glm::dvec3 lo(inf), hi(-inf);

  if (spec.kind == LightKind::Directional) {
    forEachVertex(scene, [&](glm::dvec3 p) {
      const glm::dvec3 q(glm::dot(p, light.axisX_), glm::dot(p, light.axisY_),
                         glm::dot(p, light.axisZ_));
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    });
    if (!(lo.x <= hi.x))
      throw std::invalid_argument("cannot fit a light to a scene without vertices");
    // A square footprint (square texels in world space) and a depth range, each padded so
    // that every vertex lies strictly inside; a flat scene still gets a depth range.
    const double footprint = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6}) * (1.0 + 1.0 / 64);
    const double depthRange = std::max(hi.z - lo.z, footprint / 1024) * (1.0 + 1.0 / 64);
    const glm::dvec3 centre = (lo + hi) * 0.5;
    light.origin_ = {centre.x - footprint / 2, centre.y - footprint / 2, centre.z - depthRange / 2};
    light.scale_ = {1.0 / footprint, 1.0 / footprint, 1.0 / depthRange};
    return light;
  }

  if (!isValidSpotFov(spec.fovDegrees))
    throw std::invalid_argument(
        fmt::format("spot light fov {} degrees is outside the accepted range (0, {})",
                    spec.fovDegrees, kMaxSpotFovDegrees));
  light.origin_ = glm::dvec3(spec.position);
  light.tanHalfFov_ = std::tan(glm::radians(double(spec.fovDegrees)) / 2);
  double nearest = inf, farthest = 0;
  forEachVertex(scene, [&](glm::dvec3 p) {
    const double z = glm::dot(p - light.origin_, light.axisZ_);
    if (z > 0) nearest = std::min(nearest, z);
    farthest = std::max(farthest, z);
  });
  if (!(farthest > 0))
    throw std::invalid_argument("spot light: the whole scene lies behind the light");
  light.far_ = farthest * (1.0 + 1.0 / 64);
  light.near_ = std::max(nearest * (1.0 - 1.0 / 64), light.far_ * 1e-4);
  return light;
}

glm::dvec3 Light::toView(const glm::dvec3& world) const {
  if (spec_.kind == LightKind::Directional) {
    const glm::dvec3 q(glm::dot(world, axisX_), glm::dot(world, axisY_), glm::dot(world, axisZ_));
    return (q - origin_) * scale_;
  }
  const glm::dvec3 d = world - origin_;
  return {glm::dot(d, axisX_), glm::dot(d, axisY_), glm::dot(d, axisZ_)};
}

glm::dvec3 Light::normalToWorld(const glm::dvec3& n) const {
  // Normals map by the inverse transpose of view = scale · rotation · world: rotationᵀ · scale.
  return n.x * scale_.x * axisX_ + n.y * scale_.y * axisY_ + n.z * scale_.z * axisZ_;
}

double Light::depthOfViewZ(double viewZ) const {
  if (spec_.depth == DepthDistribution::Logarithmic)
    return std::log(viewZ / near_) / std::log(far_ / near_);  // Kämpe eq. 1, without the N
  return (viewZ - near_) / (far_ - near_);
}

glm::dvec3 Light::toLightSpace(const glm::dvec3& world) const {
  const glm::dvec3 v = toView(world);
  if (spec_.kind == LightKind::Directional) return v;
  return {(v.x / (v.z * tanHalfFov_) + 1) / 2, (v.y / (v.z * tanHalfFov_) + 1) / 2,
          depthOfViewZ(v.z)};
}

Light Light::window(glm::dvec2 corner, double size, double zNear, double zFar) const {
  if (spec_.kind != LightKind::Directional)
    throw std::invalid_argument("only a directional light has orthographic windows");
  if (!(size > 0) || !(zFar > zNear))
    throw std::invalid_argument(
        fmt::format("light window of size {} and depth [{}, {}] is empty", size, zNear, zFar));
  // view' = (view − (corner, zNear)) / (size, size, zFar − zNear), with view = (q − origin)·scale.
  Light light = *this;
  light.origin_ += glm::dvec3(corner.x, corner.y, zNear) / scale_;
  light.scale_ /= glm::dvec3(size, size, zFar - zNear);
  return light;
}

PrimaryRay Light::texelRay(uint32_t i, uint32_t j, uint32_t resolution) const {
  const double x = (i + 0.5) / resolution, y = (j + 0.5) / resolution;
  if (spec_.kind == LightKind::Directional)
    return {glm::vec3(x, y, 0.0), glm::vec3(0, 0, 1), 0.0f, std::numeric_limits<float>::infinity()};
  return {glm::vec3(0.0f), glm::vec3((2 * x - 1) * tanHalfFov_, (2 * y - 1) * tanHalfFov_, 1.0),
          float(near_), float(far_)};
}

float Light::depthOfHit(float t) const {
  if (spec_.kind == LightKind::Directional) return t;
  return float(std::clamp(depthOfViewZ(t), 0.0, 1.0));
}

nlohmann::json Light::describe() const {
  auto vec = [](glm::vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  nlohmann::json json{{"type", spec_.kind == LightKind::Directional ? "directional" : "spot"},
                      {"direction", vec(spec_.direction)}};
  if (spec_.kind == LightKind::Spot) {
    json["position"] = vec(spec_.position);
    json["fov_degrees"] = spec_.fovDegrees;
    json["depth"] = spec_.depth == DepthDistribution::Logarithmic ? "log" : "linear";
    json["near"] = near_;
    json["far"] = far_;
  }
  return json;
}

}  // namespace sb
