// The dual depth map of a directional light by rasterising the scene in light space, where
// every ray is parallel to z: each triangle gives one crossing to every texel centre it
// covers. Coverage is decided exactly — vertices snapped to a 2^-28 grid, integer edge
// functions, the top-left rule — so a texel centre on an edge shared by two triangles is
// covered by exactly one of them: closed meshes never double-count or leak a crossing, which
// is what ray casting gets wrong on shared edges (and why it is slower: it must traverse the
// whole solid to find the exit depth). Embree stays the independent check (tests) and the
// path for spot lights. Under a light window (Light::window: a shadow-map cascade or tile)
// triangles reaching outside the map are clipped to it first.
#pragma once

#include <cstdint>
#include <vector>

#include "harness/light.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace sb {

class LightSpaceRasterizer {
 public:
  // Directional lights only; R a power of two in [8, 2^20].
  LightSpaceRasterizer(const Scene& scene, const Light& light, uint32_t resolution);

  // Intervals of texels [x0, x0 + w) × [y0, y0 + h), row-major with `stride`, in `mode`.
  // Returns the closed-mode fallbacks (texels whose counter never returned to zero).
  uint64_t rasterize(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, DepthMode mode, float* lo,
                     float* hi, size_t stride) const;

 private:
  // A triangle in fixed-point light space, wound counter-clockwise in (x, y).
  struct FixedTriangle {
    int32_t x[3], y[3];
    float z[3];
    int32_t texelMin[2], texelMax[2];  // the texel centres its bounding box holds (inclusive)
    int8_t sign;                       // +1 front face of a closed mesh, −1 back face, 0 open
    uint32_t mesh;
  };

  // The three edge functions of a triangle at texel (i, j)'s centre and their steps per texel
  // column and row; `need` is the least value inside (0 on an edge the triangle owns, else 1).
  struct Edges {
    int64_t start[3], perColumn[3], perRow[3], need[3];
    // No texel of the columns × rows rectangle starting at (i, j) is inside.
    bool miss(int64_t columns, int64_t rows) const;
  };
  Edges edgesAt(const FixedTriangle& t, int64_t i, int64_t j) const;

  template <class Visit>
  void coverTexels(const FixedTriangle& t, int64_t i0, int64_t i1, int64_t j0, int64_t j1,
                   Visit&& visit) const;

  uint32_t resolution_;
  int64_t halfTexel_;  // half a texel in fixed-point units: texel i's centre is (2i + 1)·halfTexel_
  uint32_t texelsPerBin_, binsPerSide_;
  std::vector<FixedTriangle> triangles_;
  // Triangle indices per bin of texels (compressed rows), nearest first: the order in which a
  // texel meets its triangles is fixed, so its crossings are too.
  std::vector<uint32_t> binStart_, binTriangles_;
};

}  // namespace sb
