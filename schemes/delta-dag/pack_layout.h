// delta-dag's packs and how they are laid out as bits (delta_dag.h has the layout itself): the
// order of shared packs, the writing of each pack with its format, and the table of formats. The
// encode step (delta_dag.cpp) chooses the values and finds the packs; this file writes them.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "schemes/delta-dag/delta_dag.h"
#include "schemes/interface/splitmix.h"

namespace sb::delta_dag {

// What one read64 reaches: a pointer and a symmetry in 57 bits.
constexpr uint32_t kMaxValueBits = 32, kMaxPointerBits = kReadBits - kSymmetryBits;

inline bool isInner(uint32_t kind) {
  return MhChild(kind) == MhChild::Full || MhChild(kind) == MhChild::Empty;
}

// Bits of the two's complement form of v.
inline uint32_t signedBits(int64_t v) {
  return uint32_t(std::bit_width(uint64_t(v < 0 ? ~v : v))) + 1;
}

// The children of one inner node after the values are chosen: what hash-consing compares.
struct Pack {
  uint8_t flags = 0;
  std::array<int32_t, kMhChildren> values{};       // key delta of a child holding a value
  std::array<uint32_t, kMhChildren> children{};    // pack of an inner child
  std::array<Symmetry, kMhChildren> symmetries{};  // and the symmetry it is read under

  auto operator<=>(const Pack&) const = default;
  uint64_t hash() const {
    uint64_t h = mixBits(flags);
    for (int k = 0; k < kMhChildren; ++k)
      h = mixBits(h ^ (uint64_t(uint32_t(values[k])) << 32 | children[k]) ^
                  uint64_t(symmetries[k]) << 61);
    return h;
  }
};

// The fields of a pack's values: one shift for all, and one width for all, or (`residualBits`
// not 0) one for the two neighbours of the predicted child and one for its residual (delta_dag.h).
struct ValueFields {
  uint8_t shift = 0, valueBits = 0, residualBits = 0;
  uint32_t bits = 0;  // of all its values' fields
};
// The residual of the value that `pack` may predict (PackShape::predictable), its values shifted
// right by `shift`: the value less its two neighbours'.
int64_t predictionResidual(const Pack& pack, uint32_t shift);
// The value fields of fewest bits for `pack`: its values' common trailing zeros as the shift, and
// with `prediction` the predicted form where it takes 4 bits fewer or more.
ValueFields fittedValues(const Pack& pack, bool prediction);

// Appends fields of up to 57 bits to a little-endian bit stream. A value wider than its field is
// refused (std::logic_error): written, it would keep only its low bits and be read as another, a
// pointer as another pack's position.
class BitWriter {
 public:
  uint64_t position() const { return bits_; }
  void put(uint64_t value, uint32_t bits) {
    if (uint32_t(std::bit_width(value)) > bits) refuseNarrowField(bits);
    append(value, bits);
  }
  // In two's complement.
  void putSigned(int64_t value, uint32_t bits) {
    if (signedBits(value) > bits) refuseNarrowField(bits);
    append(uint64_t(value) & ((uint64_t(1) << bits) - 1), bits);
  }
  // The bytes of the stream, then 8 bytes of padding (DeltaDag::read64 reads past the end).
  std::vector<uint8_t> release() const {
    std::vector<uint8_t> bytes((bits_ + 7) / 8 + 8, 0);
    for (uint64_t b = 0; b < (bits_ + 7) / 8; ++b)
      bytes[b] = uint8_t(words_[b >> 3] >> (8 * (b & 7)));
    return bytes;
  }

 private:
  [[noreturn]] void refuseNarrowField(uint32_t bits) const;
  void append(uint64_t value, uint32_t bits) {
    if (bits == 0) return;
    const uint32_t offset = uint32_t(bits_ & 63);
    words_.resize((bits_ + bits + 63) / 64, 0);
    words_[bits_ >> 6] |= value << offset;
    if (offset + bits > 64) words_[(bits_ >> 6) + 1] |= value >> (64 - offset);
    bits_ += bits;
  }
  std::vector<uint64_t> words_;
  uint64_t bits_ = 0;
};

// The packs laid out as private trees, each pack before the private trees of its children, the
// first of which follows it with no pointer (delta_dag.h). A layout is counted first: each pack's
// format and private tree measured, each shared pack placed, its bits known. Only the layout kept
// is then written, as it was counted.
struct Layout {
  uint32_t addressUnit = 0;  // shared addresses count 2^addressUnit bits
  FormatTable table;
  uint64_t bitCount = 0;
  uint64_t rootPosition = 0;
  std::vector<uint64_t> sharedPositions;  // where each shared pack lies, in layout order
  std::vector<uint64_t> ownCodes;         // without a table: each pack's own format's code
  std::vector<uint64_t> uses;             // packs per table format, then escapes
  // Each pack's table format (-1: its own, explicit) and the bits of its private tree: what
  // writing takes from the count, so that it neither searches the table nor measures again.
  std::vector<int32_t> chosen;
  std::vector<uint64_t> treeBits;
  // Written:
  BitWriter out;
  uint64_t escapes = 0, headerBits = 0, valueBits = 0, pointerBits = 0, symmetryBits = 0,
           paddingBits = 0;
  uint64_t bits() const { return bitCount; }
  // The bits of the packs, the table and the decode table a load derives from it.
  uint64_t cost() const;
};

// The order shared packs are laid out in: the most referenced first (`byReferences`) or the first
// found (the lowest id), each once the shared packs its private tree references are placed.
std::vector<uint32_t> sharedOrder(const std::vector<Pack>& packs,
                                  const std::vector<uint32_t>& references, bool byReferences);
// The address unit (log2 of its bits, at most `maxUnit`) whose addresses and padding take the
// fewest bits, for shared packs whose private trees would start at `positions` (in bits, in layout
// order, unpadded) and are referenced `references` times: a unit of 2^u bits takes u bits off each
// reference's address and pads each private tree by 2^u − 1 bits at most, (2^u − 1) / 2 on average.
uint32_t cheapestAddressUnit(const std::vector<uint64_t>& positions,
                             const std::vector<uint32_t>& references, uint32_t maxUnit);
// Counts the layout of the packs of the DAG under `rootPack`; `absolute`: the packs pointed to by
// address, whose private trees are laid out first in the order `shared`, each from a multiple of
// 2^addressUnit bits; the formats of `table`. `prediction`: packs may predict a value
// (fittedValues).
Layout countLayout(const std::vector<Pack>& packs, uint32_t rootPack,
                   const std::vector<bool>& absolute, const std::vector<uint32_t>& shared,
                   uint32_t addressUnit, bool prediction, FormatTable table);
// Writes a counted layout (the same packs and arguments) into layout.out: each pack at the place
// and in the format its count found.
void writeLayout(const std::vector<Pack>& packs, uint32_t rootPack,
                 const std::vector<bool>& absolute, const std::vector<uint32_t>& shared,
                 bool prediction, Layout& layout);
// A table of the formats that `ownCodes` (each pack's format code) hold at least `minCount` times
// (the most frequent 2^maxBits − 1, fewer than kNoSymbol), with Huffman codes of at most maxBits
// by count, the escape's by the packs left out. `eachSharedWidth`: a format may give each shared
// child its own address width; false: all the widest's.
FormatTable frequentFormats(std::vector<uint64_t> ownCodes, uint64_t minCount, uint32_t maxBits,
                            bool eachSharedWidth);
// The table a layout used, less its unused formats, with codes fitted to its uses.
FormatTable refitted(const Layout& layout, uint32_t maxBits);

}  // namespace sb::delta_dag
