// dag-mh's merge of parts without the whole hierarchy (issue 12). The MH-family part payloads
// (mh_parts.h) are read twice:
//   1. each part's root goes to the builder of the levels above the parts (as a whole build
//      joins tile roots), with the height and value count of the part's tree;
//   2. each part's inner nodes and treelets go into the DAG (DagBuilder, stored once across
//      parts), its skip-list entries are walked from its root, and its values join the value
//      list in depth-first order, behind those of the levels above that come first.
// The levels above go last, with the small parts' trees grafted under them (a treelet may span
// the part border) and the other parts' roots standing in for their trees. The structure answers
// every lookup as the whole build does and has its size; only the order of the DAG's nodes, and
// so the words that point at them, differ.
#pragma once

#include <functional>
#include <memory>

#include "schemes/dag-mh/dag.h"
#include "schemes/dag-mh/value_chunks.h"
#include "schemes/interface/parts.h"

namespace sb::dag_mh {

struct DagShape {
  int treeletHeight = 4, skipLevel = 6;  // skipLevel clamped to the map's levels
  uint32_t chunkSize = 32;
};

// The merge's result, which dag_mh.cpp turns into its decoder.
using DagDecoding = std::function<std::unique_ptr<Decoder>(Dag, ValueChunks, const ValueChunkStats&,
                                                           BuildContext&)>;

std::unique_ptr<PartMerger> dagPartMerger(const MapInfo& map, uint32_t partSize, DagShape shape,
                                          DagDecoding decoder);

}  // namespace sb::dag_mh
