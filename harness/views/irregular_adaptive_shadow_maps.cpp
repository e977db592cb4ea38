#include "harness/views/irregular_adaptive_shadow_maps.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace sb {

namespace {

// Importance in fixed point: 2^16 per unit of p, summed in integers.
constexpr double kImportanceScale = 65536.0;

}  // namespace

IrregularAdaptiveShadowMaps::IrregularAdaptiveShadowMaps(const Scene& scene, const Light& light,
                                                         IasmSettings settings)
    : scene_(scene), light_(light), settings_(std::move(settings)) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (const Mesh& mesh : scene.meshes) {
    glm::dvec3 lo(inf), hi(-inf);
    for (const glm::vec3& v : mesh.vertices) {
      const glm::dvec3 p = light.toLightSpace(glm::dvec3(v));
      lo = glm::min(lo, p), hi = glm::max(hi, p);
    }
    meshDepthRange_.emplace_back(lo.z, hi.z);
    meshFootprint_.emplace_back(lo.x, lo.y, hi.x, hi.y);
  }
  importance_.assign(size_t(settings_.grid) * settings_.grid, 0);
}

double IrregularAdaptiveShadowMaps::coveringSide(const GroundTruth& surface, glm::dvec2 eye,
                                                 glm::dvec2 ahead) const {
  // A point d = p − eye lies in the square of side s centred at eye + ahead·s/2 when, on each
  // axis, (a − ½)·s ≤ d ≤ (a + ½)·s with a = ahead/2 ∈ [−½, ½]: a lower bound on s per point.
  double side = 1e-9;
  for (size_t p = 0; p < surface.covered.size(); ++p) {
    if (!surface.covered[p]) continue;
    const glm::dvec2 d = glm::dvec2(light_.toLightSpace(glm::dvec3(surface.position[p]))) - eye;
    for (int axis = 0; axis < 2; ++axis) {
      const double a = ahead[axis] / 2;
      if (d[axis] > 0) side = std::max(side, a + 0.5 > 0 ? d[axis] / (a + 0.5) : 1e300);
      if (d[axis] < 0) side = std::max(side, a - 0.5 < 0 ? d[axis] / (a - 0.5) : 1e300);
    }
  }
  // Grown a little, so that a point on the far edge still falls inside the half-open square.
  return std::min(side * (1 + 1e-6), 4.0);
}

std::optional<uint32_t> IrregularAdaptiveShadowMaps::tileOf(const glm::dvec3& p) const {
  const glm::dvec2 local = (glm::dvec2(p) - corner_) / side_ * double(settings_.grid);
  if (!(local.x >= 0 && local.y >= 0 && local.x < settings_.grid && local.y < settings_.grid))
    return std::nullopt;
  return uint32_t(local.y) * settings_.grid + uint32_t(local.x);
}

void IrregularAdaptiveShadowMaps::accumulateImportance(const GroundTruth& surface) {
  const double k = settings_.kFraction * side_ * light_.worldPerUnitWidth();
  tbb::combinable<std::vector<uint64_t>> partial(
      [&] { return std::vector<uint64_t>(importance_.size(), 0); });
  tbb::parallel_for(size_t(0), surface.covered.size(), [&](size_t p) {
    if (!surface.covered[p]) return;
    const auto tile = tileOf(light_.toLightSpace(glm::dvec3(surface.position[p])));
    if (!tile) return;
    const double importance =
        1 + settings_.m * std::clamp(1 - surface.viewDepth[p] / k, 0.0, 1.0);  // eq. 3.1
    partial.local()[*tile] += uint64_t(std::llround(importance * kImportanceScale));
  });
  std::fill(importance_.begin(), importance_.end(), 0);
  partial.combine_each([&](const std::vector<uint64_t>& sums) {
    for (size_t t = 0; t < sums.size(); ++t) importance_[t] += sums[t];
  });
  haveImportance_ = true;
}

