#include "schemes/shared/svo.h"

#include <stdexcept>

#include <fmt/format.h>

#include "schemes/interface/morton.h"
#include "schemes/shared/voxel_dag_parts.h"

namespace sb {

SvoChild::Kind resolveByParent(std::array<SvoChild, 8>& children) {
  bool lit = false, shadowed = false, undefined = false, nodes = false;
  for (const SvoChild& child : children) {
    lit |= child.kind == SvoChild::Lit;
    shadowed |= child.kind == SvoChild::Shadowed;
    undefined |= child.kind == SvoChild::Undefined;
    nodes |= !child.homogeneous();
  }
  const SvoChild::Kind kind = parentKind(lit, shadowed, nodes);
  if (kind == SvoChild::Local && undefined)
    for (SvoChild& child : children)
      if (child.kind == SvoChild::Undefined) child.kind = SvoChild::Shadowed;
  return kind;
}

SvoChild::Kind parentKind(bool lit, bool shadowed, bool nodes) {
  if (nodes || (lit && shadowed)) return SvoChild::Local;
  return lit ? SvoChild::Lit : shadowed ? SvoChild::Shadowed : SvoChild::Undefined;
}

LocalSvo::LocalSvo(VoxelDagShape shape)
    : shape_(shape), nodes_(shape.leafParentDepth() + 1), nodeRefs_(shape.leafParentDepth() + 1) {}

SvoChild LocalSvo::addLeafmask(uint64_t litVoxels) {
  if (litVoxels == ~uint64_t(0)) return {SvoChild::Lit};
  if (litVoxels == 0) return {SvoChild::Shadowed};
  ++inserted_;
  leafmasks_.push_back(litVoxels);
  return {SvoChild::Local, uint32_t(leafmasks_.size() - 1)};
}

SvoChild LocalSvo::addNode(uint32_t depth, const std::array<SvoChild, 8>& children) {
  ++inserted_;
  nodes_[depth].push_back(children);
  return {SvoChild::Local, uint32_t(nodes_[depth].size() - 1)};
}

DagRef LocalSvo::ref(SvoChild child, uint32_t depth) const {
  switch (child.kind) {
    case SvoChild::Lit:
      return kLitRef;
    case SvoChild::Shadowed:
    case SvoChild::Undefined:
      return kShadowedRef;
    case SvoChild::Global:
      return child.index;
    case SvoChild::Local:
      return depth > shape_.leafParentDepth() ? leafmaskRefs_[child.index]
                                              : nodeRefs_[depth][child.index];
  }
  return kShadowedRef;
}

SvoChild LocalSvo::merge(SvoChild root, uint32_t rootDepth, VoxelDagBuilder& dag) {
  leafmaskRefs_.resize(leafmasks_.size());
  for (size_t i = 0; i < leafmasks_.size(); ++i) leafmaskRefs_[i] = dag.leafmask(leafmasks_[i]);
  for (uint32_t d = shape_.leafParentDepth() + 1; d-- > 0;) {
    nodeRefs_[d].resize(nodes_[d].size());
    std::array<DagRef, 8> refs;
    for (size_t i = 0; i < nodes_[d].size(); ++i) {
      for (uint32_t c = 0; c < 8; ++c) refs[c] = ref(nodes_[d][i][c], d + 1);
      nodeRefs_[d][i] = dag.node(d, refs);
    }
  }
  return merged(root, rootDepth);
}

SvoChild LocalSvo::merged(SvoChild child, uint32_t depth) const {
  return child.kind == SvoChild::Local ? SvoChild::of(ref(child, depth)) : child;
}

void LocalSvo::clear() {
  leafmasks_.clear();
  for (auto& level : nodes_) level.clear();
}

uint32_t cubeTileSize(const DualDepthTile& tile) {
  if (tile.width != tile.height || tile.width < 8 || (tile.width & (tile.width - 1)) != 0)
    throw std::invalid_argument(
        fmt::format("CPVS: tiles must be square with a power-of-two side of at least 8, got {}×{}",
                    tile.width, tile.height));
  return tile.width;
}

void TileColumns::add(uint32_t x0, uint32_t y0, uint32_t tileSize, std::vector<SvoChild> cubes,
                      VoxelDagBuilder& dag) {
  if (tileSize_ == 0) tileSize_ = tileSize;
  // A region's tiles are a run of the map's Morton order, starting at its corner's tile.
  const uint64_t first = mortonCode(region_.x0 / tileSize, region_.y0 / tileSize);
  if (tileSize != tileSize_ || tileSize > region_.size || x0 % tileSize != 0 ||
      y0 % tileSize != 0 || x0 < region_.x0 || y0 < region_.y0 || x0 - region_.x0 >= region_.size ||
      y0 - region_.y0 >= region_.size ||
      mortonCode(x0 / tileSize, y0 / tileSize) != first + tilesSeen_)
    throw std::invalid_argument(fmt::format(
        "CPVS: tile at ({}, {}) of size {} is out of Morton order, of another size or outside "
        "the {}² region at ({}, {})",
        x0, y0, tileSize, region_.size, region_.x0, region_.y0));
  ++tilesSeen_;
  stack_.push_back({tileSize, std::move(cubes)});
  const uint32_t resolution = 1u << shape_.levels;
  // Four columns of one size in a row are the quadrants of the next (Morton order).
  while (stack_.size() >= 4 && stack_.back().side < region_.size &&
         stack_[stack_.size() - 4].side == stack_.back().side) {
    const uint32_t side = stack_.back().side * 2;
    const uint32_t depth = shape_.levels - uint32_t(std::countr_zero(side));
    const Column* quadrants = &stack_[stack_.size() - 4];
    Column parent{side, std::vector<SvoChild>(resolution / side)};
    for (uint32_t m = 0; m < parent.cubes.size(); ++m) {
      std::array<SvoChild, 8> children;
      for (uint32_t c = 0; c < 8; ++c) children[c] = quadrants[c & 3].cubes[2 * m + (c >> 2)];
      const SvoChild::Kind kind = resolveByParent(children);
      if (kind != SvoChild::Local) {
        parent.cubes[m] = {kind};
        continue;
      }
      std::array<DagRef, 8> refs;
      for (uint32_t c = 0; c < 8; ++c)
        refs[c] = children[c].kind == SvoChild::Lit        ? kLitRef
                  : children[c].kind == SvoChild::Shadowed ? kShadowedRef
                                                           : children[c].index;
      parent.cubes[m] = SvoChild::of(dag.node(depth, refs));
    }
    stack_.resize(stack_.size() - 4);
    stack_.push_back(std::move(parent));
  }
}

const std::vector<SvoChild>& TileColumns::column() const {
  if (stack_.size() != 1 || stack_[0].side != region_.size)
    throw std::logic_error(fmt::format("CPVS: not every tile of the {}² region at ({}, {}) arrived",
                                       region_.size, region_.x0, region_.y0));
  return stack_[0].cubes;
}

DagRef TileColumns::root() const {
  if (region_.size != (1u << shape_.levels))
    throw std::logic_error("CPVS: a part's region has no root");
  const SvoChild root = column()[0];
  return root.kind == SvoChild::Shadowed ? kShadowedRef
         : root.kind == SvoChild::Global ? root.index
                                         : kLitRef;
}

CubeColumnEncoder::CubeColumnEncoder(const MapInfo& map, VoxelDagConfig config,
                                     const MapPart& region)
    : shape_(VoxelDagShape::of(map, config.layout)),
      svo_(shape_),
      region_(region),
      gridLevels_(config.gridLevels),
      dag_(shape_),
      columns_(shape_, region) {}

void CubeColumnEncoder::consume(const DualDepthTile& tile, BuildContext& context) {
  tileSize_ = cubeTileSize(tile);
  prepareTile(tile, context);
  std::vector<SvoChild> cubes(shape_.side(0) / tileSize_);
  for (uint32_t m = 0; m < cubes.size(); ++m) {
    context.phase("insert");
    const SvoChild root = insertCube(m * tileSize_, cubeDepth());
    context.phase("merge");
    cubes[m] = svo_.merge(root, cubeDepth(), dag_);
    cubeMerged();
    svo_.clear();
  }
  columns_.add(tile.x0, tile.y0, tileSize_, std::move(cubes), dag_);
}

void CubeColumnEncoder::countInsertion(BuildContext& context) const {
  context.count("svo nodes inserted", svo_.inserted());
  countConstruction(context);
}

std::unique_ptr<Decoder> CubeColumnEncoder::finish(BuildContext& context) {
  context.phase("merge");
  countInsertion(context);
  return finishVoxelDag(dag_, columns_.root(), gridLevels_, context);
}

void CubeColumnEncoder::finish(ByteWriter& out, BuildContext& context) {
  context.phase("merge");
  countInsertion(context);
  writeVoxelDagPart(out, dag_, region_, columns_.column());
}

void setCubeColumnBuilds(SchemeInfo& info, CubeColumnConstruction construction) {
  info.makeEncoder = [construction](const MapInfo& map, const ParamValues& params,
                                    const BuildShape&) -> std::unique_ptr<Encoder> {
    return construction(map, voxelDagConfig(map, params), params, MapPart::of(0, map.resolution));
  };
  info.makePartEncoder = [construction](const MapInfo& map, const MapPart& part,
                                        const ParamValues& params,
                                        const BuildShape&) -> std::unique_ptr<PartEncoder> {
    return construction(map, voxelDagConfig(map, params), params, part);
  };
  info.makePartMerger = [](const MapInfo& map, const ParamValues& params,
                           const BuildShape& shape) -> std::unique_ptr<PartMerger> {
    return std::make_unique<VoxelDagPartMerger>(map, voxelDagConfig(map, params), shape.partSize);
  };
}

}  // namespace sb
