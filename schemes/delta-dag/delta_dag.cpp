#include "schemes/delta-dag/delta_dag.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "schemes/delta-dag/pack_finder.h"
#include "schemes/delta-dag/pack_layout.h"
#include "schemes/delta-dag/prefix_code.h"

namespace sb::delta_dag {
namespace {

// A format enters the table if at least this many packs take it: at 4K² on the city, tangle and
// forest, 8 gave the smallest layouts of 2, 3, 4, 6, 8, 12, 16 and 32 with 8-byte table entries,
// and of 5, 6 and 8 with 5-byte ones (an escape costs about 30 bits); on the tangle at 16K², 8 and
// 16 tie and 4 is 5 % larger.
constexpr uint64_t kMinFormatUses = 8;

// Reserved once the packs are found and the hierarchy and the per-node arrays freed, per pack
// beside the store: while oriented, its references, estimated tree bits, readings and frame
// (4 + 8 + 16 + 1) with the store's room to double as readings split off (80); while copied,
// the rebuilt store with room to double (80) beside the references, order, tree bits, address
// and new id (4 + 4 + 8 + 1 + 4); while laid out, less (two counted layouts' formats and tree
// bits, 12 each, the explicit count's own codes and the places, 8 each, and the output).
constexpr uint64_t kLaterBytesPerPack = 4 + 8 + 16 + 1 + 2 * sizeof(Pack);

}  // namespace

int64_t simplestIn(int64_t lo, int64_t hi) {
  if (lo <= 0 && hi >= 0) return 0;
  if (hi < 0) return -simplestIn(-hi, -lo);
  // lo - 1 and hi agree above their highest differing bit t, where hi has a 1: clearing hi's bits
  // below t gives a multiple of 2^t in [lo, hi], and no multiple of 2^(t+1) lies there.
  const uint64_t t = std::bit_width(uint64_t(lo - 1) ^ uint64_t(hi)) - 1;
  return int64_t(uint64_t(hi) & ~((uint64_t(1) << t) - 1));
}

DeltaDag::DeltaDag(int levels, MhChild rootKind, uint32_t rootKey, uint64_t rootPosition,
                   uint32_t addressUnit, FormatTable table, std::vector<uint8_t> bytes,
                   uint64_t bits)
    : levels_(levels),
      rootKind_(rootKind),
      rootKey_(rootKey),
      rootPosition_(rootPosition),
      addressUnit_(addressUnit),
      table_(std::move(table)),
      bytes_(std::move(bytes)),
      bits_(bits) {
  for (size_t c = 0; c < table_.codes.size(); ++c)
    formats_.push_back(PackFormat::ofCode(table_.codes[c], table_.lengths[c]));
  formatCount_ = uint32_t(formats_.size());
  if (table_.lengths.empty()) {
    decode_ = {0};  // every pack starts with its explicit format
  } else {
    escapeBits_ = table_.lengths.back();
    const uint32_t longest = *std::max_element(table_.lengths.begin(), table_.lengths.end());
    codeMask_ = (uint64_t(1) << longest) - 1;
    decode_ = decodeTable(table_.lengths, longest);
  }
}

int DeltaDag::skipLevelFor(uint64_t packBits, int levels, uint64_t budget) {
  const uint64_t packBytes = packBits / 8;
  budget = std::max(packBytes / 32, std::min(budget, packBytes / 5));
  const uint64_t entryBytes = 4 * skipEntryWords(packBits);
  int level = 0;
  while (level < levels && (entryBytes << (2 * (level + 1))) <= budget) ++level;
  return level;
}

void DeltaDag::buildSkipTable(uint64_t budget) {
  skipLevel_ = skipLevelFor(bits_, levels_, budget);
  skipEntryWords_ = skipEntryWords(bits_);
  const uint32_t side = uint32_t(1) << skipLevel_;
  skip_.resize(size_t(side) * side * skipEntryWords_);
  for (uint32_t y = 0; y < side; ++y)
    for (uint32_t x = 0; x < side; ++x) {
      const uint32_t i = x << (levels_ - skipLevel_), j = y << (levels_ - skipLevel_);
      Walk walk = rootWalk();
      while (walk.kind != MhChild::Leaf && walk.level < skipLevel_ &&
             step(walk, mhChildIndex(i, j, levels_ - walk.level - 1))) {
      }
      putSkipEntry(&skip_[(size_t(y) * side + x) * skipEntryWords_], skipEntryWords_, walk,
                   skipLevel_);
    }
}

void DeltaDag::buildKeyRanges() {
  const int level = keyRangeLevel(), coarser = skipLevel_ - level;
  const uint32_t side = uint32_t(1) << level, skipSide = uint32_t(1) << skipLevel_;
  keyRanges_.assign(size_t(side) * side, {UINT32_MAX, 0});
  PackMemo<KeyOffsets> known;
  for (uint32_t y = 0; y < skipSide; ++y)
    for (uint32_t x = 0; x < skipSide; ++x) {
      const Walk walk = skipEntryWalk(&skip_[(size_t(y) * skipSide + x) * skipEntryWords_],
                                      skipEntryWords_, skipLevel_);
      KeyOffsets keys{walk.key, walk.key};
      if (walk.kind != MhChild::Leaf) {
        const KeyOffsets offsets = packKeyOffsets(walk.position, true, known);
        keys.first += offsets.first, keys.second += offsets.second;
      }
      KeyRange& range = keyRanges_[(size_t(y >> coarser) << level) + (x >> coarser)];
      if (keys.first < 0 || keys.second > kInfinityKey) keys = {0, UINT32_MAX};
      range.least = std::min(range.least, uint32_t(keys.first));
      range.greatest = std::max(range.greatest, uint32_t(keys.second));
    }
}

DeltaDag::KeyOffsets DeltaDag::packKeyOffsets(uint64_t position, bool remember,
                                              PackMemo<KeyOffsets>& known) const {
  uint32_t id = 0;
  if (remember) {
    // Filled in below, before anything reads it: no pack lies below itself.
    const auto [found, added] = known.findOrAdd(position, {});
    if (!added) return known[found];
    id = found;
  }
  const PackFormat f = format(position);
  KeyOffsets offsets{INT64_MAX, INT64_MIN};
  for (int k = 0; k < kMhChildren; ++k) {
    const MhChild kind = MhChild(childFlag(f.flags, k));
    // A step adds the value shifted, wrapping: between two depths' keys that is their difference.
    const int64_t value = childValue(f, position, uint32_t(k));
    KeyOffsets below{0, 0};  // a missing child's square, or a leaf
    if (isInner(uint32_t(kind)))
      below = packKeyOffsets(childPack(f, position, k), f.sharedMask >> k & 1, known);
    offsets.first = std::min(offsets.first, value + below.first);
    offsets.second = std::max(offsets.second, value + below.second);
  }
  if (remember) known[id] = offsets;
  return offsets;
}

uint64_t DeltaDag::skipSquaresAnsweredAbove() const {
  uint64_t answered = 0;
  for (size_t entry = 0; entry < skip_.size(); entry += skipEntryWords_)
    answered += skipEntryWalk(&skip_[entry], skipEntryWords_, skipLevel_).kind == MhChild::Leaf;
  return answered;
}

SizeBreakdown DeltaDag::size() const {
  // The layout's version, the root's kind, key and position, the address unit; the table with its
  // codes' lengths, the escape's; the packs' bits (whole bytes; the padding is not part of the
  // structure); what loading derives.
  return {{"root", 1 + 1 + 4 + 8 + 1},
          {"pack formats", storedBytes(table_) + 1},
          {"packs", (bits_ + 7) / 8},
          {"format decode table", decode_.size() * sizeof(uint16_t)},
          {"skip table", skip_.size() * sizeof(uint32_t)},
          {"key ranges", keyRanges_.size() * sizeof(KeyRange)}};
}

void DeltaDag::save(ByteWriter& out) const {
  out.put<uint8_t>(kLayoutVersion);
  out.put<uint8_t>(uint8_t(rootKind_));
  out.put<uint32_t>(rootKey_);
  out.put<uint64_t>(rootPosition_);
  out.put<uint8_t>(uint8_t(addressUnit_));
  std::vector<FormatEntry> entries;
  std::vector<uint32_t> narrowed;
  for (size_t c = 0; c < table_.codes.size(); ++c) {
    const uint64_t code = table_.codes[c];
    entries.push_back(
        FormatEntry::of((code & kEntryCodeMask) | uint64_t(table_.lengths[c]) << kFormatCodeBits));
    if (code >> kFormatCodeBits != 0) narrowed.push_back(narrowedFormat(uint32_t(c), code));
  }
  out.putArray(std::span<const FormatEntry>(entries));
  out.putArray(std::span<const uint32_t>(narrowed));
  out.put<uint8_t>(uint8_t(table_.lengths.empty() ? 0 : table_.lengths.back()));
  out.put<uint64_t>(bits_);
  out.putArray(std::span<const uint8_t>(bytes_.data(), (bits_ + 7) / 8));
}

namespace {

// Why `f` is not a format the writer writes, or "".
std::string invalidFormat(const PackFormat& f) {
  const PackShape& shape = packShape(f.flags);
  if (f.flags == 0) return "has no children";
  if (shape.hasValues
          ? f.valueBits == 0 || f.valueBits > kMaxValueBits || f.valueBits + f.shift > 32
          : f.valueBits != 0 || f.shift != 0)
    return fmt::format("has {}-bit values shifted by {}", f.valueBits, f.shift);
  if (f.residualBits != 0 && shape.predictable == kMhChildren)
    return fmt::format("predicts a value by {}-bit residuals, but not three children hold values",
                       f.residualBits);
  if ((f.sharedMask & ~shape.innerMask) != 0)
    return fmt::format("marks child {} shared, which is not inner",
                       std::countr_zero(uint32_t(f.sharedMask & ~shape.innerMask)));
  if ((f.symmetryMask & ~f.sharedMask) != 0)
    return fmt::format("gives child {} a symmetry, which is not shared",
                       std::countr_zero(uint32_t(f.symmetryMask & ~f.sharedMask)));
  if (f.hasPointerWidth() ? f.pointerBits == 0 || f.pointerBits > kMaxPointerBits
                          : f.pointerBits != 0)
    return fmt::format("has {}-bit pointers", f.pointerBits);
  if (f.sharedMask ? f.sharedBits == 0 || f.sharedBits > kMaxPointerBits : f.sharedBits != 0)
    return fmt::format("has {}-bit shared addresses", f.sharedBits);
  for (int k = 0; k < kMhChildren; ++k)
    if ((f.sharedMask >> k & 1) && (f.pointerWidth[k] == 0 || f.pointerWidth[k] > f.sharedBits))
      return fmt::format("gives shared child {} a {}-bit address", k, f.pointerWidth[k]);
  return {};
}

}  // namespace

DeltaDag DeltaDag::load(ByteReader& in, const MapInfo& map, uint64_t skipBudget) {
  if (map.resolution == 0 || !std::has_single_bit(map.resolution))
    throw FormatError(
        fmt::format("delta-dag: resolution {} is not a power of two", map.resolution));
  const int levels = std::countr_zero(map.resolution);
  // Structures saved before the version byte begin with their root's kind, 1 or 3.
  if (const uint32_t version = in.get<uint8_t>("layout version"); version != kLayoutVersion)
    throw FormatError(
        fmt::format("delta-dag: the packs are of layout {}, this build reads layout {}: build the "
                    "structure again",
                    version == uint32_t(MhChild::Full) || version == uint32_t(MhChild::Leaf)
                        ? "1 (before predicted values)"
                        : std::to_string(version),
                    kLayoutVersion));
  const auto rootKind = MhChild(in.get<uint8_t>("root kind"));
  if (rootKind != MhChild::Leaf && rootKind != MhChild::Full)
    throw FormatError(fmt::format("delta-dag: root kind {} is neither leaf (3) nor full (1)",
                                  uint32_t(rootKind)));
  if (rootKind == MhChild::Full && levels == 0)
    throw FormatError("delta-dag: a 1² map's root has no children");
  const uint32_t rootKey = in.get<uint32_t>("root key");
  if (rootKey > kInfinityKey)
    throw FormatError(fmt::format("delta-dag: root key {:#x} is not a depth", rootKey));
  const uint64_t rootPosition = in.get<uint64_t>("root position");
  const uint32_t addressUnit = in.get<uint8_t>("address unit");
  if (addressUnit > kMaxAddressUnit)
    throw FormatError(fmt::format("delta-dag: address unit 2^{} bits, at most 2^{}", addressUnit,
                                  kMaxAddressUnit));
  FormatTable table;
  const std::vector<FormatEntry> entries = in.getArray<FormatEntry>("pack formats");
  std::vector<uint32_t> narrowings(entries.size(), 0);
  const std::vector<uint32_t> narrowed = in.getArray<uint32_t>("narrowed pack formats");
  for (size_t n = 0; n < narrowed.size(); ++n) {
    const uint32_t c = narrowed[n] & 0xffff;
    if (c >= entries.size() || (n > 0 && c <= (narrowed[n - 1] & 0xffff)) || narrowed[n] >> 16 == 0)
      throw FormatError(fmt::format(
          "delta-dag: narrowed pack format {} ({:#x}) is not a narrowing of a table format after "
          "the last one's",
          n, narrowed[n]));
    narrowings[c] = narrowed[n] >> 16;
  }
  for (size_t c = 0; c < entries.size(); ++c) {
    const uint64_t entry = entries[c].value();
    const uint64_t code = (entry & kEntryCodeMask) | uint64_t(narrowings[c]) << kFormatCodeBits;
    const PackFormat format = PackFormat::ofCode(code, 0);
    const std::string invalid = invalidFormat(format);
    if (!invalid.empty())
      throw FormatError(fmt::format("delta-dag: pack format {} ({:#x}) {}", c, entry, invalid));
    if (format.code() != code)
      throw FormatError(fmt::format(
          "delta-dag: pack format {} ({:#x}) narrows the address of a child that is not shared", c,
          code));
    if (entry >> kFormatCodeBits > kMaxCodeBits)
      throw FormatError(fmt::format("delta-dag: pack format {} ({:#x}) has a {}-bit code", c, entry,
                                    entry >> kFormatCodeBits));
    table.codes.push_back(code);
    table.lengths.push_back(uint8_t(entry >> kFormatCodeBits));
  }
  const uint32_t escapeBits = in.get<uint8_t>("escape code length");
  if (entries.size() >= kNoSymbol)
    throw FormatError(
        fmt::format("delta-dag: {} pack formats, at most {}", entries.size(), kNoSymbol - 1));
  if (entries.empty() && escapeBits != 0)
    throw FormatError("delta-dag: an escape code without a table of formats");
  if (!entries.empty()) {
    table.lengths.push_back(uint8_t(escapeBits));
    if (!isPrefixCode(table.lengths, kMaxCodeBits))
      throw FormatError(
          "delta-dag: the formats' code lengths (and the escape's) are not 1 to 16 bits of a "
          "prefix code");
  }
  const uint64_t bits = in.get<uint64_t>("bit count");
  if (bits > uint64_t(in.remaining()) * 8) throw FormatError("delta-dag: packs truncated");
  const uint64_t byteCount = (bits + 7) / 8;
  std::vector<uint8_t> bytes = in.getArray<uint8_t>("packs", byteCount);
  bytes.resize(byteCount + 8, 0);
  if (bits % 8 != 0 && (bytes[byteCount - 1] >> (bits % 8)) != 0)
    throw FormatError("delta-dag: bits past the last pack are set");
  if (rootKind == MhChild::Leaf &&
      (rootPosition != 0 || addressUnit != 0 || bits != 0 || !table.lengths.empty()))
    throw FormatError("delta-dag: a leaf root with packs");
  DeltaDag dag(levels, rootKind, rootKey, rootPosition, addressUnit, std::move(table),
               std::move(bytes), bits);
  if (rootKind == MhChild::Leaf) {
    dag.buildLookupTables(skipBudget);
    return dag;
  }

  // Each pack's height (levels of packs from it down, itself included): a pack reached at level l
  // needs height ≤ levels − l. The budget bounds the recursion by the levels, however the pointers
  // chain. A shared pack's height is found once and kept. A private pack is its parent's alone, so
  // a structure as written reaches each once for each visit of its owner, at most one pack a bit
  // of the packs: reaching more means pointers crafted to reach a pack twice, whose paths multiply
  // with the levels (four children on one pack, 4^levels walks here and when the key ranges are
  // found), and it is refused. Keeping only the shared packs' heights keeps the memo small: the
  // forest at 256K² stores 31.5 M packs, 1.7 M of them shared.
  PackMemo<uint8_t> sharedHeights;  // kUnknownHeight while its packs below are visited
  constexpr uint8_t kUnknownHeight = UINT8_MAX;
  uint64_t privateVisits = 0;
  const auto fail = [](uint64_t position, const std::string& what) {
    return FormatError(fmt::format("delta-dag: the pack at bit {} {}", position, what));
  };
  const auto height = [&](auto& self, uint64_t position, bool shared, int budget) -> int {
    uint32_t id = 0;
    if (shared) {
      const auto [found, added] = sharedHeights.findOrAdd(position, kUnknownHeight);
      // A pack below itself is still kUnknownHeight, above every budget.
      if (!added && sharedHeights[found] > budget)
        throw fail(position, "lies below the texel level");
      if (!added) return sharedHeights[found];
      id = found;
    } else if (++privateVisits > bits) {
      throw fail(position, "is reached by more paths than a structure of its bits holds packs");
    }
    if (budget < 1) throw fail(position, "lies below the texel level");
    if (position >= bits) throw fail(position, "lies outside the packs");
    const uint64_t word = dag.read64(position);
    if (dag.decode_[word & dag.codeMask_] == kNoSymbol)
      throw fail(position, "starts with no format's code");
    const PackFormat f = dag.format(position);
    if (f.headerBits() > bits - position) throw fail(position, "runs past the packs");
    if (const std::string invalid = invalidFormat(f); !invalid.empty())
      throw fail(position, invalid);
    if (dag.decode_[word & dag.codeMask_] >= dag.formats_.size() &&
        f.headerBits() != dag.escapeBits_ + f.explicitBits())
      throw fail(position,
                 "is marked turned with no child turned, or predicted with 0-bit residuals");
    if (f.bits > bits - position) throw fail(position, "runs past the packs");
    int below = 0;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild kind = MhChild(childFlag(f.flags, k));
      if (hasValue(kind) && dag.childValue(f, position, uint32_t(k)) == 0)
        throw fail(position, "holds a value of 0");
      if (!isInner(uint32_t(kind))) continue;
      // Children may lie anywhere: the budget stops a cycle.
      below = std::max(
          below, self(self, dag.childPack(f, position, k), f.sharedMask >> k & 1, budget - 1));
    }
    if (shared) sharedHeights[id] = uint8_t(below + 1);
    return below + 1;
  };
  height(height, rootPosition, false, levels);
  dag.buildLookupTables(skipBudget);
  return dag;
}

