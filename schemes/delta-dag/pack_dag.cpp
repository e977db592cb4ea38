#include "schemes/delta-dag/pack_dag.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

namespace sb::delta_dag {
namespace {

// The estimates behind splitting and copying, from the layouts at 4K² (city, tangle, forest): a
// pack's header, a table's code for most and an explicit format for the rest, takes 16 to 19 bits
// on average, and a whole pack 40 to 60 (which sets an address's width).
constexpr uint64_t kEstimatedHeaderBits = 16;
constexpr uint64_t kEstimatedPackBits = 48;

std::vector<uint32_t> referenceCounts(const std::vector<Pack>& packs) {
  std::vector<uint32_t> references(packs.size(), 0);
  for (const Pack& pack : packs)
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k))) ++references[pack.children[k]];
  return references;
}

// The packs under `root`, each after the packs it references.
std::vector<uint32_t> childrenFirst(const std::vector<Pack>& packs, uint32_t root) {
  std::vector<uint32_t> order;
  std::vector<bool> seen(packs.size(), false);
  const auto visit = [&](auto& self, uint32_t id) -> void {
    seen[id] = true;
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(packs[id].flags, k)) && !seen[packs[id].children[k]])
        self(self, packs[id].children[k]);
    order.push_back(id);
  };
  visit(visit, root);
  return order;
}

// The estimated bits of a pack's private tree: itself (a mean header, its values' fields as
// fitted, predicted where `prediction` allows, its children's pointers: each shared child's field
// as wide as the widest of their `address`es, and its symmetry where it reads one turned) and the
// trees of its children that are private or `inlined` (copied into it), from `treeBits`.
uint64_t estimatedTreeBits(const Pack& pack, bool prediction,
                           const std::vector<uint32_t>& references,
                           const std::vector<uint8_t>& address, const std::vector<bool>& inlined,
                           const std::vector<uint64_t>& treeBits) {
  uint64_t bits = kEstimatedHeaderBits + fittedValues(pack, prediction).bits, after = 0, width = 0,
           fields = 0;
  for (int k = 0; k < kMhChildren; ++k) {
    if (!isInner(childFlag(pack.flags, k))) continue;
    const uint32_t child = pack.children[k];
    if (references[child] == 1 || inlined[child]) {
      bits += std::bit_width(after);  // its distance after the pack's end
      after += treeBits[child];
    } else {
      width = std::max<uint64_t>(width, address[child]), ++fields;
      bits += pack.symmetries[k] != kIdentity ? kSymmetryBits : 0;
    }
  }
  return bits + fields * width + after;
}

std::vector<uint8_t> uniformAddresses(const std::vector<Pack>& packs) {
  return std::vector<uint8_t>(packs.size(), std::bit_width(packs.size() * kEstimatedPackBits));
}

// Stored turned by f, a pack reads the same under f⁻¹ s f for each s it did.
uint8_t conjugated(uint8_t self, Symmetry f) {
  uint8_t result = 0;
  for (Symmetry s = 0; s < kSymmetries; ++s)
    if (self >> s & 1)
      result |= uint8_t(1u << kSymmetry.then[kSymmetry.inverse[f]][kSymmetry.then[s][f]]);
  return result;
}

}  // namespace

Symmetry normalised(Symmetry w, uint8_t self) {
  if (self == 1) return w;  // most packs: only the identity reads them the same
  Symmetry least = w;
  for (Symmetry s = 1; s < kSymmetries; ++s)
    if (self >> s & 1) least = std::min(least, kSymmetry.then[s][w]);
  return least;
}

Pack turned(const Pack& pack, Symmetry u, const std::vector<uint8_t>& selfSymmetries) {
  Pack result;
  for (int k = 0; k < kMhChildren; ++k) {
    const uint32_t kind = childFlag(pack.flags, k), s = kSymmetry.apply[u][k];
    result.flags |= uint8_t(kind << (2 * s));
    result.values[s] = pack.values[k];
    if (!isInner(kind)) continue;
    result.children[s] = pack.children[k];
    result.symmetries[s] = normalised(kSymmetry.then[pack.symmetries[k]][kSymmetry.inverse[u]],
                                      selfSymmetries[pack.children[k]]);
  }
  return result;
}

