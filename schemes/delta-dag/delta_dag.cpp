#include "schemes/delta-dag/delta_dag.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <limits>
#include <unordered_map>

#include "schemes/interface/splitmix.h"
#include "schemes/shared/hash_cons.h"
#include "schemes/shared/mh_parts.h"

namespace sb::delta_dag {
namespace {

constexpr uint32_t kNoPack = UINT32_MAX;
constexpr uint32_t kMaxValueBits = 32, kMaxPointerBits = 57;  // what read64 reaches

std::array<PackShape, 256> makePackShapes() {
  std::array<PackShape, 256> shapes{};
  for (uint32_t flags = 0; flags < 256; ++flags) {
    PackShape& shape = shapes[flags];
    uint8_t values = 0, inner = 0;
    for (int k = 0; k < kMhChildren; ++k) {
      shape.valuesBefore[k] = values, shape.innerBefore[k] = inner;
      const MhChild kind = MhChild(childFlag(flags, k));
      values += hasValue(kind);
      inner += kind == MhChild::Full || kind == MhChild::Empty;
    }
    shape.hasValues = values != 0, shape.hasInner = inner != 0;
    shape.headerBits = uint8_t(8 + (shape.hasValues ? 11 : 0) + (shape.hasInner ? 6 : 0));
  }
  return shapes;
}

// Bits of the two's complement form of v.
uint32_t signedBits(int64_t v) {
  return uint32_t(std::bit_width(uint64_t(v < 0 ? ~v : v))) + 1;
}

// The children of one inner node after the values are chosen: what hash-consing compares.
struct Pack {
  uint8_t flags = 0;
  std::array<int32_t, kMhChildren> values{};     // key delta of a child holding a value
  std::array<uint32_t, kMhChildren> children{};  // pack of an inner child

  bool operator==(const Pack&) const = default;
  uint64_t hash() const {
    uint64_t h = mixBits(flags);
    for (int k = 0; k < kMhChildren; ++k)
      h = mixBits(h ^ (uint64_t(uint32_t(values[k])) << 32 | children[k]));
    return h;
  }
};

// Appends fields of up to 57 bits to a little-endian bit stream.
class BitWriter {
 public:
  uint64_t position() const { return bits_; }
  void put(uint64_t value, uint32_t bits) {
    if (bits == 0) return;
    value &= (uint64_t(1) << bits) - 1;
    const uint32_t offset = uint32_t(bits_ & 63);
    words_.resize((bits_ + bits + 63) / 64, 0);
    words_[bits_ >> 6] |= value << offset;
    if (offset + bits > 64) words_[(bits_ >> 6) + 1] |= value >> (64 - offset);
    bits_ += bits;
  }
  // The bytes of the stream, then 8 bytes of padding (DeltaDag::read64 reads past the end).
  std::vector<uint8_t> release() const {
    std::vector<uint8_t> bytes((bits_ + 7) / 8 + 8, 0);
    for (uint64_t b = 0; b < (bits_ + 7) / 8; ++b)
      bytes[b] = uint8_t(words_[b >> 3] >> (8 * (b & 7)));
    return bytes;
  }

