#include "schemes/shared/offset_quadtree.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace sb {

namespace {

constexpr uint64_t kUnplaced = std::numeric_limits<uint64_t>::max();

// Depth-first placement of sibling packs: a pack right after the packs of its elder siblings'
// subtrees, padded so that its distance from the parent is a multiple of the parent level's scale.
class Layout {
 public:
  Layout(const MultiresHierarchy& hierarchy, std::span<const uint32_t> sharedChildren,
         const std::vector<uint32_t>& scales)
      : position(hierarchy.nodes.size(), kUnplaced),
        level(hierarchy.nodes.size()),
        kind(hierarchy.nodes.size()),
        hierarchy_(hierarchy),
        shared_(sharedChildren),
        scales_(scales) {
    const uint32_t root = hierarchy.root();
    position[root] = 0;
    kind[root] = hierarchy.nodes[root].hasChildren() ? MhChild::Full : MhChild::Leaf;
    words = OffsetQuadtree::kindWords(kind[root]);
    if (kind[root] == MhChild::Full) placeChildren(root);
  }

  bool pointsToSharedPack(uint32_t node) const {
    return !shared_.empty() && shared_[node] != hierarchy_.nodes[node].firstChild;
  }
  uint32_t childPack(uint32_t node) const {
    return shared_.empty() ? hierarchy_.nodes[node].firstChild : shared_[node];
  }

  std::vector<uint64_t> position;
  std::vector<uint8_t> level;
  std::vector<MhChild> kind;
  uint64_t words = 0;

 private:
  void placeChildren(uint32_t parent) {
    const MhNode& node = hierarchy_.nodes[parent];
    const uint64_t scale = scales_[level[parent]];
    words += (scale - (words - position[parent]) % scale) % scale;
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      if (node.child(k) == MhChild::None) continue;
      position[child] = words;
      level[child] = uint8_t(level[parent] + 1);
      kind[child] = node.child(k);
      words += OffsetQuadtree::kindWords(node.child(k));
      ++child;
    }
    for (uint32_t c = node.firstChild; c < child; ++c)
      if (kind[c] != MhChild::Leaf && !pointsToSharedPack(c)) placeChildren(c);
  }

  const MultiresHierarchy& hierarchy_;
  std::span<const uint32_t> shared_;
  const std::vector<uint32_t>& scales_;
};

}  // namespace

OffsetQuadtree layoutOffsetQuadtree(const MultiresHierarchy& hierarchy,
                                    std::span<const uint32_t> values,
                                    std::span<const uint32_t> sharedChildren, int offsetBits,
                                    const char* scheme) {
  const uint64_t maxOffset = (uint64_t(1) << offsetBits) - 1;
  std::vector<uint32_t> scales(size_t(std::max(hierarchy.levels, 1)), 1);
  // Offsets that do not fit grow their level's scale, and the padding that brings moves the
  // layout: repeat until every offset fits (Lefebvre & Hoppe 2007 §4; converges in a few rounds
  // since scales only grow).
  for (;;) {
    Layout layout(hierarchy, sharedChildren, scales);
    std::vector<uint64_t> needed(scales.size(), 1);
    // A merged pack is reached at the levels of all its parents, and its nodes' offsets are
    // read with each level's scale: from the highest such level down, every scale must stay 1.
    int sharedFrom = hierarchy.levels;
    for (uint32_t n = 0; n < hierarchy.nodes.size(); ++n) {
      if (layout.position[n] == kUnplaced || layout.kind[n] == MhChild::Leaf) continue;
      const uint64_t target = layout.position[layout.childPack(n)];
      if (target == kUnplaced || target <= layout.position[n])
        throw std::logic_error(fmt::format("{}: a merged subtree lies before its parent", scheme));
      const uint64_t distance = target - layout.position[n];
      const int l = layout.level[n];
      if (layout.pointsToSharedPack(n))
        sharedFrom = std::min({sharedFrom, l, layout.level[layout.childPack(n)] - 1});
      needed[size_t(l)] = std::max(needed[size_t(l)], (distance + maxOffset - 1) / maxOffset);
    }
    bool grown = false;
    for (size_t l = 0; l < scales.size(); ++l) {
      if (needed[l] <= scales[l]) continue;
      if (int(l) >= sharedFrom)
        throw std::length_error(fmt::format(
            "{}: offsets at level {} need a scale above 1, but merged subtrees reach that "
            "level; the structure is too large for {}-bit offsets",
            scheme, l, offsetBits));
      scales[l] = uint32_t(std::max<uint64_t>(std::bit_ceil(needed[l]), scales[l] * 2ull));
      grown = true;
    }
    if (grown) continue;

    OffsetQuadtree tree;
    tree.levels = hierarchy.levels;
    tree.rootKind = layout.kind[hierarchy.root()];
    tree.levelScale = scales;
    tree.words.assign(layout.words, 0);
    for (uint32_t n = 0; n < hierarchy.nodes.size(); ++n) {
      const uint64_t at = layout.position[n];
      if (at == kUnplaced) continue;
      const MhChild kind = layout.kind[n];
      if (kind != MhChild::Empty) tree.words[at] = values[n];
      if (kind == MhChild::Leaf) continue;
      const uint64_t offset = (layout.position[layout.childPack(n)] - at) / scales[layout.level[n]];
      tree.words[at + (kind == MhChild::Full)] =
          uint32_t(hierarchy.nodes[n].childFlags) | uint32_t(offset) << 8;
    }
    return tree;
  }
}

