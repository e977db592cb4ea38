// delta-dag's layout written by hand, field by field as the README's "Byte layout" gives it, and
// read back: tables, escapes, predicted values, mirrored references, address units and narrowed
// addresses as the README says, and the loader's refusals of what no writer writes.
#include <cstdint>
#include <span>
#include <vector>

#include <catch2/catch.hpp>

#include "schemes/delta-dag/delta_dag.h"
#include "schemes/interface/serial.h"

namespace sb {
namespace {

using delta_dag::DeltaDag;

// Packs written by hand, field by field in the README's order, and the payload around them: the
// layout's version, a full root at bit `root`, the address unit, the table's entries (a format's
// code | its prefix code's length << kFormatCodeBits), its narrowed formats and the escape's code
// length.
struct HandWrittenPacks {
  std::vector<uint8_t> bytes;
  uint64_t at = 0;
  void put(uint64_t value, uint32_t bits) {
    for (uint32_t b = 0; b < bits; ++b, ++at) {
      if (at / 8 == bytes.size()) bytes.push_back(0);
      bytes[at / 8] |= uint8_t((value >> b & 1) << at % 8);
    }
  }
  ByteWriter payload(uint32_t rootKey, uint64_t root, uint8_t addressUnit,
                     const std::vector<uint64_t>& entries = {}, uint8_t escapeBits = 0,
                     const std::vector<uint32_t>& narrowed = {}) const {
    ByteWriter out;
    out.put<uint8_t>(delta_dag::kLayoutVersion);
    out.put<uint8_t>(uint8_t(MhChild::Full));
    out.put<uint32_t>(rootKey);
    out.put<uint64_t>(root);
    out.put<uint8_t>(addressUnit);
    out.put<uint64_t>(entries.size());
    for (const uint64_t entry : entries)
      for (int b = 0; b < 6; ++b) out.put<uint8_t>(uint8_t(entry >> (8 * b)));
    out.putArray(std::span<const uint32_t>(narrowed));
    out.put<uint8_t>(escapeBits);
    out.put<uint64_t>(at);
    out.put<uint64_t>(bytes.size());
    for (const uint8_t byte : bytes) out.put<uint8_t>(byte);
    return out;
  }
};

// The structure a payload holds, every byte of it read.
DeltaDag loadWhole(const ByteWriter& out, const MapInfo& map) {
  ByteReader in(out.bytes());
  DeltaDag dag = DeltaDag::load(in, map);
  in.expectEnd();
  return dag;
}

// The layout with a table, written by hand from the README: a table of one format (child 0 a
// leaf, 2-bit values) whose code is 0, the escape's 1; the root pack escapes (child 0 full, value
// 1, its pack following with no pointer), the pack below uses the table (child 0 a leaf, value 1).
TEST_CASE("a hand-written layout with a table and an escape reads as the README says",
          "[delta-dag]") {
  HandWrittenPacks packs;
  packs.put(1, 1), packs.put(0b01, 8), packs.put(2, 6), packs.put(0, 5), packs.put(0, 4),
      packs.put(1, 2);               // the root's pack
  packs.put(0, 1), packs.put(1, 2);  // the pack below
  const uint32_t rootKey = 0x3f000000;
  const uint64_t format = 0b11 | uint64_t(2) << 8;
  const ByteWriter out =
      packs.payload(rootKey, 0, 0, {format | uint64_t(1) << delta_dag::kFormatCodeBits}, 1);
  const DeltaDag dag = loadWhole(out, {8, 0, DepthMode::Closed});
  CHECK(dag.texelKey(0, 0) == rootKey + 2);
  CHECK(dag.texelKey(1, 1) == rootKey + 2);
  CHECK(dag.texelKey(3, 3) == rootKey + 1);
  CHECK(dag.texelKey(2, 0) == rootKey + 1);
  CHECK(dag.texelKey(4, 0) == rootKey);
  CHECK(dag.texelKey(7, 7) == rootKey);
}

// The README's predicted value, by hand: a 2² map whose root pack has child 0 without a value
// (the root's key) and leaves 1, 2 and 3; 4-bit values 3 and 5, and child 3 predicted with the
// 2-bit residual −1, so its key is the root's + 3 + 5 − 1. A predicted pack whose residual bits
// are 0 is not one the writer writes.
TEST_CASE("a hand-written predicted value reads as the README says", "[delta-dag]") {
  const auto packsWithResidual = [](uint32_t residualBits) {
    HandWrittenPacks packs;
    packs.put(0b11111100, 8), packs.put(4, 6), packs.put(0, 5), packs.put(1, 1),
        packs.put(residualBits, 4);                                   // the format
    packs.put(3, 4), packs.put(5, 4), packs.put(0b11, residualBits);  // values, residual
    return packs;
  };
  const uint32_t rootKey = 0x3f000000;
  const ByteWriter out = packsWithResidual(2).payload(rootKey, 0, 0);
  const DeltaDag dag = loadWhole(out, {2, 0, DepthMode::Open});
  CHECK(dag.texelKey(0, 0) == rootKey);
  CHECK(dag.texelKey(1, 0) == rootKey + 3);
  CHECK(dag.texelKey(0, 1) == rootKey + 5);
  CHECK(dag.texelKey(1, 1) == rootKey + 7);
  const ByteWriter empty = packsWithResidual(0).payload(rootKey, 0, 0);
  CHECK_THROWS_AS(loadWhole(empty, {2, 0, DepthMode::Open}), FormatError);
}

// The README's layout of a reference read turned, by hand: a shared pack A at bit 0 (explicit,
// child 0 a leaf of value 1), and the root's pack after it, both children empty and shared: A
// as stored, and A mirrored in x (symmetry 1), its leaf then the top right texel's.
TEST_CASE("a hand-written reference read mirrored reads as the README says", "[delta-dag]") {
  HandWrittenPacks packs;
  packs.put(0b11, 8), packs.put(2, 6), packs.put(0, 5), packs.put(1, 2);  // A
  const uint64_t root = packs.at;
  packs.put(0b1010, 8), packs.put(0b11, 4), packs.put(1, 1), packs.put(0b10, 4),
      packs.put(5, 6);                                // flags, masks, widths
  packs.put(0, 5), packs.put(0, 5), packs.put(1, 3);  // A; A mirrored in x
  const uint32_t rootKey = 0x3f000000;
  const ByteWriter out = packs.payload(rootKey, root, 0);
  const DeltaDag dag = loadWhole(out, {4, 0, DepthMode::Closed});
  CHECK(dag.texelKey(0, 0) == rootKey + 1);
  CHECK(dag.texelKey(1, 0) == rootKey);
  CHECK(dag.texelKey(3, 0) == rootKey + 1);
  CHECK(dag.texelKey(2, 0) == rootKey);
  CHECK(dag.texelKey(0, 1) == rootKey);
  CHECK(dag.texelKey(3, 1) == rootKey);
  CHECK(dag.texelKey(2, 3) == rootKey);
}

// The README's shared addresses in units, by hand, with units of 2^3 bits: shared packs A at bit 0
// (child 0 a leaf of value 1) and B, after 3 bits of padding, at bit 24 (child 3 a leaf of value
// 1), and the root's pack after them, both children empty and shared: A at address 0, B at 3.
TEST_CASE("a hand-written layout with addresses in 8-bit units reads as the README says",
          "[delta-dag]") {
  HandWrittenPacks packs;
  packs.put(0b11, 8), packs.put(2, 6), packs.put(0, 5), packs.put(1, 2);        // A
  packs.put(0, 3);                                                              // padding
  packs.put(0b11000000, 8), packs.put(2, 6), packs.put(0, 5), packs.put(1, 2);  // B
  const uint64_t root = packs.at;
  packs.put(0b1010, 8), packs.put(0b11, 4), packs.put(0, 1),
      packs.put(2, 6);               // flags, shared mask, not turned, width
  packs.put(0, 2), packs.put(3, 2);  // A; B at 3 units of 8 bits
  const uint32_t rootKey = 0x3f000000;
  const ByteWriter out = packs.payload(rootKey, root, 3);
  const DeltaDag dag = loadWhole(out, {4, 0, DepthMode::Closed});
  CHECK(dag.texelKey(0, 0) == rootKey + 1);
  CHECK(dag.texelKey(1, 0) == rootKey);
  CHECK(dag.texelKey(3, 1) == rootKey + 1);
  CHECK(dag.texelKey(2, 0) == rootKey);
  CHECK(dag.texelKey(2, 1) == rootKey);
  CHECK(dag.texelKey(0, 3) == rootKey);
  const ByteWriter wide = packs.payload(rootKey, root, delta_dag::kMaxAddressUnit + 1);
  CHECK_THROWS_AS(loadWhole(wide, {4, 0, DepthMode::Closed}), FormatError);
}

// The README's table format with an address width for each shared child, by hand: shared packs
// A at bit 0 and B at bit 24 as above, each escaping (code 1) to its explicit format; the root's
// pack takes the table's one format (code 0): both children empty and shared, the widest address
// 2 bits, child 0's narrowed by 1 in the narrowed formats (A at address 0 in 1 bit, B at 3 in 2).
TEST_CASE(
    "a hand-written table format with its own width for each shared address reads as the "
    "README says",
    "[delta-dag]") {
  HandWrittenPacks packs;
  packs.put(1, 1), packs.put(0b11, 8), packs.put(2, 6), packs.put(0, 5), packs.put(1, 2);  // A
  packs.put(0, 2);  // padding
  packs.put(1, 1), packs.put(0b11000000, 8), packs.put(2, 6), packs.put(0, 5),
      packs.put(1, 2);  // B
  const uint64_t root = packs.at;
  packs.put(0, 1), packs.put(0, 1), packs.put(3, 2);  // the root: its code, A, B
  const uint32_t rootKey = 0x3f000000;
  const uint64_t entry =
      0b1010 | uint64_t(2) << 25 | uint64_t(0b11) << 31 | uint64_t(1) << delta_dag::kFormatCodeBits;
  const auto load = [&](const std::vector<uint32_t>& narrowed) {
    const ByteWriter out = packs.payload(rootKey, root, 3, {entry}, 1, narrowed);
    return loadWhole(out, {4, 0, DepthMode::Closed});
  };
  const DeltaDag dag = load({1u << 16});
  CHECK(dag.texelKey(0, 0) == rootKey + 1);
  CHECK(dag.texelKey(1, 0) == rootKey);
  CHECK(dag.texelKey(3, 1) == rootKey + 1);
  CHECK(dag.texelKey(2, 0) == rootKey);
  CHECK(dag.texelKey(0, 3) == rootKey);
  // Narrowed to nothing, the address of a child that is not shared, no narrowing, a format
  // outside the table, one named twice.
  CHECK_THROWS_WITH(load({0x21u << 16}), Catch::Contains("0-bit address"));
  CHECK_THROWS_WITH(load({0x101u << 16}), Catch::Contains("not shared"));
  for (const std::vector<uint32_t>& narrowed :
       std::vector<std::vector<uint32_t>>{{0}, {1 | 1u << 16}, {1u << 16, 1u << 16}})
    CHECK_THROWS_WITH(load(narrowed), Catch::Contains("is not a narrowing"));
}

// Regression: the longest explicit header, after the longest escape code, at bit 7 of a byte.
// One read from the pack's first bit holds 57 of its 61 bits, and the residual's width was read
// from past them (the city open at 64K² misread so). A 4² map: a shared pack S at bit 0 (the
// table's one format, code 0: child 0 a leaf, 2-bit values; its value 1), 4 bits of padding, and
// the root's pack escaping (its code 1 and fifteen 0s): child 0 empty and private (P0 follows),
// child 1 full with value 3 and private (P1, 3 bits after P0), child 2 full with value 5 and
// shared (S read mirrored in x), child 3 a leaf predicted with the residual −1 (3 + 5 − 1).
TEST_CASE(
    "a hand-written escape of every field after a 16-bit escape code reads as the README "
    "says",
    "[delta-dag]") {
  HandWrittenPacks packs;
  packs.put(0, 1), packs.put(1, 2);  // S
  packs.put(0, 4);                   // padding
  const uint64_t root = packs.at;
  packs.put(1, 16), packs.put(0b11010110, 8), packs.put(4, 6), packs.put(0, 5);  // flags, values
  packs.put(0b0100, 4), packs.put(1, 1), packs.put(0b0100, 4);         // shared and turned: child 2
  packs.put(5, 6), packs.put(4, 6), packs.put(1, 1), packs.put(2, 4);  // widths, the residual's
  packs.put(3, 4), packs.put(3, 5);                                    // child 1: value, P1
  packs.put(5, 4), packs.put(0, 4), packs.put(1, 3);                   // child 2: value, S, turn
  packs.put(0b11, 2);                                                  // child 3: residual
  packs.put(0, 1), packs.put(1, 2);                                    // P0
  packs.put(0, 1), packs.put(1, 2);                                    // P1
  REQUIRE(root % 8 == 7);
  const uint32_t rootKey = 0x3f000000;
  const uint64_t entry = 0b11 | uint64_t(2) << 8 | uint64_t(1) << delta_dag::kFormatCodeBits;
  const ByteWriter out = packs.payload(rootKey, root, 0, {entry}, 16);
  const DeltaDag dag = loadWhole(out, {4, 0, DepthMode::Closed});
  const uint32_t expected[4][4] = {{1, 0, 4, 3}, {0, 0, 3, 3}, {5, 6, 7, 7}, {5, 5, 7, 7}};
  for (uint32_t j = 0; j < 4; ++j)
    for (uint32_t i = 0; i < 4; ++i) CHECK(dag.texelKey(i, j) == rootKey + expected[j][i]);
}

// Regression: four private pointers to one pack, at every level, read alike but reach it by
// 4^levels paths. The loader found every pack's height once, and then the key ranges walked every
// path below the skip table's level: 4.7 s for such a chain on a 32K² map, 4× more a level. Such
// pointers are refused; a chain of one path each, as deep, is not.
TEST_CASE("a pack reached by more paths than the packs hold is refused", "[delta-dag]") {
  constexpr int levels = 12;
  const uint32_t rootKey = 0x3f000000;
  const auto chain = [&](bool fourPaths) {
    HandWrittenPacks packs;
    for (int level = 0; level + 1 < levels; ++level)
      if (fourPaths)  // four empty children: the first follows the pack, the others 0 bits after
        packs.put(0b10101010, 8), packs.put(0, 4), packs.put(1, 6), packs.put(0, 3);
      else  // child 0 empty, following the pack
        packs.put(0b10, 8), packs.put(0, 4);
    packs.put(0b11, 8), packs.put(2, 6), packs.put(0, 5), packs.put(1, 2);  // child 0 a leaf
    return packs.payload(rootKey, 0, 0);
  };
  const ByteWriter onePath = chain(false);
  const DeltaDag dag = loadWhole(onePath, {uint32_t(1) << levels, 0, DepthMode::Closed});
  CHECK(dag.texelKey(0, 0) == rootKey + 1);
  CHECK(dag.texelKey(1, 0) == rootKey);
  const ByteWriter fourPaths = chain(true);
  CHECK_THROWS_WITH(loadWhole(fourPaths, {uint32_t(1) << levels, 0, DepthMode::Closed}),
                    Catch::Contains("more paths"));
}

}  // namespace
}  // namespace sb
