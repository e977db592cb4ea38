// The multiresolution hierarchy (MH) of a dual depth map (Scandolo et al. 2016a), built once and
// shared by the three depth-interval schemes: `mh` serialises it as is, `mmh` merges its
// subtrees, `dag-mh` stores its topology as a DAG and its values in chunks.
//
// Depths are handled as *depth keys*: the bit pattern of a non-negative float32, which orders
// exactly as the floats do. Intervals are key intervals, a value chosen inside one is a float
// inside the texel's [lo, hi] bit for bit, and relative values (MMH) are exact integer
// differences instead of rounded float differences.
#pragma once

#include <bit>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "schemes/interface/parts.h"
#include "schemes/interface/scheme.h"
#include "schemes/shared/child_flags.h"

namespace sb {

// The depth key of d ≥ 0 (+0 for -0; +inf allowed). Throws std::invalid_argument for a negative
// or NaN depth: a dual depth map never holds one (DESIGN §2: z ∈ [0, 1], hi may be +inf).
uint32_t depthKey(float d);
inline float depthOfKey(uint32_t key) {
  return std::bit_cast<float>(key);
}

// A key interval [lo, hi]; a node's value may be any key inside it.
struct KeyInterval {
  uint32_t lo = 0, hi = 0;
  // The value a scheme stores for the interval: its middle key, away from both bounds so that
  // the largest number of neighbours still contain it.
  uint32_t middle() const { return lo + (hi - lo) / 2; }
};

// The 2-bit child flags of SBE16a: which of the four children exist and what they are.
enum class MhChild : uint8_t {
  None = 0,   // represented by an ancestor's value, nothing stored
  Full = 1,   // an inner node with a value of its own
  Empty = 2,  // an inner node without a value: represented by an ancestor, but has descendants
  Leaf = 3,   // a value and no descendants
};

// Full and Leaf nodes hold a value; Empty and None nodes do not.
inline bool hasValue(MhChild kind) {
  return kind == MhChild::Full || kind == MhChild::Leaf;
}

// Children are numbered by their quadrant, k = 2·(y bit) + (x bit) at the child's level, so that
// depth-first order is Morton order.
constexpr int kMhChildren = 4;
inline int mhChildIndex(uint32_t i, uint32_t j, int bit) {
  return int(((j >> bit) & 1) << 1 | ((i >> bit) & 1));
}

struct MhNode {
  KeyInterval interval;     // Full and Leaf nodes: the interval their value must lie in
  uint32_t firstChild = 0;  // index in MultiresHierarchy::nodes of the first existing child
  uint8_t childFlags = 0;   // MhChild of child k in bits 2k, 2k+1
  MhChild child(int k) const { return MhChild(childFlag(childFlags, k)); }
  bool hasChildren() const { return childFlags != 0; }
};

// The sparse quadtree. A node's existing children are contiguous in `nodes` (a sibling pack, in
// child order), packs come before their parents, and the root is the last node. The root always
// has a value: it represents the largest group of the top level.
struct MultiresHierarchy {
  uint32_t resolution = 0;  // R = 2^levels; the root is level 0, texels are level `levels`
  int levels = 0;
  std::vector<MhNode> nodes;

  uint32_t root() const { return uint32_t(nodes.size() - 1); }
  // The existing children of `node` are nodes[firstChild, firstChild + childCount).
  static int childCount(const MhNode& node);
  // Index of child k, which must exist.
  static uint32_t childNode(const MhNode& node, int k);
  // The value interval of the deepest node with a value on texel (i, j)'s path: what every
  // lookup of the hierarchy answers (SBE16a §4). For tests and the schemes' builders.
  KeyInterval texelInterval(uint32_t i, uint32_t j) const;
  // The stored nodes of `level` (not below a leaf), each with its square's Morton index among
  // the level's squares: in a merge of parts' roots, which part each root of the part level is.
  std::map<uint32_t, uint64_t> nodesAtLevel(int level) const;
};

// Stored nodes by kind (SBE16a's counts): each node counted by its parent's flag, the root by
// whether it has children.
struct MhNodeCounts {
  uint64_t full = 0, empty = 0, leaves = 0;
  void addChildrenOf(const MhNode& node) {
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = node.child(k);
      full += kind == MhChild::Full, empty += kind == MhChild::Empty,
          leaves += kind == MhChild::Leaf;
    }
  }
  void addRoot(const MhNode& root) { ++(root.hasChildren() ? full : leaves); }
};

