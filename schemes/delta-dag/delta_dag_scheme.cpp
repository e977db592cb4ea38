// The registry row of `delta-dag`: its parameters, the MH-family builds around its encode step
// (whole, and in parts without the whole hierarchy: delta_parts.h), and its loader.
#include "schemes/delta-dag/delta_dag.h"
#include "schemes/delta-dag/delta_parts.h"
#include "schemes/shared/mh_parts.h"

namespace sb {
namespace {

using delta_dag::Options;
using delta_dag::ValueChoice;

Options optionsOf(const ParamValues& params) {
  return {params.choice("values") == "middle" ? ValueChoice::Middle : ValueChoice::Simplest,
          params.choice("sharing") == "dag",
          params.choice("addresses") == "by-references",
          params.choice("formats") == "table",
          params.choice("symmetry") == "mirrors",
          params.choice("copies") == "cheaper",
          params.choice("address-unit") == "cheapest",
          params.choice("prediction") == "plane",
          params.choice("address-widths") == "each",
          uint64_t(params.integer("skip-budget")) << 10};
}

// The decoder of an encoded structure, the encode step's counters recorded.
std::unique_ptr<Decoder> decoderOf(delta_dag::Encoded encoded, BuildContext& context) {
  const delta_dag::Statistics& s = encoded.statistics;
  context.count("valued nodes", s.valuedNodes);
  context.count("tree packs", s.treePacks);
  context.count("dag packs", s.dagPacks);
  context.count("pack splits", s.packSplits);
  context.count("pack copies", s.packCopies);
  context.count("shared packs", s.sharedPacks);
  context.count("pack formats", s.formats);
  context.count("explicit formats", s.escapes);
  context.count("header bits", s.headerBits);
  context.count("value bits", s.valueBits);
  context.count("pointer bits", s.pointerBits);
  context.count("symmetry bits", s.symmetryBits);
  context.count("address unit bits", uint64_t(1) << s.addressUnit);
  context.count("padding bits", s.paddingBits);
  context.count("skip level", uint64_t(encoded.dag.skipLevel()));
  context.count("skip squares answered above", encoded.dag.skipSquaresAnsweredAbove());
  return std::make_unique<delta_dag::Decoder>(std::move(encoded.dag));
}

std::unique_ptr<Decoder> encodeDeltaDag(MultiresHierarchy hierarchy, const Options& options,
                                        BuildContext& context) {
  context.phase("encode");
  return decoderOf(delta_dag::encode(std::move(hierarchy), options,
                                     [&](uint64_t bytes, std::string_view what) {
                                       context.reserve(bytes, what);
                                     }),
                   context);
}

// Declared per node: the hierarchy and the encode step's per-node arrays, in a whole build; a
// merge of parts holds them for one part at a time (delta_parts.h). The distinct packs are
// reserved as they are found, and counted per node only where the nodes are known at their floor
// alone (delta_dag.h).
constexpr uint64_t kHeldBytesPerNode = sizeof(MhNode) + delta_dag::kEncodeBytesPerNode;
// What a merge of parts holds per node beside the packs it reserves: its structure, which took
// 1.2–1.7 bytes a node of the part files (13 bytes each) on the city, the forest and the tangle at
// 2K² and 4K², and less at larger sizes, where more is shared.
constexpr uint64_t kMergedBytesPerNode = 2;

SchemeInfo deltaDag() {
  SchemeInfo info;
  info.name = "delta-dag";
  info.paper = "this framework (issue 16): MMH's relative values in a hash-consed DAG";
  info.kind = SchemeKind::Depth;
  info.params = {
      ParamSpec::choice("values",
                        "how each value is chosen in its interval: simplest takes the number with "
                        "the most trailing zero bits relative to the parent's key (0 where it "
                        "fits, sharing and few bits), middle the interval's middle as MH and MMH",
                        "simplest", {"simplest", "middle"}, {"simplest", "middle"}),
      ParamSpec::choice("sharing",
                        "dag stores each distinct sibling pack once (hash-consing over the whole "
                        "map), tree every pack where it lies",
                        "dag", {"dag", "tree"}, {"dag", "tree"}),
      ParamSpec::choice("addresses",
                        "the order of the packs referenced more than once, laid out first and "
                        "pointed to by address: by-references the most referenced earliest, so "
                        "that their addresses are the shortest (SSVDAG: pointers by frequency), "
                        "found in the order hash-consing found them",
                        "by-references", {"by-references", "found"}, {"by-references", "found"}),
      ParamSpec::choice("formats",
                        "table indexes the most frequent pack formats (flags and field widths); "
                        "explicit writes every pack's format in full",
                        "table", {"table", "explicit"}, {"table", "explicit"}),
      ParamSpec::choice("symmetry",
                        "mirrors stores packs equal under a mirroring in x or y or a "
                        "transposition once, a shared pack's reference naming how it is turned "
                        "(SSVDAG's symmetry-aware merging); none shares only equal packs",
                        "mirrors", {"mirrors", "none"}, {"mirrors", "none"}),
      ParamSpec::choice("copies",
                        "cheaper copies a shared pack into each pack that references it where its "
                        "subtree takes fewer bits than the addresses it saves; none keeps every "
                        "equal pack shared",
                        "cheaper", {"cheaper", "none"}, {"cheaper", "none"}),
      ParamSpec::choice("address-unit",
                        "cheapest counts shared addresses in the unit of 1 to 32 bits that takes "
                        "the fewest bits, each shared subtree padded to start on one; bit counts "
                        "them in bits",
                        "cheapest", {"cheapest", "bit"}, {"cheapest", "bit"}),
      ParamSpec::choice("prediction",
                        "plane stores the value of a pack's child opposite its one valueless "
                        "child as its residual from the plane through the other three, where "
                        "that takes fewer bits (open surfaces' exact depths); none stores every "
                        "value",
                        "plane", {"plane", "none"}, {"plane", "none"}),
      ParamSpec::choice("address-widths",
                        "each lets a table format give each shared child an address of its own "
                        "width (a pack's shared children are referenced unequally often, so their "
                        "addresses differ in width); widest gives them all the widest's",
                        "each", {"each", "widest"}, {"each", "widest"}),
      ParamSpec::integer("skip-budget",
                         "KiB the skip table may take, where lookups start (DAG-MH's skip list, "
                         "§3.7; derived when loaded, counted in the size): the deepest level whose "
                         "table fits it and a fifth of the packs, or a 32nd of them where that is "
                         "more; a level deeper takes a step off every lookup for 4× the table",
                         int64_t(delta_dag::kDefaultSkipBudget >> 10), 0, int64_t(1) << 20,
                         {1024, 4096})};
  setMhBuilds(
      info,
      {[](const MapInfo&, const ParamValues& params) -> HierarchyEncode {
         return [options = optionsOf(params)](MultiresHierarchy hierarchy, BuildContext& context) {
           return encodeDeltaDag(std::move(hierarchy), options, context);
         };
       },
       [](const MapInfo& map) {
         return MhBuilder::hierarchyFloorBytes(map) / sizeof(MhNode) *
                (kHeldBytesPerNode + delta_dag::kFindingBytesPerPack);
       },
       {[](const MapInfo& map, const ParamValues& params, uint32_t partSize) {
          return delta_dag::partMerger(map, partSize, optionsOf(params), decoderOf);
        },
        kMergedBytesPerNode, delta_dag::kEncodeBytesPerNode, delta_dag::kFindingBytesPerPack}});
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues& params) -> std::unique_ptr<Decoder> {
    return std::make_unique<delta_dag::Decoder>(
        delta_dag::DeltaDag::load(in, map, optionsOf(params).skipBudget));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(deltaDag);

}  // namespace sb
