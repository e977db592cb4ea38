// The compact precomputed voxelized shadow (CPVS) DAG shared by `cpvs` and `cpvs-fast`: its
// node layout, the builder that keeps it globally minimal, and the decoder that answers point
// and exact PCF lookups from it (Sintorn et al. 2014 §4–§6; Kämpe et al. 2015 builds the same
// structure faster). Both schemes hand their nodes to VoxelDagBuilder and load with loadVoxelDag,
// so one lookup code reads both.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "schemes/interface/scheme.h"

namespace sb {

class ByteReader;

// Sintorn §4: the last three levels merge into 64-bit leafmasks of 4×4×4 voxels; §5: or 8×8×1
// voxels under parents split 1×1×8 in z, so a PCF kernel at one depth reads whole leafmasks.
enum class LeafLayout { Cube4, Slab8 };
LeafLayout leafLayoutFromString(std::string_view name);  // "cube4" or "slab8"

// A reference to a child volume: homogeneously lit, homogeneously shadowed, or a node (an id
// while building, a word offset in the final node array).
using DagRef = uint32_t;
inline constexpr DagRef kLitRef = 0xffffffffu, kShadowedRef = 0xfffffffeu;
inline bool isNodeRef(DagRef ref) {
  return ref < kShadowedRef;
}

// Sintorn §4: 16-bit childmasks, two bits per child.
inline constexpr uint32_t kChildLit = 0, kChildShadowed = 1, kChildPartial = 2;
// The childmask of a node whose children are all lit or all shadowed: never stored, the builder
// collapses such a node to kLitRef / kShadowedRef.
inline constexpr uint32_t kAllLitChildmask = 0, kAllShadowedChildmask = 0x5555;

// Bit 2c is set for each partial child c (code 0b10).
inline uint32_t partialBits(uint32_t header) {
  return (header >> 1) & ~header & 0x5555u;
}
// A node's words: its header, then one pointer per partial child.
inline uint32_t nodeWordCount(uint32_t header) {
  return 1 + uint32_t(std::popcount(partialBits(header)));
}

// The octree over R × R × R voxels (Rz = R): depth d holds cubes of side 2^(levels − d); the
// deepest node depth, levels − 3, holds the parents of the leafmasks (cubes of side 8).
struct VoxelDagShape {
  uint32_t levels = 0;  // log2 R
  LeafLayout layout = LeafLayout::Slab8;

