#include "schemes/dag-mh/dag.h"

#include <algorithm>
#include <span>
#include <stdexcept>

#include <fmt/format.h>

#include "schemes/dag-mh/value_chunks.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "schemes/shared/hash_cons.h"

namespace sb::dag_mh {

namespace {

uint32_t existingChildren(uint32_t header) {
  const uint32_t flags = header & 0xff;
  return uint32_t(std::popcount((flags | flags >> 1) & 0x55u));
}

void packSkipEntry(const Traversal& at, uint32_t* entry) {
  if (at.kind == Traversal::kNone) {
    entry[0] = 0, entry[1] = 0, entry[2] = at.lastValue, entry[3] = 0;
    return;
  }
  entry[0] = at.node, entry[1] = at.valueStart, entry[2] = at.lastValue;
  entry[3] = at.kind | uint32_t(at.level) << 2;
}

// §3.7: the skip list makes the inner nodes above skipLevel unreachable by lookups; those no
// entry leads to are dropped (DESIGN §5: size counts what a lookup may touch), the others keep
// their order, so children still precede parents. Returns which of the old word offsets were kept.
std::vector<uint8_t> dropUnreachable(Dag& dag) {
  std::vector<uint32_t> starts;
  for (uint32_t w = 0; w < dag.innerNodes.size(); w += 1 + existingChildren(dag.innerNodes[w]))
    starts.push_back(w);
  std::vector<uint8_t> innerUsed(dag.innerNodes.size(), 0);
  std::vector<uint8_t> treeletUsed(dag.treelets.size() / dag.treelet.words, 0);
  for (size_t e = 0; e < dag.skipList.size(); e += Dag::kSkipEntryWords) {
    const uint32_t kind = dag.skipList[e + 3] & 3;
    if (kind == Traversal::kInner) innerUsed[dag.skipList[e]] = 1;
    if (kind == Traversal::kTreelet) treeletUsed[dag.skipList[e]] = 1;
  }
  for (size_t s = starts.size(); s-- > 0;) {  // parents before children
    const uint32_t w = starts[s], header = dag.innerNodes[w];
    if (!innerUsed[w]) continue;
    for (uint32_t k = 0, p = w + 1; k < kMhChildren; ++k) {
      const uint32_t flag = childFlag(header, k);
      if (flag == kNoChild) continue;
      (flag == kTreeletChild ? treeletUsed : innerUsed)[dag.innerNodes[p++]] = 1;
    }
  }

  std::vector<uint32_t> treeletIndex(treeletUsed.size()), treelets;
  for (uint32_t t = 0; t < treeletUsed.size(); ++t) {
    if (!treeletUsed[t]) continue;
    treeletIndex[t] = uint32_t(treelets.size() / dag.treelet.words);
    treelets.insert(treelets.end(), dag.treeletAt(t), dag.treeletAt(t) + dag.treelet.words);
  }
  std::vector<uint32_t> innerOffset(dag.innerNodes.size()), inner;
  for (const uint32_t w : starts) {
    if (!innerUsed[w]) continue;
    innerOffset[w] = uint32_t(inner.size());
    const uint32_t header = dag.innerNodes[w];
    inner.push_back(header);
    for (uint32_t k = 0, p = w + 1; k < kMhChildren; ++k) {
      const uint32_t flag = childFlag(header, k);
      if (flag == kNoChild) continue;
      const uint32_t child = dag.innerNodes[p++];
      inner.push_back(flag == kTreeletChild ? treeletIndex[child] : innerOffset[child]);
    }
  }
  for (size_t e = 0; e < dag.skipList.size(); e += Dag::kSkipEntryWords) {
    const uint32_t kind = dag.skipList[e + 3] & 3;
    if (kind == Traversal::kInner) dag.skipList[e] = innerOffset[dag.skipList[e]];
    if (kind == Traversal::kTreelet) dag.skipList[e] = treeletIndex[dag.skipList[e]];
  }
  dag.innerNodes = std::move(inner);
  dag.treelets = std::move(treelets);
  return innerUsed;
}

}  // namespace

// §3.1: each node content stored once. Sequences of words, concatenated in the order they were
// first added; a sequence is found by its full content.
class DagBuilder::UniqueWords {
 public:
  // The word offset of a stored sequence equal to `words`, else of `words`, appended.
  uint32_t findOrAdd(std::span<const uint32_t> words) {
    uint64_t hash = mixBits(words.size());
    for (const uint32_t word : words) hash = mixBits(hash ^ word);
    const auto [id, added] = index_.findOrAdd(hash, [&](uint32_t other) {
      const Entry& entry = entries_[other];
      return entry.length == words.size() &&
             std::equal(words.begin(), words.end(), words_.begin() + entry.offset);
    });
    if (!added) return entries_[id].offset;
    if (words_.size() + words.size() > ~uint32_t(0))
      throw std::runtime_error("dag-mh: the DAG exceeds 2^32 words");
    const uint32_t offset = uint32_t(words_.size());
    entries_.push_back({offset, uint32_t(words.size())});
    words_.insert(words_.end(), words.begin(), words.end());
    return offset;
  }

