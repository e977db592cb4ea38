// cpvs-fast — fast, memory-efficient construction of voxelized shadows (Kämpe, Sintorn,
// Assarsson 2015). The output is a CPVS read by the same lookups as `cpvs`; what differs is how
// it is built (§3.2: in Z-order, reusing the node of the volume in front instead of creating an
// identical one) and how undefined space is resolved (§3.4: per 8×8 block visibility masks; above
// the leafmasks either by the masks themselves or, as the paper does, by the min-max hierarchy of
// the enter and exit depth maps).
#include <algorithm>
#include <bit>
#include <optional>

#include "schemes/shared/slice_interval.h"
#include "schemes/shared/svo.h"

namespace sb {
namespace {

inline constexpr uint32_t kNever = ~0u;

// Kämpe §3.4: the visibility masks of one 8×8 block, each with the slice where it starts and
// holding until the next one starts; bit dx + 8·dy set = lit.
struct VisibilityMasks {
  const uint32_t* starts;
  const uint64_t* lit;
  size_t count;

  size_t at(uint32_t slice) const {
    return size_t(std::upper_bound(starts, starts + count, slice) - starts) - 1;
  }
  // The first slice after `slice` where the mask changes: a shadow-casting surface.
  uint32_t nextTransition(uint32_t slice) const {
    const size_t next = at(slice) + 1;
    return next < count ? starts[next] : kNever;
  }
};

// The masks of every block of a tile, block after block.
struct TileMasks {
  std::vector<uint32_t> starts;
  std::vector<uint64_t> lit;
  std::vector<uint32_t> first{0};  // block b's masks are [first[b], first[b + 1])

  VisibilityMasks block(size_t b) const {
    return {starts.data() + first[b], lit.data() + first[b], size_t(first[b + 1] - first[b])};
  }
  void clear() { starts.clear(), lit.clear(), first.assign(1, 0); }
};

// Where a block's mask may change: exactly at the nearest exit depth of the cells still lit (as
// Kämpe §3.4 words it), or at the most aligned slice between that depth and the nearest enter
// depth of those cells — the freedom the rule leaves, used so that neighbouring blocks change at
// the same slices and large volumes stay homogeneous.
enum class Transitions { NearestExit, Aligned };

// The slice in [earliest, latest] with the most trailing zero bits: latest with every bit below
// the highest one where it differs from earliest − 1 cleared.
uint32_t mostAlignedSlice(uint32_t earliest, uint32_t latest) {
  if (earliest == 0) return 0;
  return latest & ~((uint32_t(std::bit_floor((earliest - 1) ^ latest))) - 1);
}

// Kämpe §3.4: lit until the nearest exit depth; there a mask shadows every cell already past its
// enter depth and holds until the nearest exit depth of the cells it left lit, where the next
// mask begins, until every cell is shadowed. Each mask shadows at least one more cell. Where the
// farthest enter depth comes before the nearest exit depth the paper's lit and shadowed regions
// overlap; the lit region wins, as Sintorn's min-max rule keeps lit everything above the exit.
void appendVisibilityMasks(const SliceInterval (&cells)[64], uint32_t depthResolution,
                           Transitions transitions, TileMasks& masks) {
  // The distinct enter depths in ascending order, each with its cells and their nearest exit:
  // the shadowed cells are always the groups of a prefix, and the nearest exit of the others is
  // a suffix minimum. Blocks hold few distinct depths (flat ground, roofs, empty sky).
  uint32_t enter[64], exit[65];
  uint64_t group[64];
  uint32_t groups = 0;
  for (uint32_t c = 0; c < 64; ++c) {
    const uint32_t value = cells[c].litEnd;
    uint32_t g = 0;
    while (g < groups && enter[g] < value) ++g;
    if (g == groups || enter[g] != value) {
      for (uint32_t h = groups++; h > g; --h)
        enter[h] = enter[h - 1], group[h] = group[h - 1], exit[h] = exit[h - 1];
      enter[g] = value, group[g] = 0, exit[g] = depthResolution;
    }
    group[g] |= uint64_t(1) << c;
    exit[g] = std::min(exit[g], cells[c].shadowBegin);
  }
  exit[groups] = depthResolution;
  for (uint32_t g = groups; g-- > 0;) exit[g] = std::min(exit[g], exit[g + 1]);

  masks.starts.push_back(0);
  masks.lit.push_back(~uint64_t(0));
  uint64_t shadowed = 0;
  for (uint32_t lit = 0; lit < groups && exit[lit] < depthResolution;) {
    // A mask changes only where it shadows one more cell, and after the previous change.
    const uint32_t earliest =
        std::max(enter[lit], masks.starts.back() + (masks.lit.back() != ~uint64_t(0)));
    const uint32_t next =
        transitions == Transitions::Aligned ? mostAlignedSlice(earliest, exit[lit]) : exit[lit];
    for (; lit < groups && enter[lit] <= next; ++lit) shadowed |= group[lit];
    if (masks.starts.back() == next) {
      masks.lit.back() = ~shadowed;
    } else {
      masks.starts.push_back(next);
      masks.lit.push_back(~shadowed);
    }
  }
  masks.first.push_back(uint32_t(masks.starts.size()));
}

// What classifies a volume coarser than a leafmask (the leafmasks always read the masks).
//  - Masks: a pyramid over the masks themselves, so that a volume is homogeneous exactly when its
//    resolved voxels are; undefined space is resolved once, per block, by the masks.
//  - DepthHierarchy: as Kämpe §3 and §3.4 describe it, the min-max hierarchy of the enter and
//    exit depth maps down to one entry per 8×8 block (§5.1), as Sintorn §6.1 classifies: a
//    volume before every exit depth of its footprint is lit, one after every enter depth is
//    shadowed, one that is both is undefined and left to its parent (lit beside lit, shadowed
//    beside shadowed, shadowed in a node that holds both). A coarse volume thus uses the
//    undefined space of all its blocks at once, where the masks have each fixed it for their own
//    block; only at the finest level are the masks read ("we now never have to query the finest
//    level of the min-max depth hierarchy, and instead query the visibility masks", §3.4).
enum class CoarseClassification { Masks, DepthHierarchy };

class CpvsFastEncoder final : public CubeColumnEncoder {
 public:
  CpvsFastEncoder(const MapInfo& map, VoxelDagConfig config, const MapPart& region, bool culling,
                  Transitions transitions, CoarseClassification classification)
      : CubeColumnEncoder(map, config, region),
        culling_(culling),
        transitions_(transitions),
        classification_(classification) {}

