// The structure of DAG-MH (Scandolo & Eisemann 2021 §3.1, §3.4, §3.5, §3.7): the topology of the
// multiresolution hierarchy as a DAG of inner nodes and treelets, and the skip list lookups start
// from. Values are not in it: a traversal yields the index of the texel's value in the
// depth-first value list (value_chunks.h), which is how topologies with different values become
// one node.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "schemes/dag-mh/treelet.h"
#include "schemes/interface/depth_decoder.h"
#include "schemes/shared/child_flags.h"
#include "schemes/shared/multires_hierarchy.h"

namespace sb {
class ByteReader;
class ByteWriter;
}  // namespace sb

namespace sb::dag_mh {

// §3.4: an inner node counts its descendants' values in 24 bits.
constexpr uint64_t kMaxInnerCount = (uint64_t(1) << 24) - 1;

// §3.4: the 2-bit flags of an inner node's children.
enum ChildFlag : uint32_t { kNoChild = 0, kFullInner = 1, kEmptyInner = 2, kTreeletChild = 3 };

// §3.5: where a traversal stands. `valueStart` is the index of the first value below the reached
// node's own (the first of a treelet's values, its root's included), `lastValue` the index of
// the deepest value seen above.
struct Traversal {
  enum Kind : uint32_t { kNone = 0, kInner = 1, kTreelet = 2 };
  uint32_t kind = kNone;
  uint32_t node = 0;  // kInner: word offset in innerNodes; kTreelet: treelet index
  int level = 0;      // of the reached node (0 = the root)
  uint32_t valueStart = 0, lastValue = 0;
};

struct Dag {
  int levels = 0;  // log2 R: the root is level 0, texels level `levels`
  TreeletShape treelet;
  int skipLevel = 0;
  // §3.4: per inner node a header word — child flags in bits 0–7 (child k in bits 2k, 2k+1),
  // the count of values in the node's descendants in bits 8–31 — then one 32-bit pointer per
  // existing child in child order: a word offset in innerNodes (inner children) or a treelet
  // index. Children come before their parents, so every inner pointer points backwards.
  std::vector<uint32_t> innerNodes;
  std::vector<uint32_t> treelets;  // treelet.words words each
  // §3.7: the traversal state at the 4^skipLevel nodes of level skipLevel, row-major over their
  // (i, j), four words each: the node, valueStart, lastValue, and kind (bits 0–1) with level
  // (bits 2–6). skipLevel 0 is the root's entry alone. Value indices are 32-bit here: only the
  // inner nodes below the skip level need their counts to fit 24 bits.
  static constexpr size_t kSkipEntryWords = 4;
  std::vector<uint32_t> skipList;

  uint64_t innerNodeCount() const;
  uint64_t treeletCount() const { return treelets.size() / treelet.words; }
  uint32_t innerCount(uint32_t node) const { return innerNodes[node] >> 8; }
  const uint32_t* treeletAt(uint32_t index) const {
    return treelets.data() + size_t(index) * treelet.words;
  }
  uint32_t subtreeValues(const Traversal& at) const {
    return at.kind == Traversal::kTreelet ? treelet.count(treeletAt(at.node)) : innerCount(at.node);
  }

  Traversal skipEntry(uint32_t i, uint32_t j) const {
    const int shift = levels - skipLevel;
    const uint32_t* entry =
        skipList.data() + kSkipEntryWords * ((size_t(j >> shift) << skipLevel) + (i >> shift));
    return {entry[3] & 3, entry[0], int(entry[3] >> 2), entry[1], entry[2]};
  }

  // §3.5: from `at` towards texel (i, j) through inner nodes until a node of `stopLevel`, a
  // treelet or a missing child. The values of the existing children before the one taken come
  // first in the value list, so their counts advance valueStart; a full child's value is the one
  // at valueStart.
  void descend(Traversal& at, uint32_t i, uint32_t j, int stopLevel) const {
    while (at.kind == Traversal::kInner && at.level < stopLevel) {
      const uint32_t* node = innerNodes.data() + at.node;
      const uint32_t header = node[0];
      const int c = mhChildIndex(i, j, levels - at.level - 1);
      const uint32_t flag = childFlag(header, c);
      if (flag == kNoChild) {
        at.kind = Traversal::kNone;
        return;
      }
      const uint32_t* pointer = node + 1;
      for (int k = 0; k < c; ++k) {
        const uint32_t before = childFlag(header, k);
        if (before == kNoChild) continue;
        at.valueStart += before == kTreeletChild ? treelet.count(treeletAt(*pointer))
                                                 : (before == kFullInner) + innerCount(*pointer);
        ++pointer;
      }
      at.node = *pointer;
      ++at.level;
      if (flag == kFullInner) at.lastValue = at.valueStart++;
      at.kind = flag == kTreeletChild ? Traversal::kTreelet : Traversal::kInner;
    }
  }

