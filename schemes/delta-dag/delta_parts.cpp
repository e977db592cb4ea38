#include "schemes/delta-dag/delta_parts.h"

#include <bit>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "schemes/delta-dag/pack_finder.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/mh_parts.h"

namespace sb::delta_dag {
namespace {

class DeltaDagPartMerger final : public PartMerger {
 public:
  DeltaDagPartMerger(const MapInfo& map, uint32_t partSize, const Options& options,
                     Decoding decoder)
      : partSize_(checkedPartSize("delta-dag", partSize, map)),
        levels_(std::countr_zero(map.resolution)),
        partLevel_(levels_ - std::countr_zero(partSize_)),
        options_(options),
        decoder_(std::move(decoder)),
        upperBuilder_(map),
        parts_(MapPart::countFor(map, partSize_)) {}

  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override {
    expectPart("delta-dag", next_, partSize_, part);
    context_ = &context;
    if (next_ == 0) context.phase(upper_ ? "encode" : "merge");
    PartRoot& root = parts_[part.index];
    if (!upper_) {
      root.first = readMhPartRoot(payload, part, "delta-dag");
      upperBuilder_.consume(part, {{}, root.first});
      root.upperEnd = upperBuilder_.storedNodes();
    } else {
      MhBuilder::PartHierarchy hierarchy = readMhPart(payload, part, "delta-dag");
      const MhBuilder::Pending& again = hierarchy.root;
      if (again.interval.lo != root.first.interval.lo ||
          again.interval.hi != root.first.interval.hi || again.childFlags != root.first.childFlags)
        throw FormatError(fmt::format(
            "delta-dag part {}: its root is not the one the first pass read (the file changed)",
            part.index));
      findPart(root, partTree(std::move(hierarchy)));
      findUpper(root.upperEnd);
    }
    ++next_;
  }

  bool anotherPass(BuildContext& context) override {
    expectAllParts("delta-dag", next_, parts_.size());
    if (upper_) return false;
    upper_ = upperBuilder_.finish();
    const std::vector<MhNode>& nodes = upper_->nodes;
    partOf_ = upper_->nodesAtLevel(partLevel_);
    upperPacks_.emplace(nodes.size());
    rootKey_ = uint32_t(chooseValue(nodes.back().interval, 0, options_.values));
    // The part-level nodes' children lie in their parts: their keys are where the parts begin.
    const std::vector<uint32_t> keys =
        chooseValues(nodes, rootKey_, options_.values, upperPacks_->values,
                     [&](uint32_t n) { return !partOf_.contains(n); });
    for (const auto& [n, part] : partOf_) parts_[part].key = keys[n], parts_[part].node = n;
    context_ = &context;
    finder_.emplace(options_, [this](uint64_t bytes, std::string_view what) {
      context_->reserve(bytes, what);
    });
    next_ = 0;
    return true;
  }

  std::unique_ptr<sb::Decoder> finish(BuildContext& context) override {
    expectAllParts("delta-dag", next_, parts_.size());
    if (!upper_) throw std::logic_error("delta-dag: the merge finished before its last pass");
    context_ = &context;
    findUpper(upper_->nodes.size());
    finder_->find();
    const uint32_t root = upper_->root();
    const PackReference rootPack{upperPacks_->pack[root], upperPacks_->symmetry[root]};
    FoundPacks found = std::move(*finder_).finish();
    finder_.reset(), upperPacks_.reset(), upper_.reset(), parts_ = {}, partOf_ = {};
    return decoder_(
        encodeFound(std::move(found), rootPack, rootKey_, levels_, options_,
                    [&](uint64_t bytes, std::string_view what) { context.reserve(bytes, what); }),
        context);
  }

 private:
  struct PartRoot {
    MhBuilder::Pending first;    // as the first pass read it
    uint64_t upperEnd = 0;       // where the part's nodes end among the levels above
    uint32_t key = 0;            // the key its root reconstructs
    uint32_t node = UINT32_MAX;  // its root among the levels above (if stored there)
    std::optional<Pack> pack;    // its root's pack, found in the order of the levels above
  };

  // The packs below the part's root, and the root's own, which waits for its turn among the
  // levels above (a whole hierarchy stores a part's root with the group it completes).
  void findPart(PartRoot& root, const std::vector<MhNode>& tree) {
    const MhNode& top = tree.back();
    if (!top.hasChildren()) return;
    if (root.node == UINT32_MAX)
      throw std::logic_error("delta-dag: a part's root with children is missing above the parts");
    NodePacks packs(tree.size());
    chooseValues(tree, root.key, options_.values, packs.values, [](uint32_t) { return true; });
    finder_->queueTree(std::span(tree).first(tree.size() - 1), packs);
    root.pack = finder_->childrenPack(top, packs);
    finder_->find();  // before `packs` goes
  }

  // The nodes above the parts up to `end`, in order: a part-level node's pack is its part's.
  void findUpper(uint64_t end) {
    const std::vector<MhNode>& nodes = upper_->nodes;
    for (; upperDone_ < end; ++upperDone_) {
      const uint32_t n = uint32_t(upperDone_);
      if (!nodes[n].hasChildren()) continue;
      const auto part = partOf_.find(n);
      const std::optional<Pack> pack = part != partOf_.end()
                                           ? parts_[part->second].pack
                                           : finder_->childrenPack(nodes[n], *upperPacks_);
      if (pack) finder_->queue(*pack, upperPacks_->pack[n], upperPacks_->symmetry[n]);
    }
  }

  uint32_t partSize_;
  int levels_, partLevel_;
  Options options_;
  Decoding decoder_;
  MhBuilder upperBuilder_;
  std::optional<MultiresHierarchy> upper_;  // the levels above the parts, after the first pass
  std::map<uint32_t, uint64_t> partOf_;     // its part-level nodes' parts
  std::optional<NodePacks> upperPacks_;
  uint32_t rootKey_ = 0;
  std::vector<PartRoot> parts_;
  std::optional<PackFinder> finder_;
  BuildContext* context_ = nullptr;  // of the call in progress, for the finder's reservations
  uint64_t next_ = 0, upperDone_ = 0;
};

}  // namespace

std::unique_ptr<PartMerger> partMerger(const MapInfo& map, uint32_t partSize,
                                       const Options& options, Decoding decoder) {
  return std::make_unique<DeltaDagPartMerger>(map, partSize, options, std::move(decoder));
}

}  // namespace sb::delta_dag
