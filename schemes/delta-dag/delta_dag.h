// delta-dag — the multiresolution hierarchy (SBE16a) as a DAG of sibling packs whose values are
// relative to the parent (SBE16b's idea), chosen so that equal subtrees become equal bit for bit
// and are shared across the whole map by hash-consing (as DAG-MH shares topology, Scandolo &
// Eisemann 2021 §3.1), and stored with bit widths fitted to each pack (SSVDAG's variable pointer
// widths, Villanueva et al. 2017).
//
// A pack is the four children of one inner node. Its header is its *format*: its flags and field
// widths. The structure keeps a table of the frequent formats, each with a prefix code by its
// frequency (Huffman's), and a pack begins with its format's code, or with the escape's code and
// then its format explicitly. Bit layout, little-endian bit order:
//   format code  1 to 16 bits (none where the table is empty)
//   and after the escape's:
//   flags        8 bits   the kind of child k in bits 2k, 2k+1 (MhChild: none, full, empty, leaf)
//   value bits   6 bits   } only if some child holds a value (full or leaf): the width of each
//   shift        5 bits   } value field, and the shift applied to every value of the pack
//   shared mask  4 bits   only if some child is inner (full or empty): bit k, child k's pack is
//                         shared (referenced by more than one pack)
//   turned       1 bit    only if some child is shared: 1 if some shared child is read turned
//   symmetry mask 4 bits  only if turned: bit k, child k's reference carries a symmetry
//   pointer bits 6 bits   if two or more inner children are private (not shared): the width of
//                         the pointer of each private child but the first
//   shared bits  6 bits   if one is shared: the width of every shared child's address
//   predicted    1 bit    only if exactly three children hold values: 1 if one is predicted
//   residual bits 4 bits  only if predicted: the width of the predicted value's field (below)
//   then, child by child in k order: its value (signed, value bits) if it holds one, then its
//   pointer if it is inner: a shared child's address, or a private child's distance after the
//   pack's end (none for the first private child, which starts there), then the 3-bit symmetry
//   (square_symmetry.h) of a shared child whose symmetry-mask bit is set.
// A shared child's address counts units of 2^u bits, u chosen per structure (0 to
// kMaxAddressUnit): each shared pack's private tree starts at a multiple of the unit, padded with
// zeros, so every reference to it is u bits shorter. A table format may give each shared child
// an address of its own width, up to 15 bits narrower than its widest (the most referenced packs
// lie first, so a pack's shared children's addresses often differ in width); an explicit format
// gives them all the widest's.
// A value v adds v << shift to the depth key its parent's path reconstructs (wrapping uint32, as
// MMH's key deltas). Where three children hold values and residual bits is not 0, the fourth child
// holds its parent's key (a delta of 0), and the child opposite it (k ^ 3) is *predicted*: its
// field holds r, and its value is r plus its two neighbours' values (children k ^ 1 and k ^ 2), the
// plane through the three others. On a plane the keys of a square's corners k0 + k3 = k1 + k2
// to an ulp or two, so a residual of 1 or 2 bits replaces the widest of the three values. Packs of
// a few formats dominate (leaves of one width under a node of one pointer width), so a code of a
// few bits replaces a header of up to 40 (SSVDAG's point, Villanueva et al. 2017: spend bits by
// frequency).
//
// A pack referenced once is private to its parent. A pack and its private children's trees, in k
// order, make its *private tree*, laid out in one piece, the pack first: the first private child
// follows its parent (no pointer, and a walk reads on in the same cache line), the others lie a
// short distance after it. Shared packs' private trees come first, the most referenced earliest
// (as far as their own shared children let them: each is placed before a pack points to it), so
// the addresses referenced most often are the smallest: SSVDAG's pointers by reference frequency.
// The root's private tree comes last.
//
// Packs equal under one of the square's 8 symmetries (mirrorings in x and y, transposition) are
// one pack (SSVDAG's symmetry-aware merging, Villanueva et al. 2017 §4): a pack is stored in the
// orientation that reads smallest, and a reference to a shared pack names the symmetry it is read
// under; a private pack is stored already turned the way its parent reads it, so a reference
// costs its 3 bits only where a shared pack is read turned. A walk carries one symmetry, the
// composition of those on its path, and turns each child index by it.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "schemes/delta-dag/pack_format.h"
#include "schemes/delta-dag/square_symmetry.h"
#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "schemes/shared/hash_cons.h"
#include "schemes/shared/multires_hierarchy.h"

