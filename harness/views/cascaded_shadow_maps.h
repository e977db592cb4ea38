// Cascaded shadow maps (Engel 2006; Zhang et al. 2006's parallel-split scheme), the baseline of
// Alecu 2014 §4: the view frustum cut into k slices at the practical split distances
//   s_i = λ·n·(f/n)^(i/k) + (1 − λ)·(n + (f − n)·i/k),
// each slice covered by an orthographic light frustum around its bounding sphere (so that the
// cascade's size does not change as the camera turns), snapped to whole texels (so that its
// texels do not crawl as the camera moves), rendered at R² and tested with a constant and a
// slope-scaled depth bias.
#pragma once

#include <memory>
#include <vector>

#include "harness/views/ortho_shadow_map.h"
#include "harness/views/view_technique.h"

namespace sb {

struct CsmSettings {
  uint32_t cascades = 3, resolution = 1024;  // Alecu §4.2: three 1024² cascades, 12 MiB
  double lambda = 0.5;
  DepthBias bias;
  // Fit each cascade to its slice, or every cascade to the whole scene (one cascade is then a
  // plain shadow map: the check that cascades change nothing else).
  bool fitScene = false;
};

class CascadedShadowMaps : public ViewTechnique {
 public:
  CascadedShadowMaps(const Scene& scene, const Light& light, const CsmSettings& settings);

  void prepare(const Camera& camera, const GroundTruth& surface) override;
  void shade(const Camera& camera, const GroundTruth& surface,
             std::vector<float>& visibility) override;
  uint64_t memoryBytes() const override;
  nlohmann::json frameLayout() const override;

  // The practical split distances s_0 = n … s_k = f.
  static std::vector<double> splitDistances(double n, double f, uint32_t k, double lambda);
  // The cascade a view depth falls in (the last one beyond f).
  size_t cascadeOf(double viewDepth) const;
  const std::vector<OrthoShadowMap>& cascades() const { return cascades_; }

 private:
  const Scene& scene_;
  Light light_;
  CsmSettings settings_;
  std::vector<double> splits_;
  std::vector<OrthoShadowMap> cascades_;
};

ViewTechniqueRow csmRow();

}  // namespace sb