 private:
  void prepareTile(const DualDepthTile& tile, BuildContext& context) override {
    const uint32_t resolution = shape_.side(0);
    blocksPerSide_ = tileSize() / 8;

    context.phase("visibility masks");
    sliceIntervals(tile, resolution, intervals_);
    masks_.clear();
    for (uint32_t by = 0; by < blocksPerSide_; ++by)
      for (uint32_t bx = 0; bx < blocksPerSide_; ++bx) {
        SliceInterval cells[64];
        for (uint32_t c = 0; c < 64; ++c)
          cells[c] = intervals_[size_t(by * 8 + c / 8) * tileSize() + bx * 8 + c % 8];
        appendVisibilityMasks(cells, resolution, transitions_, masks_);
      }

    context.phase("min-max");
    if (classification_ == CoarseClassification::DepthHierarchy)
      pyramid_.emplace(BlockPyramid::over(intervals_, tileSize()));
    else
      pyramid_.emplace(tileSize(), [&](uint32_t bx, uint32_t by) {
        const VisibilityMasks block = masks_.block(size_t(by) * blocksPerSide_ + bx);
        const size_t last = block.count - 1;
        return BlockPyramid::Bounds{block.lit[0] != ~uint64_t(0) ? 0
                                    : block.count > 1            ? block.starts[1]
                                                                 : kNever,
                                    block.lit[last] == 0 ? block.starts[last] : kNever};
      });

    reuse_.assign(shape_.leafParentDepth() + 2, {});
    for (uint32_t d = cubeDepth(); d < reuse_.size(); ++d) {
      const uint32_t perSide = tileSize() / footprint(d);
      reuse_[d].assign(size_t(perSide) * perSide, ReuseEntry{});
    }
  }

  SvoChild insertCube(uint32_t z0, uint32_t depth) override {
    uint32_t nextSurface = 0;
    return insert(0, 0, z0, depth, nextSurface);
  }

  // Volumes of the next cube may reuse this cube's nodes, now in the DAG.
  void cubeMerged() override {
    for (const auto& [entry, depth] : localEntries_) entry->ref = svo_.merged(entry->ref, depth);
    localEntries_.clear();
  }

