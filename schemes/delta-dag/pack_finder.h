// delta-dag's encode step up to its layout: values chosen top-down, packs found bottom-up by
// hash-consing. A whole build runs it over the whole hierarchy (delta_dag.cpp), a merge of parts
// over one part at a time and the levels above them (delta_parts.h), in the very order of the
// whole hierarchy's nodes, so that both find the same packs with the same ids.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "schemes/delta-dag/pack_dag.h"
#include "schemes/shared/hash_cons.h"
#include "schemes/shared/multires_hierarchy.h"

namespace sb::delta_dag {

inline constexpr uint32_t kNoPack = UINT32_MAX;

// The relative value of a node holding interval [lo, hi] below a path that reconstructs `parent`.
int32_t chooseValue(const KeyInterval& interval, uint32_t parent, ValueChoice choice);

// Top-down over a tree whose root is its last node, holding key `rootKey`: each value relative to
// the key its parent's path reconstructs, into `values`. Nodes `descend` refuses have their
// children elsewhere (a part's root among the levels above the parts). Returns each node's key.
template <class Descend>
std::vector<uint32_t> chooseValues(std::span<const MhNode> nodes, uint32_t rootKey,
                                   ValueChoice choice, std::vector<int32_t>& values,
                                   Descend&& descend) {
  std::vector<uint32_t> keys(nodes.size());
  keys[nodes.size() - 1] = rootKey;
  for (size_t n = nodes.size(); n-- > 0;) {
    const MhNode& node = nodes[n];
    if (!node.hasChildren() || !descend(uint32_t(n))) continue;
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = node.child(k);
      if (kind == MhChild::None) continue;
      keys[child] = keys[n];
      if (hasValue(kind)) {
        values[child] = chooseValue(nodes[child].interval, keys[n], choice);
        keys[child] += uint32_t(values[child]);
      }
      ++child;
    }
  }
  return keys;
}

// Per node of one tree, what its parent's pack takes from it: its value and the pack found for
// its children (kNoPack: none; kQueuedPack: queued, not found yet) with the symmetry reading it.
struct NodePacks {
  explicit NodePacks(size_t nodes)
      : values(nodes, 0), pack(nodes, kNoPack), symmetry(nodes, kIdentity) {}
  std::vector<int32_t> values;
  std::vector<uint32_t> pack;
  std::vector<Symmetry> symmetry;
};

// The packs found, for the layout (encodeFound).
struct FoundPacks {
  std::vector<Pack> packs;
  std::vector<uint8_t> selfSymmetries;
  Statistics statistics;  // valued nodes, tree packs and distinct packs counted
};

// Hash-consing of packs, children first. Packs equal under a symmetry are one: each is stored
// turned to the orientation that compares smallest, and its node reads it under the symmetry that
// turns it back (the first, where the pack is itself symmetric: those that read it the same are
// its self-symmetries). A lookup reads a slot of the index, then the hash and the pack it names,
// each a likely miss in the cache: packs are queued in batches, their slots and then what the
// slots name prefetched before the first is looked up (the forest at 16K²: 7.7 M packs in 2.45 s
// one by one, 1.9 s in batches of 16 to 128 alike). Ids follow the order packs are queued in.
class PackFinder {
 public:
  PackFinder(const Options& options, ReserveMemory reserve)
      : options_(options), reserve_(std::move(reserve)) {}

  // The pack of `node`'s children, their values and packs in `tree`, or none where no child is
  // left. A whole build's MH stores a child only where its interval misses its parent's, which
  // holds the parent's key, so no value is 0; a hierarchy merged from crafted part files may
  // break that rule (fuzzing found one). A child whose value is 0 then needs none (a leaf becomes
  // nothing, a full node empty), and an inner child left without a pack becomes a leaf or
  // nothing: the loader refuses a 0. Finds the queued packs first where a child's is among them.
  std::optional<Pack> childrenPack(const MhNode& node, const NodePacks& tree);
  // Queues `pack`: `id` and `symmetry` receive the stored pack and its reading once it is found
  // (find), and must stay in place until then.
  void queue(const Pack& pack, uint32_t& id, Symmetry& symmetry);
  // Queues the packs of `nodes` in their order (children before parents), their children's
  // values and packs in `tree`, which receives theirs.
  void queueTree(std::span<const MhNode> nodes, NodePacks& tree) {
    for (uint32_t n = 0; n < nodes.size(); ++n)
      if (nodes[n].hasChildren())
        if (const std::optional<Pack> pack = childrenPack(nodes[n], tree))
          queue(*pack, tree.pack[n], tree.symmetry[n]);
  }
  // Finds every queued pack.
  void find();
  // The packs, every queued one found.
  FoundPacks finish() &&;

 private:
  static constexpr uint32_t kQueuedPack = kNoPack - 1;
  static constexpr size_t kBatch = 32;
  // The first count of distinct packs at which hash-consing reserves (kFindingBytesPerPack), and
  // every power of two above it: where the store, the hashes and the slots double.
  static constexpr uint64_t kFirstReserve = uint64_t(1) << 16;
  struct Queued {
    Pack pack;  // turned to the orientation that compares smallest
    uint64_t hash;
    uint32_t* id;
    Symmetry* symmetry;
    Symmetry read;      // the symmetry that turns it back
    uint8_t readsSame;  // bit u: turned by u, the pack compares as the smallest
  };

  Options options_;
  ReserveMemory reserve_;
  FoundPacks found_;
  HashConsIndex index_;
  uint64_t nextReserve_ = kFirstReserve;
  std::vector<Queued> batch_;
};

// The rest of the encode step, from the packs found: oriented, copied where cheaper and laid out
// (delta_dag.cpp). `root` is the root's pack (kNoPack: the map is one leaf) read under its
// symmetry, `rootKey` the root's key.
Encoded encodeFound(FoundPacks found, PackReference root, uint32_t rootKey, int levels,
                    const Options& options, const ReserveMemory& reserve);

}  // namespace sb::delta_dag