Encoded encode(MultiresHierarchy hierarchy, const Options& options, const ReserveMemory& reserve) {
  const std::vector<MhNode>& nodes = hierarchy.nodes;
  const uint32_t root = hierarchy.root();
  const uint32_t rootKey = uint32_t(chooseValue(nodes[root].interval, 0, options.values));
  PackFinder finder(options, reserve);
  PackReference rootPack;
  {
    NodePacks tree(nodes.size());
    chooseValues(nodes, rootKey, options.values, tree.values, [](uint32_t) { return true; });
    finder.queueTree(nodes, tree);
    finder.find();
    rootPack = {tree.pack[root], tree.symmetry[root]};
  }
  const int levels = hierarchy.levels;
  hierarchy = {};
  return encodeFound(std::move(finder).finish(), rootPack, rootKey, levels, options, reserve);
}

Encoded encodeFound(FoundPacks found, PackReference root, uint32_t rootKey, int levels,
                    const Options& options, const ReserveMemory& reserve) {
  std::vector<Pack>& packs = found.packs;
  std::vector<uint8_t>& selfSymmetries = found.selfSymmetries;
  Statistics& stats = found.statistics;
  ++stats.valuedNodes;  // the root
  uint32_t rootPack = root.pack;
  const Symmetry rootSymmetry = root.symmetry;
  reserve(packs.size() * kLaterBytesPerPack,
          fmt::format("delta-dag: laying out {} distinct packs", packs.size()));

  if (rootPack == kNoPack) {
    DeltaDag dag(levels, MhChild::Leaf, rootKey, 0, 0, {}, std::vector<uint8_t>(8, 0), 0);
    dag.buildLookupTables(options.skipBudget);
    return {std::move(dag), stats};
  }
  if (options.sharing && options.symmetry)
    stats.packSplits = orient(packs, selfSymmetries, {rootPack, rootSymmetry}, options.prediction);
  if (options.sharing && options.copies)
    rootPack =
        copyCheapShared(packs, selfSymmetries, rootPack, options.prediction, stats.packCopies);
  selfSymmetries = {};
  std::vector<uint32_t> references(packs.size(), 0);
  for (const Pack& pack : packs)
    for (int k = 0; k < kMhChildren; ++k)
      if (isInner(childFlag(pack.flags, k))) ++references[pack.children[k]];
  const std::vector<uint32_t> shared = sharedOrder(packs, references, options.byReferences);
  std::vector<bool> absolute(packs.size(), false);
  for (const uint32_t id : shared) absolute[id] = true;
  stats.sharedPacks = uint64_t(std::count_if(references.begin(), references.end(),
                                             [](uint32_t count) { return count > 1; }));
  // Laid out with explicit formats; then with a table of the formats their packs take at least
  // kMinFormatUses times, coded by their counts (prefix_code.h); then once more with that table
  // refitted to the uses its layout made (shorter headers shorten pointers, which changes
  // formats). The smallest layout, tables counted, is kept: a pack's format may be any of the
  // table's that holds it, so what a table saves is known only by laying it out. Codes are at
  // most as long as keeps the decode table within 1/64 of the explicit layout's bits.
  // Every layout is counted, and only the smallest written.
  // Shared addresses count the unit their places in that layout (with addresses in bits) make the
  // cheapest (pack_layout.h), and every layout after it uses that unit.
  Layout best = countLayout(packs, rootPack, absolute, shared, 0, options.prediction, {});
  if (options.addressUnits) {
    std::vector<uint32_t> sharedReferences;
    for (const uint32_t id : shared) sharedReferences.push_back(references[id]);
    const uint32_t unit =
        cheapestAddressUnit(best.sharedPositions, sharedReferences, kMaxAddressUnit);
    if (unit != 0)
      best = countLayout(packs, rootPack, absolute, shared, unit, options.prediction, {});
  }
  const uint32_t unit = best.addressUnit;
  const auto keepSmaller = [&](Layout next) {
    if (next.cost() < best.cost()) best = std::move(next);
  };
  const uint32_t maxBits =
      std::min<uint32_t>(kMaxCodeBits, std::bit_width(best.bits() / (64 * 16)) - 1);
  if (options.formatTable && best.bits() >= 64 * 16 * 16) {
    keepSmaller(countLayout(
        packs, rootPack, absolute, shared, unit, options.prediction,
        frequentFormats(std::move(best.ownCodes), kMinFormatUses, maxBits, options.sharedWidths)));
    if (!best.table.codes.empty())
      keepSmaller(countLayout(packs, rootPack, absolute, shared, unit, options.prediction,
                              refitted(best, maxBits)));
  }
  writeLayout(packs, rootPack, absolute, shared, options.prediction, best);
  stats.formats = best.table.codes.size();
  stats.escapes = best.escapes;
  stats.headerBits = best.headerBits, stats.valueBits = best.valueBits;
  stats.pointerBits = best.pointerBits, stats.symmetryBits = best.symmetryBits;
  stats.addressUnit = best.addressUnit, stats.paddingBits = best.paddingBits;
  const uint64_t bits = best.bits();
  DeltaDag dag(levels, MhChild::Full, rootKey, best.rootPosition, best.addressUnit,
               std::move(best.table), best.out.release(), bits);
  dag.buildLookupTables(options.skipBudget);
  return {std::move(dag), stats};
}

}  // namespace sb::delta_dag
