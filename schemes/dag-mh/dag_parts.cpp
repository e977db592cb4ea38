#include "schemes/dag-mh/dag_parts.h"

#include <bit>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "schemes/shared/mh_parts.h"

namespace sb::dag_mh {
namespace {

class DagPartMerger final : public PartMerger {
 public:
  DagPartMerger(const MapInfo& map, uint32_t partSize, DagShape shape, DagDecoding decoder)
      : map_(map),
        partSize_(checkedPartSize("dag-mh", partSize, map)),
        levels_(std::countr_zero(map.resolution)),
        partLevel_(levels_ - std::countr_zero(partSize_)),
        shape_(shape),
        decoder_(std::move(decoder)),
        upperBuilder_(map),
        builder_(levels_, shape.treeletHeight, shape.skipLevel),
        values_(shape.chunkSize),
        parts_(MapPart::countFor(map, partSize_)) {}

  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override {
    expectPart("dag-mh", next_, partSize_, part);
    if (next_ == 0) context.phase(upper_ ? "dag" : "merge");
    MhBuilder::PartHierarchy hierarchy = readMhPart(payload, part, "dag-mh");
    if (!upper_) upperBuilder_.consume(part, {{}, hierarchy.root});
    const std::vector<MhNode> tree = partTree(std::move(hierarchy));
    const uint32_t root = uint32_t(tree.size() - 1);
    TreeAttributes attributes(tree.size());
    DagBuilder::measure(tree, attributes);
    PartRoot& partRoot = parts_[part.index];
    if (!upper_) {
      partRoot.height = attributes.height[root];
      partRoot.descendants = attributes.descendants[root];
    } else {
      builder_.add(tree, attributes);
      partRoot.reference = attributes.reference[root];
      if (partRoot.height <= shape_.treeletHeight) partRoot.graft = tree;
      addSkipEntries(part, tree, attributes);
      emitUpTo(part.index);
      forEachValue(tree, root, false, [&](const KeyInterval& v) { values_.append(v, &stats_); });
    }
    ++next_;
  }

  bool anotherPass(BuildContext&) override {
    expectAllParts("dag-mh", next_, parts_.size());
    if (upper_) return false;
    upper_ = upperBuilder_.finish();
    partOf_ = upper_->nodesAtLevel(partLevel_);
    // The levels above with every part's root standing in for its tree: value counts, the
    // state lookups reach each part's root in, and the value list's order.
    TreeAttributes attributes(upper_->nodes.size());
    for (const auto& [n, part] : partOf_) {
      attributes.given[n] = 1;
      attributes.height[n] = parts_[part].height;
      attributes.descendants[n] = parts_[part].descendants;
    }
    DagBuilder::measure(upper_->nodes, attributes);
    const uint32_t root = upper_->root();
    if (1 + attributes.descendants[root] > ValueChunks::kMaxValues)
      throw std::runtime_error(fmt::format(
          "dag-mh: the hierarchy holds {} values, more than 32-bit value indices address",
          1 + attributes.descendants[root]));
    Traversal start;
    start.kind =
        attributes.height[root] <= shape_.treeletHeight ? Traversal::kTreelet : Traversal::kInner;
    start.valueStart = start.kind == Traversal::kInner;
    for (const auto& [n, part] : partOf_) {
      const auto [at, reached] = builder_.walk(upper_->nodes, attributes, root, start,
                                               mortonX(part), mortonY(part), partLevel_);
      if (reached == n && at.kind == Traversal::kInner) parts_[part].arrival = at;
    }
    const auto visit = [&](const auto& self, uint32_t n, bool valued) -> void {
      if (valued) events_.push_back({upper_->nodes[n].interval, kNoPart});
      if (const auto part = partOf_.find(n); part != partOf_.end()) {
        events_.push_back({{}, part->second});
        return;
      }
      const MhNode& node = upper_->nodes[n];
      for (int k = 0; k < kMhChildren; ++k)
        if (node.child(k) != MhChild::None)
          self(self, MultiresHierarchy::childNode(node, k), hasValue(node.child(k)));
    };
    visit(visit, root, true);
    next_ = 0;
    return true;
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    expectAllParts("dag-mh", next_, parts_.size());
    if (!upper_) throw std::logic_error("dag-mh: the merge finished before its last pass");
    emitUpTo(parts_.size());
    values_.close(&stats_);

    // The levels above: small parts' trees grafted first (packs before parents), then the upper
    // nodes, whose part-level nodes either point into their graft or stand in for their part.
    std::vector<MhNode> nodes;
    std::map<uint32_t, uint32_t> graftedChildren;
    for (const auto& [n, part] : partOf_) {
      const std::vector<MhNode>& graft = parts_[part].graft;
      if (graft.empty() || !graft.back().hasChildren()) continue;
      const uint32_t offset = uint32_t(nodes.size());
      for (size_t g = 0; g + 1 < graft.size(); ++g) {
        MhNode node = graft[g];
        if (node.hasChildren()) node.firstChild += offset;
        nodes.push_back(node);
      }
      graftedChildren[n] = graft.back().firstChild + offset;
    }
    const uint32_t upperStart = uint32_t(nodes.size());
    for (uint32_t n = 0; n < upper_->nodes.size(); ++n) {
      MhNode node = upper_->nodes[n];
      if (const auto grafted = graftedChildren.find(n); grafted != graftedChildren.end())
        node.firstChild = grafted->second;
      else if (node.hasChildren() && !partOf_.count(n))
        node.firstChild += upperStart;
      nodes.push_back(node);
    }
    TreeAttributes attributes(nodes.size());
    for (const auto& [n, part] : partOf_) {
      const PartRoot& partRoot = parts_[part];
      if (partRoot.height <= shape_.treeletHeight) continue;
      attributes.given[upperStart + n] = 1;
      attributes.height[upperStart + n] = partRoot.height;
      attributes.descendants[upperStart + n] = partRoot.descendants;
      attributes.reference[upperStart + n] = partRoot.reference;
    }
    DagBuilder::measure(nodes, attributes);
    builder_.add(nodes, attributes);
    const uint32_t root = uint32_t(nodes.size() - 1);
    const Traversal start = builder_.rootState(nodes, attributes, root);
    const int skipLevel = builder_.dag().skipLevel;
    for (uint32_t y = 0; y < (1u << skipLevel); ++y)
      for (uint32_t x = 0; x < (1u << skipLevel); ++x) {
        const auto [at, reached] = builder_.walk(nodes, attributes, root, start, x, y, skipLevel);
        // Entries that walk on into a part were set while the part was read.
        if (attributes.given[reached] && at.kind == Traversal::kInner && at.level < skipLevel)
          continue;
        builder_.setSkipEntry(x, y, at);
      }
    return decoder_(builder_.finish(), std::move(values_), stats_, context);
  }

