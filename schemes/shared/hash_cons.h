// Hash-consing: the index that makes a DAG out of a tree by storing each distinct node once
// (Sintorn §3 for the voxel DAG, Scandolo & Eisemann 2021 §3.1 for DAG-MH). Open addressing over
// ids; each id's full hash is kept, so growing never rereads the nodes and most mismatches are
// rejected without touching them. The caller stores the nodes, id by id, and says when two are
// the same.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace sb {

class HashConsIndex {
 public:
  // The id of a stored node with `hash` for which same(id) holds, and false; otherwise the next
  // id (count() before the call), now taken, and true: the caller then stores the node as it.
  template <class Same>
  std::pair<uint32_t, bool> findOrAdd(uint64_t hash, Same&& same) {
    if ((hashes_.size() + 1) * 2 > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t s = hash & mask;; s = (s + 1) & mask) {
      if (slots_[s] == 0) {
        const uint32_t id = uint32_t(hashes_.size());
        hashes_.push_back(hash);
        slots_[s] = id + 1;
        return {id, true};
      }
      const uint32_t id = slots_[s] - 1;
      if (hashes_[id] == hash && same(id)) return {id, false};
    }
  }

  size_t count() const { return hashes_.size(); }

  // Hints for a findOrAdd(hash) to come, which reads hash's first slot, then the hash of the id
  // it names and the caller's node of that id, each a likely miss in the cache. prefetchSlot
  // brings the slot in; prefetchNamed, once it is there, the hash of the id it names, and
  // calls `named` with that id (to bring in the node). Neither changes the index.
  void prefetchSlot(uint64_t hash) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[hash & (slots_.size() - 1)]);
  }
  template <class Named>
  void prefetchNamed(uint64_t hash, Named&& named) const {
    if (slots_.empty()) return;
    if (const uint32_t slot = slots_[hash & (slots_.size() - 1)]; slot != 0) {
      __builtin_prefetch(&hashes_[slot - 1]);
      named(slot - 1);
    }
  }

 private:
  void grow() {
    slots_.assign(std::max<size_t>(1024, slots_.size() * 2), 0);
    const size_t mask = slots_.size() - 1;
    for (uint32_t id = 0; id < hashes_.size(); ++id) {
      size_t s = hashes_[id] & mask;
      while (slots_[s] != 0) s = (s + 1) & mask;
      slots_[s] = id + 1;
    }
  }

  std::vector<uint64_t> hashes_;  // id → hash
  std::vector<uint32_t> slots_;   // id + 1, 0 = empty
};

}  // namespace sb
