// dag-mh — DAG encoding for compressed shadow maps (Scandolo & Eisemann 2021). The
// multiresolution hierarchy of the dual depth map (schemes/shared/multires_hierarchy.h) is split
// into its topology, stored as a DAG of inner nodes and treelets (dag.h, treelet.h), and its
// values, listed depth-first and compressed in chunks (value_chunks.h). A lookup walks the DAG
// from the skip list to the index of the texel's value and reads the value from its chunk.
#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "schemes/dag-mh/dag.h"
#include "schemes/dag-mh/dag_parts.h"
#include "schemes/dag-mh/value_chunks.h"
#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/mh_parts.h"

namespace sb {
namespace {

using dag_mh::Dag;
using dag_mh::DagShape;
using dag_mh::ValueChunks;

DagShape dagShape(const MapInfo& map, const ParamValues& params) {
  const int levels = std::countr_zero(map.resolution);
  return {int(params.integer("treelet-height")),
          std::min(int(params.integer("skip-level")), levels),
          uint32_t(params.integer("chunk-size"))};
}

class DagMhDecoder final : public DepthDecoder<DagMhDecoder> {
 public:
  DagMhDecoder(uint32_t resolution, Dag dag, ValueChunks values)
      : resolution_(resolution), dag_(std::move(dag)), values_(std::move(values)) {}

  uint32_t resolution() const { return resolution_; }
  float depth(uint32_t i, uint32_t j) const { return values_.value(dag_.valueIndex(i, j)); }
  uint64_t litTexels(const TexelRect& rect, float z) const {
    // Neighbouring blocks often hold one value (missing children answer the value above): each
    // run of one index is decoded from its chunk once.
    uint64_t lit = 0;
    uint32_t lastIndex = ValueChunks::kMaxValues;  // no index yet
    bool lastLit = false;
    dag_.forEachValueBlock(rect, [&](uint32_t index, uint64_t texels) {
      if (index != lastIndex) lastLit = z <= values_.value(lastIndex = index);
      lit += lastLit ? texels : 0;
    });
    return lit;
  }

  SizeBreakdown size() const override {
    return {{"inner nodes", dag_.innerNodes.size() * sizeof(uint32_t)},
            {"treelets", dag_.treelets.size() * sizeof(uint32_t)},
            {"chunk infos", values_.infoSize()},
            {"chunk factors", values_.factorSize()},
            {"skip list", dag_.skipList.size() * sizeof(uint32_t)}};
  }

  // Payload: u32 treelet height, u32 chunk size, u32 skip level (clamped), u32 value count, then
  // the arrays of Dag::save and ValueChunks::save.
  void save(ByteWriter& out) const override {
    out.put<uint32_t>(uint32_t(dag_.treelet.height));
    out.put<uint32_t>(values_.chunkSize());
    out.put<uint32_t>(uint32_t(dag_.skipLevel));
    out.put<uint32_t>(values_.valueCount());
    dag_.save(out);
    values_.save(out);
  }