  void countConstruction(BuildContext& context) const override {
    context.count("nodes culled", culled_);
  }

  // Kämpe §3.2: per depth and footprint, the last volume completed there, the slice after it,
  // and the first shadow-casting surface after its start. The next volume behind it is the
  // same volume when no surface lies in either of them.
  struct ReuseEntry {
    uint32_t zEnd = kNever;
    uint32_t nextSurface = 0;
    SvoChild ref;
  };

  // Footprint (texels per side) and slices of a volume at depth d; d = leafParentDepth() + 1
  // means a leafmask.
  uint32_t footprint(uint32_t depth) const {
    return depth > shape_.leafParentDepth() ? shape_.leafSide() : shape_.side(depth);
  }
  uint32_t slices(uint32_t depth) const {
    return depth > shape_.leafParentDepth() ? 64 / (shape_.leafSide() * shape_.leafSide())
                                            : shape_.side(depth);
  }
  ReuseEntry& entry(uint32_t x, uint32_t y, uint32_t depth) {
    const uint32_t side = footprint(depth), perSide = tileSize() / side;
    return reuse_[depth][size_t(y / side) * perSide + x / side];
  }
  VisibilityMasks block(uint32_t x, uint32_t y) const {
    return masks_.block(size_t(y / 8) * blocksPerSide_ + x / 8);
  }

  // The volume at `depth` whose tile-local corner is (x, y, z), in Z-order; sets `nextSurface`
  // to the first slice after z where a surface may change its voxels: §3.2 takes it from the
  // min-max hierarchy for a homogeneous volume (a lit one stays lit-or-undefined until litUntil,
  // an undefined one until then too, a shadowed one for ever) and from the finest level below a
  // split one. Reusing a volume for the one behind it before that slice is lossless under
  // either classification: a voxel's state only goes lit, undefined, shadowed with depth, and
  // before that slice none the reused node holds lit or undefined-as-lit turns shadowed.
  //
  // Over the masks it also gives the structure built without reuse, as the masks' pyramid is
  // exact. With the depth hierarchy it need not: the volume behind may already lie past every
  // enter depth of a footprint that the one in front was lit or split in, where a fresh build
  // would classify it undefined or shadowed. The paper's reuse keeps the node in front there,
  // which is one more way of resolving undefined space (measured smaller, README).
  SvoChild insert(uint32_t x, uint32_t y, uint32_t z, uint32_t depth, uint32_t& nextSurface) {
    const uint32_t side = shape_.side(depth);
    const BlockPyramid::Bounds& bounds = pyramid_->footprint(x, y, side);
    switch (pyramid_->classify(x, y, side, z, z + side - 1)) {
      case BlockPyramid::Volume::Shadowed:
        return complete(x, y, z, depth, {SvoChild::Shadowed}, nextSurface = kNever);
      case BlockPyramid::Volume::Lit:
        return complete(x, y, z, depth, {SvoChild::Lit}, nextSurface = bounds.litUntil);
      case BlockPyramid::Volume::Undefined:  // resolved by the parent (resolveByParent)
        return complete(x, y, z, depth, {SvoChild::Undefined}, nextSurface = bounds.litUntil);
      case BlockPyramid::Volume::Mixed:
        break;
    }
    if (SvoChild reused; reuse(x, y, z, depth, reused, nextSurface)) return reused;

    std::array<SvoChild, 8> children;
    nextSurface = kNever;
    for (uint32_t c = 0; c < 8; ++c) {
      uint32_t childNext = 0;
      if (depth < shape_.leafParentDepth()) {
        const uint32_t half = side / 2;
        children[c] = insert(x + (c & 1) * half, y + (c >> 1 & 1) * half, z + (c >> 2) * half,
                             depth + 1, childNext);
      } else if (shape_.layout == LeafLayout::Slab8) {
        children[c] = leafmask(x, y, z + c, childNext);
      } else {
        children[c] = leafmask(x + (c & 1) * 4, y + (c >> 1 & 1) * 4, z + (c >> 2) * 4, childNext);
      }
      nextSurface = std::min(nextSurface, childNext);
    }
    const SvoChild::Kind kind = resolveByParent(children);
    const SvoChild node = kind == SvoChild::Local ? svo_.addNode(depth, children) : SvoChild{kind};
    return complete(x, y, z, depth, node, nextSurface);
  }