std::vector<uint64_t> unmergedPositions(const MultiresHierarchy& hierarchy) {
  const std::vector<uint32_t> unscaled(size_t(std::max(hierarchy.levels, 1)), 1);
  return std::move(Layout(hierarchy, {}, unscaled).position);
}

SizeBreakdown OffsetQuadtree::size() const {
  return {{"nodes", words.size() * sizeof(uint32_t)},
          {"level scales", levelScale.size() * sizeof(uint32_t)}};
}

void OffsetQuadtree::save(ByteWriter& out) const {
  out.put<uint8_t>(uint8_t(rootKind));
  out.putArray<uint32_t>(levelScale);
  out.putArray<uint32_t>(words);
}

OffsetQuadtree OffsetQuadtree::load(ByteReader& in, const MapInfo& map, const char* scheme) {
  OffsetQuadtree tree;
  tree.levels = std::countr_zero(map.resolution);
  if (tree.levels > 21)  // the check below keeps 3 bits per level in a 64-bit word
    throw FormatError(
        fmt::format("{}: {} levels are more than the format holds", scheme, tree.levels));
  const uint8_t root = in.get<uint8_t>("root kind");
  if (root != uint8_t(MhChild::Full) && root != uint8_t(MhChild::Leaf))
    throw FormatError(
        fmt::format("{}: root kind {} is neither a full node nor a leaf", scheme, root));
  tree.rootKind = MhChild(root);
  tree.levelScale = in.getArray<uint32_t>("level scales", size_t(std::max(tree.levels, 1)));
  tree.words = in.getArray<uint32_t>("nodes");
  for (uint32_t scale : tree.levelScale)
    if (scale == 0) throw FormatError(fmt::format("{}: a level scale is 0", scheme));
  if (tree.words.size() < kindWords(tree.rootKind))
    throw FormatError(fmt::format("{}: {} words cannot hold the root", scheme, tree.words.size()));

  // A node is checked once per (kind, level) it is reached as: a merged pack is reached from
  // several parents, possibly at several levels, and each reading must stay in bounds.
  const uint64_t size = tree.words.size();
  std::vector<uint64_t> seen(size);
  struct Visit {
    uint64_t position;
    MhChild kind;
    int level;
  };
  std::vector<Visit> stack{{0, tree.rootKind, 0}};
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    if (visit.kind == MhChild::Leaf) continue;
    const uint32_t link = tree.words[visit.position + (visit.kind == MhChild::Full)];
    const uint32_t flags = link & 0xff;
    if (flags == 0)
      throw FormatError(
          fmt::format("{}: inner node at word {} has no children", scheme, visit.position));
    if (visit.level >= tree.levels)
      throw FormatError(fmt::format("{}: node at word {} has children below the texel level",
                                    scheme, visit.position));
    const uint64_t first = visit.position + uint64_t(link >> 8) * tree.levelScale[visit.level];
    if (first <= visit.position || first > size || size - first < siblingWords(flags, kMhChildren))
      throw FormatError(fmt::format("{}: children of the node at word {} lie outside the nodes",
                                    scheme, visit.position));
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(flags, k));
      if (kind == MhChild::None) continue;
      const uint64_t at = first + siblingWords(flags, k);
      const uint64_t bit = uint64_t(1) << (3 * visit.level + int(kind) - 1);
      if (seen[at] & bit) continue;
      seen[at] |= bit;
      stack.push_back({at, kind, visit.level + 1});
    }
  }
  return tree;
}

}  // namespace sb
