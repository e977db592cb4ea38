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

std::unique_ptr<Decoder> mhDecoder(OffsetQuadtree tree, const MhNodeCounts& counts,
                                   BuildContext& context) {
  context.count("full nodes", counts.full);
  context.count("empty nodes", counts.empty);
  context.count("leaves", counts.leaves);
  return std::make_unique<MhDecoder>(std::move(tree));
}

std::unique_ptr<Decoder> encodeMh(MultiresHierarchy hierarchy, BuildContext& context) {
  context.phase("serialise");
  // SBE16a §5: each interval is replaced by one representative, its middle.
  std::vector<uint32_t> values(hierarchy.nodes.size());
  MhNodeCounts counts;
  for (size_t n = 0; n < values.size(); ++n) {
    values[n] = hierarchy.nodes[n].interval.middle();
    counts.addChildrenOf(hierarchy.nodes[n]);
  }
  counts.addRoot(hierarchy.nodes.back());
  return mhDecoder(layoutOffsetQuadtree(hierarchy, values, {}, kOffsetBits, "mh"), counts, context);
}

SchemeInfo mh() {
  SchemeInfo info;
  info.name = "mh";
  info.paper = "Scandolo, Bauszat & Eisemann 2016, compressed multiresolution hierarchies";
  info.kind = SchemeKind::Depth;
  // A merge of parts lays the structure out part by part: it holds the structure's words (two a
  // node at most, padding aside) and one part with its layout (a position, level, kind and value
  // a node).
  setMhBuilds(info, {[](const MapInfo&, const ParamValues&) -> HierarchyEncode { return encodeMh; },
                     MhBuilder::hierarchyFloorBytes,
                     {[](const MapInfo& map, const ParamValues&, uint32_t partSize) {
                        return partwiseMhMerger(map, "mh", partSize, kOffsetBits, mhDecoder);
                      },
                      8, 14}});
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues&) -> std::unique_ptr<Decoder> {
    return std::make_unique<MhDecoder>(OffsetQuadtree::load(in, map, "mh"));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(mh);

}  // namespace sb