  // The leafmask with corner (x, y, z), read from the block's visibility masks.
  SvoChild leafmask(uint32_t x, uint32_t y, uint32_t z, uint32_t& nextSurface) {
    const uint32_t depth = shape_.leafParentDepth() + 1;
    const VisibilityMasks masks = block(x, y);
    if (SvoChild reused; reuse(x, y, z, depth, reused, nextSurface)) return reused;
    nextSurface = masks.nextTransition(z);
    uint64_t lit = 0;
    if (shape_.layout == LeafLayout::Slab8) {
      lit = masks.lit[masks.at(z)];
    } else {
      const uint64_t slabs[4] = {masks.lit[masks.at(z)], masks.lit[masks.at(z + 1)],
                                 masks.lit[masks.at(z + 2)], masks.lit[masks.at(z + 3)]};
      lit = cube4FromSlabs(slabs, (x >> 2) & 1, (y >> 2) & 1);
    }
    return complete(x, y, z, depth, svo_.addLeafmask(lit), nextSurface);
  }

  // §3.2: the volume is the one in front of it again when the previous volume at this footprint
  // ended where this one starts and no surface begins before this one ends.
  bool reuse(uint32_t x, uint32_t y, uint32_t z, uint32_t depth, SvoChild& reused,
             uint32_t& nextSurface) {
    if (!culling_) return false;
    ReuseEntry& previous = entry(x, y, depth);
    if (previous.zEnd != z || z + slices(depth) - 1 >= previous.nextSurface) return false;
    ++culled_;
    previous.zEnd = z + slices(depth);
    reused = previous.ref;
    nextSurface = previous.nextSurface;
    return true;
  }

  SvoChild complete(uint32_t x, uint32_t y, uint32_t z, uint32_t depth, SvoChild volume,
                    uint32_t nextSurface) {
    ReuseEntry& completed = entry(x, y, depth);
    completed = {z + slices(depth), nextSurface, volume};
    if (volume.kind == SvoChild::Local) localEntries_.emplace_back(&completed, depth);
    return volume;
  }

  bool culling_;
  Transitions transitions_;
  CoarseClassification classification_;
  uint32_t blocksPerSide_ = 0;
  std::vector<SliceInterval> intervals_;
  TileMasks masks_;
  std::optional<BlockPyramid> pyramid_;
  std::vector<std::vector<ReuseEntry>> reuse_;
  std::vector<std::pair<ReuseEntry*, uint32_t>> localEntries_;  // this cube's nodes, by depth
  uint64_t culled_ = 0;
};

SchemeInfo cpvsFast() {
  SchemeInfo info = voxelDagScheme(
      "cpvs-fast",
      "Kämpe, Sintorn, Assarsson 2015, Fast, Memory-Efficient Construction of Voxelized Shadows");
  info.params.push_back(ParamSpec::choice("culling",
                                          "reuse the node of the volume in front instead of "
                                          "building an identical one (§3.2); off for Table 1's "
                                          "comparison",
                                          "on", {"on", "off"}, {"on", "off"}));
  info.params.push_back(ParamSpec::choice("transitions",
                                          "where a block's visibility mask changes (§3.4): at the "
                                          "nearest exit depth, or at the most aligned slice the "
                                          "rule allows",
                                          "aligned", {"nearest-exit", "aligned"},
                                          {"nearest-exit", "aligned"}));
  info.params.push_back(ParamSpec::choice(
      "coarse-classification",
      "what classifies volumes above the leafmasks: the visibility masks' own pyramid, or the "
      "min-max hierarchy of the enter and exit depth maps with Sintorn's parent rule for "
      "undefined volumes, as Kämpe §3/§3.4 do (the masks then only at the finest level)",
      "masks", {"masks", "depth-hierarchy"}, {"masks", "depth-hierarchy"}));
  setCubeColumnBuilds(info, [](const MapInfo& map, const VoxelDagConfig& config,
                               const ParamValues& params, const MapPart& region) {
    return std::make_unique<CpvsFastEncoder>(
        map, config, region, params.choice("culling") == "on",
        params.choice("transitions") == "aligned" ? Transitions::Aligned : Transitions::NearestExit,
        params.choice("coarse-classification") == "depth-hierarchy"
            ? CoarseClassification::DepthHierarchy
            : CoarseClassification::Masks);
  });
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(cpvsFast);

}  // namespace sb
