#include "schemes/delta-dag/pack_layout.h"

#include <algorithm>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

#include "schemes/delta-dag/prefix_code.h"
#include "schemes/shared/hash_cons.h"

namespace sb::delta_dag {

// The order shared packs are laid out in: the most referenced first (or the first found), each
// once the shared packs its private tree references are placed (Kahn's topological order with a
// priority).
std::vector<uint32_t> sharedOrder(const std::vector<Pack>& packs,
                                  const std::vector<uint32_t>& references, bool byReferences) {
  const auto isShared = [&](uint32_t id) { return references[id] > 1; };
  const auto priority = [&](uint32_t id) { return byReferences ? references[id] : 0; };
  // For each shared pack, the shared packs its private tree points to.
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
  using Ready = std::pair<uint32_t, uint32_t>;  // priority, then the lower id first
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
    if (needs.empty()) ready.push({priority(id), id});
  }
  std::vector<uint32_t> order;
  while (!ready.empty()) {
    const uint32_t id = ready.top().second;
    ready.pop();
    order.push_back(id);
    for (const uint32_t dependent : dependents[id])
      if (--waiting[dependent] == 0) ready.push({priority(dependent), dependent});
  }
  return order;
}

namespace {

// How one pack is written: its own format (what the next table counts), the table format it
// uses (`index`), which `format` then is where written, and its pointers.
struct PackEncoding {
  uint64_t ownCode = 0;
  PackFormat format;
  int64_t index = -1;  // into the table, or -1: explicit
  std::array<uint64_t, kMhChildren> pointers{};
};

// A layout counted, or written as it was counted.
enum class LayoutPass : uint8_t { Count, Write };

uint8_t widthFor(uint8_t width, uint64_t pointer) {
  return uint8_t(std::max<uint32_t>({width, 1u, uint32_t(std::bit_width(pointer))}));
}

// A format with shared addresses of their own widths joins the table where its packs save this
// many bits or more: a table entry takes 64 bits, and each format more lengthens the others'
// codes. Of 0 to 4096, 128 to 512 made the smallest structures (the city open at 16K², 0.912 of
// the widest's width for all at 256; the city closed and the forest static within 0.2 %, where 0
// took 1.0 and 0.4 % more).
constexpr uint64_t kMinOwnWidthsGain = 256;

// A pack predicts a value where that saves this many bits or more (fittedValues).
constexpr uint32_t kMinPredictionGain = 4;

// What a pack needs of a table format to be written in it.
struct FormatNeed {
  uint16_t bits;  // its explicit format's: a table format must take fewer
  uint8_t shift, pointerBits, symmetryMask;
  uint32_t sharedWidths;  // PackFormat::sharedWidths
  // Its values' widths at its own shift: all, all but the predictable one, and the residual's (0
  // where the residual is 0). A format of d bits less shift needs each of them d bits wider, but
  // a residual of 0, which takes 1 bit at every shift.
  uint8_t widest, neighbours, residual;
  bool operator==(const FormatNeed&) const = default;
  uint64_t hash() const {
    return mixBits(uint64_t(bits) | uint64_t(shift) << 16 | uint64_t(pointerBits) << 24 |
                   uint64_t(symmetryMask) << 32 | uint64_t(widest) << 40 |
                   uint64_t(neighbours) << 48 | uint64_t(residual) << 56) ^
           mixBits(sharedWidths);
  }
};

// `form`: the pack's explicit format; `sharedWidths`: its shared addresses' own widths.
FormatNeed needOf(const Pack& pack, const PackFormat& form, uint32_t sharedWidths) {
  FormatNeed need{form.bits, form.shift, form.pointerBits, form.symmetryMask, sharedWidths, 0,
                  0,         0};
  const uint32_t predictable = packShape(pack.flags).predictable;
  for (uint32_t k = 0; k < kMhChildren; ++k) {
    if (!hasValue(MhChild(childFlag(pack.flags, int(k))))) continue;
    const uint8_t bits = uint8_t(signedBits(pack.values[k] >> form.shift));
    need.widest = std::max(need.widest, bits);
    if (k != predictable) need.neighbours = std::max(need.neighbours, bits);
  }
  if (predictable < kMhChildren)
    if (const int64_t residual = predictionResidual(pack, form.shift); residual != 0)
      need.residual = uint8_t(signedBits(residual));
  return need;
}

// A table format as the search compares it: 12 bytes, so that a group's scan reads few lines.
struct FormatFit {
  uint16_t bits;
  uint8_t shift, valueBits, residualBits, pointerBits, symmetryMask;
  uint32_t sharedWidths;
};

// Whether each byte of `widths` is at least the same byte of `needed`, all below 128: no byte's
// difference borrows from the next, so each keeps its top bit.
bool eachAtLeast(uint32_t widths, uint32_t needed) {
  return (((widths | 0x80808080u) - needed) & 0x80808080u) == 0x80808080u;
}

// Whether a format holds a pack: its pointers at least as wide, the symmetries it needs, and its
// values fit, predicted or not as the format says. Evaluated without branches: which test fails
// varies from format to format, and mispredicted branches took most of the scan's time.
bool holds(const FormatFit& g, const FormatNeed& need) {
  const int d = int(need.shift) - int(g.shift);
  const bool predicted = g.residualBits != 0;
  const int residual = need.residual != 0 ? need.residual + d : 1;
  return (d >= 0) & (g.pointerBits >= need.pointerBits) &
         eachAtLeast(g.sharedWidths, need.sharedWidths) &
         ((need.symmetryMask & ~g.symmetryMask) == 0) &
         ((predicted ? need.neighbours : need.widest) + d <= g.valueBits) &
         (!predicted | (residual <= g.residualBits));
}

// The table's formats of one flags and shared mask (PackFormat::groupKey), in runs of one widest
// shared address (PackFormat::sharedBits), ascending, each run by the bits its formats take: a
// pack's search skips the runs too narrow for it, where formats of narrower addresses are many.
constexpr uint32_t kFormatGroups = 1u << 12;
struct FormatGroup {
  struct Run {
    uint8_t sharedBits;
    uint32_t begin, end;  // into fits
  };
  std::vector<FormatFit> fits;
  std::vector<uint32_t> index;  // into the table
  std::vector<Run> runs;
};

// The format of `group` that holds the pack and takes the fewest bits, fewer than its explicit
// format, the first in the table of those; -1 if none. Each run wide enough is scanned up to the
// bits of the best found so far, in blocks of 32 tested at once. (With each shared child's own
// width the city open at 8K² has groups of up to 6840 formats; scanned whole up to the bits, a
// search read 1750 of them.)
int32_t cheapestHolder(const FormatGroup& group, const FormatNeed& need) {
  constexpr size_t kBlock = 32;
  uint32_t widest = 0;
  for (int k = 0; k < kMhChildren; ++k)
    widest = std::max(widest, need.sharedWidths >> (8 * k) & 255);
  int32_t best = -1;
  uint32_t most = need.bits - 1u;  // the bits a better holder may take
  for (const FormatGroup::Run& run : group.runs) {
    if (run.sharedBits < widest) continue;
    for (size_t begin = run.begin; begin < run.end; begin += kBlock) {
      const size_t end = std::min<size_t>(run.end, begin + kBlock);
      uint32_t held = 0, cheaper = 0;
      for (size_t i = begin; i < end; ++i) {
        held |= uint32_t(holds(group.fits[i], need)) << (i - begin);
        cheaper |= uint32_t(group.fits[i].bits <= most) << (i - begin);
      }
      if ((held &= cheaper) != 0) {
        const size_t i = begin + std::countr_zero(held);
        const auto found = int32_t(group.index[i]);
        if (best < 0 || group.fits[i].bits < most || found < best)
          best = found, most = group.fits[i].bits;
        break;
      }
      if (size_t(std::countr_one(cheaper)) < end - begin) break;  // the rest take more bits
    }
  }
  return best;
}

// The cheapest holder of each need met, by group: many packs need the same (the city open at
// 8K²: 0.36 M distinct needs for 2.2 M packs).
class HolderMemo {
 public:
  int32_t cheapest(const std::vector<FormatGroup>& groups, uint32_t groupKey,
                   const FormatNeed& need) {
    const auto [id, added] = index_.findOrAdd(need.hash() ^ groupKey, [&](uint32_t other) {
      return groupKeys_[other] == groupKey && needs_[other] == need;
    });
    if (added) {
      groupKeys_.push_back(groupKey), needs_.push_back(need);
      holders_.push_back(cheapestHolder(groups[groupKey], need));
    }
    return holders_[id];
  }

