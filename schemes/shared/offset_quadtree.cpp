#include "schemes/shared/offset_quadtree.h"

#include <algorithm>
#include <bit>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

namespace sb {

namespace {

constexpr uint64_t kUnplaced = std::numeric_limits<uint64_t>::max();

// Where a placement starts: `top` is placed already, at `position` as a `kind` node of `level`,
// and its descendants' packs follow from word `firstFree` on.
struct LayoutStart {
  uint32_t top = 0;
  uint64_t position = 0;
  int level = 0;
  MhChild kind = MhChild::Leaf;
  uint64_t firstFree = 0;
};

// Nodes of one level whose descendants are laid out elsewhere (the parts of a merge): each
// stands for a block of `words(node)` words where its children's pack would begin.
struct LayoutBlocks {
  int level = -1;
  std::function<uint64_t(uint32_t node)> words;
};

// Depth-first placement of sibling packs: a pack right after the packs of its elder siblings'
// subtrees, padded so that its distance from the parent is a multiple of the parent level's scale.
// Everything below a node is contiguous and depends on the node's position only through that
// first padding, which is what lets PartwiseLayout place parts one by one.
class Layout {
 public:
  Layout(const MultiresHierarchy& hierarchy, std::span<const uint32_t> sharedChildren,
         const std::vector<uint32_t>& scales, const LayoutStart& start,
         const LayoutBlocks& blocks = {})
      : position(hierarchy.nodes.size(), kUnplaced),
        level(hierarchy.nodes.size()),
        kind(hierarchy.nodes.size()),
        hierarchy_(hierarchy),
        shared_(sharedChildren),
        scales_(scales),
        blocks_(blocks) {
    position[start.top] = start.position;
    level[start.top] = uint8_t(start.level);
    kind[start.top] = start.kind;
    words = start.firstFree;
    if (start.kind == MhChild::Full || start.kind == MhChild::Empty) placeChildren(start.top);
  }

  bool pointsToSharedPack(uint32_t node) const {
    return !shared_.empty() && shared_[node] != hierarchy_.nodes[node].firstChild;
  }
  uint32_t childPack(uint32_t node) const {
    return shared_.empty() ? hierarchy_.nodes[node].firstChild : shared_[node];
  }
  // Where the children of a placed inner node begin.
  uint64_t childrenAt(uint32_t node) const {
    return level[node] == blocks_.level ? blockAt.at(node) : position[childPack(node)];
  }

  std::vector<uint64_t> position;
  std::vector<uint8_t> level;
  std::vector<MhChild> kind;
  std::map<uint32_t, uint64_t> blockAt;  // the first word of each block
  uint64_t words = 0;

 private:
  void placeChildren(uint32_t parent) {
    const MhNode& node = hierarchy_.nodes[parent];
    const uint64_t scale = scales_[level[parent]];
    words += (scale - (words - position[parent]) % scale) % scale;
    if (level[parent] == blocks_.level) {
      blockAt[parent] = words;
      words += blocks_.words(parent);
      return;
    }
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
  LayoutBlocks blocks_;
};

LayoutStart wholeTree(const MultiresHierarchy& hierarchy) {
  const uint32_t root = hierarchy.root();
  const MhChild kind = hierarchy.nodes[root].hasChildren() ? MhChild::Full : MhChild::Leaf;
  return {root, 0, 0, kind, OffsetQuadtree::kindWords(kind)};
}

// The scale each level's offsets need (at least 1), and the highest level merged packs reach
// (MMH): a merged pack is reached at the levels of all its parents, and its nodes' offsets are
// read with each level's scale, so from that level down every scale must stay 1.
struct ScaleNeeds {
  std::vector<uint64_t> perLevel;
  int sharedFrom;
  explicit ScaleNeeds(int levels) : perLevel(size_t(std::max(levels, 1)), 1), sharedFrom(levels) {}