  size_t count() const { return entries_.size(); }
  std::vector<uint32_t> release() { return std::move(words_); }

 private:
  struct Entry {
    uint32_t offset, length;
  };

  std::vector<uint32_t> words_;
  std::vector<Entry> entries_;  // id → its words
  HashConsIndex index_;
};

DagBuilder::DagBuilder(int levels, int treeletHeight, int skipLevel)
    : treelets_(std::make_unique<UniqueWords>()), innerNodes_(std::make_unique<UniqueWords>()) {
  dag_.levels = levels;
  dag_.treelet = TreeletShape::of(treeletHeight);
  dag_.skipLevel = std::min(skipLevel, levels);
  dag_.skipList.resize(Dag::kSkipEntryWords << (2 * dag_.skipLevel));
  bitmap_.resize(dag_.treelet.words);
}

DagBuilder::~DagBuilder() = default;

void DagBuilder::measure(std::span<const MhNode> nodes, TreeAttributes& a) {
  for (uint32_t n = 0; n < nodes.size(); ++n) {
    if (a.given[n]) continue;
    a.height[n] = 1, a.descendants[n] = 0;
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild type = nodes[n].child(k);
      if (type == MhChild::None) continue;
      const uint32_t child = nodes[n].firstChild + c++;
      a.height[n] = std::max<uint8_t>(a.height[n], a.height[child] + 1);
      a.descendants[n] += hasValue(type) + a.descendants[child];
    }
  }
}

uint32_t DagBuilder::treelet(std::span<const MhNode> nodes, const TreeAttributes& a, uint32_t n,
                             bool valued) {
  const TreeletShape& shape = dag_.treelet;
  const auto fill = [&](const auto& self, uint32_t node, bool hasOwn, int depth,
                        uint32_t bit) -> void {
    if (hasOwn) shape.setValue(bitmap_.data(), bit);
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild type = nodes[node].child(k);
      if (type == MhChild::None) continue;
      self(self, nodes[node].firstChild + c++, hasValue(type), depth + 1,
           bit + 1 + uint32_t(k) * shape.subtreeBits[depth + 1]);
    }
  };
  std::fill(bitmap_.begin(), bitmap_.end(), 0u);
  fill(fill, n, valued, 0, 0);
  bitmap_[0] |= uint32_t(valued + a.descendants[n]);  // the count, in the low countBits
  return treelets_->findOrAdd(bitmap_) / shape.words;
}