 private:
  HashConsIndex index_;
  std::vector<uint32_t> groupKeys_;
  std::vector<FormatNeed> needs_;
  std::vector<int32_t> holders_;
};

}  // namespace

int64_t predictionResidual(const Pack& pack, uint32_t shift) {
  const uint32_t k = packShape(pack.flags).predictable;
  return int64_t(pack.values[k] >> shift) - (pack.values[k ^ 1] >> shift) -
         (pack.values[k ^ 2] >> shift);
}

ValueFields fittedValues(const Pack& pack, bool prediction) {
  ValueFields fields;
  const PackShape& shape = packShape(pack.flags);
  if (!shape.hasValues) return fields;
  uint32_t shift = 32, values = 0;
  for (int k = 0; k < kMhChildren; ++k)
    if (hasValue(MhChild(childFlag(pack.flags, k))))
      shift = std::min<uint32_t>(shift, std::countr_zero(uint32_t(pack.values[k]))), ++values;
  fields.shift = uint8_t(shift);
  const auto widest = [&](uint32_t except) {
    uint32_t bits = 0;
    for (uint32_t k = 0; k < kMhChildren; ++k)
      if (k != except && hasValue(MhChild(childFlag(pack.flags, int(k)))))
        bits = std::max(bits, signedBits(pack.values[k] >> shift));
    return bits;
  };
  fields.valueBits = uint8_t(widest(kMhChildren));
  fields.bits = values * fields.valueBits;
  if (prediction && shape.predictable < kMhChildren) {
    const uint32_t residualBits = signedBits(predictionResidual(pack, shift));
    const uint32_t neighbourBits = widest(shape.predictable);
    // Predicted where that saves kMinPredictionGain bits or more: a prediction that saves fewer
    // takes a format of its own, which the table pays for (4 of 1 to 12 bits made the smallest
    // structures, on the city open at 8K², the forest static and the city closed at 16K²).
    if (residualBits <= kMaxResidualBits &&
        2 * neighbourBits + residualBits + kMinPredictionGain <= fields.bits)
      fields = {fields.shift, uint8_t(neighbourBits), uint8_t(residualBits),
                2 * neighbourBits + residualBits};
  }
  return fields;
}

