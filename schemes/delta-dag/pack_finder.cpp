#include "schemes/delta-dag/pack_finder.h"

#include <fmt/format.h>

namespace sb::delta_dag {

static_assert(sizeof(Pack) == 40, "kFindingBytesPerPack counts 40 bytes a pack");

int32_t chooseValue(const KeyInterval& interval, uint32_t parent, ValueChoice choice) {
  const int64_t lo = int64_t(interval.lo) - parent, hi = int64_t(interval.hi) - parent;
  const int64_t value =
      choice == ValueChoice::Simplest ? simplestIn(lo, hi) : int64_t(interval.middle()) - parent;
  return int32_t(value);  // keys are at most +inf's, 0x7f800000: differences fit int32
}

std::optional<Pack> PackFinder::childrenPack(const MhNode& node, const NodePacks& tree) {
  const uint32_t children = uint32_t(MultiresHierarchy::childCount(node));
  for (uint32_t child = node.firstChild; child < node.firstChild + children; ++child)
    if (tree.pack[child] == kQueuedPack) {
      find();
      break;
    }
  Pack pack;
  uint32_t child = node.firstChild;
  for (int k = 0; k < kMhChildren; ++k) {
    MhChild kind = node.child(k);
    if (kind == MhChild::None) continue;
    if (hasValue(kind)) {
      ++found_.statistics.valuedNodes;
      if (tree.values[child] == 0) kind = kind == MhChild::Leaf ? MhChild::None : MhChild::Empty;
    }
    if (isInner(uint32_t(kind)) && tree.pack[child] == kNoPack)
      kind = kind == MhChild::Full ? MhChild::Leaf : MhChild::None;
    if (hasValue(kind)) pack.values[k] = tree.values[child];
    if (isInner(uint32_t(kind)))
      pack.children[k] = tree.pack[child], pack.symmetries[k] = tree.symmetry[child];
    pack.flags |= uint8_t(uint32_t(kind) << (2 * k));
    ++child;
  }
  if (pack.flags == 0) return std::nullopt;
  ++found_.statistics.treePacks;
  return pack;
}

void PackFinder::queue(const Pack& pack, uint32_t& id, Symmetry& symmetry) {
  Queued queued{pack, 0, &id, &symmetry, kIdentity, 1};
  if (options_.sharing && options_.symmetry)
    for (Symmetry u = 1; u < kSymmetries; ++u) {
      if (turnedFlags(pack.flags, u) > queued.pack.flags) continue;  // flags compare first
      const Pack candidate = turned(pack, u, found_.selfSymmetries);
      if (candidate < queued.pack) queued.pack = candidate, queued.read = u, queued.readsSame = 0;
      if (candidate == queued.pack) queued.readsSame |= uint8_t(1u << u);
    }
  queued.hash = queued.pack.hash();
  if (options_.sharing) index_.prefetchSlot(queued.hash);
  id = kQueuedPack;
  batch_.push_back(queued);
  if (batch_.size() == kBatch) find();
}

void PackFinder::find() {
  std::vector<Pack>& packs = found_.packs;
  if (options_.sharing)
    for (const Queued& queued : batch_)
      index_.prefetchNamed(queued.hash, [&](uint32_t id) { __builtin_prefetch(&packs[id]); });
  for (const Queued& queued : batch_) {
    if (packs.size() == nextReserve_) {
      reserve_(nextReserve_ * kFindingBytesPerPack,
               fmt::format("delta-dag: hash-consing past {} distinct packs", nextReserve_));
      nextReserve_ *= 2;
    }
    const auto [id, added] =
        options_.sharing
            ? index_.findOrAdd(queued.hash,
                               [&](uint32_t other) { return packs[other] == queued.pack; })
            : std::pair{uint32_t(packs.size()), true};
    if (added) {
      packs.push_back(queued.pack);
      uint8_t self = 0;
      for (Symmetry u = 0; u < kSymmetries; ++u)
        if (queued.readsSame >> u & 1)
          self |= uint8_t(1u << kSymmetry.then[u][kSymmetry.inverse[queued.read]]);
      found_.selfSymmetries.push_back(self);
    }
    *queued.id = id, *queued.symmetry = queued.read;
  }
  batch_.clear();
}

FoundPacks PackFinder::finish() && {
  find();
  found_.statistics.dagPacks = found_.packs.size();
  return std::move(found_);
}

}  // namespace sb::delta_dag
