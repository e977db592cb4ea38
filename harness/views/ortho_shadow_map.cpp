#include "harness/views/ortho_shadow_map.h"

#include <algorithm>
#include <cmath>

#include "harness/light_space_rasterizer.h"

namespace sb {

OrthoShadowMap::OrthoShadowMap(const Scene& scene, const Light& parent, glm::dvec2 corner,
                               double size, double zNear, double zFar, uint32_t resolution)
    : light_(parent.window(corner, size, zNear, zFar)),
      corner_(corner),
      size_(size),
      resolution_(resolution),
      towardsLight_(-glm::normalize(glm::dvec3(parent.spec().direction))) {
  const LightSpaceRasterizer rasterizer(scene, light_, resolution);
  depth_.resize(size_t(resolution) * resolution);
  std::vector<float> unused(depth_.size());
  rasterizer.rasterize(0, 0, resolution, resolution, DepthMode::Open, depth_.data(), unused.data(),
                       resolution);
}

bool OrthoShadowMap::covers(const glm::dvec3& p) const {
  return p.x >= corner_.x && p.y >= corner_.y && p.x < corner_.x + size_ && p.y < corner_.y + size_;
}

bool OrthoShadowMap::lit(const glm::dvec3& world, const glm::dvec3& normal,
                         const DepthBias& bias) const {
  const glm::dvec3 v = light_.toView(world);
  const auto texel = [&](double u) {
    return std::clamp<int64_t>(int64_t(std::floor(u * resolution_)), 0, resolution_ - 1);
  };
  const float stored = depth_[size_t(texel(v.y)) * resolution_ + size_t(texel(v.x))];
  const double cosine = std::max(std::abs(glm::dot(normal, towardsLight_)), 1e-6);
  const double slope =
      std::min(std::sqrt(std::max(0.0, 1 - cosine * cosine)) / cosine, bias.maxSlope);
  const double texelWorld = light_.worldPerUnitWidth() / resolution_;
  const double biasDepth =
      texelWorld * (bias.constantTexels + bias.slopeTexels * slope) / light_.worldPerUnitDepth();
  return v.z - biasDepth <= stored;
}

}  // namespace sb