namespace sb::delta_dag {

// How each stored value is chosen inside its interval, relative to its parent's key.
enum class ValueChoice : uint8_t {
  // The number with the most trailing zero bits in the relative interval, 0 where the interval
  // holds the parent's key: few significant bits, and the same number for every subtree whose
  // relative intervals overlap enough, so that hash-consing finds them equal.
  Simplest,
  // The interval's middle key, as MH and MMH store it: the ablation's baseline.
  Middle,
};

// The bytes the skip table may take by default (DeltaDag::skipLevelFor): 1 MiB.
constexpr uint64_t kDefaultSkipBudget = uint64_t(1) << 20;

// Each direction can be switched off, so that its effect is measured alone (the ablation).
struct Options {
  ValueChoice values = ValueChoice::Simplest;
  bool sharing = true;       // hash-cons equal packs; false stores the tree
  bool byReferences = true;  // shared packs laid out the most referenced first; false: as found
  bool formatTable = true;   // a table of frequent formats; false: every format explicit
  bool symmetry = true;      // packs equal under a mirroring or transposition are one pack
  bool copies = true;        // shared packs smaller than the addresses they save are copied
  bool addressUnits = true;  // shared addresses in the unit that takes fewest bits; false: bits
  bool prediction = true;    // a pack's value opposite its valueless child predicted from a plane
  bool sharedWidths = true;  // a table format gives each shared child its own address width
  uint64_t skipBudget = kDefaultSkipBudget;  // bytes the skip table may take (skipLevelFor)
};

// The widest unit of a shared address: 2^5 bits.
constexpr uint32_t kMaxAddressUnit = 5;

// The number a ValueChoice::Simplest value takes in [lo, hi] (lo ≤ hi): 0 if the interval holds
// 0, else the unique number with the most trailing zero bits.
int64_t simplestIn(int64_t lo, int64_t hi);

// A saved structure begins with its layout's version: 3 since a shared child's address width of
// its own, 2 since predicted values. (Layout 1 began with the root's kind.)
constexpr uint8_t kLayoutVersion = 3;

// The key of +inf, the greatest a depth takes: keys up to it are in depth order.
inline constexpr uint32_t kInfinityKey = 0x7f800000;

class DeltaDag {
 public:
  // Where a walk stands: the pack of an inner node at bit `position` (none for a leaf), read under
  // `symmetry`, and the key its path gives.
  struct Walk {
    uint64_t position;
    uint32_t key;
    MhChild kind;
    Symmetry symmetry;
    uint8_t level;
  };

  // A walk at the skip level as the table keeps it: its key, then its place, 1 + its pack's
  // position × 8 + its symmetry, or 0 for a walk that ended above the level (a missing child's
  // square takes the key as a leaf's does), so that neither the kind nor the level takes bits.
  // The place takes one word where the packs hold fewer than 2^29 bits (64 MiB: every closed
  // cell built up to 64K²), two above: entries of 8 or 12 bytes.
  static uint32_t skipEntryWords(uint64_t packBits) { return packBits < (1u << 29) ? 2 : 3; }
  static void putSkipEntry(uint32_t* entry, uint32_t words, const Walk& walk, int skipLevel) {
    const uint64_t place = walk.kind == MhChild::Leaf || walk.level < skipLevel
                               ? 0
                               : 1 + (walk.position << 3 | walk.symmetry);
    entry[0] = walk.key;
    entry[1] = uint32_t(place);
    if (words == 3) entry[2] = uint32_t(place >> 32);
  }
  static Walk skipEntryWalk(const uint32_t* entry, uint32_t words, int skipLevel) {
    const uint64_t place = words == 2 ? entry[1] : entry[1] | uint64_t(entry[2]) << 32;
    return {(place - 1) >> 3, entry[0], place == 0 ? MhChild::Leaf : MhChild::Full,
            Symmetry((place - 1) & 7), uint8_t(skipLevel)};
  }