void DagBuilder::add(std::span<const MhNode> nodes, TreeAttributes& a) {
  // §3.1, §3.4: inner nodes bottom-up; the descendants' value count (not the node's own value,
  // which the parent's flag tells) lets a full and an empty node with equal subtrees share one.
  // A count over 24 bits is saturated and the node remembered: it is only an error if the node
  // stays reachable below the skip level (the skip list keeps 32-bit indices, §3.7).
  const int treeletHeight = dag_.treelet.height;
  std::vector<uint32_t> words;
  for (uint32_t n = 0; n < nodes.size(); ++n) {
    if (a.given[n] || a.height[n] <= treeletHeight) continue;
    words.assign(1, uint32_t(std::min<uint64_t>(a.descendants[n], kMaxInnerCount)) << 8);
    for (int k = 0, c = 0; k < kMhChildren; ++k) {
      const MhChild type = nodes[n].child(k);
      if (type == MhChild::None) continue;
      const uint32_t child = nodes[n].firstChild + c++;
      uint32_t flag = kTreeletChild;
      if (a.height[child] <= treeletHeight)
        a.reference[child] = treelet(nodes, a, child, hasValue(type));
      else
        flag = type == MhChild::Full ? kFullInner : kEmptyInner;
      words.push_back(a.reference[child]);
      words[0] |= flag << (2 * k);
    }
    a.reference[n] = innerNodes_->findOrAdd(words);
    if (a.descendants[n] > kMaxInnerCount) overflowing_.push_back(a.reference[n]);
  }
}

std::pair<Traversal, uint32_t> DagBuilder::walk(std::span<const MhNode> nodes,
                                                const TreeAttributes& a, uint32_t n, Traversal at,
                                                uint32_t x, uint32_t y, int stopLevel) const {
  const int shift = dag_.levels - stopLevel;
  while (at.kind == Traversal::kInner && at.level < stopLevel && !a.given[n]) {
    const int c = mhChildIndex(x << shift, y << shift, dag_.levels - at.level - 1);
    const MhChild type = nodes[n].child(c);
    if (type == MhChild::None) {
      at.kind = Traversal::kNone;
      break;
    }
    uint32_t child = nodes[n].firstChild;
    for (int k = 0; k < c; ++k) {
      const MhChild before = nodes[n].child(k);
      if (before == MhChild::None) continue;
      at.valueStart += uint32_t(hasValue(before) + a.descendants[child]);
      ++child;
    }
    n = child, at.node = a.reference[child], ++at.level;
    if (a.height[child] <= dag_.treelet.height)
      at.kind = Traversal::kTreelet;
    else if (type == MhChild::Full)
      at.lastValue = at.valueStart++;
  }
  return {at, n};
}

void DagBuilder::setSkipEntry(uint32_t x, uint32_t y, const Traversal& at) {
  packSkipEntry(at, &dag_.skipList[Dag::kSkipEntryWords * ((size_t(y) << dag_.skipLevel) + x)]);
}

Dag DagBuilder::finish() {
  dag_.innerNodes = innerNodes_->release();
  dag_.treelets = treelets_->release();
  const std::vector<uint8_t> kept =
      dag_.skipLevel > 0 ? dropUnreachable(dag_) : std::vector<uint8_t>(dag_.innerNodes.size(), 1);
  for (const uint32_t node : overflowing_)
    if (kept[node])
      throw std::runtime_error(fmt::format(
          "dag-mh: an inner node below skip level {} holds {} values or more, beyond its 24-bit "
          "count (§3.4); raise skip-level",
          dag_.skipLevel, kMaxInnerCount));
  return std::move(dag_);
}

void forEachValue(std::span<const MhNode> nodes, uint32_t n, bool valued,
                  const std::function<void(const KeyInterval&)>& visit) {
  std::vector<std::pair<uint32_t, bool>> stack{{n, valued}};
  while (!stack.empty()) {
    const auto [node, hasOwn] = stack.back();
    stack.pop_back();
    if (hasOwn) visit(nodes[node].interval);
    for (int k = kMhChildren - 1, c = MultiresHierarchy::childCount(nodes[node]); k >= 0; --k) {
      const MhChild type = nodes[node].child(k);
      if (type != MhChild::None) stack.emplace_back(nodes[node].firstChild + --c, hasValue(type));
    }
  }
}