void IrregularAdaptiveShadowMaps::prepare(const Camera& camera, const GroundTruth& surface) {
  const uint32_t g = settings_.grid, count = g * g;
  eye_ = glm::dvec2(light_.toLightSpace(camera.eye));
  if (settings_.placeOverScene) {
    corner_ = glm::dvec2(0), side_ = 1;
  } else {
    // Fig. 3.1: the camera on the circle inscribed in the square, the square's centre ahead of
    // it along the view direction as the light sees it. The thesis sizes the square to hold the
    // scene; here it is the least square so placed that holds every visible point (the whole
    // frame is shadowed, as CSM's cascades shadow it), times `extent`.
    glm::dvec2 ahead = glm::dvec2(light_.toLightSpace(camera.target)) - eye_;
    ahead = glm::length(ahead) > 0 ? glm::normalize(ahead) : glm::dvec2(0);
    side_ = coveringSide(surface, eye_, ahead) * settings_.extentFraction;
    corner_ = eye_ + ahead * (side_ / 2) - side_ / 2;
  }
  // §3.4: the first frame has no previous frame; it is ranked by its own analysis, as every frame
  // is with `same-frame` (the ranking a perfectly coherent camera would get).
  if (!haveImportance_ || settings_.sameFrameImportance) accumulateImportance(surface);
  std::vector<uint32_t> byRank(count);
  std::iota(byRank.begin(), byRank.end(), 0u);
  std::stable_sort(byRank.begin(), byRank.end(),
                   [&](uint32_t a, uint32_t b) { return importance_[a] > importance_[b]; });
  tileResolution_.assign(count, 0);
  for (uint32_t rank = 0; rank < count; ++rank)
    tileResolution_[byRank[rank]] = settings_.resolutions[rank];

  tiles_.clear();
  tiles_.resize(count);
  tileDepthRange_.assign(count, glm::dvec2(0));
  const double tileSide = side_ / g;
  for (uint32_t t = 0; t < count; ++t) {
    const glm::dvec2 corner = corner_ + tileSide * glm::dvec2(t % g, t / g);
    // §3.5: near and far from the objects whose footprint overlaps the tile's frustum; over the
    // whole scene, the light's own (a plain shadow map).
    if (settings_.placeOverScene) {
      tileDepthRange_[t] = {0, 1};
      tiles_[t].emplace(scene_, light_, corner, tileSide, 0.0, 1.0, tileResolution_[t]);
      continue;
    }
    glm::dvec2 depth(std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity());
    for (size_t m = 0; m < meshFootprint_.size(); ++m) {
      const glm::dvec4& f = meshFootprint_[m];
      if (f.z < corner.x || f.w < corner.y || f.x > corner.x + tileSide ||
          f.y > corner.y + tileSide)
        continue;
      depth = {std::min(depth.x, meshDepthRange_[m].x), std::max(depth.y, meshDepthRange_[m].y)};
    }
    if (!(depth.x < depth.y)) continue;  // empty: nothing renders into it, every lookup is lit
    tileDepthRange_[t] = depth;
    tiles_[t].emplace(scene_, light_, corner, tileSide, depth.x, depth.y, tileResolution_[t]);
  }
}

void IrregularAdaptiveShadowMaps::shade(const Camera&, const GroundTruth& surface,
                                        std::vector<float>& visibility) {
  visibility.assign(surface.covered.size(), 0.0f);
  tbb::parallel_for(size_t(0), surface.covered.size(), [&](size_t p) {
    if (!surface.covered[p]) return;
    const glm::dvec3 world(surface.position[p]);
    const auto tile = tileOf(light_.toLightSpace(world));
    const bool lit = !tile || !tiles_[*tile] ||
                     tiles_[*tile]->lit(world, glm::dvec3(surface.normal[p]), settings_.bias);
    visibility[p] = lit ? 1.0f : 0.0f;
  });
  accumulateImportance(surface);  // §3.3: for the next frame
}