  DeltaDag() = default;
  // Without its lookup tables: a lookup needs buildLookupTables first.
  DeltaDag(int levels, MhChild rootKind, uint32_t rootKey, uint64_t rootPosition,
           uint32_t addressUnit, FormatTable table, std::vector<uint8_t> bytes, uint64_t bits);

  uint32_t resolution() const { return uint32_t(1) << levels_; }
  int levels() const { return levels_; }
  uint64_t bits() const { return bits_; }

  Walk rootWalk() const { return {rootPosition_, rootKey_, rootKind_, kIdentity, 0}; }

  // One step of a walk to child k of its inner node; false where that child is missing (its
  // square is answered by the walk's key).
  bool step(Walk& walk, int k) const {
    const uint64_t word = read64(walk.position);
    const uint32_t symbol = decode_[word & codeMask_];
    return symbol < formatCount_ ? step(formats_[symbol], walk, k)
                                 : step(explicitFormatAt(walk.position), walk, k);
  }

  // Where a walk to texel (i, j) stands at the skip level (a leaf where it ended above it).
  Walk skipWalk(uint32_t i, uint32_t j) const {
    const uint32_t shift = uint32_t(levels_ - skipLevel_);
    const size_t square = (size_t(j >> shift) << skipLevel_) + (i >> shift);
    return skipEntryWalk(&skip_[square * skipEntryWords_], skipEntryWords_, skipLevel_);
  }

  uint32_t texelKey(uint32_t i, uint32_t j) const {
    Walk walk = skipWalk(i, j);
    while (walk.kind != MhChild::Leaf && step(walk, mhChildIndex(i, j, levels_ - walk.level - 1))) {
    }
    return walk.key;
  }

  // The least and greatest key of the texels of one square of the key-range table, one level
  // above the skip table's: a kernel whose keys there all give one answer needs no walk. Not
  // known (greatest above +inf's key) where a path's deltas leave the depths' keys, which only a
  // crafted structure's do.
  struct KeyRange {
    uint32_t least, greatest;
    bool known() const { return greatest <= kInfinityKey; }
  };
  KeyRange keyRange(uint32_t i, uint32_t j) const {
    const int level = keyRangeLevel();
    const uint32_t shift = uint32_t(levels_ - level);
    return keyRanges_[(size_t(j >> shift) << level) + (i >> shift)];
  }
  int keyRangeLevel() const { return std::max(skipLevel_ - 1, 0); }

  // The keys of the texels of `rect` in one walk (issue 13): down to the lowest node holding the
  // whole rectangle, then level by level into each child it overlaps; a missing child or a leaf
  // gives its whole overlap one key: visit(key, texels) once for it. A rectangle across the edge of
  // a skip-table square (a 9×9 kernel, 6 % of them where the squares are 256 texels wide) is walked
  // from each of the at most 4 squares it overlaps, rather than from the node above them all. Where
  // `settles(range)` says that every key of its square's known range answers alike, such a part
  // is visited once, with the least key, and not walked.
  template <class Settles, class Visit>
  void forEachKeyBlock(const TexelRect& rect, Settles&& settles, Visit&& visit) const {
    const uint32_t shift = uint32_t(levels_ - skipLevel_);
    const uint32_t x0 = rect.i0 >> shift, x1 = rect.i1 >> shift;
    const uint32_t y0 = rect.j0 >> shift, y1 = rect.j1 >> shift;
    if (uint64_t(x1 - x0 + 1) * (y1 - y0 + 1) > 4) return keyBlocksFrom(rootWalk(), rect, visit);
    const uint32_t side = uint32_t(1) << shift;
    for (uint32_t y = y0; y <= y1; ++y)
      for (uint32_t x = x0; x <= x1; ++x) {
        const TexelRect part{std::max(rect.i0, x << shift), std::max(rect.j0, y << shift),
                             std::min(rect.i1, (x << shift) + (side - 1)),
                             std::min(rect.j1, (y << shift) + (side - 1))};
        if (const KeyRange range = keyRange(part.i0, part.j0); range.known() && settles(range))
          visit(range.least, part.texels());
        else
          keyBlocksFrom(skipWalk(part.i0, part.j0), part, visit);
      }
  }
  template <class Visit>
  void forEachKeyBlock(const TexelRect& rect, Visit&& visit) const {
    forEachKeyBlock(
        rect, [](const KeyRange&) { return false; }, visit);
  }