Traversal DagBuilder::rootState(std::span<const MhNode> nodes, TreeAttributes& a, uint32_t root) {
  Traversal start;
  const bool rootIsTreelet = a.height[root] <= dag_.treelet.height;
  if (rootIsTreelet) a.reference[root] = treelet(nodes, a, root, true);
  start.kind = rootIsTreelet ? Traversal::kTreelet : Traversal::kInner;
  start.node = a.reference[root];
  start.valueStart = rootIsTreelet ? 0 : 1;  // the root's value is index 0
  return start;
}

DagBuild buildDag(const MultiresHierarchy& hierarchy, int treeletHeight, int skipLevel) {
  const std::span<const MhNode> nodes = hierarchy.nodes;
  const uint32_t root = hierarchy.root();
  TreeAttributes attributes(nodes.size());
  DagBuilder::measure(nodes, attributes);
  const uint64_t valueCount = 1 + attributes.descendants[root];
  if (valueCount > ValueChunks::kMaxValues)
    throw std::runtime_error(
        fmt::format("dag-mh: the hierarchy holds {} values, more than 32-bit value indices address",
                    valueCount));
  DagBuilder builder(hierarchy.levels, treeletHeight, skipLevel);
  builder.add(nodes, attributes);
  const Traversal start = builder.rootState(nodes, attributes, root);
  const int skip = builder.dag().skipLevel;
  for (uint32_t y = 0; y < (1u << skip); ++y)
    for (uint32_t x = 0; x < (1u << skip); ++x)
      builder.setSkipEntry(x, y, builder.walk(nodes, attributes, root, start, x, y, skip).first);

  DagBuild built;
  built.dag = builder.finish();
  built.values.reserve(valueCount);
  forEachValue(nodes, root, true, [&](const KeyInterval& value) { built.values.push_back(value); });
  return built;
}

uint64_t Dag::innerNodeCount() const {
  uint64_t count = 0;
  for (size_t w = 0; w < innerNodes.size(); w += 1 + existingChildren(innerNodes[w])) ++count;
  return count;
}

void Dag::save(ByteWriter& out) const {
  out.putArray<uint32_t>(innerNodes);
  out.putArray<uint32_t>(treelets);
  out.putArray<uint32_t>(skipList);
}