  void add(const Layout& layout, size_t nodes, uint64_t maxOffset, const char* scheme) {
    for (uint32_t n = 0; n < nodes; ++n) {
      if (layout.position[n] == kUnplaced || layout.kind[n] == MhChild::Leaf) continue;
      const uint64_t target = layout.childrenAt(n);
      if (target == kUnplaced || target <= layout.position[n])
        throw std::logic_error(fmt::format("{}: a merged subtree lies before its parent", scheme));
      const int l = layout.level[n];
      if (layout.pointsToSharedPack(n))
        sharedFrom = std::min({sharedFrom, l, layout.level[layout.childPack(n)] - 1});
      const uint64_t distance = target - layout.position[n];
      perLevel[size_t(l)] = std::max(perLevel[size_t(l)], (distance + maxOffset - 1) / maxOffset);
    }
  }

  // Grows the scales offsets do not fit (Lefebvre & Hoppe 2007 §4; scales only grow, so the
  // rounds converge in a few); true if one grew.
  bool grow(std::vector<uint32_t>& scales, int offsetBits, const char* scheme) const {
    bool grown = false;
    for (size_t l = 0; l < scales.size(); ++l) {
      if (perLevel[l] <= scales[l]) continue;
      if (int(l) >= sharedFrom)
        throw std::length_error(fmt::format(
            "{}: offsets at level {} need a scale above 1, but merged subtrees reach that "
            "level; the structure is too large for {}-bit offsets",
            scheme, l, offsetBits));
      scales[l] = uint32_t(std::max<uint64_t>(std::bit_ceil(perLevel[l]), scales[l] * 2ull));
      grown = true;
    }
    return grown;
  }
};

// Writes every placed node's words: its value (`values[n]`, Full and Leaf nodes), then its child
// flags and scaled offset (inner nodes).
void writeNodes(const Layout& layout, const MultiresHierarchy& hierarchy,
                std::span<const uint32_t> values, const std::vector<uint32_t>& scales,
                std::vector<uint32_t>& words) {
  for (uint32_t n = 0; n < hierarchy.nodes.size(); ++n) {
    const uint64_t at = layout.position[n];
    if (at == kUnplaced) continue;
    const MhChild kind = layout.kind[n];
    if (kind != MhChild::Empty) words[at] = values[n];
    if (kind == MhChild::Leaf) continue;
    const uint64_t offset = (layout.childrenAt(n) - at) / scales[layout.level[n]];
    words[at + (kind == MhChild::Full)] = uint32_t(hierarchy.nodes[n].childFlags) | uint32_t(offset)
                                                                                        << 8;
  }
}

uint64_t maxOffsetOf(int offsetBits) {
  return (uint64_t(1) << offsetBits) - 1;
}

std::vector<uint32_t> middles(const MultiresHierarchy& hierarchy) {
  std::vector<uint32_t> values(hierarchy.nodes.size());
  for (size_t n = 0; n < values.size(); ++n) values[n] = hierarchy.nodes[n].interval.middle();
  return values;
}

}  // namespace

OffsetQuadtree layoutOffsetQuadtree(const MultiresHierarchy& hierarchy,
                                    std::span<const uint32_t> values,
                                    std::span<const uint32_t> sharedChildren, int offsetBits,
                                    const char* scheme) {
  std::vector<uint32_t> scales(size_t(std::max(hierarchy.levels, 1)), 1);
  // Offsets that do not fit grow their level's scale, and the padding that brings moves the
  // layout: repeat until every offset fits.
  for (;;) {
    Layout layout(hierarchy, sharedChildren, scales, wholeTree(hierarchy));
    ScaleNeeds needs(hierarchy.levels);
    needs.add(layout, hierarchy.nodes.size(), maxOffsetOf(offsetBits), scheme);
    if (needs.grow(scales, offsetBits, scheme)) continue;

    OffsetQuadtree tree;
    tree.levels = hierarchy.levels;
    tree.rootKind = layout.kind[hierarchy.root()];
    tree.levelScale = scales;
    tree.words.assign(layout.words, 0);
    writeNodes(layout, hierarchy, values, scales, tree.words);
    return tree;
  }
}

std::vector<uint32_t> unmergedPositions(const MultiresHierarchy& hierarchy, const char* scheme) {
  std::vector<uint32_t> positions(hierarchy.nodes.size(), 0);
  const uint32_t root = hierarchy.root();
  uint64_t words = OffsetQuadtree::kindWords(hierarchy.nodes[root].hasChildren() ? MhChild::Full
                                                                                 : MhChild::Leaf);
  // Layout's placement with every scale 1: a pack right after the packs of its elder siblings'
  // subtrees. Held in 32 bits, a third of Layout's bytes, since MMH keeps it beside the whole
  // hierarchy while matching.
  const auto place = [&](auto&& self, uint32_t parent) -> void {
    const MhNode& node = hierarchy.nodes[parent];
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      if (node.child(k) == MhChild::None) continue;
      positions[child++] = uint32_t(words);
      words += OffsetQuadtree::kindWords(node.child(k));
    }
    if (words > std::numeric_limits<uint32_t>::max())
      throw std::length_error(fmt::format(
          "{}: the hierarchy takes more than 2^32 words laid out without merges", scheme));
    for (uint32_t c = node.firstChild; c < child; ++c)
      if (hierarchy.nodes[c].hasChildren()) self(self, c);
  };
  if (hierarchy.nodes[root].hasChildren()) place(place, root);
  return positions;
}

PartwiseLayout::PartwiseLayout(int levels, int partLevel, uint64_t partCount, int offsetBits,
                               const char* scheme)
    : levels_(levels),
      partLevel_(partLevel),
      offsetBits_(offsetBits),
      scheme_(scheme),
      scales_(size_t(std::max(levels, 1)), 1),
      needed_(scales_.size(), 1),
      blockWords_(partCount, 0),
      blocks_(partCount) {}

void PartwiseLayout::measure(uint64_t part, const MultiresHierarchy& tree) {
  // Placed as if its root stood at word 0: inside the block only distances count.
  const uint32_t root = tree.root();
  const MhChild kind = tree.nodes[root].hasChildren() ? MhChild::Empty : MhChild::Leaf;
  const Layout layout(tree, {}, scales_, {root, 0, partLevel_, kind, 1});
  if (kind == MhChild::Leaf) return;
  ScaleNeeds needs(levels_);
  needs.add(layout, tree.nodes.size(), maxOffsetOf(offsetBits_), scheme_);
  for (size_t l = size_t(partLevel_) + 1; l < needed_.size(); ++l)
    needed_[l] = std::max(needed_[l], needs.perLevel[l]);
  blockWords_.at(part) = layout.words - layout.childrenAt(root);
}

bool PartwiseLayout::settle(const MultiresHierarchy& upper) {
  const std::map<uint32_t, uint64_t> partOf = upper.nodesAtLevel(partLevel_);
  const Layout layout(upper, {}, scales_, wholeTree(upper),
                      {partLevel_, [&](uint32_t n) { return blockWords_.at(partOf.at(n)); }});
  ScaleNeeds needs(levels_);
  needs.add(layout, upper.nodes.size(), maxOffsetOf(offsetBits_), scheme_);
  for (size_t l = 0; l < needed_.size(); ++l)
    needs.perLevel[l] = std::max(needs.perLevel[l], needed_[l]);
  std::fill(needed_.begin(), needed_.end(), 1);
  if (needs.grow(scales_, offsetBits_, scheme_)) return false;

  for (const auto& [n, at] : layout.blockAt)
    blocks_[partOf.at(n)] = {layout.position[n], at, layout.kind[n]};
  rootKind_ = layout.kind[upper.root()];
  words_.assign(layout.words, 0);
  writeNodes(layout, upper, middles(upper), scales_, words_);
  return true;
}

void PartwiseLayout::write(uint64_t part, const MultiresHierarchy& tree) {
  const Block& block = blocks_.at(part);
  if (block.kind != MhChild::Full && block.kind != MhChild::Empty) return;
  const Layout layout(tree, {}, scales_,
                      {tree.root(), block.position, partLevel_, block.kind, block.start});
  writeNodes(layout, tree, middles(tree), scales_, words_);
}

OffsetQuadtree PartwiseLayout::finish() {
  OffsetQuadtree tree;
  tree.levels = levels_;
  tree.rootKind = rootKind_;
  tree.levelScale = scales_;
  tree.words = std::move(words_);
  return tree;
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
