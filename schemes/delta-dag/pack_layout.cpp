#include "schemes/delta-dag/pack_layout.h"

#include <algorithm>
#include <queue>
#include <stdexcept>

namespace sb::delta_dag {

// The order shared packs are laid out in: the most referenced first, each once the shared packs
// its private block references are placed (Kahn's topological order with a priority).
std::vector<uint32_t> sharedOrder(const std::vector<Pack>& packs,
                                  const std::vector<uint32_t>& references) {
  const auto isShared = [&](uint32_t id) { return references[id] > 1; };
  // For each shared pack, the shared packs its private block points to.
  std::vector<std::vector<uint32_t>> dependents(packs.size());
  std::vector<uint32_t> waiting(packs.size(), 0);
  std::vector<uint32_t> needs;
  const auto collect = [&](auto& self, uint32_t id) -> void {
    const Pack& pack = packs[id];
    for (int k = 0; k < kMhChildren; ++k) {
      if (!isInner(childFlag(pack.flags, k))) continue;
      const uint32_t child = pack.children[k];
      if (isShared(child))
        needs.push_back(child);
      else
        self(self, child);
    }
  };
  using Ready = std::pair<uint32_t, uint32_t>;  // references, then the lower id first
  const auto later = [](const Ready& a, const Ready& b) {
    return a.first != b.first ? a.first < b.first : a.second > b.second;
  };
  std::priority_queue<Ready, std::vector<Ready>, decltype(later)> ready(later);
  for (uint32_t id = 0; id < packs.size(); ++id) {
    if (!isShared(id)) continue;
    needs.clear();
    collect(collect, id);
    std::sort(needs.begin(), needs.end());
    needs.erase(std::unique(needs.begin(), needs.end()), needs.end());
    for (const uint32_t need : needs) dependents[need].push_back(id);
    waiting[id] = uint32_t(needs.size());
    if (needs.empty()) ready.push({references[id], id});
  }
  std::vector<uint32_t> order;
  while (!ready.empty()) {
    const uint32_t id = ready.top().second;
    ready.pop();
    order.push_back(id);
    for (const uint32_t dependent : dependents[id])
      if (--waiting[dependent] == 0) ready.push({references[dependent], dependent});
  }
  return order;
}

// `absolute`: the packs pointed to by address, laid out first in the order `shared`.
Layout layOut(const std::vector<Pack>& packs, uint32_t rootPack, const std::vector<bool>& absolute,
              const std::vector<uint32_t>& shared, uint32_t formatBits,
              std::vector<uint64_t> codes) {
  Layout layout;
  layout.formatBits = formatBits;
  // The table's formats by flags and shared mask.
  std::unordered_map<uint32_t, std::vector<uint32_t>> groups;
  for (uint32_t c = 0; c < codes.size(); ++c) {
    const PackFormat g = PackFormat::ofCode(codes[c]);
    groups[g.flags | g.sharedMask << 8].push_back(c);
  }
  layout.codes = std::move(codes);
  for (auto& [key, group] : groups) {
    const PackShape& shape = packShape(key & 0xff);
    const uint32_t valued = shape.valuesBefore[3] + hasValue(MhChild(childFlag(key, 3)));
    const uint32_t sharedCount = uint32_t(std::popcount(key >> 8));
    const uint32_t relative = uint32_t(std::popcount(uint32_t(shape.innerMask))) - sharedCount;
    const auto bitsOf = [&](uint32_t c) {
      const PackFormat g = PackFormat::ofCode(layout.codes[c]);
      return valued * g.valueBits + relative * g.pointerBits + sharedCount * g.sharedBits;
    };
    std::stable_sort(group.begin(), group.end(),
                     [&](uint32_t a, uint32_t b) { return bitsOf(a) < bitsOf(b); });
  }
  const uint64_t escape = (uint64_t(1) << formatBits) - 1;
  BitWriter& out = layout.out;
  std::vector<uint64_t> placed(packs.size(), UINT64_MAX);
  // Writes one pack, whose children are all placed.
  const auto write = [&](uint32_t id) {
    const Pack& pack = packs[id];
    const PackShape& shape = packShape(pack.flags);
    PackFormat f;
    f.flags = pack.flags;
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k)) && absolute[pack.children[k]])
        f.sharedMask |= uint8_t(1u << k);
    const uint64_t position = out.position();
    placed[id] = position;
    uint32_t shift = 32;
    for (int k = 0; k < kMhChildren; ++k)
      if (hasValue(MhChild(childFlag(pack.flags, k))))
        shift = std::min<uint32_t>(shift, std::countr_zero(uint32_t(pack.values[k])));
    f.shift = uint8_t(shape.hasValues ? shift : 0);
    std::array<uint64_t, kMhChildren> pointers{};
    for (int k = 0; k < kMhChildren; ++k) {
      const uint32_t kind = childFlag(pack.flags, k);
      if (hasValue(MhChild(kind)))
        f.valueBits = uint8_t(std::max(uint32_t(f.valueBits), signedBits(pack.values[k] >> shift)));
      if (!isInner(kind)) continue;
      const uint64_t target = placed[pack.children[k]];
      if (target == UINT64_MAX) throw std::logic_error("delta-dag: a shared pack placed late");
      const bool sharedChild = f.sharedMask >> k & 1;
      pointers[k] = sharedChild ? target : position - target;
      uint8_t& bits = sharedChild ? f.sharedBits : f.pointerBits;
      bits = uint8_t(std::max<uint32_t>({bits, 1u, uint32_t(std::bit_width(pointers[k]))}));
    }
    if (std::max(f.pointerBits, f.sharedBits) > kMaxPointerBits)
      throw std::length_error("delta-dag: a pointer needs more than 57 bits");
    ++layout.formatCounts[f.code()];
    // The table's format that holds this pack in the fewest bits: its own, or one of the same
    // flags and mask whose widths are at least as wide and whose shift is at most as large; an
    // escape where no table format is cheaper than the explicit one.
    const auto fieldBits = [&](const PackFormat& g) {
      uint32_t bits = 0;
      for (int k = 0; k < kMhChildren; ++k) {
        const uint32_t kind = childFlag(pack.flags, k);
        bits += hasValue(MhChild(kind)) ? g.valueBits : 0;
        bits += isInner(kind) ? (g.sharedMask >> k & 1 ? g.sharedBits : g.pointerBits) : 0;
      }
      return bits;
    };
    const auto holds = [&](const PackFormat& g) {
      if (g.shift > f.shift || g.pointerBits < f.pointerBits || g.sharedBits < f.sharedBits)
        return false;
      for (int k = 0; k < kMhChildren; ++k)
        if (hasValue(MhChild(childFlag(pack.flags, k))) &&
            signedBits(pack.values[k] >> g.shift) > g.valueBits)
          return false;
      return true;
    };
    PackFormat use = f;
    uint32_t bestBits = f.explicitBits() + fieldBits(f);
    int64_t index = -1;
    // A group is sorted by the bits its formats give the group's packs: the first that holds
    // this pack is the cheapest.
    if (const auto group = groups.find(f.flags | f.sharedMask << 8); group != groups.end())
      for (const uint32_t c : group->second) {
        const PackFormat g = PackFormat::ofCode(layout.codes[c]);
        if (fieldBits(g) >= bestBits) break;
        if (holds(g)) {
          use = g, index = c;
          break;
        }
      }
    if (index >= 0) {
      out.put(uint64_t(index), formatBits);
      layout.headerBits += formatBits;
    } else {
      ++layout.escapes;
      out.put(escape, formatBits);
      out.put(f.flags, 8);
      if (shape.hasValues) out.put(f.valueBits, 6), out.put(f.shift, 5);
      if (shape.hasInner) {
        out.put(f.sharedMask, 4);
        if (shape.innerMask & ~f.sharedMask) out.put(f.pointerBits, 6);
        if (f.sharedMask) out.put(f.sharedBits, 6);
      }
      layout.headerBits += formatBits + f.explicitBits();
    }
    for (int k = 0; k < kMhChildren; ++k) {
      const uint32_t kind = childFlag(pack.flags, k);
      if (hasValue(MhChild(kind))) {
        out.put(uint64_t(int64_t(pack.values[k] >> use.shift)), use.valueBits);
        layout.valueBits += use.valueBits;
      }
      if (isInner(kind)) {
        const uint32_t bits = use.sharedMask >> k & 1 ? use.sharedBits : use.pointerBits;
        out.put(pointers[k], bits);
        layout.pointerBits += bits;
      }
    }
  };
  const auto privateChildren = [&](uint32_t id, auto&& visit) {
    const Pack& pack = packs[id];
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k)) && !absolute[pack.children[k]] &&
          placed[pack.children[k]] == UINT64_MAX)
        visit(pack.children[k]);
  };
  // Children first, depth first.
  const auto place = [&](auto& self, uint32_t id) -> void {
    privateChildren(id, [&](uint32_t child) {
      if (placed[child] == UINT64_MAX) self(self, child);
    });
    write(id);
  };
  for (const uint32_t id : shared) place(place, id);
  if (placed[rootPack] == UINT64_MAX) place(place, rootPack);
  layout.rootPosition = placed[rootPack];
  return layout;
}

// A table of 2^b − 1 formats: the most frequent of these counts (one index is the escape).
std::vector<uint64_t> mostFrequent(const std::unordered_map<uint64_t, uint64_t>& counts,
                                   uint32_t b) {
  std::vector<std::pair<uint64_t, uint64_t>> byFrequency;
  for (const auto& [code, count] : counts) byFrequency.push_back({count, code});
  std::sort(byFrequency.begin(), byFrequency.end(), std::greater<>());
  std::vector<uint64_t> codes;
  for (size_t e = 0; e < byFrequency.size() && e + 1 < (uint64_t(1) << b); ++e)
    codes.push_back(byFrequency[e].second);
  return codes;
}

}  // namespace sb::delta_dag