 private:
  uint32_t resolution_;
  Dag dag_;
  ValueChunks values_;
};

std::unique_ptr<Decoder> dagMhDecoder(uint32_t resolution, Dag dag, ValueChunks values,
                                      const dag_mh::ValueChunkStats& stats, BuildContext& context) {
  context.count("inner nodes", dag.innerNodeCount());
  context.count("treelets", dag.treeletCount());
  context.count("values", values.valueCount());
  context.count("values covered by representative", stats.covered);
  context.count("factor values", stats.factors);
  context.count("factor bits", stats.factorBits);
  context.count("chunks", values.infoSize() / values.infoBytes());
  return std::make_unique<DagMhDecoder>(resolution, std::move(dag), std::move(values));
}

std::unique_ptr<Decoder> encodeDagMh(MultiresHierarchy hierarchy, uint32_t resolution,
                                     DagShape config, BuildContext& context) {
  context.phase("dag");
  dag_mh::DagBuild built = dag_mh::buildDag(hierarchy, config.treeletHeight, config.skipLevel);
  hierarchy = {};  // the values phase needs only the DAG and the value intervals
  context.phase("values");
  dag_mh::ValueChunkStats stats;
  ValueChunks values(built.values, config.chunkSize, &stats);
  return dagMhDecoder(resolution, std::move(built.dag), std::move(values), stats, context);
}

SchemeInfo dagMh() {
  SchemeInfo info;
  info.name = "dag-mh";
  info.paper = "Scandolo & Eisemann 2021, DAG encoding for compressed shadow maps";
  info.kind = SchemeKind::Depth;
  info.params = {
      ParamSpec::integer("treelet-height",
                         "levels a treelet spans: subtrees this low are bitmaps instead of inner "
                         "nodes (§3.2; §4.3 finds 4 best)",
                         4, 1, 5, {2, 3, 4, 5}),
      ParamSpec::integer("chunk-size",
                         "values per chunk of the value list: one representative and factor "
                         "size each (§3.3; Table 4 finds 32 best)",
                         32, 16, 128, {16, 32, 64, 128})
          .satisfying("one of 16, 32, 64, 128",
                      [](int64_t size) { return std::has_single_bit(uint64_t(size)); }),
      ParamSpec::integer("skip-level",
                         "level whose nodes a dense skip list holds, where lookups start (§3.7); "
                         "0 = the root alone; capped at log2 R",
                         6, 0, 10, {0, 6}),
  };
  // A whole build holds the hierarchy (16 bytes a node), then per node a height, a descendant
  // count, a DAG reference and a flag (14 bytes), and the value intervals (8 bytes each).
  // Hierarchies keep a fraction of the texels as nodes (a tenth on the full city), and the
  // format caps values at 2^24. A merge of parts holds the DAG and the chunked values it grows
  // (measured 2.0 bytes a node of the structure on the forest, 1.4 on the city, 2.3 with the hash
  // tables: 5 declared) and one part with its attributes (14 bytes a node: dag_parts.h).
  setMhBuilds(info, {[](const MapInfo& map, const ParamValues& params) -> HierarchyEncode {
                       return [resolution = map.resolution, config = dagShape(map, params)](
                                  MultiresHierarchy hierarchy, BuildContext& context) {
                         return encodeDagMh(std::move(hierarchy), resolution, config, context);
                       };
                     },
                     [](const MapInfo& map) {
                       return std::min<uint64_t>(map.texelCount() / 2, uint64_t(1) << 26) * 32;
                     },
                     {[](const MapInfo& map, const ParamValues& params, uint32_t partSize) {
                        return dag_mh::dagPartMerger(
                            map, partSize, dagShape(map, params),
                            [resolution = map.resolution](Dag dag, ValueChunks values,
                                                          const dag_mh::ValueChunkStats& stats,
                                                          BuildContext& context) {
                              return dagMhDecoder(resolution, std::move(dag), std::move(values),
                                                  stats, context);
                            });
                      },
                      5, 14}});
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues& params) -> std::unique_ptr<Decoder> {
    if (!validResolution(map.resolution))
      throw FormatError(
          fmt::format("dag-mh: resolution {} is not a valid map size", map.resolution));
    const DagShape config = dagShape(map, params);
    const auto expect = [&](const char* what, uint32_t wanted) {
      const uint32_t stored = in.get<uint32_t>(what);
      if (stored != wanted)
        throw FormatError(
            fmt::format("{}: {} stored, the parameters give {}", what, stored, wanted));
    };
    expect("dag-mh treelet height", uint32_t(config.treeletHeight));
    expect("dag-mh chunk size", config.chunkSize);
    expect("dag-mh skip level", uint32_t(config.skipLevel));
    const uint32_t valueCount = in.get<uint32_t>("dag-mh value count");
    if (valueCount == 0 || valueCount > ValueChunks::kMaxValues)
      throw FormatError(fmt::format("dag-mh value count: {} is not in [1, {}]", valueCount,
                                    ValueChunks::kMaxValues));
    Dag dag = Dag::load(in, std::countr_zero(map.resolution), config.treeletHeight,
                        config.skipLevel, valueCount);
    ValueChunks values = ValueChunks::load(in, config.chunkSize, valueCount);
    return std::make_unique<DagMhDecoder>(map.resolution, std::move(dag), std::move(values));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(dagMh);

}  // namespace sb
