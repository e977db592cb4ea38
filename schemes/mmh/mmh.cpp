// mmh — merged multiresolution hierarchies (Scandolo, Bauszat & Eisemann 2016b): the MH with
// values relative to their parent, so that subtrees of equal topology and intersecting
// intervals anywhere in the lowest levels are stored once. Lookups walk the quadtree as MH does,
// summing values on the way down (Alg. 1).
#include <fmt/format.h>

#include "schemes/mmh/subtree_matching.h"
#include "schemes/shared/mh_parts.h"
#include "schemes/shared/offset_quadtree.h"

namespace sb {
namespace {

// SBE16b §3.3: the padding of the MH node becomes offset bits, since a merged subtree may lie far
// from the parents that share it; merges stay in the lowest 12 levels, where offsets are unscaled.
constexpr int kOffsetBits = 24;
constexpr int kMergeLevels = 12;

using MmhDecoder = OffsetQuadtreeDecoder<OffsetQuadtree::Values::Relative>;
using MmhFloatDecoder = OffsetQuadtreeDecoder<OffsetQuadtree::Values::RelativeFloat>;

// The float-differences variant saves a byte before the tree: which values it holds, float
// differences or, where the unmerged hierarchy is not lossless in float sums, key deltas.
enum class ValueKind : uint8_t { KeyDeltas = 0, FloatDifferences = 1 };

std::unique_ptr<Decoder> encodeMmh(MultiresHierarchy hierarchy, const MatchingOptions& options,
                                   BuildContext& context) {
  context.phase("hash");
  const MergedHierarchy merged = [&] {
    SubtreeMatcher matcher(hierarchy, options);
    context.phase("match");
    return matcher.match();
  }();
  context.phase("serialise");
  const MatchingStatistics& s = merged.statistics;
  context.count("pairs tested", s.pairsTested);
  context.count("rejected interval", s.rejectedInterval);
  context.count("rejected offset", s.rejectedOffset);
  context.count("rejected full test", s.rejectedFullTest);
  context.count("merges", s.merges);
  context.count("nodes removed", s.nodesRemoved);
  OffsetQuadtree tree =
      layoutOffsetQuadtree(hierarchy, merged.values, merged.sharedChildren, kOffsetBits, "mmh");
  if (options.values == RelativeValues::KeyDeltas)
    return std::make_unique<MmhDecoder>(std::move(tree));
  context.count("rejected rounding", s.rejectedRounding);
  context.count("unrepresentable nodes", s.unrepresentable);
  context.count("float values", merged.floatValues ? 1 : 0);
  if (!merged.floatValues) {
    context.count("float trial merges", merged.floatTrial.merges);
    context.count("float trial nodes removed", merged.floatTrial.nodesRemoved);
    context.count("float trial rejected full test", merged.floatTrial.rejectedFullTest);
    context.count("float trial rejected rounding", merged.floatTrial.rejectedRounding);
    context.count("float trial bytes", merged.floatTrialWords * 4);
  }
  if (merged.floatValues)
    return std::make_unique<MmhFloatDecoder>(std::move(tree), uint8_t(ValueKind::FloatDifferences));
  return std::make_unique<MmhDecoder>(std::move(tree), uint8_t(ValueKind::KeyDeltas));
}

SchemeInfo mmh() {
  SchemeInfo info;
  info.name = "mmh";
  info.paper = "Scandolo, Bauszat & Eisemann 2016, merged multiresolution hierarchies";
  info.kind = SchemeKind::Depth;
  info.params = {
      ParamSpec::integer("search-distance",
                         "entries of a collision list each subtree is tested against (SBE16b §3.2)",
                         1000, 0, 100000000, {0, 10, 100, 250, 500, 1000, 2000, 5000, 10000}),
      ParamSpec::choice("interval-test",
                        "early rejection by aggregated bounds (SBE16b §3.2): both-ways tests each "
                        "subtree against the other, paper only the earlier against the later (Alg. "
                        "3); the merges are the same, the rejection counters differ",
                        "both-ways", {"both-ways", "paper"}, {"both-ways", "paper"}),
      ParamSpec::choice("relative-values",
                        "how relative values are formed (issue 14): key-deltas stores exact "
                        "differences of depth keys (float ulps), float-differences float32 depth "
                        "differences summed in float32 and matched in depth units (SBE16b §3), "
                        "falling back to key deltas where float sums cannot be lossless",
                        "key-deltas", {"key-deltas", "float-differences"},
                        {"key-deltas", "float-differences"})};
  // A merge of parts joins the whole hierarchy (16 bytes a node, reserved from the part files)
  // and runs the encode step, whose largest moment is the layout: per node the matched values
  // and shared children (8 bytes), the layout's position, level and kind (10) and the
  // structure's words (at most two a node, 8). Hashing and matching hold less, some 25 bytes a
  // node where 57% of the nodes head packs that may merge (the most of city, forest, tangle and
  // terrain at 4K²–16K²): the reconstructed keys (4); while hashing, the topology hashes and
  // heights (9); while matching, the unmerged positions, shared children and pack states (9);
  // and per pack that may merge, its entry (4) and its subtree's aggregated bounds (16, gone
  // before the values, 4, are taken).
  setMhBuilds(info, {[](const MapInfo&, const ParamValues& params) -> HierarchyEncode {
                       const MatchingOptions options{
                           uint32_t(params.integer("search-distance")), kMergeLevels, kOffsetBits,
                           params.choice("interval-test") == "paper" ? IntervalTest::Paper
                                                                     : IntervalTest::BothWays,
                           params.choice("relative-values") == "float-differences"
                               ? RelativeValues::FloatDifferences
                               : RelativeValues::KeyDeltas};
                       return [options](MultiresHierarchy hierarchy, BuildContext& context) {
                         return encodeMmh(std::move(hierarchy), options, context);
                       };
                     },
                     MhBuilder::hierarchyFloorBytes,
                     {{}, sizeof(MhNode) + 26, 0}});
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues& params) -> std::unique_ptr<Decoder> {
    if (params.choice("relative-values") == "key-deltas")
      return std::make_unique<MmhDecoder>(OffsetQuadtree::load(in, map, "mmh"));
    const uint8_t kind = in.get<uint8_t>("value kind");
    if (kind == uint8_t(ValueKind::FloatDifferences))
      return std::make_unique<MmhFloatDecoder>(OffsetQuadtree::load(in, map, "mmh"), kind);
    if (kind == uint8_t(ValueKind::KeyDeltas))
      return std::make_unique<MmhDecoder>(OffsetQuadtree::load(in, map, "mmh"), kind);
    throw FormatError(fmt::format(
        "mmh: value kind {} is neither key deltas (0) nor float differences (1)", kind));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(mmh);

}  // namespace sb
