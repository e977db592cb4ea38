#include "schemes/shared/voxel_dag_parts.h"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "schemes/interface/serial.h"
#include "schemes/shared/child_flags.h"

namespace sb {

namespace {

// The depth of the cubes of side `partSize`: the depth of a part's column.
uint32_t columnDepth(const VoxelDagShape& shape, uint32_t partSize) {
  return shape.levels - uint32_t(std::countr_zero(partSize));
}

}  // namespace

void writeVoxelDagPart(ByteWriter& out, const VoxelDagBuilder& dag, const MapPart& region,
                       std::span<const SvoChild> column) {
  const VoxelDagShape& shape = dag.shape();
  out.putArray<uint64_t>(dag.storedLeafmasks());
  for (uint32_t d = shape.leafParentDepth() + 1; d-- > columnDepth(shape, region.size);)
    out.putArray<uint32_t>(dag.storedNodes(d));
  std::vector<uint32_t> cubes(column.size());
  for (size_t m = 0; m < column.size(); ++m)
    cubes[m] = column[m].kind == SvoChild::Lit         ? kLitRef
               : column[m].kind == SvoChild::Shadowed  ? kShadowedRef
               : column[m].kind == SvoChild::Undefined ? kUndefinedCube
                                                       : column[m].index;
  out.putArray<uint32_t>(cubes);
}

VoxelDagPartMerger::VoxelDagPartMerger(const MapInfo& map, VoxelDagConfig config, uint32_t partSize)
    : shape_(VoxelDagShape::of(map, config.layout)),
      gridLevels_(config.gridLevels),
      partSize_(partSize),
      dag_(shape_),
      columns_(shape_, MapPart::of(0, map.resolution)) {
  if (!std::has_single_bit(partSize) || partSize < 8 || partSize > map.resolution)
    throw std::invalid_argument(
        fmt::format("CPVS: part size {} is not a power of two from 8 to the resolution {}",
                    partSize, map.resolution));
}

void VoxelDagPartMerger::add(const MapPart& part, ByteReader& payload, BuildContext& context) {
  const MapPart expected = MapPart::of(partsSeen_, partSize_);
  if (part.size != partSize_ || part.index != partsSeen_ || part.x0 != expected.x0 ||
      part.y0 != expected.y0)
    throw std::invalid_argument(fmt::format(
        "CPVS: part {} ({}² at ({}, {})) arrived where part {} ({}² at ({}, {})) was "
        "expected",
        part.index, part.size, part.x0, part.y0, partsSeen_, partSize_, expected.x0, expected.y0));
  context.phase("merge parts");
  // The whole payload is validated before any of it enters the DAG, so that a refused part
  // leaves the merge as it was.
  Payload read;
  try {
    read = this->read(payload);
  } catch (const FormatError& error) {
    throw FormatError(fmt::format("part {}: {}", part.index, error.what()));
  }
  columns_.add(part.x0, part.y0, part.size, insert(read), dag_);
  ++partsSeen_;
}

VoxelDagPartMerger::Payload VoxelDagPartMerger::read(ByteReader& in) const {
  Payload part;
  part.leafmasks = in.getArray<uint64_t>("CPVS part leafmasks");
  for (size_t id = 0; id < part.leafmasks.size(); ++id)
    if (part.leafmasks[id] == 0 || part.leafmasks[id] == ~uint64_t(0))
      throw FormatError(fmt::format("CPVS part: leafmask {} is homogeneous", id));

  // Whether a node or the column references each id of the depth below (leafmasks first): the
  // part encoder writes only what its column reaches.
  std::vector<bool> referenced(part.leafmasks.size(), false);
  auto checkReferenced = [&](const char* what, uint32_t depth) {
    for (size_t id = 0; id < referenced.size(); ++id)
      if (!referenced[id])
        throw FormatError(
            fmt::format("CPVS part: {} {} at depth {} is referenced by nothing", what, id, depth));
  };
  const uint32_t leafParent = shape_.leafParentDepth(), top = columnDepth(shape_, partSize_);
  for (uint32_t d = leafParent + 1; d-- > top;) {
    std::vector<uint32_t>& words =
        part.nodes.emplace_back(in.getArray<uint32_t>("CPVS part nodes"));
    uint32_t count = 0;
    for (size_t w = 0; w < words.size(); w += nodeWordCount(words[w]), ++count) {
      const uint32_t header = words[w];
      if (header > 0xffffu || header == kAllLitChildmask || header == kAllShadowedChildmask)
        throw FormatError(
            fmt::format("CPVS part: node header {:#x} at word {} of depth {}", header, w, d));
      for (uint32_t c = 0; c < 8; ++c)
        if (childFlag(header, int(c)) == 3)
          throw FormatError(fmt::format(
              "CPVS part: invalid child code in the node at word {} of depth {}", w, d));
      if (w + nodeWordCount(header) > words.size())
        throw FormatError(fmt::format("CPVS part: the node at word {} overruns depth {}", w, d));
      for (uint32_t p = 1; p < nodeWordCount(header); ++p) {
        const uint32_t id = words[w + p];
        if (id >= referenced.size())
          throw FormatError(
              fmt::format("CPVS part: the node at word {} of depth {} names child "
                          "{} of {}",
                          w, d, id, referenced.size()));
        referenced[id] = true;
      }
    }
    checkReferenced(d == leafParent ? "leafmask" : "node", d + 1);
    referenced.assign(count, false);
  }

  const uint32_t cubeCount = (1u << shape_.levels) / partSize_;
  part.column = in.getArray<uint32_t>("CPVS part column", cubeCount);
  for (uint32_t m = 0; m < cubeCount; ++m) {
    const uint32_t cube = part.column[m];
    if (cube < referenced.size())
      referenced[cube] = true;
    else if (cube != kLitRef && cube != kShadowedRef && cube != kUndefinedCube)
      throw FormatError(
          fmt::format("CPVS part: column cube {} names node {} of {}", m, cube, referenced.size()));
  }
  checkReferenced("node", top);
  return part;
}

std::vector<SvoChild> VoxelDagPartMerger::insert(const Payload& part) {
  std::vector<DagRef> below(part.leafmasks.size());
  for (size_t id = 0; id < part.leafmasks.size(); ++id)
    below[id] = dag_.leafmask(part.leafmasks[id]);
  uint32_t depth = shape_.leafParentDepth();
  for (const std::vector<uint32_t>& words : part.nodes) {
    std::vector<DagRef> inserted;
    for (size_t w = 0; w < words.size(); w += nodeWordCount(words[w])) {
      std::array<DagRef, 8> children;
      for (uint32_t c = 0, slot = 1; c < 8; ++c) {
        const uint32_t code = childFlag(words[w], int(c));
        children[c] = code == kChildLit        ? kLitRef
                      : code == kChildShadowed ? kShadowedRef
                                               : below[words[w + slot++]];
      }
      inserted.push_back(dag_.node(depth, children));
    }
    below = std::move(inserted);
    --depth;
  }
  std::vector<SvoChild> column(part.column.size());
  for (size_t m = 0; m < column.size(); ++m) {
    const uint32_t cube = part.column[m];
    column[m] = cube == kLitRef          ? SvoChild{SvoChild::Lit}
                : cube == kShadowedRef   ? SvoChild{SvoChild::Shadowed}
                : cube == kUndefinedCube ? SvoChild{SvoChild::Undefined}
                                         : SvoChild{SvoChild::Global, below[cube]};
  }
  return column;
}

std::unique_ptr<Decoder> VoxelDagPartMerger::finish(BuildContext& context) {
  context.phase("merge parts");
  return finishVoxelDag(dag_, columns_.root(), gridLevels_, context);
}

}  // namespace sb
