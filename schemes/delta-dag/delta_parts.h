// delta-dag's merge of parts without the whole hierarchy. The MH-family part payloads
// (mh_parts.h) are read twice:
//   1. each part's root alone (readMhPartRoot) goes to the builder of the levels above the parts
//      (as a whole build joins tile roots), which then choose their values top-down, down to
//      each part's root;
//   2. each part's values are chosen below its root's key and its packs found (pack_finder.h),
//      and the levels above are found as far as the whole hierarchy orders their nodes before
//      the next part's.
// The packs are found in the whole build's order, so they get the same ids, and the structure is
// the whole build's, byte for byte. The merge holds the packs found and one part.
#pragma once

#include <functional>
#include <memory>

#include "schemes/delta-dag/delta_dag.h"
#include "schemes/interface/parts.h"

namespace sb::delta_dag {

using Decoding = std::function<std::unique_ptr<sb::Decoder>(Encoded, BuildContext&)>;

std::unique_ptr<PartMerger> partMerger(const MapInfo& map, uint32_t partSize,
                                       const Options& options, Decoding decoder);

}  // namespace sb::delta_dag