  static VoxelDagShape of(const MapInfo& map, LeafLayout layout);
  uint32_t leafParentDepth() const { return levels - 3; }
  uint32_t side(uint32_t depth) const { return 1u << (levels - depth); }
  // The child of the node at `depth` containing voxel (x, y, z).
  uint32_t childIndex(uint32_t x, uint32_t y, uint32_t z, uint32_t depth) const {
    if (depth == leafParentDepth() && layout == LeafLayout::Slab8) return z & 7;
    const uint32_t bit = levels - depth - 1;
    return ((x >> bit) & 1) | ((y >> bit) & 1) << 1 | ((z >> bit) & 1) << 2;
  }
  // Leafmask footprint in x and y (4 or 8 texels) and the bit of voxel (x, y, z) in its leafmask.
  uint32_t leafSide() const { return layout == LeafLayout::Slab8 ? 8 : 4; }
  uint32_t leafBit(uint32_t x, uint32_t y, uint32_t z) const {
    return layout == LeafLayout::Slab8 ? (x & 7) | (y & 7) << 3
                                       : (x & 3) | (y & 3) << 2 | (z & 3) << 4;
  }
  // The volume one leafmask covers, in voxels.
  uint64_t leafVolume() const { return 64; }
};

// The cube4 leafmask (bit x + 4y + 16z) of the 4×4 quadrant (quadrantX, quadrantY) of an 8×8
// block over four consecutive slices, from the block's 8×8 masks of those slices (bit x + 8y).
inline uint64_t cube4FromSlabs(const uint64_t (&slabs)[4], uint32_t quadrantX, uint32_t quadrantY) {
  uint64_t cube = 0;
  for (uint32_t dz = 0; dz < 4; ++dz) {
    const uint64_t slab = slabs[dz] >> (32 * quadrantY + 4 * quadrantX);
    for (uint32_t dy = 0; dy < 4; ++dy) cube |= (slab >> (8 * dy) & 0xf) << (16 * dz + 4 * dy);
  }
  return cube;
}

// The registry row every CPVS-format scheme starts from: voxel kind, the parameters of the
// structure (leaf layout, top-level grid), the build memory (a tile's working arrays; the DAG is
// what the build produces) and the loader. A scheme adds its own parameters and encoder.
SchemeInfo voxelDagScheme(std::string name, std::string paper);

// The structure's parameter values for a map: the grid replaces at most the levels above the
// leaf parents.
struct VoxelDagConfig {
  LeafLayout layout;
  uint32_t gridLevels;
};
VoxelDagConfig voxelDagConfig(const MapInfo& map, const ParamValues& params);

// The final structure. Nodes are stored depth by depth from the grid's depth down to the leaf
// parents: a header word (childmask in the low 16 bits; the VOAA occupancy, the fraction of the
// node's voxels that are lit in 1/65535ths, in the high 16 — Sintorn §5), then one 32-bit
// pointer per partial child in child order: a word offset into `nodes`, or, from a leaf parent,
// an index into `leafmasks` (bit set = lit voxel).
struct VoxelDag {
  VoxelDagShape shape;
  uint32_t gridLevels = 0;
  std::vector<DagRef> grid;  // (2^gridLevels)³ refs to the nodes at depth gridLevels
  std::vector<uint32_t> nodes;
  std::vector<uint64_t> leafmasks;
  std::vector<uint32_t> depthBegin;  // word offset where each stored depth starts, and the end
};

// Keeps the DAG globally minimal while it is built: every node and leafmask is looked up by its
// full content in its depth's table before it is added (Kämpe 2013 merging), and homogeneous
// ones collapse to kLitRef / kShadowedRef, so two volumes with identical voxels always get the
// same reference.
class VoxelDagBuilder {
 public:
  explicit VoxelDagBuilder(VoxelDagShape shape);
  ~VoxelDagBuilder();

  DagRef leafmask(uint64_t litVoxels);
  // A node at `depth` from its children's references (ids at depth + 1, or leafmask ids).
  DagRef node(uint32_t depth, const std::array<DagRef, 8>& children);

  const VoxelDagShape& shape() const { return shape_; }
  uint64_t nodeCount() const;
  uint64_t leafmaskCount() const;
  // The distinct nodes at `depth` in id order, each as its header (childmask only) and one id
  // per partial child; the distinct leafmasks in id order. What a part payload carries.
  std::span<const uint32_t> storedNodes(uint32_t depth) const;
  std::span<const uint64_t> storedLeafmasks() const;

  // Lays the DAG out for lookups with the top `gridLevels` levels replaced by a grid.
  VoxelDag finish(DagRef root, uint32_t gridLevels);

 private:
  struct Table;
  VoxelDagShape shape_;
  std::vector<std::unique_ptr<Table>> depths_;  // one per node depth
  std::unique_ptr<Table> leafmasks_;
};

std::unique_ptr<Decoder> makeVoxelDagDecoder(VoxelDag dag);
// The end of every CPVS build, whole or merged from parts: the DAG laid out under `root` with
// its counters ("dag nodes", "dag leafmasks") reported.
std::unique_ptr<Decoder> finishVoxelDag(VoxelDagBuilder& dag, DagRef root, uint32_t gridLevels,
                                        BuildContext& context);
// Reads and validates what the decoder's save() wrote; throws FormatError.
std::unique_ptr<Decoder> loadVoxelDag(ByteReader& in, const VoxelDagShape& shape,
                                      uint32_t gridLevels);

}  // namespace sb
