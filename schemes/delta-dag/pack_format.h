// A delta-dag pack's *format*: its flags and field widths, the places of its fields that follow
// from them, its code in the table of frequent formats and the table's stored entries (the bit
// layout is delta_dag.h's). The decoder reads a format per step and the writer fits one per pack,
// so both take it from here.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "schemes/shared/multires_hierarchy.h"

namespace sb::delta_dag {

// Field widths of a pack, from its flags.
struct PackShape {
  bool hasValues, hasInner;
  uint8_t innerMask;  // bit k: child k is inner (full or empty)
  // Where exactly three children hold values, the one opposite the fourth, which a pack may
  // predict; kMhChildren elsewhere.
  uint8_t predictable;
};
constexpr std::array<PackShape, 256> makePackShapes() {
  std::array<PackShape, 256> shapes{};
  for (uint32_t flags = 0; flags < 256; ++flags) {
    PackShape& shape = shapes[flags];
    uint8_t values = 0, valueless = 0;
    for (int k = 0; k < kMhChildren; ++k) {
      const uint32_t kind = childFlag(flags, k);
      const bool holds = kind == uint32_t(MhChild::Full) || kind == uint32_t(MhChild::Leaf);
      values += holds;
      if (!holds) valueless = uint8_t(k);
      if (kind == uint32_t(MhChild::Full) || kind == uint32_t(MhChild::Empty))
        shape.innerMask |= uint8_t(1u << k);
    }
    shape.hasValues = values != 0, shape.hasInner = shape.innerMask != 0;
    shape.predictable = uint8_t(values == 3 ? valueless ^ 3 : kMhChildren);
  }
  return shapes;
}
inline constexpr std::array<PackShape, 256> kPackShapes = makePackShapes();
inline const PackShape& packShape(uint32_t flags) {
  return kPackShapes[flags & 0xff];
}

// A format's code as a table entry stores it; in memory, each shared child's narrowing follows, 4
// bits a child, stored apart (PackFormat::narrowings): few formats narrow any.
constexpr uint32_t kFormatCodeBits = 43, kSymmetryBits = 3;
constexpr uint64_t kEntryCodeMask = (uint64_t(1) << kFormatCodeBits) - 1;
// What one unaligned 64-bit read reaches from any bit of a byte: 64 − 7 bits.
constexpr uint32_t kReadBits = 57;
// A shared child's address is at most this many bits narrower than the pack's widest: the code
// keeps the difference in 4 bits.
constexpr uint32_t kMaxNarrowing = 15;
// A predicted value's residual takes at most 15 bits (its width's field takes 4).
constexpr uint32_t kMaxResidualBits = 15;

// A pack's format: its flags, which inner children are shared, the widths, and where its fields
// lie (derived from the rest and the bits of its header).
struct PackFormat {
  uint8_t flags = 0, valueBits = 0, shift = 0, sharedMask = 0, pointerBits = 0, sharedBits = 0;
  uint8_t symmetryMask = 0, residualBits = 0;
  std::array<uint8_t, kMhChildren> pointerWidth{};  // child k's pointer field: 0 if implicit
  std::array<uint16_t, kMhChildren> fieldAt{};      // child k's first field, from the pack's start
  uint16_t bits = 0;                                // the whole pack's
  // Its name in the table: kFormatCodeBits bits, then its narrowings.
  uint64_t code() const {
    return uint64_t(flags) | uint64_t(valueBits) << 8 | uint64_t(shift) << 14 |
           uint64_t(pointerBits) << 19 | uint64_t(sharedBits) << 25 | uint64_t(sharedMask) << 31 |
           uint64_t(symmetryMask) << 35 | uint64_t(residualBits) << 39 |
           uint64_t(narrowings()) << kFormatCodeBits;
  }
  // Shared child k's address is narrower than the widest by (narrowings >> 4k) & 15 bits.
  uint32_t narrowings() const {
    uint32_t narrowings = 0;
    for (int k = 0; k < kMhChildren; ++k)
      if (sharedMask >> k & 1) narrowings |= uint32_t(sharedBits - pointerWidth[k]) << (4 * k);
    return narrowings;
  }
  static PackFormat ofCode(uint64_t code, uint32_t headerBits) {
    PackFormat f{uint8_t(code),
                 uint8_t(code >> 8 & 63),
                 uint8_t(code >> 14 & 31),
                 uint8_t(code >> 31 & 15),
                 uint8_t(code >> 19 & 63),
                 uint8_t(code >> 25 & 63),
                 uint8_t(code >> 35 & 15),
                 uint8_t(code >> 39 & 15)};
    for (int k = 0; k < kMhChildren; ++k)
      if (f.sharedMask >> k & 1)
        f.pointerWidth[k] = uint8_t(f.sharedBits - (code >> (kFormatCodeBits + 4 * k) & 15));
    f.derive(headerBits);
    return f;
  }
  // Gives each shared child k an address of widths[k] bits, but no narrower than kMaxNarrowing
  // less the widest (`sharedBits`). Where a pack's shared children are referenced unequally often,
  // their addresses differ in width (the most referenced packs lie first): one width for all took
  // 11 % of the open city's bits at 8K² (scripts/ablations/delta-dag-address-widths.sh).
  void setSharedWidths(const std::array<uint8_t, kMhChildren>& widths) {
    sharedBits = 0;
    for (int k = 0; k < kMhChildren; ++k)
      if (sharedMask >> k & 1) sharedBits = std::max(sharedBits, widths[k]);
    for (int k = 0; k < kMhChildren; ++k)
      if (sharedMask >> k & 1)
        pointerWidth[k] = uint8_t(std::max<int>(widths[k], sharedBits - int(kMaxNarrowing)));
  }
  // The shared children's address widths, a byte each (0 for the others), as the format search
  // compares them.
  uint32_t sharedWidths() const {
    uint32_t widths = 0;
    for (int k = 0; k < kMhChildren; ++k)
      if (sharedMask >> k & 1) widths |= uint32_t(pointerWidth[k]) << (8 * k);
    return widths;
  }
  // The private inner children (not shared): the first of them follows the pack and needs no
  // pointer, so the others' pointers need a width only if there are two or more.
  uint32_t privateMask() const { return packShape(flags).innerMask & ~uint32_t(sharedMask); }
  bool hasPointerWidth() const { return std::popcount(privateMask()) >= 2; }
  // A pack may take the formats of its flags and shared mask (with the symmetries it needs).
  uint32_t groupKey() const { return flags | uint32_t(sharedMask) << 8; }
  // The bits of its explicit form: flags, then the fields the flags and the mask call for. The
  // explicit form gives every shared child the widest's width.
  uint32_t explicitBits() const {
    const PackShape& shape = packShape(flags);
    return 8 + (shape.hasValues ? 11 : 0) +
           (shape.predictable < kMhChildren ? 1 + (residualBits ? 4 : 0) : 0) +
           (shape.hasInner ? 4 + (hasPointerWidth() ? 6 : 0) +
                                 (sharedMask ? 1 + (symmetryMask ? 4 : 0) + 6 : 0)
                           : 0);
  }
  // Derived from the fields above rather than kept: a step reads its format from a table of up
  // to 2^16 formats, and each byte more takes more of them out of the cache (the forest at 16K²
  // holds 47 K; its view point lookups, three runs in turn with `dag-mh`'s: 1.06–1.13× with
  // formats of 28 bytes, 0.98–1.03× with 24, 0.94–0.95× at 22 before predictions).
  uint32_t headerBits() const { return fieldAt[0]; }
  // The predicted child, kMhChildren if none.
  uint32_t predicted() const {
    return residualBits ? packShape(flags).predictable : uint32_t(kMhChildren);
  }
  // Child k's value field: 0 where it holds no value.
  uint32_t valueWidth(int k) const {
    return !hasValue(MhChild(childFlag(flags, k))) ? 0
           : uint32_t(k) == predicted()            ? residualBits
                                                   : valueBits;
  }
  // Sets the private children's pointer widths and the fields' places after a header of `header`
  // bits; the shared children's widths are set before (setSharedWidths).
  void derive(uint32_t header) {
    const uint32_t implicit = privateMask() & -privateMask();
    uint32_t at = header;
    for (int k = 0; k < kMhChildren; ++k) {
      const uint32_t child = 1u << k;
      fieldAt[k] = uint16_t(at);
      if (!(sharedMask & child))
        pointerWidth[k] = uint8_t(privateMask() & ~implicit & child ? pointerBits : 0);
      at += valueWidth(k) + pointerWidth[k] + (symmetryMask & child ? kSymmetryBits : 0);
    }
    bits = uint16_t(at);
  }
};

static_assert(sizeof(PackFormat) == 22, "a format's bytes decide how many stay in the cache");

// The table of frequent formats and their prefix code (prefix_code.h): format c's code takes
// lengths[c] bits, the escape's lengths.back(). Both empty: no table, no escape code, every
// format explicit.
struct FormatTable {
  std::vector<uint64_t> codes;   // PackFormat::code()
  std::vector<uint8_t> lengths;  // codes.size() + 1 of them, or none
};

// A table entry as stored: a format's code (less its narrowings) and its prefix code's length <<
// kFormatCodeBits, in 6 little-endian bytes.
struct FormatEntry {
  std::array<uint8_t, 6> bytes;
  static FormatEntry of(uint64_t value) {
    FormatEntry entry;
    for (size_t b = 0; b < entry.bytes.size(); ++b) entry.bytes[b] = uint8_t(value >> (8 * b));
    return entry;
  }
  uint64_t value() const {
    uint64_t value = 0;
    for (size_t b = 0; b < bytes.size(); ++b) value |= uint64_t(bytes[b]) << (8 * b);
    return value;
  }
};

static_assert(sizeof(FormatEntry) == 6);

// A table format that narrows a shared address, as stored after the entries: its index in the
// table | its narrowings << 16.
inline uint32_t narrowedFormat(uint32_t index, uint64_t code) {
  return index | uint32_t(code >> kFormatCodeBits) << 16;
}

// The bytes of a table as stored: its entries and its narrowed formats.
inline uint64_t storedBytes(const FormatTable& table) {
  uint64_t bytes = table.codes.size() * sizeof(FormatEntry);
  for (const uint64_t code : table.codes)
    if (code >> kFormatCodeBits != 0) bytes += sizeof(uint32_t);
  return bytes;
}

}  // namespace sb::delta_dag