  // The skip table's level for packs of `packBits` bits: the deepest whose table takes at most
  // `budget` bytes and 1/5 of the packs' bytes, or 1/32 of them where that is more
  // (buildSkipTable).
  static int skipLevelFor(uint64_t packBits, int levels, uint64_t budget = kDefaultSkipBudget);
  int skipLevel() const { return skipLevel_; }
  // The skip table's squares whose walk ended above its level: a lookup there reads only the entry.
  uint64_t skipSquaresAnsweredAbove() const;

  SizeBreakdown size() const;
  void save(ByteWriter& out) const;
  // Validates every pack reachable from the root: fields inside the structure, widths the writer
  // uses, no value of 0, children only above the texel level (so no cycle). Throws FormatError.
  // The skip table takes at most `skipBudget` bytes (skipLevelFor).
  static DeltaDag load(ByteReader& in, const MapInfo& map,
                       uint64_t skipBudget = kDefaultSkipBudget);

  // The skip table within `skipBudget` bytes (skipLevelFor), then the key ranges: both derived
  // from the packs.
  void buildLookupTables(uint64_t skipBudget) {
    buildSkipTable(skipBudget);
    buildKeyRanges();
  }

 private:
  // `rect`'s keys from a walk standing above it.
  template <class Visit>
  void keyBlocksFrom(Walk walk, const TexelRect& rect, Visit& visit) const {
    const int common = levels_ - std::bit_width((rect.i0 ^ rect.i1) | (rect.j0 ^ rect.j1));
    while (walk.kind != MhChild::Leaf && walk.level < common)
      if (!step(walk, mhChildIndex(rect.i0, rect.j0, levels_ - walk.level - 1)))
        return visit(walk.key, rect.texels());
    if (walk.kind == MhChild::Leaf) return visit(walk.key, rect.texels());
    const uint32_t corner = ~((uint32_t(1) << (levels_ - walk.level)) - 1);
    walkRect(walk, rect.i0 & corner, rect.j0 & corner, rect, visit);
  }

