// Building a CPVS cube by cube (Sintorn §6.1 tiled construction; Kämpe §3 "insert" and
// "merge"): a cube's sparse voxel octree is inserted into a LocalSvo, merged into the global
// VoxelDagBuilder, and the tiles' columns of cubes are joined into the top of the octree — over
// the whole map, or over one part whose DAG and column the merge joins (voxel_dag_parts.h).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "schemes/interface/parts.h"
#include "schemes/shared/voxel_dag.h"

namespace sb {

// A child volume while the tree is built: homogeneous (lit, shadowed, or undefined — inside
// closed geometry or between the static layers, free to take either value), a node of the
// LocalSvo being built, or a node already in the DAG.
struct SvoChild {
  enum Kind : uint8_t { Lit, Shadowed, Undefined, Local, Global };
  Kind kind = Lit;
  uint32_t index = 0;

  static SvoChild of(DagRef ref) {
    return ref == kLitRef        ? SvoChild{Lit}
           : ref == kShadowedRef ? SvoChild{Shadowed}
                                 : SvoChild{Global, ref};
  }
  bool homogeneous() const { return kind <= Undefined; }
};

// Sintorn §6.1: once its children are known the parent decides the undefined ones — with only
// lit (or only shadowed) siblings they join them and the parent is homogeneous; next to both,
// they become shadowed. Returns the parent's kind: homogeneous, or Local when it needs a node.
SvoChild::Kind resolveByParent(std::array<SvoChild, 8>& children);
// The same rule for a parent of any arity, from which kinds its children hold: Lit, Shadowed or
// Undefined when it is homogeneous, else Local (its undefined children become shadowed).
SvoChild::Kind parentKind(bool lit, bool shadowed, bool nodes);

// The SVO nodes of one cube, inserted top-down and then merged bottom-up into the DAG.
class LocalSvo {
 public:
  explicit LocalSvo(VoxelDagShape shape);

  SvoChild addLeafmask(uint64_t litVoxels);
  SvoChild addNode(uint32_t depth, const std::array<SvoChild, 8>& children);

  // Moves every node into the DAG, deepest first, and gives the DAG reference of the root, a
  // child at `rootDepth` (an undefined root stays undefined).
  SvoChild merge(SvoChild root, uint32_t rootDepth, VoxelDagBuilder& dag);
  // After merge(): the DAG reference of a child at `depth` (leafParentDepth() + 1: a leafmask).
  SvoChild merged(SvoChild child, uint32_t depth) const;
  void clear();

  uint64_t inserted() const { return inserted_; }

 private:
  DagRef ref(SvoChild child, uint32_t depth) const;

  VoxelDagShape shape_;
  std::vector<uint64_t> leafmasks_;
  std::vector<DagRef> leafmaskRefs_;
  std::vector<std::vector<std::array<SvoChild, 8>>> nodes_;  // by depth
  std::vector<std::vector<DagRef>> nodeRefs_;
  uint64_t inserted_ = 0;
};

// The side of a tile the voxel schemes can build from: square, a power of two, at least 8.
// Throws std::invalid_argument otherwise.
uint32_t cubeTileSize(const DualDepthTile& tile);

// Joins the columns of cubes that the tiles of a region produce (tiles in Morton order, all of
// one size) into the levels of the octree above them, up to the region's side, resolving
// undefined volumes by the parent rule. The region is the whole map, one part of it (its column
// of cubes then stays open for the merge), or the whole map again when the merge joins the
// parts' columns as tiles of the part's side.
class TileColumns {
 public:
  TileColumns(VoxelDagShape shape, const MapPart& region) : shape_(shape), region_(region) {}

  // `cubes` are the tile's cubes of side `tileSize`, nearest the light first. Throws
  // std::invalid_argument for tiles of another size, outside the region or out of Morton order.
  void add(uint32_t x0, uint32_t y0, uint32_t tileSize, std::vector<SvoChild> cubes,
           VoxelDagBuilder& dag);
  // Once every tile has arrived: the region's column of cubes of its side, undefined ones kept.
  const std::vector<SvoChild>& column() const;
  // The root of a whole map's region (an undefined root is taken as lit).
  DagRef root() const;

 private:
  struct Column {
    uint32_t side;
    std::vector<SvoChild> cubes;
  };
  VoxelDagShape shape_;
  MapPart region_;
  std::vector<Column> stack_;
  uint32_t tileSize_ = 0;
  uint64_t tilesSeen_ = 0;
};

// The encoder both CPVS constructions share (Sintorn §6.1, tiled): per tile, its column of cubes
// is inserted cube by cube into the LocalSvo (phase "insert"), merged into the region's DAG
// ("merge") and joined to the levels above. Over the whole map it is the scheme's Encoder and
// finish() lays the DAG out; over one part it is the PartEncoder and finish() writes the part's
// DAG and column of cubes (voxel_dag_parts.h). A construction supplies the tile's preparation
// and the insertion of one cube.
class CubeColumnEncoder : public Encoder, public PartEncoder {
 public:
  CubeColumnEncoder(const MapInfo& map, VoxelDagConfig config, const MapPart& region);

  void consume(const DualDepthTile& tile, BuildContext& context) final;
  std::unique_ptr<Decoder> finish(BuildContext& context) final;
  void finish(ByteWriter& out, BuildContext& context) final;

 protected:
  // Everything the cubes of this tile need (slice runs, masks, pyramid), under phases it names.
  virtual void prepareTile(const DualDepthTile& tile, BuildContext& context) = 0;
  // The cube of side tileSize() at depth `depth` whose tile-local corner is (0, 0, z0).
  virtual SvoChild insertCube(uint32_t z0, uint32_t depth) = 0;
  // Called after each cube's merge, while svo_.merged() still knows its nodes.
  virtual void cubeMerged() {}
  virtual void countConstruction(BuildContext&) const {}

  uint32_t tileSize() const { return tileSize_; }
  uint32_t cubeDepth() const { return shape_.levels - uint32_t(std::countr_zero(tileSize_)); }

  VoxelDagShape shape_;
  LocalSvo svo_;

 private:
  void countInsertion(BuildContext& context) const;

  MapPart region_;
  uint32_t gridLevels_;
  VoxelDagBuilder dag_;
  TileColumns columns_;
  uint32_t tileSize_ = 0;
};

// A construction of one CPVS scheme over a region (the whole map, or a part).
using CubeColumnConstruction = std::function<std::unique_ptr<CubeColumnEncoder>(
    const MapInfo&, const VoxelDagConfig&, const ParamValues&, const MapPart& region)>;
// Gives a CPVS scheme its whole build and its build in parts from its construction.
void setCubeColumnBuilds(SchemeInfo& info, CubeColumnConstruction construction);

}  // namespace sb