  // The index of texel (i, j)'s value: the deepest node with a value on its path.
  uint32_t valueIndex(uint32_t i, uint32_t j) const {
    Traversal at = skipEntry(i, j);
    descend(at, i, j, levels);
    if (at.kind == Traversal::kTreelet)
      if (const auto before = treelet.lookup(treeletAt(at.node), i, j, at.level, levels))
        return at.valueStart + *before;
    return at.lastValue;
  }

  // The value index of every texel of `rect` in one walk (issue 13): from each skip entry the
  // rectangle overlaps, a point walk (descend) down to the lowest node holding the whole
  // rectangle, then into every child it overlaps. A missing child, or a treelet node with no value
  // below it, gives its whole overlap the value of the deepest node above: visit(index, texels)
  // once for it.
  template <class Visit>
  void forEachValueBlock(const TexelRect& rect, Visit&& visit) const {
    const int shift = levels - skipLevel;
    for (uint32_t y = rect.j0 >> shift; y <= rect.j1 >> shift; ++y)
      for (uint32_t x = rect.i0 >> shift; x <= rect.i1 >> shift; ++x) {
        // A skip entry may stand above its square (a treelet or a missing child higher up): the
        // walk from it keeps to the part of the rectangle inside the square.
        const uint32_t x0 = x << shift, y0 = y << shift, last = (uint32_t(1) << shift) - 1;
        const TexelRect inside{std::max(rect.i0, x0), std::max(rect.j0, y0),
                               std::min(rect.i1, x0 + last), std::min(rect.j1, y0 + last)};
        const int common =
            levels - std::bit_width((inside.i0 ^ inside.i1) | (inside.j0 ^ inside.j1));
        Traversal at = skipEntry(x0, y0);
        descend(at, inside.i0, inside.j0, common);
        const uint32_t corner = ~((uint32_t(1) << (levels - at.level)) - 1);
        walkRect(at, inside.i0 & corner, inside.j0 & corner, inside, visit);
      }
  }

  void save(ByteWriter& out) const;
  // Reads what save() wrote and checks that every lookup stays inside the arrays and yields a
  // value index below `valueCount`; throws FormatError naming "dag-mh" and the field.
  static Dag load(ByteReader& in, int levels, int treeletHeight, int skipLevel,
                  uint32_t valueCount);

 private:
  // The node `at` reached covers the square of side 2^(levels − at.level) at (x0, y0), which
  // overlaps `rect`; value indices advance over the children before each as descend() does.
  template <class Visit>
  void walkRect(const Traversal& at, uint32_t x0, uint32_t y0, const TexelRect& rect,
                Visit& visit) const {
    const uint32_t side = uint32_t(1) << (levels - at.level);
    if (at.kind == Traversal::kNone) return visit(at.lastValue, overlap(rect, x0, y0, side));
    if (at.kind == Traversal::kTreelet) {
      const uint32_t* bits = treeletAt(at.node);
      return walkTreelet(bits, TreeletRanks(treelet, bits), 0, 0,
                         std::min(treelet.height - 1, levels - at.level), at.valueStart,
                         at.lastValue, x0, y0, side, rect, visit);
    }
    const uint32_t* node = innerNodes.data() + at.node;
    const uint32_t header = node[0], half = side / 2;
    const uint32_t* pointer = node + 1;
    const uint32_t midX = x0 + half, midY = y0 + half;
    const bool columns[2] = {rect.i0 < midX, rect.i1 >= midX};
    const bool rows[2] = {rect.j0 < midY, rect.j1 >= midY};
    uint32_t valueStart = at.valueStart;
    // The children after the last one entered need no value count.
    const int lastEntered = int(rows[1]) << 1 | int(columns[1]);
    for (int k = 0; k <= lastEntered; ++k) {
      const uint32_t flag = childFlag(header, k);
      const bool entered = columns[k & 1] && rows[k >> 1];
      const uint32_t cx = x0 + (k & 1) * half, cy = y0 + (k >> 1) * half;
      if (flag == kNoChild) {
        if (entered) visit(at.lastValue, overlap(rect, cx, cy, half));
        continue;
      }
      const uint32_t reference = *pointer++;
      if (entered) {
        Traversal child{flag == kTreeletChild ? Traversal::kTreelet : Traversal::kInner, reference,
                        at.level + 1, valueStart, at.lastValue};
        if (flag == kFullInner) child.lastValue = child.valueStart++;
        walkRect(child, cx, cy, rect, visit);
      }
      valueStart += flag == kTreeletChild ? treelet.count(treeletAt(reference))
                                          : (flag == kFullInner) + innerCount(reference);
    }
  }