  // A step with the format of the walk's pack, to the child the walk's symmetry turns k into.
  bool step(const PackFormat& f, Walk& walk, int k) const {
    const uint32_t s = kSymmetry.apply[walk.symmetry][k];
    const MhChild child = MhChild(childFlag(f.flags, s));
    if (child == MhChild::None) return false;
    const uint64_t at = walk.position + f.fieldAt[s];
    // One read holds the value, the pointer and the symmetry where they fit 57 bits together.
    uint32_t valueBits = f.valueBits;
    const uint32_t pointerBits = f.pointerWidth[s];
    uint64_t field = read64(at);
    if (hasValue(child)) {
      uint32_t value;
      if (f.residualBits == 0) {
        value = uint32_t(int64_t(field << (64 - valueBits)) >> (64 - valueBits));
      } else {
        // Without a branch on the child: in a predicting pack it is the predicted one as often as
        // not.
        const bool predicted = s == f.predicted();
        valueBits = predicted ? f.residualBits : valueBits;
        value = uint32_t(int64_t(field << (64 - valueBits)) >> (64 - valueBits)) +
                (neighboursValue(f, walk.position, s) & (0u - uint32_t(predicted)));
      }
      walk.key += value << f.shift;
      field = valueBits + pointerBits + kSymmetryBits <= kReadBits ? field >> valueBits
                                                                   : read64(at + valueBits);
    }
    if (child != MhChild::Leaf) {
      const uint64_t pointer = field & ((uint64_t(1) << pointerBits) - 1);
      if (f.sharedMask >> s & 1) {
        walk.position = pointer << addressUnit_;
        if (f.symmetryMask >> s & 1)
          walk.symmetry = kSymmetry.then[field >> pointerBits & 7][walk.symmetry];
      } else {
        walk.position += f.bits + pointer;
      }
    }
    walk.kind = child;
    ++walk.level;
    return true;
  }
  // The sum of the values of the predicted child k's neighbours k ^ 1 and k ^ 2, unshifted: the
  // plane through them and the valueless child opposite k, which holds the parent's key.
  uint32_t neighboursValue(const PackFormat& f, uint64_t position, uint32_t k) const {
    return uint32_t(readSigned(position + f.fieldAt[k ^ 1], f.valueBits) +
                    readSigned(position + f.fieldAt[k ^ 2], f.valueBits));
  }
  // Child k's key delta (0 where it holds no value).
  int32_t childValue(const PackFormat& f, uint64_t position, uint32_t k) const {
    const uint32_t bits = f.valueWidth(int(k));
    if (bits == 0) return 0;
    uint32_t value = uint32_t(readSigned(position + f.fieldAt[k], bits));
    if (k == f.predicted()) value += neighboursValue(f, position, k);
    return int32_t(value << f.shift);
  }
  // The format of the pack at `position`.
  PackFormat format(uint64_t position) const {
    const uint32_t symbol = decode_[read64(position) & codeMask_];
    if (symbol < formatCount_) return formats_[symbol];
    return explicitFormatAt(position);
  }
  // The explicit format of the pack at `position`, read from the escape code's end: one read
  // holds 57 bits, the escape code takes up to 16 and the explicit fields up to 45 (a pack with
  // values, a turned shared child, private pointers and a predicted value). Read with the code,
  // the fields past 57 bits read as 0: on the city open at 64K², whose escape code takes 16 bits,
  // packs beginning at bit 4 to 7 of a byte read their residual's width wrong, the fields after it
  // misplaced, and the build's key ranges walked off the packs.
  PackFormat explicitFormatAt(uint64_t position) const {
    return explicitFormat(read64(position + escapeBits_), escapeBits_);
  }
  // An explicit format from its first bits, after `escapeBits` bits of escape code. Out of line,
  // so that a walk's loop stays small for the table's formats (a fifth of the forest's packs
  // escape; its view point lookups at 16K², in turn with `dag-mh`'s: 0.92–1.01× against
  // 0.96–1.04× inline, 0.92–0.98× before predictions).
  [[gnu::noinline]] static PackFormat explicitFormat(uint64_t word, uint32_t escapeBits) {
    PackFormat f;
    f.flags = uint8_t(word & 0xff);
    const PackShape& shape = packShape(f.flags);
    uint32_t at = 8;
    if (shape.hasValues) f.valueBits = (word >> 8) & 63, f.shift = (word >> 14) & 31, at = 19;
    if (shape.hasInner) {
      f.sharedMask = uint8_t((word >> at) & 15), at += 4;
      if (f.sharedMask && (word >> at++ & 1)) f.symmetryMask = uint8_t((word >> at) & 15), at += 4;
      if (f.hasPointerWidth()) f.pointerBits = (word >> at) & 63, at += 6;
      if (f.sharedMask) {
        const auto widest = uint8_t((word >> at) & 63);
        f.setSharedWidths({widest, widest, widest, widest}), at += 6;
      }
    }
    // Last, so that the fields before keep their places whether a pack predicts or not.
    if (shape.predictable < kMhChildren && (word >> at++ & 1))
      f.residualBits = (word >> at) & 15, at += 4;
    f.derive(escapeBits + at);
    return f;
  }
  // 64 bits from bit `position` on: the bytes carry 8 bytes of padding past the last bit.
  uint64_t read64(uint64_t position) const {
    uint64_t word;
    std::memcpy(&word, bytes_.data() + (position >> 3), sizeof word);
    return word >> (position & 7);
  }
  uint64_t readUnsigned(uint64_t position, uint32_t bits) const {
    return read64(position) & ((uint64_t(1) << bits) - 1);
  }
  int64_t readSigned(uint64_t position, uint32_t bits) const {
    return int64_t(read64(position) << (64 - bits)) >> (64 - bits);
  }

