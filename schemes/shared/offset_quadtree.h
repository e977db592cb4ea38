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

#include <bit>
#include <cstdint>
#include <optional>
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
  // stores it relative to the parent's reconstructed key (the sum along the path, SBE16b Alg. 1),
  // as a wrapping uint32 key delta (Relative) or, as the paper does, as a float32 difference
  // summed in float32 (RelativeFloat: the key is the bit pattern of the running float sum).
  enum class Values { Absolute, Relative, RelativeFloat };

  // The key a path gives at a node holding `word`, below a path that gave `key`.
  template <Values mode>
  static uint32_t combine(uint32_t key, uint32_t word) {
    if constexpr (mode == Values::Absolute) return word;
    if constexpr (mode == Values::Relative) return key + word;
    return std::bit_cast<uint32_t>(std::bit_cast<float>(key) + std::bit_cast<float>(word));
  }

  // Where a walk stands: the `kind` node of `level` at word `position`, and the key its path
  // gives.
  struct Walk {
    uint64_t position;
    MhChild kind;
    int level;
    uint32_t key;
  };
  Walk rootWalk() const { return {0, rootKind, 0, words[0]}; }

  // One step of a walk, to child k of its inner node; false where that child is missing (the
  // walk stays, and its key answers the child's whole square).
  template <Values mode>
  bool step(Walk& walk, int k) const {
    const uint32_t link = words[walk.position + (walk.kind == MhChild::Full)];
    const uint32_t flags = link & 0xff;
    const MhChild child = MhChild(childFlag(flags, k));
    if (child == MhChild::None) return false;
    walk.position += uint64_t(link >> 8) * levelScale[walk.level] + siblingWords(flags, k);
    walk.kind = child;
    ++walk.level;
    if (child != MhChild::Empty) walk.key = combine<mode>(walk.key, words[walk.position]);
    return true;
  }

  // The key texel (i, j) reads, walking no deeper than `deepest` (the map `levels − deepest`
  // levels up: hierarchical PCF).
  template <Values mode>
  uint32_t texelKey(uint32_t i, uint32_t j, int deepest) const {
    Walk walk = rootWalk();
    while (walk.kind != MhChild::Leaf && walk.level < deepest &&
           step<mode>(walk, mhChildIndex(i, j, levels - walk.level - 1))) {
    }
    return walk.key;
  }

  // The keys of the texels of `rect` in one walk (issue 13, as the MH reference code filters): a
  // point walk down to the lowest node holding the whole rectangle, whose level is where the
  // corners' coordinates first differ, then into each child the rectangle overlaps. A missing
  // child or a leaf above the texel level gives its whole overlap one key: visit(key, texels)
  // once for it.
  template <Values mode, class Visit>
  void forEachKeyBlock(const TexelRect& rect, Visit&& visit) const {
    const int common = levels - std::bit_width((rect.i0 ^ rect.i1) | (rect.j0 ^ rect.j1));
    Walk walk = rootWalk();
    while (walk.kind != MhChild::Leaf && walk.level < common)
      if (!step<mode>(walk, mhChildIndex(rect.i0, rect.j0, levels - walk.level - 1)))
        return visit(walk.key, rect.texels());
    if (walk.kind == MhChild::Leaf) return visit(walk.key, rect.texels());
    const uint32_t corner = ~((uint32_t(1) << (levels - walk.level)) - 1);
    walkRect<mode>(walk, rect.i0 & corner, rect.j0 & corner, rect, visit);
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

 private:
  // The inner node `walk` stands on covers the square at (x0, y0) that holds `rect`'s part below
  // it; a child is entered where the rectangle reaches its side of the square's middle.
  template <Values mode, class Visit>
  void walkRect(const Walk& walk, uint32_t x0, uint32_t y0, const TexelRect& rect,
                Visit& visit) const {
    const uint32_t half = uint32_t(1) << (levels - walk.level - 1);
    const uint32_t link = words[walk.position + (walk.kind == MhChild::Full)];
    const uint32_t flags = link & 0xff;
    const uint32_t midX = x0 + half, midY = y0 + half;
    const bool columns[2] = {rect.i0 < midX, rect.i1 >= midX};
    const bool rows[2] = {rect.j0 < midY, rect.j1 >= midY};
    uint64_t at = walk.position + uint64_t(link >> 8) * levelScale[walk.level];
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild child = MhChild(childFlag(flags, k));
      if (columns[k & 1] && rows[k >> 1]) {
        const uint32_t cx = x0 + (k & 1) * half, cy = y0 + (k >> 1) * half;
        const uint32_t key = child == MhChild::None || child == MhChild::Empty
                                 ? walk.key
                                 : combine<mode>(walk.key, words[at]);
        if (child == MhChild::None || child == MhChild::Leaf)
          visit(key, overlap(rect, cx, cy, half));
        else
          walkRect<mode>(Walk{at, child, walk.level + 1, key}, cx, cy, rect, visit);
      }
      at += kindWords(child);
    }
  }
};

// The decoder of `mh` (absolute values) and `mmh` (relative values): point, exact PCF and
// hierarchical PCF, since every level of the hierarchy is a complete shadow map (SBE16a) read by
// stopping the walk.
template <OffsetQuadtree::Values mode>
class OffsetQuadtreeDecoder final : public HierarchicalDepthDecoder<OffsetQuadtreeDecoder<mode>> {
 public:
  // `tag`, where given, is a byte saved before the tree (mmh's float-differences variant: which
  // values the tree holds).
  explicit OffsetQuadtreeDecoder(OffsetQuadtree tree, std::optional<uint8_t> tag = {})
      : tree_(std::move(tree)), tag_(tag) {}

  uint32_t resolution() const { return uint32_t(1) << tree_.levels; }
  float depth(uint32_t i, uint32_t j) const {
    return depthOfKey(tree_.texelKey<mode>(i, j, tree_.levels));
  }
  uint64_t litTexels(const TexelRect& rect, float z) const {
    uint64_t lit = 0;
    tree_.forEachKeyBlock<mode>(
        rect, [&](uint32_t key, uint64_t texels) { lit += z <= depthOfKey(key) ? texels : 0; });
    return lit;
  }
  float coarseDepth(uint32_t i, uint32_t j, int coarser) const {
    return depthOfKey(tree_.texelKey<mode>(i << coarser, j << coarser, tree_.levels - coarser));
  }
  SizeBreakdown size() const override {
    SizeBreakdown size = tree_.size();
    if (tag_) size.push_back({"value kind", 1});
    return size;
  }
  void save(ByteWriter& out) const override {
    if (tag_) out.put<uint8_t>(*tag_);
    tree_.save(out);
  }

 private:
  OffsetQuadtree tree_;
  std::optional<uint8_t> tag_;
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