uint64_t IrregularAdaptiveShadowMaps::memoryBytes() const {
  // The structured buffer holds every tile at its resolution, rendered into or not (§3.2).
  uint64_t texels = 0;
  for (uint32_t r : settings_.resolutions) texels += uint64_t(r) * r;
  return texels * sizeof(float);
}

nlohmann::json IrregularAdaptiveShadowMaps::frameLayout() const {
  nlohmann::json near = nlohmann::json::array(), far = nlohmann::json::array();
  for (const glm::dvec2& d : tileDepthRange_) near.push_back(d.x), far.push_back(d.y);
  return {{"square", {corner_.x, corner_.y, side_}},
          {"eye", {eye_.x, eye_.y}},
          {"tile_resolutions", tileResolution_},
          {"tile_near", near},
          {"tile_far", far}};
}

namespace {

// The named resolution sets, each grid² resolutions largest first.
std::vector<uint32_t> resolutionSet(const std::string& name) {
  if (name == "alecu")  // Alecu §4.2
    return {1024, 512, 512, 256, 128, 128, 128, 128, 64, 64, 32, 32, 16, 16, 16, 16};
  if (name == "even-256") return std::vector<uint32_t>(16, 256);  // one 1024² map, split evenly
  if (name == "single-1024") return {1024};
  return {4096};  // single-4096
}

}  // namespace

ViewTechniqueRow iasmRow() {
  return {
      "iasm",
      "irregular adaptive shadow maps (Alecu 2014)",
      {ParamSpec::integer("grid", "tiles per side of the light frustum", 4, 1, 8),
       ParamSpec::choice("resolution-set",
                         "tile resolutions handed out by rank: alecu (§4.2, 6.5 MB), even-256 "
                         "(16 × 256²), single-1024, single-4096 (one tile)",
                         "alecu", {"alecu", "even-256", "single-1024", "single-4096"}),
       ParamSpec::integer("m", "importance weight m of eq. 3.1", 4, 0, 1000),
       ParamSpec::integer("k", "importance range k of eq. 3.1, in percent of the frustum side", 50,
                          1, 1000),
       ParamSpec::integer("extent",
                          "frustum side in percent of the least square ahead of the camera that "
                          "holds every visible point",
                          100, 1, 1000),
       ParamSpec::choice("importance",
                         "tiles ranked by the previous frame's importance (§3.3), or by this "
                         "frame's own",
                         "previous-frame", {"previous-frame", "same-frame"}),
       ParamSpec::choice("placement", "the frustum ahead of the camera (§3.2), or the whole scene",
                         "ahead", {"ahead", "scene"}),
       ParamSpec::integer("constant-bias", "depth bias in hundredths of a texel", 50, 0, 10000),
       ParamSpec::integer("slope-bias", "slope-scaled depth bias in hundredths of a texel", 100, 0,
                          10000)},
      [](const Scene& scene, const Light& light, const ParamValues& values) {
        IasmSettings s;
        s.grid = uint32_t(values.integer("grid"));
        s.resolutions = resolutionSet(values.choice("resolution-set"));
        if (s.resolutions.size() != size_t(s.grid) * s.grid)
          throw ParamError(fmt::format(
              "iasm: resolution-set '{}' has {} tiles, but grid={} needs {}",
              values.choice("resolution-set"), s.resolutions.size(), s.grid, s.grid * s.grid));
        s.m = double(values.integer("m"));
        s.kFraction = values.integer("k") / 100.0;
        s.extentFraction = values.integer("extent") / 100.0;
        s.placeOverScene = values.choice("placement") == "scene";
        s.sameFrameImportance = values.choice("importance") == "same-frame";
        s.bias.constantTexels = values.integer("constant-bias") / 100.0;
        s.bias.slopeTexels = values.integer("slope-bias") / 100.0;
        return std::make_unique<IrregularAdaptiveShadowMaps>(scene, light, s);
      }};
}

}  // namespace sb
