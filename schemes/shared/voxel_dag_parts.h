// A CPVS built in parts (parts.h): each part is built as the whole map is, tile by tile into a
// DAG of its own, but stops at the part's column of cubes; the merge re-inserts every part's
// nodes into one DAG that hash-conses across parts, and joins the parts' columns as the whole
// build joins its tiles' columns (TileColumns). Sintorn §6.1 builds high resolutions this way:
// sub-DAGs of tiles combined into the final minimal DAG. The merged DAG holds exactly the whole
// build's nodes, so a part border costs no byte.
//
// Part payload (little-endian; arrays are a u64 count, then the elements):
//   u64[]  the part's distinct leafmasks, id order (never all lit or all shadowed)
//   u32[]  per node depth, from the leaf parents up to the part's column depth (log2 R/P): the
//          depth's distinct nodes in id order, each a childmask word (bits 0–15, no code 3, not
//          all lit or all shadowed) and one id per partial child: a leafmask id below the leaf
//          parents, else a node id of the depth below; every id below is referenced
//   u32[]  the part's column, R/P cubes of side P nearest the light first: kLitRef,
//          kShadowedRef, kUndefinedCube, or a node id of the column depth
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "schemes/interface/parts.h"
#include "schemes/shared/svo.h"

namespace sb {

// A cube of a part's column left undefined: the merge decides it with its siblings.
inline constexpr uint32_t kUndefinedCube = 0xfffffffdu;

// The payload of the part `region` from its DAG and its column of cubes.
void writeVoxelDagPart(ByteWriter& out, const VoxelDagBuilder& dag, const MapPart& region,
                       std::span<const SvoChild> column);

// Joins part payloads, parts in index order, into the final CPVS. Holds the global DAG and one
// part's payload with its id mapping.
class VoxelDagPartMerger final : public PartMerger {
 public:
  VoxelDagPartMerger(const MapInfo& map, VoxelDagConfig config, uint32_t partSize);

  // Throws FormatError naming the part for a payload the part encoder would not write.
  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override;
  std::unique_ptr<Decoder> finish(BuildContext& context) override;

 private:
  struct Payload {
    std::vector<uint64_t> leafmasks;
    std::vector<std::vector<uint32_t>> nodes;  // words by depth, the leaf parents first
    std::vector<uint32_t> column;
  };
  // Reads and validates a whole payload; throws FormatError.
  Payload read(ByteReader& in) const;
  // Re-inserts the part's nodes deepest first; returns its column in global references.
  std::vector<SvoChild> insert(const Payload& part);

  VoxelDagShape shape_;
  uint32_t gridLevels_, partSize_;
  VoxelDagBuilder dag_;
  TileColumns columns_;
  uint64_t partsSeen_ = 0;
};

}  // namespace sb