 private:
  std::vector<uint64_t> words_;
  uint64_t bits_ = 0;
};

// The relative value of a node holding interval [lo, hi] below a path that reconstructs `parent`.
int32_t chooseValue(const KeyInterval& interval, uint32_t parent, ValueChoice choice) {
  const int64_t lo = int64_t(interval.lo) - parent, hi = int64_t(interval.hi) - parent;
  const int64_t value =
      choice == ValueChoice::Simplest ? simplestIn(lo, hi) : int64_t(interval.middle()) - parent;
  return int32_t(value);  // keys are at most +inf's, 0x7f800000: differences fit int32
}

}  // namespace

int64_t simplestIn(int64_t lo, int64_t hi) {
  if (lo <= 0 && hi >= 0) return 0;
  if (hi < 0) return -simplestIn(-hi, -lo);
  // lo - 1 and hi agree above their highest differing bit t, where hi has a 1: clearing hi's bits
  // below t gives a multiple of 2^t in [lo, hi], and no multiple of 2^(t+1) lies there.
  const uint64_t t = std::bit_width(uint64_t(lo - 1) ^ uint64_t(hi)) - 1;
  return int64_t(uint64_t(hi) & ~((uint64_t(1) << t) - 1));
}

const PackShape& packShape(uint32_t flags) {
  static const std::array<PackShape, 256> shapes = makePackShapes();
  return shapes[flags & 0xff];
}

DeltaDag::DeltaDag(int levels, MhChild rootKind, uint32_t rootKey, uint64_t rootPosition,
                   std::vector<uint8_t> bytes, uint64_t bits)
    : levels_(levels),
      rootKind_(rootKind),
      rootKey_(rootKey),
      rootPosition_(rootPosition),
      bytes_(std::move(bytes)),
      bits_(bits) {}

SizeBreakdown DeltaDag::size() const {
  // The root's kind, key and position, and the packs' bits (whole bytes; the padding is not
  // part of the structure).
  return {{"root", 1 + 4 + 8}, {"packs", (bits_ + 7) / 8}};
}

void DeltaDag::save(ByteWriter& out) const {
  out.put<uint8_t>(uint8_t(rootKind_));
  out.put<uint32_t>(rootKey_);
  out.put<uint64_t>(rootPosition_);
  out.put<uint64_t>(bits_);
  out.putArray(std::span<const uint8_t>(bytes_.data(), (bits_ + 7) / 8));
}

DeltaDag DeltaDag::load(ByteReader& in, const MapInfo& map) {
  if (map.resolution == 0 || !std::has_single_bit(map.resolution))
    throw FormatError(
        fmt::format("delta-dag: resolution {} is not a power of two", map.resolution));
  const int levels = std::countr_zero(map.resolution);
  const auto rootKind = MhChild(in.get<uint8_t>("root kind"));
  if (rootKind != MhChild::Leaf && rootKind != MhChild::Full)
    throw FormatError(fmt::format("delta-dag: root kind {} is neither leaf (3) nor full (1)",
                                  uint32_t(rootKind)));
  if (rootKind == MhChild::Full && levels == 0)
    throw FormatError("delta-dag: a 1² map's root has no children");
  const uint32_t rootKey = in.get<uint32_t>("root key");
  if (rootKey > 0x7f800000u)
    throw FormatError(fmt::format("delta-dag: root key {:#x} is not a depth", rootKey));
  const uint64_t rootPosition = in.get<uint64_t>("root position");
  const uint64_t bits = in.get<uint64_t>("bit count");
  if (bits > uint64_t(in.remaining()) * 8) throw FormatError("delta-dag: packs truncated");
  const uint64_t byteCount = (bits + 7) / 8;
  std::vector<uint8_t> bytes = in.getArray<uint8_t>("packs", byteCount);
  bytes.resize(byteCount + 8, 0);
  if (bits % 8 != 0 && (bytes[byteCount - 1] >> (bits % 8)) != 0)
    throw FormatError("delta-dag: bits past the last pack are set");
  if (rootKind == MhChild::Leaf && (rootPosition != 0 || bits != 0))
    throw FormatError("delta-dag: a leaf root with packs");
  DeltaDag dag(levels, rootKind, rootKey, rootPosition, std::move(bytes), bits);
  if (rootKind == MhChild::Leaf) return dag;

  // Each pack's height (levels of packs from it down, itself included) once: a pack reached at
  // level l needs height ≤ levels − l. The budget bounds the recursion by the levels, however
  // the pointers chain.
  std::unordered_map<uint64_t, int> heights;
  const auto fail = [](uint64_t position, const std::string& what) {
    return FormatError(fmt::format("delta-dag: the pack at bit {} {}", position, what));
  };
  const auto height = [&](auto& self, uint64_t position, int budget) -> int {
    if (const auto found = heights.find(position); found != heights.end()) {
      if (found->second > budget) throw fail(position, "lies below the texel level");
      return found->second;
    }
    if (budget < 1) throw fail(position, "lies below the texel level");
    if (position >= bits || bits - position < 8) throw fail(position, "lies outside the packs");
    const uint64_t word = dag.read64(position);
    const uint32_t flags = uint32_t(word & 0xff);
    if (flags == 0) throw fail(position, "has no children");
    const PackShape& shape = packShape(flags);
    const Fields f = fields(word, shape);
    if (shape.hasValues &&
        (f.valueBits == 0 || f.valueBits > kMaxValueBits || f.valueBits + f.shift > 32))
      throw fail(position, fmt::format("has {}-bit values shifted by {}", f.valueBits, f.shift));
    if (shape.hasInner && (f.pointerBits == 0 || f.pointerBits > kMaxPointerBits))
      throw fail(position, fmt::format("has {}-bit pointers", f.pointerBits));
    uint64_t at = position + shape.headerBits;
    int below = 0;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(flags, k));
      if (kind == MhChild::None) continue;
      const uint64_t fieldBits =
          (hasValue(kind) ? f.valueBits : 0) + (kind != MhChild::Leaf ? f.pointerBits : 0);
      if (at > bits || bits - at < fieldBits) throw fail(position, "runs past the packs");
      if (hasValue(kind)) {
        if (dag.readSigned(at, f.valueBits) == 0) throw fail(position, "holds a value of 0");
        at += f.valueBits;
      }
      if (kind != MhChild::Leaf) {
        const uint64_t pointer = dag.readUnsigned(at, f.pointerBits);
        at += f.pointerBits;
        if (pointer == 0 || pointer > position)
          throw fail(position, fmt::format("points {} bits back", pointer));
        below = std::max(below, self(self, position - pointer, budget - 1));
      }
    }
    heights.emplace(position, below + 1);
    return below + 1;
  };
  height(height, rootPosition, levels);
  return dag;
}

