// mh — compressed multiresolution hierarchies (Scandolo, Bauszat & Eisemann 2016a): the sparse
// quadtree of the dual depth map's intervals, each stored node holding an absolute depth, with
// 16-bit scaled child offsets. A lookup returns the deepest stored depth on the texel's path.
#include <fmt/format.h>

#include "schemes/interface/depth_decoder.h"
#include "schemes/shared/multires_hierarchy.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {
namespace {

// SBE16a §5: 16-bit offsets, the other 8 bits of the 64-bit node are padding.
constexpr int kOffsetBits = 16;

class MhDecoder final : public HierarchicalDepthDecoder<MhDecoder> {
 public:
  MhDecoder(uint32_t resolution, OffsetQuadtree tree)
      : resolution_(resolution), tree_(std::move(tree)) {}

  uint32_t resolution() const { return resolution_; }
  float depth(uint32_t i, uint32_t j) const {
    return depthOfKey(tree_.texelKey<OffsetQuadtree::Values::Absolute>(i, j, tree_.levels));
  }
  // SBE16a: every level of the hierarchy is a complete shadow map, read by stopping the walk.
  float coarseDepth(uint32_t i, uint32_t j, int coarser) const {
    return depthOfKey(tree_.texelKey<OffsetQuadtree::Values::Absolute>(i << coarser, j << coarser,
                                                                       tree_.levels - coarser));
  }
  SizeBreakdown size() const override { return tree_.size(); }
  void save(ByteWriter& out) const override { tree_.save(out); }

 private:
  uint32_t resolution_;
  OffsetQuadtree tree_;
};

class MhEncoder final : public Encoder {
 public:
  explicit MhEncoder(const MapInfo& map) : map_(map), builder_(map) {}

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    if (!started_) context.phase("mh"), started_ = true;
    builder_.consume(tile);
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    const MultiresHierarchy hierarchy = builder_.finish();
    context.phase("serialise");
    // SBE16a §5: each interval is replaced by one representative, its middle.
    std::vector<uint32_t> values(hierarchy.nodes.size());
    uint64_t kinds[4] = {};
    for (size_t n = 0; n < values.size(); ++n) {
      const MhNode& node = hierarchy.nodes[n];
      values[n] = node.interval.middle();
      for (int k = 0; k < kMhChildren; ++k) ++kinds[int(node.child(k))];
    }
    context.count("full nodes", kinds[int(MhChild::Full)] + hierarchy.nodes.back().hasChildren());
    context.count("empty nodes", kinds[int(MhChild::Empty)]);
    context.count("leaves", kinds[int(MhChild::Leaf)] + !hierarchy.nodes.back().hasChildren());
    return std::make_unique<MhDecoder>(
        map_.resolution, layoutOffsetQuadtree(hierarchy, values, {}, kOffsetBits, "mh"));
  }

 private:
  MapInfo map_;
  MhBuilder builder_;
  bool started_ = false;
};

SchemeInfo mh() {
  SchemeInfo info;
  info.name = "mh";
  info.paper = "Scandolo, Bauszat & Eisemann 2016, compressed multiresolution hierarchies";
  info.kind = SchemeKind::Depth;
  info.buildBytes = [](const MapInfo& map, const Params&) {
    return MhBuilder::workingBytes(std::min<uint32_t>(map.resolution, 512));
  };
  info.makeEncoder = [](const MapInfo& map, const Params&) -> std::unique_ptr<Encoder> {
    return std::make_unique<MhEncoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map, const Params&) -> std::unique_ptr<Decoder> {
    return std::make_unique<MhDecoder>(map.resolution, OffsetQuadtree::load(in, map, "mh"));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(mh);

}  // namespace sb
