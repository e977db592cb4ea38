// cpvs — Compact Precomputed Voxelized Shadows (Sintorn, Kämpe, Olsson, Assarsson 2014): the
// shadowed space voxelized in light space, built top-down from a min-max hierarchy of the dual
// depth map and reduced to its minimal DAG (§3, §4, §6.1).
#include <optional>

#include <fmt/format.h>

#include "schemes/interface/serial.h"
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
    pyramid_.emplace(tileSize(), [&](uint32_t bx, uint32_t by) {
      BlockPyramid::Bounds bounds{~0u, 0};
      for (uint32_t y = by * 8; y < by * 8 + 8; ++y)
        for (uint32_t x = bx * 8; x < bx * 8 + 8; ++x) {
          const SliceInterval& interval = intervals_[size_t(y) * tileSize() + x];
          bounds.litUntil = std::min(bounds.litUntil, interval.shadowBegin);
          bounds.shadowFrom = std::max(bounds.shadowFrom, interval.litEnd);
        }
      return bounds;
    });
  }

  SvoChild insertCube(uint32_t z0, uint32_t depth) override { return insert(0, 0, z0, depth); }

  // The volume at `depth` whose tile-local corner is (x, y, z): classified against the min-max
  // pyramid, else split and its undefined children decided by the parent rule (§6.1).
  SvoChild insert(uint32_t x, uint32_t y, uint32_t z, uint32_t depth) {
    const uint32_t side = shape_.side(depth);
    const BlockPyramid::Bounds& bounds = pyramid_->footprint(x, y, side);
    const bool mayBeLit = z + side - 1 < bounds.litUntil, mayBeShadowed = z >= bounds.shadowFrom;
    if (mayBeLit && mayBeShadowed) return {SvoChild::Undefined};
    if (mayBeLit) return {SvoChild::Lit};
    if (mayBeShadowed) return {SvoChild::Shadowed};

    std::array<SvoChild, 8> children;
    if (depth == shape_.leafParentDepth()) {
      for (uint32_t c = 0; c < 8; ++c)
        children[c] = shape_.layout == LeafLayout::Slab8
                          ? leafmask(x, y, z + c, 8, 1)
                          : leafmask(x + (c & 1) * 4, y + (c >> 1 & 1) * 4, z + (c >> 2) * 4, 4, 4);
    } else {
      const uint32_t half = side / 2;
      for (uint32_t c = 0; c < 8; ++c)
        children[c] =
            insert(x + (c & 1) * half, y + (c >> 1 & 1) * half, z + (c >> 2) * half, depth + 1);
    }
    const SvoChild::Kind kind = resolveByParent(children);
    return kind == SvoChild::Local ? svo_.addNode(depth, children) : SvoChild{kind};
  }

  // A leafmask of side × side texels and `slices` slices (8×8×1 or 4×4×4). Within a mixed
  // leafmask the undefined voxels become shadowed, as the parent rule does one level up.
  SvoChild leafmask(uint32_t x, uint32_t y, uint32_t z, uint32_t side, uint32_t slices) {
    uint64_t lit = 0, shadowed = 0;
    for (uint32_t dz = 0, bit = 0; dz < slices; ++dz)
      for (uint32_t dy = 0; dy < side; ++dy)
        for (uint32_t dx = 0; dx < side; ++dx, ++bit) {
          const SliceInterval& interval = intervals_[size_t(y + dy) * tileSize() + x + dx];
          lit |= uint64_t(z + dz < interval.litEnd) << bit;
          shadowed |= uint64_t(z + dz >= interval.shadowBegin) << bit;
        }
    if (lit == 0 && shadowed == 0) return {SvoChild::Undefined};
    if (shadowed == 0) return {SvoChild::Lit};
    if (lit == 0) return {SvoChild::Shadowed};
    return svo_.addLeafmask(lit);
  }

  std::vector<SliceInterval> intervals_;
  std::optional<BlockPyramid> pyramid_;
};

SchemeInfo cpvs() {
  SchemeInfo info = voxelDagScheme(
      "cpvs", "Sintorn, Kämpe, Olsson, Assarsson 2014, Compact Precomputed Voxelized Shadows");
  info.makeEncoder = [](const MapInfo& map, const Params& params) -> std::unique_ptr<Encoder> {
    return std::make_unique<CpvsEncoder>(map, voxelDagConfig(findScheme("cpvs"), map, params));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(cpvs);

}  // namespace sb