uint32_t cheapestAddressUnit(const std::vector<uint64_t>& positions,
                             const std::vector<uint32_t>& references, uint32_t maxUnit) {
  uint32_t cheapest = 0;
  uint64_t fewest = UINT64_MAX;
  for (uint32_t unit = 0; unit <= maxUnit; ++unit) {
    // Counted in half bits: each private tree is padded by (2^unit − 1) / 2 bits on average.
    const uint64_t padding = (uint64_t(1) << unit) - 1;
    uint64_t halfBits = 0;
    for (size_t i = 0; i < positions.size(); ++i) {
      const uint64_t padded = positions[i] + i * padding / 2;
      halfBits += padding + 2 * uint64_t(references[i]) * widthFor(0, padded >> unit);
    }
    if (halfBits < fewest) fewest = halfBits, cheapest = unit;
  }
  return cheapest;
}

uint64_t Layout::cost() const {
  const uint32_t longest =
      table.lengths.empty() ? 0 : *std::max_element(table.lengths.begin(), table.lengths.end());
  return bits() + 8 * storedBytes(table) + (uint64_t(16) << longest);
}

namespace {

// Counts `layout` (its table and address unit set), or writes it as it was counted.
void layOut(const std::vector<Pack>& packs, uint32_t rootPack, const std::vector<bool>& absolute,
            const std::vector<uint32_t>& shared, bool prediction, Layout& layout, LayoutPass pass) {
  const FormatTable& table = layout.table;
  const uint32_t addressUnit = layout.addressUnit;
  std::vector<PackFormat> formats;
  for (uint32_t c = 0; c < table.codes.size(); ++c)
    formats.push_back(PackFormat::ofCode(table.codes[c], table.lengths[c]));
  // What a count searches: the table's formats by flags and shared mask, each group by the bits
  // its formats take (the first of a group that holds a pack is the cheapest), and each format's
  // bits alone, an array that stays in the cache (the forest at 16K² has 47 K formats: 1 MB of
  // them, 94 KB of bits).
  std::vector<uint16_t> formatBits;
  std::vector<FormatGroup> groups;
  HolderMemo holders;
  if (pass == LayoutPass::Count) {
    std::vector<uint32_t> byBits;
    for (uint32_t c = 0; c < formats.size(); ++c)
      formatBits.push_back(formats[c].bits), byBits.push_back(c);
    std::stable_sort(byBits.begin(), byBits.end(), [&](uint32_t a, uint32_t b) {
      return std::pair(formats[a].sharedBits, formatBits[a]) <
             std::pair(formats[b].sharedBits, formatBits[b]);
    });
    groups.resize(kFormatGroups);
    for (const uint32_t c : byBits) {
      const PackFormat& g = formats[c];
      FormatGroup& group = groups[g.groupKey()];
      if (group.runs.empty() || group.runs.back().sharedBits != g.sharedBits)
        group.runs.push_back({g.sharedBits, uint32_t(group.fits.size()), 0});
      group.fits.push_back({g.bits, g.shift, g.valueBits, g.residualBits, g.pointerBits,
                            g.symmetryMask, g.sharedWidths()});
      group.index.push_back(c);
      group.runs.back().end = uint32_t(group.fits.size());
    }
  }
  const std::vector<uint32_t> codes = canonicalCodes(table.lengths);
  const uint32_t escapeBits = table.lengths.empty() ? 0 : table.lengths.back();
  const uint32_t escapeCode = table.lengths.empty() ? 0 : codes.back();

  std::vector<uint64_t> placed(packs.size(), UINT64_MAX);
  // Measured when counted: each pack's private tree's bits, and the table format it uses (its
  // widths are the same when written): -1 explicit, -2 not yet found.
  std::vector<uint64_t>& treeBits = layout.treeBits;
  std::vector<int32_t>& chosen = layout.chosen;
  if (pass == LayoutPass::Count) {
    layout.uses.assign(table.codes.size() + 1, 0);
    treeBits.assign(packs.size(), 0), chosen.assign(packs.size(), -2);
  }
  // A pack's private tree (itself and, in k order, the private trees of its children that are
  // not shared) is laid out in one piece.
  const auto forPrivateChildren = [&](const Pack& pack, auto&& visit) {
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k)) && !absolute[pack.children[k]])
        visit(k, pack.children[k]);
  };
  // Child k's pointer is a shared child's address, or the bits of the private trees between the
  // pack's end and child k's: 0 for the first, which needs no field.
  const auto encode = [&](uint32_t id) {
    const Pack& pack = packs[id];
    PackEncoding e;
    PackFormat& f = e.format;
    f.flags = pack.flags;
    std::array<uint8_t, kMhChildren> sharedWidths{};
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k)) && absolute[pack.children[k]]) {
        f.sharedMask |= uint8_t(1u << k);
        if (pack.symmetries[k] != kIdentity) f.symmetryMask |= uint8_t(1u << k);
        if (placed[pack.children[k]] == UINT64_MAX)
          throw std::logic_error("delta-dag: a shared pack placed late");
        e.pointers[k] = placed[pack.children[k]] >> addressUnit;
        sharedWidths[k] = widthFor(0, e.pointers[k]);
      }
    uint64_t after = 0;
    forPrivateChildren(pack, [&](int k, uint32_t child) {
      if (after != 0) f.pointerBits = widthFor(f.pointerBits, after);
      e.pointers[k] = after;
      after += treeBits[child];
    });
    const ValueFields values = fittedValues(pack, prediction);
    f.shift = values.shift, f.valueBits = values.valueBits, f.residualBits = values.residualBits;
    f.setSharedWidths(sharedWidths);
    if (std::max(f.pointerBits, f.sharedBits) > kMaxPointerBits)
      throw std::length_error("delta-dag: a pointer needs more than 54 bits");
    e.ownCode = f.code();
    const uint32_t ownWidths = f.sharedWidths();
    f.setSharedWidths({f.sharedBits, f.sharedBits, f.sharedBits, f.sharedBits});  // explicit
    f.derive(escapeBits + f.explicitBits());
    if (chosen[id] == -2)
      chosen[id] = table.codes.empty()
                       ? -1
                       : holders.cheapest(groups, f.groupKey(), needOf(pack, f, ownWidths));
    e.index = chosen[id];
    if (e.index >= 0 && pass == LayoutPass::Write) e.format = formats[e.index];
    return e;
  };
  const auto measure = [&](auto& self, uint32_t id) -> void {
    uint64_t bits = 0;
    forPrivateChildren(packs[id], [&](int, uint32_t child) {
      self(self, child);
      bits += treeBits[child];
    });
    const PackEncoding e = encode(id);
    if (table.codes.empty()) layout.ownCodes.push_back(e.ownCode);
    ++layout.uses[e.index >= 0 ? e.index : table.codes.size()];
    treeBits[id] = bits + (e.index >= 0 ? formatBits[e.index] : e.format.bits);
  };

  BitWriter& out = layout.out;
  const auto write = [&](const Pack& pack, const PackEncoding& e) {
    const PackFormat& f = e.format;
    const PackShape& shape = packShape(f.flags);
    if (e.index >= 0) {
      out.put(codes[e.index], f.headerBits());
    } else {
      ++layout.escapes;
      out.put(escapeCode, escapeBits);
      out.put(f.flags, 8);
      if (shape.hasValues) out.put(f.valueBits, 6), out.put(f.shift, 5);
      if (shape.hasInner) {
        out.put(f.sharedMask, 4);
        if (f.sharedMask) out.put(f.symmetryMask != 0, 1);
        if (f.symmetryMask) out.put(f.symmetryMask, 4);
        if (f.hasPointerWidth()) out.put(f.pointerBits, 6);
        if (f.sharedMask) out.put(f.sharedBits, 6);
      }
      if (shape.predictable < kMhChildren) out.put(f.residualBits != 0, 1);
      if (f.residualBits) out.put(f.residualBits, 4);
    }
    layout.headerBits += f.headerBits();
    for (int k = 0; k < kMhChildren; ++k) {
      if (const uint32_t bits = f.valueWidth(k); bits != 0) {
        out.putSigned(uint32_t(k) == f.predicted() ? predictionResidual(pack, f.shift)
                                                   : int64_t(pack.values[k] >> f.shift),
                      bits);
        layout.valueBits += bits;
      }
      out.put(e.pointers[k], f.pointerWidth[k]);
      layout.pointerBits += f.pointerWidth[k];
      if (f.symmetryMask >> k & 1) {
        out.put(pack.symmetries[k], kSymmetryBits);
        layout.symmetryBits += kSymmetryBits;
      }
    }
  };
  const auto place = [&](auto& self, uint32_t id) -> void {
    const PackEncoding e = encode(id);
    const uint64_t position = out.position();
    placed[id] = position;
    write(packs[id], e);
    forPrivateChildren(packs[id], [&](int k, uint32_t child) {
      if (out.position() != position + e.format.bits + e.pointers[k])
        throw std::logic_error("delta-dag: a private tree measured wrong");
      self(self, child);
    });
  };
  // Counted, a private tree is placed where its measure says the written one will lie.
  uint64_t counted = 0;
  const auto lay = [&](uint32_t id) {
    if (pass == LayoutPass::Write) return place(place, id);
    measure(measure, id);
    placed[id] = counted;
    counted += treeBits[id];
  };
  const uint64_t unitMask = (uint64_t(1) << addressUnit) - 1;
  for (const uint32_t id : shared) {
    const uint64_t position = pass == LayoutPass::Write ? out.position() : counted;
    const uint64_t padding = (0 - position) & unitMask;
    if (pass == LayoutPass::Write) {
      out.put(0, uint32_t(padding));
      layout.paddingBits += padding;
    } else {
      counted += padding;
      layout.sharedPositions.push_back(position + padding);
    }
    lay(id);
  }
  if (placed[rootPack] == UINT64_MAX) lay(rootPack);
  if (pass == LayoutPass::Count) {
    layout.rootPosition = placed[rootPack];
    layout.bitCount = counted;
  } else if (out.position() != layout.bitCount || placed[rootPack] != layout.rootPosition) {
    throw std::logic_error("delta-dag: a layout written otherwise than counted");
  }
}

}  // namespace