  // A node of a walk over a rectangle: where the walk stands, and its square's corner.
  struct SquareWalk {
    Walk walk;
    uint32_t x0, y0;
  };
  // `rect`'s keys below the inner node `walk` stands at, whose square has its corner at (x0, y0):
  // level by level rather than depth first, so that the packs of one level are read one after the
  // other, each prefetched when its parent's step found it, and their cache misses overlap (with
  // visitTexelChildren, the open city's view 9×9 at 16K² took 0.59× the depth-first walk's time;
  // delta-dag README, "Kernels level by level"). The levels are kept per thread, so `visit` must
  // not walk this structure.
  template <class Visit>
  void walkRect(const Walk& walk, uint32_t x0, uint32_t y0, const TexelRect& rect,
                Visit& visit) const {
    thread_local std::vector<SquareWalk> level, next;
    level.assign(1, SquareWalk{walk, x0, y0});
    for (uint32_t half = uint32_t(1) << (levels_ - walk.level - 1); !level.empty(); half >>= 1) {
      next.clear();
      for (const SquareWalk& node : level) {
        // Bit k: child k overlaps the rectangle.
        const uint32_t midX = node.x0 + half, midY = node.y0 + half;
        const uint32_t columns = (rect.i0 < midX ? 0b0101u : 0) | (rect.i1 >= midX ? 0b1010u : 0);
        const uint32_t rows = (rect.j0 < midY ? 0b0011u : 0) | (rect.j1 >= midY ? 0b1100u : 0);
        const PackFormat f = format(node.walk.position);  // once for the four children
        if (half == 1) {
          visitTexelChildren(f, node.walk, columns & rows, visit);
          continue;
        }
        for (uint32_t overlaps = columns & rows; overlaps; overlaps &= overlaps - 1) {
          const int k = std::countr_zero(overlaps);
          const uint32_t cx = node.x0 + (k & 1) * half, cy = node.y0 + (k >> 1) * half;
          Walk child = node.walk;
          if (!step(f, child, k) || child.kind == MhChild::Leaf) {
            visit(child.key, overlap(rect, cx, cy, half));
          } else {
            __builtin_prefetch(bytes_.data() + (child.position >> 3));
            next.push_back({child, cx, cy});
          }
        }
      }
      std::swap(level, next);
    }
  }
  // The keys of the texels in `overlaps` (bit k: child k) below a pack one level above the
  // texels, whose children are leaves or missing. Such a pack's fields are values alone, one
  // after another: where all four fit one read's 57 bits, each is cut from it by its place and the
  // next's, without a branch on its kind (the forest's and the open city's view 9×9 at 16K² in
  // 0.90× and 0.86× the time of a field read per texel; delta-dag README, "Texel packs in one
  // read").
  template <class Visit>
  void visitTexelChildren(const PackFormat& f, const Walk& walk, uint32_t overlaps,
                          Visit& visit) const {
    const uint32_t first = f.fieldAt[0];
    if (f.bits - first > kReadBits) {
      for (; overlaps; overlaps &= overlaps - 1) {
        const uint32_t s = kSymmetry.apply[walk.symmetry][std::countr_zero(overlaps)];
        visit(walk.key + uint32_t(childValue(f, walk.position, s)), 1);
      }
      return;
    }
    const uint64_t fields = read64(walk.position + first);
    std::array<uint32_t, kMhChildren> delta;
    for (int k = 0; k < kMhChildren; ++k) {
      const uint32_t end = k + 1 < kMhChildren ? f.fieldAt[k + 1] : f.bits;
      delta[k] = uint32_t(signedField(fields >> (f.fieldAt[k] - first), end - f.fieldAt[k]));
    }
    if (const uint32_t p = f.predicted(); p < uint32_t(kMhChildren))
      delta[p] += delta[p ^ 1] + delta[p ^ 2];
    for (; overlaps; overlaps &= overlaps - 1) {
      const uint32_t s = kSymmetry.apply[walk.symmetry][std::countr_zero(overlaps)];
      visit(walk.key + (delta[s] << f.shift), 1);
    }
  }
  // The low `bits` bits of `field` as a signed number, 0 where `bits` is 0 (shifted in two steps,
  // as one shift by 64 is undefined).
  static int64_t signedField(uint64_t field, uint32_t bits) {
    return int64_t((field << (63 - bits)) << 1) >> (63 - bits) >> 1;
  }