Encoded encode(MultiresHierarchy hierarchy, const Options& options) {
  const std::vector<MhNode>& nodes = hierarchy.nodes;
  Statistics stats;

  // Top-down: each value relative to the key its parent's path reconstructs.
  std::vector<uint32_t> keys(nodes.size());
  std::vector<int32_t> values(nodes.size(), 0);
  const uint32_t root = hierarchy.root();
  keys[root] = uint32_t(chooseValue(nodes[root].interval, 0, options.values));
  for (uint32_t n = root + 1; n-- > 0;) {
    const MhNode& node = nodes[n];
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = node.child(k);
      if (kind == MhChild::None) continue;
      keys[child] = keys[n];
      if (hasValue(kind)) {
        values[child] = chooseValue(nodes[child].interval, keys[n], options.values);
        keys[child] += uint32_t(values[child]);
      }
      ++child;
    }
  }
  const uint32_t rootKey = keys[root];
  keys = {};

  // Bottom-up: each inner node's pack, found among those stored or stored. A child whose value is
  // 0 (its interval held its parent's key) needs none: a leaf becomes nothing, a full node empty.
  // An inner child left without a pack is then a leaf or nothing.
  std::vector<uint32_t> packOf(nodes.size(), kNoPack);
  std::vector<Pack> packs;
  HashConsIndex index;
  for (uint32_t n = 0; n < nodes.size(); ++n) {
    const MhNode& node = nodes[n];
    if (!node.hasChildren()) continue;
    Pack pack;
    uint32_t child = node.firstChild;
    for (int k = 0; k < kMhChildren; ++k) {
      MhChild kind = node.child(k);
      if (kind == MhChild::None) continue;
      if (hasValue(kind)) {
        ++stats.valuedNodes;
        if (values[child] == 0) {
          ++stats.demotedNodes;
          kind = kind == MhChild::Leaf ? MhChild::None : MhChild::Empty;
        }
      }
      if (kind == MhChild::Full || kind == MhChild::Empty) {
        if (packOf[child] == kNoPack)
          kind = kind == MhChild::Full ? MhChild::Leaf : MhChild::None;
        else
          pack.children[k] = packOf[child];
      }
      if (hasValue(kind)) pack.values[k] = values[child];
      pack.flags |= uint8_t(uint32_t(kind) << (2 * k));
      ++child;
    }
    if (pack.flags == 0) continue;
    ++stats.treePacks;
    const auto [id, added] =
        options.sharing
            ? index.findOrAdd(pack.hash(), [&](uint32_t other) { return packs[other] == pack; })
            : std::pair{uint32_t(packs.size()), true};
    if (added) packs.push_back(pack);
    packOf[n] = id;
  }
  stats.dagPacks = packs.size();
  ++stats.valuedNodes;  // the root
  const uint32_t rootPack = packOf[root];
  values = {}, packOf = {};

  // Children first, each pack once: every pointer reaches back, to a pack already placed. A
  // pack's widths are known when it is written, since all it points to lies behind it.
  BitWriter out;
  std::vector<uint64_t> placed(packs.size(), UINT64_MAX);
  const auto place = [&](auto& self, uint32_t id) -> void {
    const Pack& pack = packs[id];
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(pack.flags, k));
      if ((kind == MhChild::Full || kind == MhChild::Empty) &&
          placed[pack.children[k]] == UINT64_MAX)
        self(self, pack.children[k]);
    }
    const uint64_t position = out.position();
    placed[id] = position;
    const PackShape& shape = packShape(pack.flags);
    uint32_t shift = 32, valueBits = 0, pointerBits = 0;
    for (int k = 0; k < kMhChildren; ++k)
      if (hasValue(MhChild(childFlag(pack.flags, k))))
        shift = std::min<uint32_t>(shift, std::countr_zero(uint32_t(pack.values[k])));
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(pack.flags, k));
      if (hasValue(kind)) valueBits = std::max(valueBits, signedBits(pack.values[k] >> shift));
      if (kind == MhChild::Full || kind == MhChild::Empty)
        pointerBits = std::max<uint32_t>(
            pointerBits, uint32_t(std::bit_width(position - placed[pack.children[k]])));
    }
    if (pointerBits > kMaxPointerBits)
      throw std::length_error("delta-dag: a pointer needs more than 57 bits");
    out.put(pack.flags, 8);
    if (shape.hasValues) out.put(valueBits, 6), out.put(shift, 5);
    if (shape.hasInner) out.put(pointerBits, 6);
    stats.headerBits += shape.headerBits;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(pack.flags, k));
      if (hasValue(kind)) {
        out.put(uint64_t(int64_t(pack.values[k] >> shift)), valueBits);
        stats.valueBits += valueBits;
      }
      if (kind == MhChild::Full || kind == MhChild::Empty) {
        out.put(position - placed[pack.children[k]], pointerBits);
        stats.pointerBits += pointerBits;
      }
    }
  };
  if (rootPack == kNoPack)
    return {DeltaDag(hierarchy.levels, MhChild::Leaf, rootKey, 0, std::vector<uint8_t>(8, 0), 0),
            stats};
  place(place, rootPack);
  const uint64_t bits = out.position();
  return {DeltaDag(hierarchy.levels, MhChild::Full, rootKey, placed[rootPack], out.release(), bits),
          stats};
}

}  // namespace sb::delta_dag