uint64_t orient(std::vector<Pack>& packs, std::vector<uint8_t>& selfSymmetries, PackReference root,
                bool prediction) {
  const std::vector<uint32_t> references = referenceCounts(packs);
  std::vector<uint64_t> treeBits(packs.size(), 0);
  {
    const std::vector<uint8_t> address = uniformAddresses(packs);
    const std::vector<bool> inlined(packs.size(), false);
    for (uint32_t id = 0; id < packs.size(); ++id)
      treeBits[id] =
          estimatedTreeBits(packs[id], prediction, references, address, inlined, treeBits);
  }
  // Parents first, as a pack's id is above its children's: when a pack is turned, every reading
  // of it is counted. A reading other than the pack's whose references' symmetries would cost
  // more bits than the pack's tree gets a pack of its own, turned its way (split).
  std::vector<std::array<uint16_t, kSymmetries>> readings(packs.size());  // saturating counts
  std::vector<Symmetry> frame(packs.size(), kIdentity);
  std::unordered_map<uint64_t, uint32_t> split;  // pack × 8 + reading → its own pack
  const auto countReadings = [&](const Pack& pack) {
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k))) {
        uint16_t& count = readings[pack.children[k]][pack.symmetries[k]];
        count += count < UINT16_MAX;
      }
  };
  readings[root.pack][root.symmetry] = 1;
  for (uint32_t id = uint32_t(packs.size()); id-- > 0;) {
    const auto counts = readings[id];
    const Symmetry f = Symmetry(std::max_element(counts.begin(), counts.end()) - counts.begin());
    const Pack stored = packs[id];
    const uint8_t self = selfSymmetries[id];
    for (Symmetry o = 0; o < kSymmetries; ++o) {
      if (o == f || uint64_t(counts[o]) * kSymmetryBits <= treeBits[id]) continue;
      split.emplace(uint64_t(id) * kSymmetries + o, uint32_t(packs.size()));
      packs.push_back(turned(stored, kSymmetry.inverse[o], selfSymmetries));
      selfSymmetries.push_back(conjugated(self, o));
      frame.push_back(kIdentity);
      countReadings(packs.back());
    }
    frame[id] = f;
    if (f != kIdentity) {
      packs[id] = turned(stored, kSymmetry.inverse[f], selfSymmetries);
      selfSymmetries[id] = conjugated(self, f);
    }
    countReadings(packs[id]);
  }
  // A reference read under w reads its own pack unturned where w was split off, else the child
  // stored turned by f under f⁻¹ w.
  for (Pack& pack : packs)
    for (int k = 0; k < kMhChildren; ++k) {
      if (!isInner(childFlag(pack.flags, k))) continue;
      const uint32_t child = pack.children[k];
      if (const auto own = split.find(uint64_t(child) * kSymmetries + pack.symmetries[k]);
          own != split.end()) {
        pack.children[k] = own->second, pack.symmetries[k] = kIdentity;
      } else {
        pack.symmetries[k] =
            normalised(kSymmetry.then[kSymmetry.inverse[frame[child]]][pack.symmetries[k]],
                       selfSymmetries[child]);
      }
    }
  return split.size();
}

uint32_t copyCheapShared(std::vector<Pack>& packs, const std::vector<uint8_t>& selfSymmetries,
                         uint32_t rootPack, bool prediction, uint64_t& copies) {
  const std::vector<uint32_t> references = referenceCounts(packs);
  const std::vector<uint32_t> order = childrenFirst(packs, rootPack);
  std::vector<uint64_t> treeBits(packs.size(), 0);
  std::vector<uint8_t> address = uniformAddresses(packs);
  std::vector<bool> copied(packs.size(), false);
  // First with every address as wide as the packs' bits need, to place the shared packs as the
  // layout will, the most referenced first (pack_layout.h): then each address is as wide as the
  // bits before it.
  for (const uint32_t id : order)
    treeBits[id] = estimatedTreeBits(packs[id], prediction, references, address, copied, treeBits);
  std::vector<uint32_t> shared;
  for (const uint32_t id : order)
    if (references[id] > 1) shared.push_back(id);
  std::stable_sort(shared.begin(), shared.end(),
                   [&](uint32_t a, uint32_t b) { return references[a] > references[b]; });
  uint64_t position = 0;
  for (const uint32_t id : shared)
    address[id] = uint8_t(std::bit_width(position)), position += treeBits[id];
  // Then children first, whether each shared pack is copied: shared by r packs it costs its tree
  // and r addresses, copied r trees.
  for (const uint32_t id : order) {
    treeBits[id] = estimatedTreeBits(packs[id], prediction, references, address, copied, treeBits);
    copied[id] =
        references[id] > 1 && (references[id] - 1) * treeBits[id] < references[id] * address[id];
  }
  // Parents' packs rebuilt after their children's, each copy of a pack turned the way its
  // reference reads it (a private pack of a copied pack is copied with it); the shared packs not
  // copied once each.
  // Room for as many copies as packs, which the encode step reserved (delta_dag.cpp): growing
  // the store moves it and faults its new pages in (the forest at 16K²: 2.1 M packs, 74 K copies).
  std::vector<Pack> rebuilt;
  rebuilt.reserve(2 * packs.size());
  std::vector<uint32_t> rebuiltAs(packs.size(), UINT32_MAX);
  const auto rebuild = [&](auto& self, Pack pack) -> uint32_t {
    for (int k = 0; k < kMhChildren; ++k) {
      if (!isInner(childFlag(pack.flags, k))) continue;
      const uint32_t child = pack.children[k];
      if (copied[child] || references[child] == 1) {
        const Symmetry read = pack.symmetries[k];
        pack.children[k] =
            self(self, read == kIdentity
                           ? packs[child]
                           : turned(packs[child], kSymmetry.inverse[read], selfSymmetries));
        pack.symmetries[k] = kIdentity;
      } else {
        if (rebuiltAs[child] == UINT32_MAX) rebuiltAs[child] = self(self, packs[child]);
        pack.children[k] = rebuiltAs[child];
      }
    }
    rebuilt.push_back(pack);
    return uint32_t(rebuilt.size() - 1);
  };
  const uint32_t root = rebuild(rebuild, packs[rootPack]);
  copies = rebuilt.size() - packs.size();
  packs = std::move(rebuilt);
  return root;
}

}  // namespace sb::delta_dag