  // DAG-MH's skip list (Scandolo & Eisemann 2021 §3.7), derived from the packs: the walk to
  // every square of the skip level, row by row, so that a lookup starts there. The level is the
  // deepest whose table takes at most the budget (1 MiB by default) and 1/5 of the packs' bytes,
  // or 1/32 of them where that is more. The packs just below DAG-MH's level 6 lie apart, each
  // followed by its private tree, so a walk's first steps there miss the second-level cache: a
  // table that holds them within 1 MiB (the L2 a core of the machine it was chosen on) takes those
  // steps off every walk, and 1/5 keeps the small structures small (the terrain at 16K² stays at
  // level 5, 8 KiB). A larger budget takes another step off where a level more fits (delta-dag
  // README, "A skip table's budget").
  void buildSkipTable(uint64_t budget);
  // Each square's key range at the level above the skip table's, from each skip entry's key and
  // its pack's offsets (packKeyOffsets): 1/4 of the skip table's squares, 8 bytes each, at most a
  // quarter of its bytes. Uniform 9×9 kernels at 16K² took about as long with ranges two levels
  // above, one above or at the skip level (scripts/ablations/delta-dag-kernel-ranges.sh: the city
  // 58, 47, 45 ns, 300–400 without; the forest 474, 358, 433), and finer ranges cost 16–64× the
  // bytes and leave view kernels over 3× the point lookup (delta-dag README, "At cdd3b1f").
  void buildKeyRanges();
  // What a walk over every pack keeps of the packs it must not walk twice, by position.
  template <class Value>
  class PackMemo {
   public:
    // The id of the pack at `position` and false if kept, else a new id holding `initial` and true.
    std::pair<uint32_t, bool> findOrAdd(uint64_t position, const Value& initial) {
      const auto found = index_.findOrAdd(
          mixBits(position), [&](uint32_t other) { return positions_[other] == position; });
      if (found.second) positions_.push_back(position), values_.push_back(initial);
      return found;
    }
    Value& operator[](uint32_t id) { return values_[id]; }

   private:
    HashConsIndex index_;
    std::vector<uint64_t> positions_;  // id → the pack's position
    std::vector<Value> values_;
  };
  // The least and greatest sum of the deltas from the key a walk enters the pack at `position`
  // with down to each of its texels (a symmetry only moves them). Each pack's is found once:
  // `known` keeps those of shared packs and of the packs `remember` names.
  using KeyOffsets = std::pair<int64_t, int64_t>;
  KeyOffsets packKeyOffsets(uint64_t position, bool remember, PackMemo<KeyOffsets>& known) const;
  // Where the pack of inner child k of the pack at `position` lies: a shared child's address, or
  // its distance after the pack's end.
  uint64_t childPack(const PackFormat& f, uint64_t position, int k) const {
    const uint64_t at = position + f.fieldAt[k] + f.valueWidth(k);
    const uint64_t pointer = readUnsigned(at, f.pointerWidth[k]);
    return f.sharedMask >> k & 1 ? pointer << addressUnit_ : position + f.bits + pointer;
  }