// Builds the MH bottom-up tile by tile (SBE16a §3, "tiled construction"): each tile's levels are
// reduced to one node, and the tile roots, arriving in Morton order, are reduced the same way to
// the root. At every 2×2 group the largest subset of children whose intervals intersect moves
// up as the parent's interval (their intersection); the others are stored.
//
// The reduction is local, each parent decided by its four children alone, so a build in parts
// (parts.h) reproduces the whole build exactly: a part's builder reduces the part's tiles to
// the part's root and stops there, undecided (finishPart); the whole map's builder takes the
// parts' hierarchies in part order, appends their nodes and reduces their roots as it reduces
// tile roots, so that it ends with the very nodes, in the very order, of a whole build.
class MhBuilder {
 public:
  // A node of the bottom-up reduction before its parent decides whether to store it.
  struct Pending {
    KeyInterval interval;
    uint32_t firstChild = 0;
    uint8_t childFlags = 0;
  };
  // What a part contributes: the nodes its tiles stored (child indices local to `nodes`, packs
  // before their parents) and its root, which the parents above the part decide on.
  struct PartHierarchy {
    std::vector<MhNode> nodes;
    Pending root;
  };

  // The whole map's hierarchy, from its tiles or from its parts' hierarchies.
  explicit MhBuilder(const MapInfo& map);
  // One part's hierarchy, from the part's tiles (finishPart).
  MhBuilder(const MapInfo& map, const MapPart& part);

  // Tiles must be square, a power of two wide, inside the builder's map or part, and arrive in
  // Morton order (the harness's order). Throws std::invalid_argument.
  void consume(const DualDepthTile& tile);
  // A part's hierarchy, validated (readMhPart); parts, like tiles, arrive in Morton order (part
  // index order). Throws std::invalid_argument.
  void consume(const MapPart& part, const PartHierarchy& hierarchy);
  // Room for `nodes` nodes in all, for a merge that counts them from its part files: a vector
  // left to grow doubles, holding up to twice the nodes' bytes, three times while it moves.
  void reserve(uint64_t nodes) { hierarchy_.nodes.reserve(nodes); }
  // The nodes stored so far: in a builder of the levels above the parts, where the nodes of the
  // part just consumed end in the whole hierarchy's order (a part's nodes are appended, then the
  // groups its root completes are stored).
  uint64_t storedNodes() const { return hierarchy_.nodes.size(); }
  // The map's hierarchy once every tile or part arrived (std::logic_error before).
  MultiresHierarchy finish();
  // A part builder's hierarchy once the part's tiles arrived (std::logic_error before).
  PartHierarchy finishPart();

  // The builder's working memory beyond the nodes it keeps, for SchemeInfo::buildBytes.
  static uint64_t workingBytes(uint32_t tileSize);
  // The hierarchy the builder grows, at its smallest: a node per 64 texels, below what every
  // scene measured so far keeps (a tenth of the texels on the full city, a 40th on the terrain
  // closed), so that a build refused for it would not have fit.
  static uint64_t hierarchyFloorBytes(const MapInfo& map);

 private:
  // Checks that the square of side `size` at (x0, y0) is the next of the region's Morton order.
  void expectNext(uint32_t x0, uint32_t y0, uint32_t size, const char* what);
  // Stores the children the chosen group leaves out as the parent's sibling pack.
  Pending store(Pending parent, const Pending (&children)[kMhChildren]);
  // Reduces the root of a finished square at `level` with its waiting siblings, as far up as
  // Morton order has completed groups of four.
  void join(int level, Pending root);

  MultiresHierarchy hierarchy_;
  // The square this builder reduces: the map, or one part of it, at level regionLevel_.
  uint32_t regionX0_ = 0, regionY0_ = 0, regionSize_ = 0;
  int regionLevel_ = 0;
  uint64_t nextTexel_ = 0;  // Morton index, within the region, of the next texel to arrive
  std::vector<Pending> level_, next_;
  // Roots waiting for their three siblings, by level: Morton order completes each group of four
  // before the next begins.
  std::vector<std::pair<int, Pending>> waiting_;
};

// A scheme's step from the hierarchy to its structure, named phases and counters included: one
// function per scheme, which whole builds and merges of parts (mh_parts.h) both call.
using HierarchyEncode =
    std::function<std::unique_ptr<Decoder>(MultiresHierarchy hierarchy, BuildContext& context)>;

// The encoder the MH-family schemes share: tiles go into an MhBuilder under the phase "mh", then
// the scheme's encode step takes the hierarchy.
class HierarchyEncoder final : public Encoder {
 public:
  HierarchyEncoder(const MapInfo& map, HierarchyEncode encode)
      : builder_(map), encode_(std::move(encode)) {}
  void consume(const DualDepthTile& tile, BuildContext& context) override {
    if (!started_) context.phase("mh"), started_ = true;
    builder_.consume(tile);
  }
  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    return encode_(builder_.finish(), context);
  }

 private:
  MhBuilder builder_;
  HierarchyEncode encode_;
  bool started_ = false;
};

}  // namespace sb
