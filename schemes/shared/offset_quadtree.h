// The serialised sparse quadtree of MH and MMH (SBE16a §5, after Lefebvre & Hoppe 2007): nodes in
// depth-first order with siblings contiguous, and in each inner node one offset to its first
// child, scaled by a per-level factor so that it fits a few bits.
//
// Words (32-bit):  full inner node  [value][child flags : 8 | offset : 24]
//                  empty inner node [child flags : 8 | offset : 24]
//                  leaf             [value]
// A node's children start at (node position + offset · scale[node level]) plus padding the layout
// inserted; the flags give each child's kind, hence its size and where child k lies. `mh` uses
// 16 of the 24 offset bits (SBE16a's 64-bit node, 8 bits of padding); `mmh` all 24 (SBE16b §3.3).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/child_flags.h"
#include "schemes/shared/multires_hierarchy.h"

namespace sb {

struct OffsetQuadtree {
  int levels = 0;                    // texels are at level `levels`
  MhChild rootKind = MhChild::Leaf;  // Full (with children) or Leaf
  std::vector<uint32_t> levelScale;  // offset scale of the inner nodes of level l, l < levels
  std::vector<uint32_t> words;

  // How values combine down a path: MH stores each node's depth key (the deepest wins); MMH
  // stores it relative to the parent's reconstructed key (the sum along the path, SBE16b Alg. 1).
  enum class Values { Absolute, Relative };

  // The key texel (i, j) reads, walking no deeper than `deepest` (the map `levels − deepest`
  // levels up: hierarchical PCF).
  template <Values mode>
  uint32_t texelKey(uint32_t i, uint32_t j, int deepest) const {
    uint64_t position = 0;
    MhChild kind = rootKind;
    uint32_t key = words[0];
    for (int level = 0; kind != MhChild::Leaf && level < deepest; ++level) {
      const uint32_t link = words[position + (kind == MhChild::Full)];
      const uint32_t flags = link & 0xff;
      const int k = mhChildIndex(i, j, levels - level - 1);
      const MhChild child = MhChild(childFlag(flags, k));
      if (child == MhChild::None) break;
      position += uint64_t(link >> 8) * levelScale[level] + siblingWords(flags, k);
      kind = child;
      if (child == MhChild::Empty) continue;
      key = mode == Values::Relative ? key + words[position] : words[position];
    }
    return key;
  }

  // Words taken by the children before child k, from the parent's flags.
  static uint32_t siblingWords(uint32_t flags, int k) {
    uint32_t words = 0;
    for (int m = 0; m < k; ++m) words += kindWords(MhChild(childFlag(flags, m)));
    return words;
  }
  static uint32_t kindWords(MhChild kind) {
    return kind == MhChild::None ? 0 : kind == MhChild::Full ? 2 : 1;
  }

  SizeBreakdown size() const;
  void save(ByteWriter& out) const;
  // Validates every node reachable from the root at every level it is reached at: offsets inside
  // the file, children only above the texel level, no inner node without children. `scheme`
  // names the scheme in errors.
  static OffsetQuadtree load(ByteReader& in, const MapInfo& map, const char* scheme);
};

// The decoder of `mh` (absolute values) and `mmh` (relative values): point, exact PCF and
// hierarchical PCF, since every level of the hierarchy is a complete shadow map (SBE16a) read by
// stopping the walk.
template <OffsetQuadtree::Values mode>
class OffsetQuadtreeDecoder final : public HierarchicalDepthDecoder<OffsetQuadtreeDecoder<mode>> {
 public:
  explicit OffsetQuadtreeDecoder(OffsetQuadtree tree) : tree_(std::move(tree)) {}

  uint32_t resolution() const { return uint32_t(1) << tree_.levels; }
  float depth(uint32_t i, uint32_t j) const {
    return depthOfKey(tree_.texelKey<mode>(i, j, tree_.levels));
  }
  float coarseDepth(uint32_t i, uint32_t j, int coarser) const {
    return depthOfKey(tree_.texelKey<mode>(i << coarser, j << coarser, tree_.levels - coarser));
  }
  SizeBreakdown size() const override { return tree_.size(); }
  void save(ByteWriter& out) const override { tree_.save(out); }

 private:
  OffsetQuadtree tree_;
};

// Lays the hierarchy out in depth-first order. `values[n]` is the word stored for node n (Full
// and Leaf nodes). `sharedChildren` (MMH) gives, per node, the first child of the sibling pack
// its offset points to when that pack is another node's (a merged subtree; it must lie later in
// depth-first order); empty for none. Scales grow from 1 where an offset does not fit
// `offsetBits`; a level whose nodes point to shared packs must keep scale 1 (SBE16b §3.3), else
// std::length_error names `scheme` and the level.
OffsetQuadtree layoutOffsetQuadtree(const MultiresHierarchy& hierarchy,
                                    std::span<const uint32_t> values,
                                    std::span<const uint32_t> sharedChildren, int offsetBits,
                                    const char* scheme);

// An offset quadtree without merged subtrees laid out part by part, as a merge of parts reads
// them (`mh`, mh_parts.h), without ever holding the whole hierarchy: depth-first placement puts
// everything below a part's root in one contiguous block, whose inner layout depends on the
// scales alone, so the structure is the upper levels' packs with the parts' blocks between them.
// The scales grow as layoutOffsetQuadtree's do, one pass over the parts per round: measure()
// every part, then settle(); once settle() finds the scales final, write() every part, then
// finish(). The result is layoutOffsetQuadtree's with every value the node's middle, word for
// word. A part's tree is its stored nodes with its root appended last (MultiresHierarchy order).
class PartwiseLayout {
 public:
  PartwiseLayout(int levels, int partLevel, uint64_t partCount, int offsetBits, const char* scheme);
  void measure(uint64_t part, const MultiresHierarchy& tree);
  // `upper` is the hierarchy above the parts (MhBuilder fed the parts' roots alone): lays it
  // out around the measured blocks and grows the scales that need it. True when none grew and
  // the parts are to be written, false when they are to be measured again.
  bool settle(const MultiresHierarchy& upper);
  void write(uint64_t part, const MultiresHierarchy& tree);
  OffsetQuadtree finish();

 private:
  struct Block {
    uint64_t position = 0, start = 0;  // of the part's root, and of its children's pack
    MhChild kind = MhChild::None;
  };
  int levels_, partLevel_, offsetBits_;
  const char* scheme_;
  std::vector<uint32_t> scales_;
  std::vector<uint64_t> needed_;      // by level, below the part level, from this round's parts
  std::vector<uint64_t> blockWords_;  // by part
  std::vector<Block> blocks_;         // by part, once the scales are final
  MhChild rootKind_ = MhChild::Leaf;
  std::vector<uint32_t> words_;
};

// The word position of every node laid out without merged subtrees and with every scale 1: MMH's
// conservative bound on a merged offset (SBE16b §3.3: merging only shortens distances). Throws
// std::length_error naming `scheme` beyond 2^32 words.
std::vector<uint32_t> unmergedPositions(const MultiresHierarchy& hierarchy, const char* scheme);

}  // namespace sb
