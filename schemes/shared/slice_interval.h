// The voxel view of the dual depth map (DESIGN §4) shared by the voxel schemes: each texel's
// column of Rz slices splits into lit, undefined and shadowed runs, and a min-max pyramid over
// 8×8 texel blocks classifies whole volumes at once (Sintorn §6.1, Kämpe §3).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "schemes/interface/scheme.h"

namespace sb {

// Slices [0, litEnd) are lit (centre ≤ lo), [shadowBegin, Rz) are shadowed (centre > hi), and
// the slices between lie in the undefined band. litEnd ≤ shadowBegin because lo ≤ hi.
struct SliceInterval {
  uint32_t litEnd, shadowBegin;
};

// The number of slices k whose centre (k + ½)/Rz is ≤ depth, which is the first slice beyond it.
// Exact in float: depth·Rz only shifts the exponent (Rz a power of two), − ½ is exact below
// 2^23 > Rz, and a rounded difference never crosses an integer, so this decides exactly as the
// reference's float test voxelCentre(k) ≤ depth; branch-free so that a tile's loop vectorises.
inline uint32_t firstSliceBeyond(float depth, uint32_t depthResolution) {
  const float count = std::floor(depth * float(depthResolution) - 0.5f) + 1.0f;
  return uint32_t(std::clamp(count, 0.0f, float(depthResolution)));
}

// The tile's slice intervals, row-major like the tile, into `intervals` (reused from tile to
// tile, so that no tile pays for fresh pages).
inline void sliceIntervals(const DualDepthTile& tile, uint32_t depthResolution,
                           std::vector<SliceInterval>& intervals) {
  intervals.resize(tile.lo.size());
  for (size_t t = 0; t < intervals.size(); ++t)
    intervals[t] = {firstSliceBeyond(tile.lo[t], depthResolution),
                    firstSliceBeyond(tile.hi[t], depthResolution)};
}

// A pyramid over the 8×8 texel blocks of a square tile holding, per footprint, the smallest
// slice at which some voxel may no longer be lit and the largest slice before which some voxel
// must still be lit. A volume over slices [z0, z1] can be entirely lit when z1 < litUntil and
// entirely shadowed when z0 ≥ shadowFrom (the min-max hierarchy of Sintorn §6.1).
class BlockPyramid {
 public:
  static constexpr uint32_t kBlock = 8;
  struct Bounds {
    uint32_t litUntil, shadowFrom;
  };

  // `blockBounds` gives the bounds of block (bx, by); the tile has `tileSize` texels per side.
  template <class BlockBounds>
  BlockPyramid(uint32_t tileSize, BlockBounds&& blockBounds) {
    for (uint32_t side = tileSize / kBlock; side >= 1; side /= 2) {
      levels_.emplace_back(size_t(side) * side);
      sides_.push_back(side);
    }
    auto& base = levels_[0];
    for (uint32_t by = 0; by < sides_[0]; ++by)
      for (uint32_t bx = 0; bx < sides_[0]; ++bx)
        base[size_t(by) * sides_[0] + bx] = blockBounds(bx, by);
    for (size_t l = 1; l < levels_.size(); ++l)
      for (uint32_t y = 0; y < sides_[l]; ++y)
        for (uint32_t x = 0; x < sides_[l]; ++x) {
          Bounds merged{~0u, 0};
          for (uint32_t c = 0; c < 4; ++c) {
            const Bounds& child = at(l - 1, 2 * x + (c & 1), 2 * y + (c >> 1));
            merged.litUntil = std::min(merged.litUntil, child.litUntil);
            merged.shadowFrom = std::max(merged.shadowFrom, child.shadowFrom);
          }
          levels_[l][size_t(y) * sides_[l] + x] = merged;
        }
  }

  // The bounds of the footprint of `side` texels (a multiple of 8) whose tile-local origin is
  // (x, y).
  const Bounds& footprint(uint32_t x, uint32_t y, uint32_t side) const {
    const uint32_t level = uint32_t(std::countr_zero(side / kBlock));
    return at(level, x / side, y / side);
  }

  // What the bounds say of the volume over slices [z0, z1] of a footprint: every voxel lit or
  // undefined (Lit), shadowed or undefined (Shadowed), undefined (Undefined), or both lit and
  // shadowed voxels in it (Mixed).
  enum class Volume { Lit, Shadowed, Undefined, Mixed };
  Volume classify(uint32_t x, uint32_t y, uint32_t side, uint32_t z0, uint32_t z1) const {
    const Bounds& bounds = footprint(x, y, side);
    const bool mayBeLit = z1 < bounds.litUntil, mayBeShadowed = z0 >= bounds.shadowFrom;
    return mayBeLit && mayBeShadowed ? Volume::Undefined
           : mayBeLit                ? Volume::Lit
           : mayBeShadowed           ? Volume::Shadowed
                                     : Volume::Mixed;
  }

  // The pyramid over a square tile's slice intervals (row-major, `tileSize` per side).
  static BlockPyramid over(const std::vector<SliceInterval>& intervals, uint32_t tileSize) {
    return BlockPyramid(tileSize, [&](uint32_t bx, uint32_t by) {
      Bounds bounds{~0u, 0};
      for (uint32_t y = by * kBlock; y < (by + 1) * kBlock; ++y)
        for (uint32_t x = bx * kBlock; x < (bx + 1) * kBlock; ++x) {
          const SliceInterval& interval = intervals[size_t(y) * tileSize + x];
          bounds.litUntil = std::min(bounds.litUntil, interval.shadowBegin);
          bounds.shadowFrom = std::max(bounds.shadowFrom, interval.litEnd);
        }
      return bounds;
    });
  }

 private:
  const Bounds& at(size_t level, uint32_t x, uint32_t y) const {
    return levels_[level][size_t(y) * sides_[level] + x];
  }
  std::vector<std::vector<Bounds>> levels_;
  std::vector<uint32_t> sides_;
};

}  // namespace sb