  // Node n, at depth d of a treelet whose values start at `valueStart`, covers the square of
  // side `side` at (x0, y0), which overlaps `rect`; `inherited` is the value its path gives so
  // far. Alg. 1 on every path at once: the deepest node with a value answers.
  template <class Visit>
  void walkTreelet(const uint32_t* bits, const TreeletRanks& ranks, uint32_t n, int d, int deepest,
                   uint32_t valueStart, uint32_t inherited, uint32_t x0, uint32_t y0, uint32_t side,
                   const TexelRect& rect, Visit& visit) const {
    if (treelet.hasValue(bits, n)) inherited = valueStart + ranks.valuesBefore(n);
    if (d == deepest || ranks.valuesIn(n + 1, n + treelet.subtreeBits[d]) == 0)
      return visit(inherited, overlap(rect, x0, y0, side));
    const uint32_t half = side / 2;
    for (int l = 0; l < kMhChildren; ++l) {
      const uint32_t cx = x0 + (l & 1) * half, cy = y0 + (l >> 1) * half;
      if (overlap(rect, cx, cy, half) != 0)
        walkTreelet(bits, ranks, n + 1 + uint32_t(l) * treelet.subtreeBits[d + 1], d + 1, deepest,
                    valueStart, inherited, cx, cy, half, rect, visit);
    }
  }
};

// What building the DAG gives: the structure, and the value intervals in the order of the value
// list (depth-first pre-order of the nodes with a value; the root's is index 0).
struct DagBuild {
  Dag dag;
  std::vector<KeyInterval> values;
};

// Per node of a tree handed to DagBuilder: what its parent and the skip list need of it.
// Nodes marked `given` come with their attributes and without their children (in a merge of
// parts, a part's root seen from the levels above it).
struct TreeAttributes {
  std::vector<uint8_t> height;        // levels the node's subtree spans, 1 for a leaf
  std::vector<uint64_t> descendants;  // values below the node
  std::vector<uint32_t> reference;    // inner node word offset, or treelet index
  std::vector<uint8_t> given;
  explicit TreeAttributes(size_t nodes)
      : height(nodes, 1), descendants(nodes, 0), reference(nodes, 0), given(nodes, 0) {}
};

// The DAG grown tree by tree: a whole hierarchy at once, or a merge's parts one by one and then
// the levels above them (dag_parts.h). Every inner node and treelet is stored once, whichever
// tree it came from.
class DagBuilder {
 public:
  DagBuilder(int levels, int treeletHeight, int skipLevel);
  ~DagBuilder();

  // Heights and descendant counts of the nodes that are not given, packs before parents.
  static void measure(std::span<const MhNode> nodes, TreeAttributes& attributes);
  // §3.1, §3.2, §3.4: stores the inner nodes of a measured tree and the treelets of their
  // children; references of nodes that are not given.
  void add(std::span<const MhNode> nodes, TreeAttributes& attributes);
  // §3.2: the treelet of node n's subtree, stored once.
  uint32_t treelet(std::span<const MhNode> nodes, const TreeAttributes& attributes, uint32_t n,
                   bool valued);
  // §3.7: from node n, reached in state `at`, towards the square (x, y) of level `stopLevel` (in
  // that level's coordinates) as Dag::descend would, but with exact value counts. Stops early at
  // a given node, returned beside the state.
  std::pair<Traversal, uint32_t> walk(std::span<const MhNode> nodes,
                                      const TreeAttributes& attributes, uint32_t n, Traversal at,
                                      uint32_t x, uint32_t y, int stopLevel) const;
  void setSkipEntry(uint32_t x, uint32_t y, const Traversal& at);
  // The state lookups start in at the root, which is stored as a treelet if it is one.
  Traversal rootState(std::span<const MhNode> nodes, TreeAttributes& attributes, uint32_t root);
  // The DAG once every skip entry is set; throws as buildDag does.
  Dag finish();

  const Dag& dag() const { return dag_; }

 private:
  class UniqueWords;
  Dag dag_;
  std::unique_ptr<UniqueWords> treelets_, innerNodes_;
  std::vector<uint32_t> overflowing_;  // inner nodes whose count saturated
  std::vector<uint32_t> bitmap_;
};

// The value list's order, depth-first pre-order of the nodes with a value: calls `visit` with
// each value interval below node n, and n's own first if `valued`.
void forEachValue(std::span<const MhNode> nodes, uint32_t n, bool valued,
                  const std::function<void(const KeyInterval&)>& visit);

// §3.1, §3.2: the hierarchy's topology as a DAG, every inner node and treelet stored once;
// `skipLevel` is clamped to the map's levels. Throws std::runtime_error naming dag-mh when an
// inner node that lookups reach (one below the skip level) holds more values than its 24-bit
// count, or the map more than 32-bit value indices, hold.
DagBuild buildDag(const MultiresHierarchy& hierarchy, int treeletHeight, int skipLevel);

}  // namespace sb::dag_mh