void BitWriter::refuseNarrowField(uint32_t bits) const {
  throw std::logic_error(
      fmt::format("delta-dag: a value wider than its {}-bit field at bit {}", bits, bits_));
}

Layout countLayout(const std::vector<Pack>& packs, uint32_t rootPack,
                   const std::vector<bool>& absolute, const std::vector<uint32_t>& shared,
                   uint32_t addressUnit, bool prediction, FormatTable table) {
  Layout layout;
  layout.addressUnit = addressUnit;
  layout.table = std::move(table);
  layOut(packs, rootPack, absolute, shared, prediction, layout, LayoutPass::Count);
  return layout;
}

void writeLayout(const std::vector<Pack>& packs, uint32_t rootPack,
                 const std::vector<bool>& absolute, const std::vector<uint32_t>& shared,
                 bool prediction, Layout& layout) {
  layOut(packs, rootPack, absolute, shared, prediction, layout, LayoutPass::Write);
}

FormatTable frequentFormats(std::vector<uint64_t> ownCodes, uint64_t minCount, uint32_t maxBits,
                            bool eachSharedWidth) {
  // Counted by sorting: a hash map's update per pack took 8 % of a build (forest 16K², perf).
  std::sort(ownCodes.begin(), ownCodes.end());
  std::vector<std::pair<uint64_t, uint64_t>> counts;  // code, packs
  for (const uint64_t code : ownCodes)
    if (counts.empty() || counts.back().first != code)
      counts.push_back({code, 1});
    else
      ++counts.back().second;
  // Counted with widths rounded up to even: packs a bit apart share the wider format, so fewer
  // formats hold more packs (4K²: 2 to 4 % smaller than exact widths). Each pack counts for its
  // format with every shared address as wide as the widest, and with `eachSharedWidth` also for
  // its format with each address's own width, where that differs: counted only in the latter,
  // packs split among more formats, fewer of them frequent enough (the forest static at 16K²
  // took 2.7 % more, twice the escapes), while now the table holds the formats it held without
  // own widths, and those with own widths that save enough (kMinOwnWidthsGain).
  const auto even = [](uint32_t bits, uint32_t most) { return std::min(bits + (bits & 1), most); };
  std::unordered_map<uint64_t, uint64_t> widest, own;
  for (const auto& [code, count] : counts) {
    PackFormat f = PackFormat::ofCode(code, 0);
    f.valueBits = uint8_t(even(f.valueBits, 32 - f.shift));
    if (f.residualBits) f.residualBits = uint8_t(even(f.residualBits, kMaxResidualBits));
    f.pointerBits = uint8_t(even(f.pointerBits, kMaxPointerBits));
    if (f.symmetryMask) f.symmetryMask = f.sharedMask;
    std::array<uint8_t, kMhChildren> ownWidths{};
    for (int k = 0; k < kMhChildren; ++k)
      ownWidths[k] = uint8_t(even(f.pointerWidth[k], kMaxPointerBits));
    const auto sharedBits = uint8_t(even(f.sharedBits, kMaxPointerBits));
    f.setSharedWidths({sharedBits, sharedBits, sharedBits, sharedBits});
    const uint64_t widestCode = f.code();
    widest[widestCode] += count;
    f.setSharedWidths(ownWidths);
    if (eachSharedWidth && f.code() != widestCode) own[f.code()] += count;
  }
  struct Candidate {
    uint64_t count, code;
    bool widest;
    auto operator<=>(const Candidate&) const = default;
  };
  std::vector<Candidate> byFrequency;
  uint64_t left = 0;  // the packs of no format taken, as wide as the widest
  for (const auto& [code, count] : widest)
    byFrequency.push_back({count, code, true}), left += count;
  for (const auto& [code, count] : own) {
    const PackFormat f = PackFormat::ofCode(code, 0);
    uint64_t saved = 0;  // address bits a pack saves
    for (int k = 0; k < kMhChildren; ++k)
      if (f.sharedMask >> k & 1) saved += f.sharedBits - f.pointerWidth[k];
    if (count * saved >= kMinOwnWidthsGain) byFrequency.push_back({count, code, false});
  }
  std::sort(byFrequency.begin(), byFrequency.end(), std::greater<>());
  const size_t most = std::min<size_t>((size_t(1) << maxBits) - 1, kNoSymbol - 1);
  FormatTable table;
  std::vector<uint64_t> uses;
  for (const Candidate& candidate : byFrequency) {
    if (candidate.count < minCount || table.codes.size() == most) break;
    table.codes.push_back(candidate.code), uses.push_back(candidate.count);
    if (candidate.widest) left -= candidate.count;
  }
  if (table.codes.empty()) return {};
  uses.push_back(std::max<uint64_t>(left, 1));
  table.lengths = huffmanLengths(uses, maxBits);
  return table;
}

FormatTable refitted(const Layout& layout, uint32_t maxBits) {
  FormatTable table;
  std::vector<uint64_t> uses;
  for (size_t c = 0; c < layout.table.codes.size(); ++c)
    if (layout.uses[c] > 0)
      table.codes.push_back(layout.table.codes[c]), uses.push_back(layout.uses[c]);
  if (table.codes.empty()) return {};
  uses.push_back(std::max<uint64_t>(layout.uses.back(), 1));
  table.lengths = huffmanLengths(uses, maxBits);
  return table;
}

}  // namespace sb::delta_dag