  int levels_ = 0;
  int skipLevel_ = 0;
  uint32_t skipEntryWords_ = 2;
  std::vector<uint32_t> skip_;        // skipEntryWords_ words a square
  std::vector<KeyRange> keyRanges_;   // row by row
  MhChild rootKind_ = MhChild::Leaf;  // Leaf (one key for the map) or Full (a pack below)
  uint32_t rootKey_ = 0;
  uint64_t rootPosition_ = 0;
  uint32_t addressUnit_ = 0;  // a shared address counts 2^addressUnit_ bits
  FormatTable table_;
  std::vector<PackFormat> formats_;  // the table's, each with its code's length as header
  uint32_t formatCount_ = 0;         // formats_.size(), kept so that a step need not divide
  uint32_t escapeBits_ = 0;
  uint64_t codeMask_ = 0;         // the bits that decode a code: 2^(the longest code) − 1
  std::vector<uint16_t> decode_;  // the symbol each value of those bits starts (prefix_code.h)
  std::vector<uint8_t> bytes_;    // bits_ bits, then 8 bytes of padding
  uint64_t bits_ = 0;
};

// What the encode step measured, for the build record's counters.
struct Statistics {
  uint64_t valuedNodes = 0;           // MH nodes holding a value
  uint64_t treePacks = 0;             // inner nodes with a pack left after demotion
  uint64_t dagPacks = 0;              // distinct packs stored (one per symmetry class)
  uint64_t packSplits = 0;            // readings of a pack split off as packs of their own
  uint64_t packCopies = 0;            // packs added by copying small shared ones
  uint64_t sharedPacks = 0;           // of the packs stored, those referenced by more than one
  uint64_t formats = 0, escapes = 0;  // formats in the table, packs whose format is explicit
  uint64_t headerBits = 0, valueBits = 0, pointerBits = 0, symmetryBits = 0;
  uint32_t addressUnit = 0;  // a shared address counts 2^addressUnit bits
  uint64_t paddingBits = 0;  // before shared packs, to start them on a unit
};

struct Encoded {
  DeltaDag dag;
  Statistics statistics;
};

// Beside the hierarchy, per node, the encode step holds the reconstructed keys and relative
// values (8) and each inner node's pack and symmetry (4 + 1).
inline constexpr uint64_t kEncodeBytesPerNode = 8 + 4 + 1;
// Per distinct pack while hash-consing finds them: the pack store, the self-symmetries and the
// index's hashes at twice their count, as they double (2 × (40 + 1 + 8)), and its slots at four
// a pack (16). The distinct packs are known only as they are found (the forest at 16K² keeps
// 27 % of its 7.7 M tree packs, at most one an inner node), so the encode step reserves these
// bytes each time their count reaches a power of two (BuildContext::reserve). A merge declares
// before it only the nodes its part files count; a declaration from the nodes' floor (a whole
// build, or a merge before its part files exist) counts these bytes per node as well.
inline constexpr uint64_t kFindingBytesPerPack = 2 * (40 + 1 + 8) + 16;
// Asked before memory is taken: `bytes` more than held now, `what` for the error.
using ReserveMemory = std::function<void(uint64_t bytes, std::string_view what)>;

// The encode step from the hierarchy (HierarchyEncode's work): values chosen top-down, packs
// hash-consed bottom-up, laid out as private trees.
Encoded encode(
    MultiresHierarchy hierarchy, const Options& options,
    const ReserveMemory& reserve = [](uint64_t, std::string_view) {});

class Decoder final : public DepthDecoder<Decoder> {
 public:
  explicit Decoder(DeltaDag dag) : dag_(std::move(dag)) {}
  uint32_t resolution() const { return dag_.resolution(); }
  float depth(uint32_t i, uint32_t j) const { return depthOfKey(dag_.texelKey(i, j)); }
  uint64_t litTexels(const TexelRect& rect, float z) const {
    uint64_t lit = 0;
    // Keys up to +inf's are in depth order: z at most the least key's depth lights every texel of
    // the range, z above the greatest's none.
    dag_.forEachKeyBlock(
        rect,
        [z](const DeltaDag::KeyRange& range) {
          return z <= depthOfKey(range.least) || z > depthOfKey(range.greatest);
        },
        [&](uint32_t key, uint64_t texels) { lit += z <= depthOfKey(key) ? texels : 0; });
    return lit;
  }
  SizeBreakdown size() const override { return dag_.size(); }
  void save(ByteWriter& out) const override { dag_.save(out); }

 private:
  DeltaDag dag_;
};

}  // namespace sb::delta_dag
