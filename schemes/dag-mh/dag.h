// The structure of DAG-MH (Scandolo & Eisemann 2021 §3.1, §3.4, §3.5, §3.7): the topology of the
// multiresolution hierarchy as a DAG of inner nodes and treelets, and the skip list lookups start
// from. Values are not in it: a traversal yields the index of the texel's value in the
// depth-first value list (value_chunks.h), which is how topologies with different values become
// one node.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "schemes/dag-mh/treelet.h"
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

  void save(ByteWriter& out) const;
  // Reads what save() wrote and checks that every lookup stays inside the arrays and yields a
  // value index below `valueCount`; throws FormatError naming "dag-mh" and the field.
  static Dag load(ByteReader& in, int levels, int treeletHeight, int skipLevel,
                  uint32_t valueCount);
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
