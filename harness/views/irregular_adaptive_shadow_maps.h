// Irregular adaptive shadow maps (Alecu 2014, ch. 3): one orthographic light frustum split into
// a g×g grid of equal light-space tiles, each with a shadow map of its own resolution.
// - §3.2, Fig. 3.1: the frustum's square is placed ahead of the camera, the camera on the circle
//   inscribed in it, so that the view direction crosses the whole square.
// - §3.3: while a frame is shaded, every pixel adds its importance p = 1 + m·(1 − w/k) (w its
//   view depth, the bracket clamped to [0, 1]) to the tile it falls in, in integers as the
//   thesis's InterlockedAdd, so that the sums do not depend on thread order.
// - §3.4: the next frame ranks the tiles by that importance and hands out a fixed set of
//   resolutions by rank, the largest to the most important tile.
// - §3.5: each tile's near and far planes are fitted to the objects overlapping its frustum (the
//   thesis's forward renderer, from object bounds); a tile no object overlaps is not rendered.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "harness/views/ortho_shadow_map.h"
#include "harness/views/view_technique.h"

namespace sb {

struct IasmSettings {
  uint32_t grid = 4;
  // Per rank, largest first; grid² entries. Alecu §4.2: 1×1024, 2×512, 1×256, 4×128, 2×64,
  // 2×32, 4×16 = 6 860 800 bytes at 32 bits.
  std::vector<uint32_t> resolutions;
  double m = 4, kFraction = 0.5;  // k as a fraction of the frustum's side
  double extentFraction = 1.0;  // the square's side as a fraction of the least that holds the frame
  bool placeOverScene = false;  // the whole light map instead (one tile: a plain shadow map)
  bool sameFrameImportance = false;  // rank by this frame's importance, not the previous one's
  DepthBias bias;
};

class IrregularAdaptiveShadowMaps : public ViewTechnique {
 public:
  IrregularAdaptiveShadowMaps(const Scene& scene, const Light& light, IasmSettings settings);

  void prepare(const Camera& camera, const GroundTruth& surface) override;
  void shade(const Camera& camera, const GroundTruth& surface,
             std::vector<float>& visibility) override;
  uint64_t memoryBytes() const override;
  nlohmann::json frameLayout() const override;

  // The tile (row-major in the grid) holding a parent light-space point, if the square does.
  std::optional<uint32_t> tileOf(const glm::dvec3& lightPoint) const;
  const std::vector<std::optional<OrthoShadowMap>>& tiles() const { return tiles_; }
  const std::vector<uint32_t>& tileResolutions() const { return tileResolution_; }

 private:
  void accumulateImportance(const GroundTruth& surface);
  double coveringSide(const GroundTruth& surface, glm::dvec2 eye, glm::dvec2 ahead) const;

  const Scene& scene_;
  Light light_;
  IasmSettings settings_;
  std::vector<glm::dvec2> meshDepthRange_;  // per mesh, its light-space z bounds
  std::vector<glm::dvec4> meshFootprint_;   // per mesh, its light-space (x0, y0, x1, y1)
  glm::dvec2 corner_{0};                    // the square, in light-space units
  double side_ = 1;
  glm::dvec2 eye_{0};  // the camera, in light-space units: where it sits among the tiles
  std::vector<uint64_t> importance_;  // §3.3, fixed point, of the last shaded frame
  bool haveImportance_ = false;
  std::vector<uint32_t> tileResolution_;
  std::vector<glm::dvec2> tileDepthRange_;
  std::vector<std::optional<OrthoShadowMap>> tiles_;  // empty tiles hold no map
};

ViewTechniqueRow iasmRow();

}  // namespace sb
