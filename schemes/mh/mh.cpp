// mh — compressed multiresolution hierarchies (Scandolo, Bauszat & Eisemann 2016a): the sparse
// quadtree of the dual depth map's intervals, each stored node holding an absolute depth, with
// 16-bit scaled child offsets. A lookup returns the deepest stored depth on the texel's path.
#include <fmt/format.h>

#include "schemes/shared/mh_parts.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {
namespace {

// SBE16a §5: 16-bit offsets, the other 8 bits of the 64-bit node are padding.
constexpr int kOffsetBits = 16;

using MhDecoder = OffsetQuadtreeDecoder<OffsetQuadtree::Values::Absolute>;

std::unique_ptr<Decoder> encodeMh(MultiresHierarchy hierarchy, BuildContext& context) {
  context.phase("serialise");
  // SBE16a §5: each interval is replaced by one representative, its middle.
  std::vector<uint32_t> values(hierarchy.nodes.size());
  uint64_t kinds[4] = {};
  for (size_t n = 0; n < values.size(); ++n) {
    const MhNode& node = hierarchy.nodes[n];
    values[n] = node.interval.middle();
    for (int k = 0; k < kMhChildren; ++k) ++kinds[int(node.child(k))];
  }
  const bool rootHasChildren = hierarchy.nodes.back().hasChildren();
  context.count("full nodes", kinds[int(MhChild::Full)] + rootHasChildren);
  context.count("empty nodes", kinds[int(MhChild::Empty)]);
  context.count("leaves", kinds[int(MhChild::Leaf)] + !rootHasChildren);
  return std::make_unique<MhDecoder>(
      layoutOffsetQuadtree(hierarchy, values, {}, kOffsetBits, "mh"));
}

SchemeInfo mh() {
  SchemeInfo info;
  info.name = "mh";
  info.paper = "Scandolo, Bauszat & Eisemann 2016, compressed multiresolution hierarchies";
  info.kind = SchemeKind::Depth;
  // The encode step keeps per node its value (4 bytes), its position, level and kind in the
  // layout (10) and at least a word of the structure (4).
  setMhBuilds(info, {[](const MapInfo&, const ParamValues&) -> HierarchyEncode { return encodeMh; },
                     MhBuilder::hierarchyFloorBytes, 18});
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues&) -> std::unique_ptr<Decoder> {
    return std::make_unique<MhDecoder>(OffsetQuadtree::load(in, map, "mh"));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(mh);

}  // namespace sb