 private:
  static constexpr uint64_t kNoPart = ~uint64_t(0);

  struct PartRoot {
    uint8_t height = 1;
    uint64_t descendants = 0;
    uint32_t reference = 0;
    std::optional<Traversal> arrival;  // the state lookups reach the root in, as an inner node
    std::vector<MhNode> graft;         // the part's tree, if a treelet may hold it
  };
  // The value list's order above the parts: an upper node's value, or a part's values.
  struct ValueEvent {
    KeyInterval value;
    uint64_t part = kNoPart;
  };

  // §3.7: the skip entries of the squares inside the part, walked on from its root.
  void addSkipEntries(const MapPart& part, std::span<const MhNode> tree,
                      const TreeAttributes& attributes) {
    const int skipLevel = builder_.dag().skipLevel;
    const std::optional<Traversal>& arrival = parts_[part.index].arrival;
    if (skipLevel <= partLevel_ || !arrival) return;
    Traversal at = *arrival;
    at.node = attributes.reference[tree.size() - 1];
    const int shift = levels_ - skipLevel;
    for (uint32_t y = part.y0 >> shift; y < (part.y0 + part.size) >> shift; ++y)
      for (uint32_t x = part.x0 >> shift; x < (part.x0 + part.size) >> shift; ++x)
        builder_.setSkipEntry(
            x, y,
            builder_.walk(tree, attributes, uint32_t(tree.size() - 1), at, x, y, skipLevel).first);
  }

  // Appends the upper values that come before part `end`'s values in depth-first order.
  void emitUpTo(uint64_t end) {
    for (; nextEvent_ < events_.size(); ++nextEvent_) {
      const ValueEvent& event = events_[nextEvent_];
      if (event.part == kNoPart) {
        values_.append(event.value, &stats_);
        continue;
      }
      if (event.part >= end) break;
    }
    if (nextEvent_ < events_.size() && events_[nextEvent_].part == end) ++nextEvent_;
  }

  MapInfo map_;
  uint32_t partSize_;
  int levels_, partLevel_;
  DagShape shape_;
  DagDecoding decoder_;
  MhBuilder upperBuilder_;
  std::optional<MultiresHierarchy> upper_;  // the levels above the parts, after the first pass
  std::map<uint32_t, uint64_t> partOf_;     // its part-level nodes' parts
  DagBuilder builder_;
  ValueChunks values_;
  ValueChunkStats stats_;
  std::vector<PartRoot> parts_;
  std::vector<ValueEvent> events_;
  size_t nextEvent_ = 0;
  uint64_t next_ = 0;
};

}  // namespace

std::unique_ptr<PartMerger> dagPartMerger(const MapInfo& map, uint32_t partSize, DagShape shape,
                                          DagDecoding decoder) {
  return std::make_unique<DagPartMerger>(map, partSize, shape, std::move(decoder));
}

}  // namespace sb::dag_mh
