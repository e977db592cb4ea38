// cpvs — Compact Precomputed Voxelized Shadows (Sintorn, Kämpe, Olsson, Assarsson 2014): the
// shadowed space voxelized in light space, built top-down from a min-max hierarchy of the dual
// depth map and reduced to its minimal DAG (§3, §4, §6.1).
#include <algorithm>
#include <optional>

#include "schemes/shared/slice_interval.h"
#include "schemes/shared/svo.h"

namespace sb {
namespace {

class CpvsEncoder final : public CubeColumnEncoder {
 public:
  using CubeColumnEncoder::CubeColumnEncoder;

 private:
  void prepareTile(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("min-max");
    sliceIntervals(tile, shape_.side(0), intervals_);
    pyramid_.emplace(BlockPyramid::over(intervals_, tileSize()));
  }

  SvoChild insertCube(uint32_t z0, uint32_t depth) override { return insert(0, 0, z0, depth); }

  // The volume at `depth` whose tile-local corner is (x, y, z): classified against the min-max
  // pyramid, else split and its undefined children decided by the parent rule (§6.1).
  SvoChild insert(uint32_t x, uint32_t y, uint32_t z, uint32_t depth) {
    const uint32_t side = shape_.side(depth);
    switch (pyramid_->classify(x, y, side, z, z + side - 1)) {
      case BlockPyramid::Volume::Undefined:
        return {SvoChild::Undefined};
      case BlockPyramid::Volume::Lit:
        return {SvoChild::Lit};
      case BlockPyramid::Volume::Shadowed:
        return {SvoChild::Shadowed};
      case BlockPyramid::Volume::Mixed:
        break;
    }

    std::array<SvoChild, 8> children;
    if (depth == shape_.leafParentDepth()) {
      leafmasks(x, y, z, children);
    } else {
      const uint32_t half = side / 2;
      for (uint32_t c = 0; c < 8; ++c)
        children[c] =
            insert(x + (c & 1) * half, y + (c >> 1 & 1) * half, z + (c >> 2) * half, depth + 1);
    }
    const SvoChild::Kind kind = resolveByParent(children);
    return kind == SvoChild::Local ? svo_.addNode(depth, children) : SvoChild{kind};
  }

  // The eight leafmasks of the 8×8×8 leaf parent at (x, y, z). Per texel the slices it keeps lit
  // and those it must shadow are runs of the eight, so each texel gives two bytes (bit s: slice
  // z + s) and an 8×8 bit transpose per row of texels turns them into per-slice masks. Within a
  // mixed leafmask the undefined voxels become shadowed, as the parent rule does one level up.
  void leafmasks(uint32_t x, uint32_t y, uint32_t z, std::array<SvoChild, 8>& children) {
    uint64_t lit[8] = {}, shadowed[8] = {};
    for (uint32_t dy = 0; dy < 8; ++dy) {
      uint64_t litRow = 0, shadowedRow = 0;
      for (uint32_t dx = 0; dx < 8; ++dx) {
        const SliceInterval& interval = intervals_[size_t(y + dy) * tileSize() + x + dx];
        const uint32_t litSlices = std::clamp<int64_t>(int64_t(interval.litEnd) - z, 0, 8);
        const uint32_t beforeShadow = std::clamp<int64_t>(int64_t(interval.shadowBegin) - z, 0, 8);
        litRow |= uint64_t((1u << litSlices) - 1) << (8 * dx);
        shadowedRow |= uint64_t((0xffu << beforeShadow) & 0xffu) << (8 * dx);
      }
      litRow = transposeBits8x8(litRow), shadowedRow = transposeBits8x8(shadowedRow);
      for (uint32_t s = 0; s < 8; ++s) {
        lit[s] |= (litRow >> (8 * s) & 0xff) << (8 * dy);
        shadowed[s] |= (shadowedRow >> (8 * s) & 0xff) << (8 * dy);
      }
    }
    for (uint32_t c = 0; c < 8; ++c) {
      uint64_t childLit = lit[c], childShadowed = shadowed[c];
      if (shape_.layout == LeafLayout::Cube4) {
        const uint32_t z0 = 4 * (c >> 2);
        childLit =
            cube4FromSlabs({lit[z0], lit[z0 + 1], lit[z0 + 2], lit[z0 + 3]}, c & 1, c >> 1 & 1);
        childShadowed =
            cube4FromSlabs({shadowed[z0], shadowed[z0 + 1], shadowed[z0 + 2], shadowed[z0 + 3]},
                           c & 1, c >> 1 & 1);
      }
      children[c] = childLit == 0 && childShadowed == 0 ? SvoChild{SvoChild::Undefined}
                    : childShadowed == 0                ? SvoChild{SvoChild::Lit}
                    : childLit == 0                     ? SvoChild{SvoChild::Shadowed}
                                                        : svo_.addLeafmask(childLit);
    }
  }

  // Bit j of byte i moves to bit i of byte j (Hacker's Delight §7.3).
  static uint64_t transposeBits8x8(uint64_t x) {
    x = (x & 0xaa55aa55aa55aa55ull) | (x & 0x00aa00aa00aa00aaull) << 7 |
        (x >> 7 & 0x00aa00aa00aa00aaull);
    x = (x & 0xcccc3333cccc3333ull) | (x & 0x0000cccc0000ccccull) << 14 |
        (x >> 14 & 0x0000cccc0000ccccull);
    x = (x & 0xf0f0f0f00f0f0f0full) | (x & 0x00000000f0f0f0f0ull) << 28 |
        (x >> 28 & 0x00000000f0f0f0f0ull);
    return x;
  }

  std::vector<SliceInterval> intervals_;
  std::optional<BlockPyramid> pyramid_;
};

SchemeInfo cpvs() {
  SchemeInfo info = voxelDagScheme(
      "cpvs", "Sintorn, Kämpe, Olsson, Assarsson 2014, Compact Precomputed Voxelized Shadows");
  setCubeColumnBuilds(info, [](const MapInfo& map, const VoxelDagConfig& config, const ParamValues&,
                               const MapPart& region) {
    return std::make_unique<CpvsEncoder>(map, config, region);
  });
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(cpvs);

}  // namespace sb
