// The dual depth map (DESIGN §3): for every texel an interval [lo, hi], ray cast with Embree in
// the light's view space, produced tile by tile.
//
// Texels are computed in packets of 4×4 aligned to absolute texel coordinates, and a texel's
// interval depends only on its own packet (ray casting) or its own bin of triangles
// (rasterising): so it is the same float whatever the tile size, tile order or thread count,
// and the reference re-computes exactly the same packet.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "harness/light.h"
#include "harness/light_space_rasterizer.h"
#include "scenes/scene.h"
#include "schemes/interface/parts.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct DepthInterval {
  float lo, hi;
};

// How the map is computed. Directional lights rasterise in light space by default (exact
// coverage, several times faster); ray casting with Embree serves spot lights and is the
// independent check.
enum class DepthMethod { Rasterize, RayCast };
std::string_view toString(DepthMethod method);

class DepthSource {
 public:
  static constexpr uint32_t kPacketWidth = 4, kPacketHeight = 4;
  static constexpr uint32_t kPacketSize = kPacketWidth * kPacketHeight;
  using Packet = std::array<DepthInterval, kPacketSize>;

  // R must be a power of two in [8, 2^20]. Rasterize falls back to RayCast for spot lights.
  DepthSource(const Scene& scene, const Light& light, DepthMode mode, uint32_t resolution,
              DepthMethod method = DepthMethod::Rasterize);
  ~DepthSource();
  DepthSource(const DepthSource&) = delete;
  DepthSource& operator=(const DepthSource&) = delete;

  DepthMode mode() const { return mode_; }
  DepthMethod method() const { return rasterizer_ ? DepthMethod::Rasterize : DepthMethod::RayCast; }
  uint32_t resolution() const { return resolution_; }
  const Light& light() const { return light_; }

  // Texels [x0, x0 + w) × [y0, y0 + h) into `tile`; x0, y0, w and h multiples of 4.
  void trace(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, DualDepthTile& tile) const;
  // The packet whose top-left texel is (i0, i0) (multiples of 4), row-major.
  Packet tracePacket(uint32_t i0, uint32_t j0) const;
  // The reference path for one texel: re-traces its packet alone.
  DepthInterval texel(uint32_t i, uint32_t j) const;

  // The closest hit of any ray in view space (camera rays for view samples), with the
  // geometric normal; t < 0 when the ray hits nothing.
  struct Hit {
    float t;
    glm::vec3 normal;
  };
  Hit intersect(const glm::vec3& origin, const glm::vec3& direction) const;

  // Closed mode: texels whose front/back counter never returned to zero (a ray grazing shared
  // edges, or more crossings than are followed) or whose first hit was a back face. They fall
  // back to hi = lo, which is always correct. Counted over everything traced so far.
  uint64_t closedFallbacks() const { return closedFallbacks_.load(); }

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
  std::unique_ptr<LightSpaceRasterizer> rasterizer_;
  Light light_;
  DepthMode mode_;
  uint32_t resolution_;
  mutable std::atomic<uint64_t> closedFallbacks_{0};
};

// The tile size used when none is given: 512, or the whole map when smaller.
uint32_t defaultTileSize(uint32_t resolution);

struct StreamStats {
  double traceThreadSeconds = 0;  // summed over the threads that traced
  double wallSeconds = 0;
};

// Streams the whole map to `consume` as square tiles of `tileSize` (a power of two ≤ R, ≥ 8)
// in Morton order, traced in parallel and consumed in order on one thread at a time.
// `progress` (optional) is called after each consumed tile with texels done so far.
StreamStats streamDualDepth(const DepthSource& source, uint32_t tileSize,
                            const std::function<void(const DualDepthTile&)>& consume,
                            const std::function<void(uint64_t texelsDone)>& progress = {});
// The same over one part of the map (parts.h): its tiles are a run of the whole map's Morton
// order, streamed in that order; `tileSize` must not exceed the part.
StreamStats streamDualDepth(const DepthSource& source, uint32_t tileSize, const MapPart& part,
                            const std::function<void(const DualDepthTile&)>& consume,
                            const std::function<void(uint64_t texelsDone)>& progress = {});

}  // namespace sb
