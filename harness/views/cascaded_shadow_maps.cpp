#include "harness/views/cascaded_shadow_maps.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

namespace sb {

namespace {

// The four corners of the view frustum's cross-section at view depth w (distance along the
// forward axis).
std::array<glm::dvec3, 4> crossSection(const Camera& camera, double aspect, double w) {
  const CameraBasis b = basisOf(camera);
  const double h = std::tan(glm::radians(camera.fovYDegrees) / 2) * w, x = h * aspect;
  const glm::dvec3 centre = camera.eye + w * b.forward;
  return {centre - x * b.right - h * b.up, centre + x * b.right - h * b.up,
          centre - x * b.right + h * b.up, centre + x * b.right + h * b.up};
}

}  // namespace

CascadedShadowMaps::CascadedShadowMaps(const Scene& scene, const Light& light,
                                       const CsmSettings& settings)
    : scene_(scene), light_(light), settings_(settings) {}

std::vector<double> CascadedShadowMaps::splitDistances(double n, double f, uint32_t k,
                                                       double lambda) {
  std::vector<double> s(k + 1);
  for (uint32_t i = 0; i <= k; ++i) {
    const double t = double(i) / k;
    s[i] = lambda * n * std::pow(f / n, t) + (1 - lambda) * (n + (f - n) * t);
  }
  s.front() = n, s.back() = f;
  return s;
}

size_t CascadedShadowMaps::cascadeOf(double viewDepth) const {
  const auto at = std::upper_bound(splits_.begin() + 1, splits_.end() - 1, viewDepth);
  return size_t(at - (splits_.begin() + 1));
}

void CascadedShadowMaps::prepare(const Camera& camera, const GroundTruth& surface) {
  cascades_.clear();
  splits_.clear();
  if (settings_.fitScene) {
    for (uint32_t c = 0; c < settings_.cascades; ++c)
      cascades_.emplace_back(scene_, light_, glm::dvec2(0), 1.0, 0.0, 1.0, settings_.resolution);
    return;
  }
  const ViewDepthRange range = viewDepthRange(surface);
  if (!range.any) return;  // nothing visible, nothing to shadow
  // The frame's own depth bounds stand for the camera's near and far planes (as sample
  // distribution shadow maps fit them): no cascade is spent on depths the frame does not show.
  splits_ = splitDistances(range.nearest, range.farthest, settings_.cascades, settings_.lambda);
  const double aspect = double(surface.width) / surface.height;
  const double unit = light_.worldPerUnitWidth();
  for (uint32_t c = 0; c < settings_.cascades; ++c) {
    std::array<glm::dvec3, 8> corners;
    const auto nearSection = crossSection(camera, aspect, splits_[c]);
    const auto farSection = crossSection(camera, aspect, splits_[c + 1]);
    std::copy(nearSection.begin(), nearSection.end(), corners.begin());
    std::copy(farSection.begin(), farSection.end(), corners.begin() + 4);
    glm::dvec3 centre(0);
    for (const glm::dvec3& p : corners) centre += p / 8.0;
    double radius = 0;
    for (const glm::dvec3& p : corners) radius = std::max(radius, glm::distance(p, centre));
    // The sphere's square in light space, grown by a texel so that snapping its corner down to
    // the texel grid still leaves the whole sphere inside.
    const double texel = 2 * radius / unit / settings_.resolution;
    const double size = 2 * radius / unit + 2 * texel;
    const glm::dvec3 c0 = light_.toLightSpace(centre);
    const glm::dvec2 corner = glm::floor((glm::dvec2(c0) - size / 2) / texel) * texel;
    cascades_.emplace_back(scene_, light_, corner, size, 0.0, 1.0, settings_.resolution);
  }
}

void CascadedShadowMaps::shade(const Camera&, const GroundTruth& surface,
                               std::vector<float>& visibility) {
  visibility.assign(surface.covered.size(), 0.0f);
  tbb::parallel_for(size_t(0), surface.covered.size(), [&](size_t p) {
    if (!surface.covered[p]) return;
    const glm::dvec3 world(surface.position[p]);
    const OrthoShadowMap& cascade =
        settings_.fitScene ? cascades_.front() : cascades_[cascadeOf(surface.viewDepth[p])];
    if (!cascade.covers(light_.toLightSpace(world))) return visibility[p] = 1.0f, void();
    visibility[p] = cascade.lit(world, glm::dvec3(surface.normal[p]), settings_.bias) ? 1.0f : 0.0f;
  });
}

uint64_t CascadedShadowMaps::memoryBytes() const {
  uint64_t bytes = 0;
  for (const OrthoShadowMap& cascade : cascades_) bytes += cascade.bytes();
  return bytes;
}

nlohmann::json CascadedShadowMaps::frameLayout() const {
  return {{"splits", splits_}};
}

ViewTechniqueRow csmRow() {
  return {"csm",
          "cascaded shadow maps (Engel 2006), practical splits (Zhang et al. 2006); Alecu 2014's "
          "baseline",
          {ParamSpec::integer("cascades", "number of cascades", 3, 1, 8),
           ParamSpec::integer("resolution", "texels per side of each cascade", 1024, 8, 16384)
               .satisfying("a power of two",
                           [](int64_t v) { return std::has_single_bit(uint64_t(v)); }),
           ParamSpec::integer("lambda",
                              "practical split weight λ in percent (0 uniform, 100 logarithmic)",
                              50, 0, 100, {0, 25, 50, 75, 100}),
           ParamSpec::integer("constant-bias", "depth bias in hundredths of a texel", 50, 0, 10000),
           ParamSpec::integer("slope-bias", "slope-scaled depth bias in hundredths of a texel", 100,
                              0, 10000),
           ParamSpec::choice("fit", "cascade frusta: fitted to the view slices, or the whole scene",
                             "view-slices", {"view-slices", "scene"})},
          [](const Scene& scene, const Light& light, const ParamValues& values) {
            CsmSettings s;
            s.cascades = uint32_t(values.integer("cascades"));
            s.resolution = uint32_t(values.integer("resolution"));
            s.lambda = values.integer("lambda") / 100.0;
            s.bias.constantTexels = values.integer("constant-bias") / 100.0;
            s.bias.slopeTexels = values.integer("slope-bias") / 100.0;
            s.fitScene = values.choice("fit") == "scene";
            return std::make_unique<CascadedShadowMaps>(scene, light, s);
          }};
}

}  // namespace sb