Dag Dag::load(ByteReader& in, int levels, int treeletHeight, int skipLevel, uint32_t valueCount) {
  Dag dag;
  dag.levels = levels;
  dag.treelet = TreeletShape::of(treeletHeight);
  dag.skipLevel = skipLevel;
  dag.innerNodes = in.getArray<uint32_t>("dag-mh inner nodes");
  dag.treelets = in.getArray<uint32_t>("dag-mh treelets");
  dag.skipList =
      in.getArray<uint32_t>("dag-mh skip list", uint64_t(kSkipEntryWords) << (2 * skipLevel));
  const TreeletShape& shape = dag.treelet;
  if (dag.treelets.size() % shape.words != 0)
    throw FormatError(fmt::format("dag-mh: {} treelet words are not whole {}-word treelets",
                                  dag.treelets.size(), shape.words));
  const uint64_t treeletCount = dag.treelets.size() / shape.words;

  // Each treelet's count is the number of its set bits, and no bit lies past its nodes.
  const uint32_t usedBits = (shape.countBits + shape.bits) % 32;
  for (uint64_t t = 0; t < treeletCount; ++t) {
    const uint32_t* words = dag.treeletAt(uint32_t(t));
    uint32_t set = 0;
    for (uint32_t w = 0; w < shape.words; ++w) set += uint32_t(std::popcount(words[w]));
    set -= uint32_t(std::popcount(shape.count(words)));
    if (set != shape.count(words))
      throw FormatError(fmt::format("dag-mh: treelet {} counts {} values but has {} set bits", t,
                                    shape.count(words), set));
    if (usedBits != 0 && words[shape.words - 1] >> usedBits != 0)
      throw FormatError(fmt::format("dag-mh: treelet {} has bits past its nodes", t));
  }

  // Inner nodes: each parses inside the array, has children, points to treelets that exist and
  // to inner nodes that start strictly before it (so there are no cycles), and counts exactly
  // its children's values — then a traversal's value indices stay inside its subtree's range.
  // A node spanning more levels than the map could be reached with no texel bit left for a child
  // index; heights are checked against every level a node is entered at (skip list below).
  std::vector<uint8_t> heightAt(dag.innerNodes.size(), 0);  // 0: no node starts there
  for (size_t w = 0; w < dag.innerNodes.size();) {
    const uint32_t header = dag.innerNodes[w];
    if ((header & 0xff) == 0)
      throw FormatError(fmt::format("dag-mh: inner node at word {} has no children", w));
    const size_t end = w + 1 + existingChildren(header);
    if (end > dag.innerNodes.size())
      throw FormatError(fmt::format("dag-mh: inner node at word {} overruns the inner nodes", w));
    uint64_t values = 0;
    int height = 0;
    for (uint32_t k = 0, p = uint32_t(w) + 1; k < kMhChildren; ++k) {
      const uint32_t flag = childFlag(header, k);
      if (flag == kNoChild) continue;
      const uint32_t child = dag.innerNodes[p++];
      if (flag == kTreeletChild) {
        if (child >= treeletCount)
          throw FormatError(fmt::format("dag-mh: inner node at word {} points to treelet {} of {}",
                                        w, child, treeletCount));
        values += shape.count(dag.treeletAt(child));
        height = std::max(height, 2);
      } else {
        if (child >= w || heightAt[child] == 0)
          throw FormatError(fmt::format(
              "dag-mh: inner node at word {} points to word {}, not an earlier inner node", w,
              child));
        values += (flag == kFullInner) + dag.innerCount(child);
        height = std::max(height, heightAt[child] + 1);
      }
    }
    if (values != header >> 8)
      throw FormatError(
          fmt::format("dag-mh: inner node at word {} counts {} values, its children hold {}", w,
                      header >> 8, values));
    if (height > levels + 1)
      throw FormatError(
          fmt::format("dag-mh: inner node at word {} spans more levels than the map", w));
    heightAt[w] = uint8_t(height);
    w = end;
  }

  // Skip list entries: the kind, level and node agree, the node is entered at a level its
  // subtree fits below, and the values it leads to lie in the value list.
  for (size_t e = 0; e < dag.skipList.size(); e += kSkipEntryWords) {
    const uint32_t* entry = &dag.skipList[e];
    const uint32_t kind = entry[3] & 3, level = entry[3] >> 2, start = entry[1];
    const auto fail = [&](const char* what) {
      throw FormatError(fmt::format("dag-mh: skip list entry {}: {}", e / kSkipEntryWords, what));
    };
    if (entry[2] >= valueCount) fail("last value index out of range");
    if (level > uint32_t(skipLevel)) fail("a level below the skip level");
    if (kind == Traversal::kNone) {
      if (entry[0] != 0 || entry[1] != 0 || entry[3] != 0)
        fail("an entry without a node has node fields");
    } else if (kind == Traversal::kInner) {
      if (level != uint32_t(skipLevel)) fail("an inner node not at the skip level");
      if (entry[0] >= dag.innerNodes.size() || heightAt[entry[0]] == 0)
        fail("no inner node at its word offset");
      if (level + heightAt[entry[0]] > uint32_t(levels) + 1) fail("its node spans past the texels");
      if (uint64_t(start) + dag.innerCount(entry[0]) > valueCount)
        fail("its values run past the value list");
    } else if (kind == Traversal::kTreelet) {
      if (entry[0] >= treeletCount) fail("treelet index out of range");
      if (uint64_t(start) + shape.count(dag.treeletAt(entry[0])) > valueCount)
        fail("its values run past the value list");
    } else {
      fail("invalid kind");
    }
  }
  return dag;
}

}  // namespace sb::dag_mh
