// Builds of the MH-family schemes (`mh`, `mmh`, `dag-mh`), whole and in parts (parts.h), around
// one encode step per scheme: the step from the multiresolution hierarchy to the scheme's
// structure. A part encoder reduces its part's tiles to the part's hierarchy (MhBuilder in part
// mode) and writes it as the part payload; the merger validates each payload, joins it under the
// upper levels exactly as a whole build joins tile roots (SBE16a §3, tiled construction;
// Scandolo & Eisemann 2021 merge tiles on the CPU), and after the last part hands the
// hierarchy, node for node the whole build's, to the scheme's encode step.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/multires_hierarchy.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {

// Part payload (little-endian):
//   u64  part index, u32 part side            the part it belongs to
//   u32  root lo, u32 root hi, u32 root first child, u8 root child flags
//                                             the part's root, which the levels above decide on
//   u64  node count n, then n × 13 bytes      the stored nodes, packs before their parents:
//        u32 lo, u32 hi, u32 first child (index among the n, 0 without children), u8 child flags
inline constexpr size_t kMhPartNodeBytes = 13;
void writeMhPart(ByteWriter& out, const MapPart& part, const MhBuilder::PartHierarchy& hierarchy);
// Reads and validates a payload: a tree whose packs partition the nodes, each before its
// parent, no deeper than the texels, child flags matching the children, intervals of depth keys
// with lo ≤ hi. Throws FormatError naming `scheme`, the part and what is wrong.
MhBuilder::PartHierarchy readMhPart(ByteReader& in, const MapPart& part, const std::string& scheme);
// A payload's root alone, its header checked as readMhPart checks it and its nodes passed over
// unread: for a merge's pass that needs only the parts' roots (delta_parts.h), whose next pass
// reads every payload whole with readMhPart.
MhBuilder::Pending readMhPartRoot(ByteReader& in, const MapPart& part, const std::string& scheme);

// How an MH-family scheme gets from the hierarchy to its structure, and what that costs.
struct MhEncoding {
  // The scheme's encode step for a map and parameters.
  std::function<HierarchyEncode(const MapInfo&, const ParamValues&)> encodeFor;
  // A whole build's bytes beyond the tiles' working memory, the hierarchy included.
  std::function<uint64_t(const MapInfo&)> wholeBuildBytes;
  // The merge of parts, and what it holds per node of the hierarchy (counted from the part
  // files, or its floor before they exist) and per node of the one part it reads beside its
  // payload and nodes. Without `makeMerger` the merge joins the whole hierarchy and runs the
  // encode step on it (`mmh`): per node the hierarchy's 16 bytes and the encode step's arrays.
  // With it the scheme merges without ever holding the whole hierarchy (`mh`:
  // partwiseMhMerger; `dag-mh`: dag_parts.h; `delta-dag`: delta_parts.h), and holds per node its
  // share of the structure.
  struct Merge {
    std::function<std::unique_ptr<PartMerger>(const MapInfo&, const ParamValues&,
                                              uint32_t partSize)>
        makeMerger;
    uint64_t bytesPerNode = 0, partBytesPerNode = 0;
    // What the encode step reserves during the merge (BuildContext::reserve), assumed per node
    // where the nodes are known only at their floor (before the part files exist).
    uint64_t reservedBytesPerNode = 0;
  } merge;
};

// Checks of a merger's input shared by the MH family's mergers: the part size (a power of two
// below R; returned) and that `part` is the one expected next (std::invalid_argument).
uint32_t checkedPartSize(const std::string& scheme, uint32_t partSize, const MapInfo& map);
void expectPart(const std::string& scheme, uint64_t next, uint32_t partSize, const MapPart& part);
// Checks that all `count` parts arrived in a pass (std::logic_error otherwise).
void expectAllParts(const std::string& scheme, uint64_t merged, uint64_t count);
// A part's hierarchy as a tree: its stored nodes with its root appended last.
std::vector<MhNode> partTree(MhBuilder::PartHierarchy hierarchy);

// The merge of an offset quadtree of the nodes' middles without merged subtrees (`mh`): laid out
// part by part (PartwiseLayout), the parts read once per round of scales, and handed to
// `decoder`. The first pass also feeds the parts' roots alone to the builder of the levels above
// them.
std::unique_ptr<PartMerger> partwiseMhMerger(
    const MapInfo& map, std::string scheme, uint32_t partSize, int offsetBits,
    std::function<std::unique_ptr<Decoder>(OffsetQuadtree, const MhNodeCounts&, BuildContext&)>
        decoder);

// Fills in `info`'s buildBytes, makeEncoder, makePartEncoder and makePartMerger; `info.name`
// names the scheme in errors. For a build in parts, buildBytes declares, by shape.step, one
// part's encoder (its tiles' working memory, its hierarchy and payload), the merge (the whole
// hierarchy and the encode step, or the partwise layout's words, and one part's payload, nodes
// and layout) or the larger, each hierarchy at its floor: a node per 64 texels up to 16K², 256
// per texel row beyond (mh_parts.cpp), or counted from the part files once they exist.
void setMhBuilds(SchemeInfo& info, MhEncoding encoding);

}  // namespace sb
