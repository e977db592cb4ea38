#include "schemes/shared/voxel_dag.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "schemes/interface/capabilities.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"
#include "schemes/shared/child_flags.h"
#include "schemes/shared/hash_cons.h"

namespace sb {

LeafLayout leafLayoutFromString(std::string_view name) {
  if (name == "cube4") return LeafLayout::Cube4;
  if (name == "slab8") return LeafLayout::Slab8;
  throw std::invalid_argument(fmt::format("unknown leaf layout '{}' (cube4 or slab8)", name));
}

VoxelDagShape VoxelDagShape::of(const MapInfo& map, LeafLayout layout) {
  if (!validResolution(map.resolution) || map.depthResolution != map.resolution)
    throw std::invalid_argument(
        fmt::format("CPVS needs a cube of voxels: resolution {} with {} depth slices",
                    map.resolution, map.depthResolution));
  return {uint32_t(std::countr_zero(map.resolution)), layout};
}

namespace {

// What a CPVS build holds beside its tiles and its DAG: the harness's tile buffers and the
// allocator's slack (measured above the process's baseline on city closed at 2K²: 34 MiB).
constexpr uint64_t kBuildSlackBytes = uint64_t(32) << 20;
// Bytes a build holds per byte of the final DAG at its peak: while the DAG grows, each node's
// words, its offset, its hash and two slots of a table kept at most half full (about 3×); at
// the end the laid-out copy and the lit counts of every node (measured: 4.7× on city closed from
// 8K² to 256K²).
constexpr uint64_t kDagBuildFactor = 5;

// The DAG a CPVS of side R grows to. With closed objects it scales as the silhouettes, a curve
// (Kämpe 2015 §3.1), and hash-consing shares more as R grows: measured on cpvs-fast city:full
// closed, 9.9 MiB at 4K², 29.7 MiB at 16K², 244 MiB at 256K² (issue 12), i.e. R^0.77.
uint64_t expectedDagBytes(uint32_t resolution) {
  return uint64_t(10.0 * double(1 << 20) * std::pow(double(resolution) / 4096.0, 0.77));
}

}  // namespace

SchemeInfo voxelDagScheme(std::string name, std::string paper) {
  SchemeInfo info;
  info.name = name;
  info.paper = std::move(paper);
  info.kind = SchemeKind::Voxel;
  info.params = {
      ParamSpec::choice("leaf-layout",
                        "leafmask shape: cube4 (4×4×4 voxels, Sintorn §4) or slab8 (8×8×1 under "
                        "1×1×8 parents, for PCF, §5)",
                        "slab8", {"cube4", "slab8"}, {"cube4", "slab8"}),
      ParamSpec::integer("grid-levels",
                         "top levels replaced by a grid of (2^n)³ pointers (Sintorn §6.2); capped "
                         "at log2(R) − 3",
                         0, 0, 8, {0, 5, 7}),
  };
  info.buildBytes = [](const MapInfo& map, const ParamValues&, const BuildShape& shape) {
    const uint64_t tile = std::min(map.resolution, shape.tileSize);
    const uint64_t tileArrays = tile * tile * 24, dag = expectedDagBytes(map.resolution);
    if (!shape.inParts(map)) return kBuildSlackBytes + tileArrays + kDagBuildFactor * dag;
    // A part's DAG, and so its payload, taken as the part's share of the map's side: above the
    // measured share (city closed 8K² in parts of 2K²: 13% of the DAG, not 25%).
    const uint64_t part = dag * shape.partSize / map.resolution;
    // Once the parts exist, the merged DAG is bounded by their payloads together (merging only
    // shares) and measured at 43% (city closed 256K², 64 parts) to 79% (forest static 128K², 16
    // parts) of them: kDagBuildFactor times the middle, 60%, and the part being read.
    const BuildShape::PartFiles& files = shape.partFiles;
    const uint64_t merge = files.totalBytes
                               ? kDagBuildFactor * files.totalBytes * 3 / 5 + files.largestBytes
                               : kDagBuildFactor * dag + part;
    return kBuildSlackBytes + shape.partsBytes(tileArrays + kDagBuildFactor * part, merge);
  };
  info.load = [](ByteReader& in, const MapInfo& map, const ParamValues& params) {
    const VoxelDagConfig config = voxelDagConfig(map, params);
    return loadVoxelDag(in, VoxelDagShape::of(map, config.layout), config.gridLevels);
  };
  return info;
}

VoxelDagConfig voxelDagConfig(const MapInfo& map, const ParamValues& params) {
  const VoxelDagShape shape =
      VoxelDagShape::of(map, leafLayoutFromString(params.choice("leaf-layout")));
  return {shape.layout, std::min(uint32_t(params.integer("grid-levels")), shape.leafParentDepth())};
}

// ---------------------------------------------------------------------------------------------
// Builder

// One depth's unique table: open addressing over ids, each id's full hash kept so that growing
// never rehashes contents and most mismatches are rejected without touching them.
// One depth's distinct nodes, or the distinct leafmasks.
struct VoxelDagBuilder::Table {
  std::vector<uint32_t> words;    // node depths: every node's words, concatenated
  std::vector<uint32_t> offsets;  // node depths: id → its first word
  std::vector<uint64_t> masks;    // the leafmask table: id → mask
  HashConsIndex index;

  size_t count() const { return index.count(); }

  // The id of a stored entry with this hash for which same(id) holds; otherwise a new id.
  template <class Same>
  std::pair<uint32_t, bool> findOrAdd(uint64_t hash, Same&& same) {
    const auto found = index.findOrAdd(hash, same);
    if (found.second && found.first >= kShadowedRef)
      throw std::runtime_error("CPVS: more than 2^32 − 2 nodes at one depth");
    return found;
  }
};

namespace {

uint32_t childCode(uint32_t header, uint32_t child) {
  return childFlag(header, int(child));
}
// The position of child c's pointer among the node's words.
uint32_t pointerSlot(uint32_t header, uint32_t child) {
  return 1 + uint32_t(std::popcount(partialBits(header) & ((1u << (2 * child)) - 1)));
}

}  // namespace

VoxelDagBuilder::VoxelDagBuilder(VoxelDagShape shape) : shape_(shape) {
  for (uint32_t d = 0; d <= shape.leafParentDepth(); ++d)
    depths_.push_back(std::make_unique<Table>());
  leafmasks_ = std::make_unique<Table>();
}
VoxelDagBuilder::~VoxelDagBuilder() = default;

DagRef VoxelDagBuilder::leafmask(uint64_t litVoxels) {
  if (litVoxels == ~uint64_t(0)) return kLitRef;
  if (litVoxels == 0) return kShadowedRef;
  Table& table = *leafmasks_;
  const auto [id, added] = table.findOrAdd(
      mixBits(litVoxels), [&](uint32_t other) { return table.masks[other] == litVoxels; });
  if (added) table.masks.push_back(litVoxels);
  return id;
}

DagRef VoxelDagBuilder::node(uint32_t depth, const std::array<DagRef, 8>& children) {
  uint32_t header = 0, lit = 0, shadowed = 0;
  for (uint32_t c = 0; c < 8; ++c) {
    if (children[c] == kLitRef) {
      ++lit;
    } else if (children[c] == kShadowedRef) {
      header |= kChildShadowed << (2 * c);
      ++shadowed;
    } else {
      header |= kChildPartial << (2 * c);
    }
  }
  if (lit == 8) return kLitRef;
  if (shadowed == 8) return kShadowedRef;

  Table& table = *depths_.at(depth);
  const uint32_t begin = uint32_t(table.words.size());
  table.words.push_back(header);
  uint64_t hash = mixBits(header);
  for (uint32_t c = 0; c < 8; ++c)
    if (isNodeRef(children[c])) {
      table.words.push_back(children[c]);
      hash = mixBits(hash ^ children[c]);
    }
  const uint32_t length = uint32_t(table.words.size()) - begin;
  const auto [id, added] = table.findOrAdd(hash, [&](uint32_t other) {
    const uint32_t* a = table.words.data() + table.offsets[other];
    return a[0] == header && std::equal(a + 1, a + length, table.words.data() + begin + 1);
  });
  if (added)
    table.offsets.push_back(begin);
  else
    table.words.resize(begin);
  return id;
}

uint64_t VoxelDagBuilder::nodeCount() const {
  uint64_t count = 0;
  for (const auto& table : depths_) count += table->count();
  return count;
}
uint64_t VoxelDagBuilder::leafmaskCount() const {
  return leafmasks_->count();
}
std::span<const uint32_t> VoxelDagBuilder::storedNodes(uint32_t depth) const {
  return depths_.at(depth)->words;
}
std::span<const uint64_t> VoxelDagBuilder::storedLeafmasks() const {
  return leafmasks_->masks;
}

VoxelDag VoxelDagBuilder::finish(DagRef root, uint32_t gridLevels) {
  const uint32_t leafParent = shape_.leafParentDepth();
  if (gridLevels > leafParent)
    throw std::invalid_argument(
        fmt::format("CPVS: {} grid levels exceed the {} node levels", gridLevels, leafParent));
  // Lit voxels below every node, for the VOAA occupancy in the spare header bits (Sintorn §5).
  std::vector<std::vector<uint64_t>> litVoxels(leafParent + 1);
  for (uint32_t d = leafParent + 1; d-- > gridLevels;) {
    const Table& table = *depths_[d];
    const uint64_t childVolume =
        d == leafParent ? shape_.leafVolume() : uint64_t(1) << (3 * (shape_.levels - d - 1));
    litVoxels[d].resize(table.count());
    for (uint32_t id = 0; id < table.count(); ++id) {
      const uint32_t* words = table.words.data() + table.offsets[id];
      uint64_t lit = 0;
      for (uint32_t c = 0, slot = 1; c < 8; ++c) {
        const uint32_t code = childCode(words[0], c);
        if (code == kChildLit) lit += childVolume;
        if (code != kChildPartial) continue;
        const uint32_t child = words[slot++];
        lit += d == leafParent ? uint64_t(std::popcount(leafmasks_->masks[child]))
                               : litVoxels[d + 1][child];
      }
      litVoxels[d][id] = lit;
    }
  }

  VoxelDag dag;
  dag.shape = shape_;
  dag.gridLevels = gridLevels;
  std::vector<uint64_t> base(leafParent + 2, 0);
  for (uint32_t d = gridLevels; d <= leafParent; ++d) {
    dag.depthBegin.push_back(uint32_t(base[d]));
    base[d + 1] = base[d] + depths_[d]->words.size();
  }
  if (base[leafParent + 1] >= kShadowedRef)
    throw std::runtime_error("CPVS: the DAG exceeds 2^32 − 2 words of nodes");
  dag.depthBegin.push_back(uint32_t(base[leafParent + 1]));
  dag.nodes.reserve(base[leafParent + 1]);
  for (uint32_t d = gridLevels; d <= leafParent; ++d) {
    const Table& table = *depths_[d];
    const double volume = double(shape_.side(d)) * shape_.side(d) * shape_.side(d);
    for (uint32_t id = 0; id < table.count(); ++id) {
      const uint32_t* words = table.words.data() + table.offsets[id];
      const uint32_t occupancy = uint32_t(std::lround(65535.0 * double(litVoxels[d][id]) / volume));
      dag.nodes.push_back((words[0] & 0xffffu) | occupancy << 16);
      for (uint32_t w = 1; w < nodeWordCount(words[0]); ++w)
        dag.nodes.push_back(
            d == leafParent ? words[w] : uint32_t(base[d + 1]) + depths_[d + 1]->offsets[words[w]]);
    }
  }
  dag.leafmasks = leafmasks_->masks;

  // The grid holds, for each cube at depth gridLevels, the reference the tree gives it.
  const uint32_t cells = 1u << gridLevels, cellShift = shape_.levels - gridLevels;
  dag.grid.resize(size_t(cells) * cells * cells);
  for (uint32_t gz = 0; gz < cells; ++gz)
    for (uint32_t gy = 0; gy < cells; ++gy)
      for (uint32_t gx = 0; gx < cells; ++gx) {
        const uint32_t x = gx << cellShift, y = gy << cellShift, z = gz << cellShift;
        DagRef ref = root;
        for (uint32_t d = 0; d < gridLevels && isNodeRef(ref); ++d) {
          const Table& table = *depths_[d];
          const uint32_t* words = table.words.data() + table.offsets[ref];
          const uint32_t c = shape_.childIndex(x, y, z, d), code = childCode(words[0], c);
          ref = code == kChildLit        ? kLitRef
                : code == kChildShadowed ? kShadowedRef
                                         : words[pointerSlot(words[0], c)];
        }
        if (isNodeRef(ref)) ref = uint32_t(base[gridLevels]) + depths_[gridLevels]->offsets[ref];
        dag.grid[(size_t(gz) * cells + gy) * cells + gx] = ref;
      }
  return dag;
}

// ---------------------------------------------------------------------------------------------
// Decoder

namespace {

class VoxelDagDecoder final : public Decoder, public VoxelOccupancy {
 public:
  explicit VoxelDagDecoder(VoxelDag dag) : dag_(std::move(dag)) {}

  const VoxelOccupancy* voxelOccupancy() const override { return this; }

  uint32_t depthOfSide(uint32_t side) const override {
    const VoxelDagShape& shape = dag_.shape;
    const uint32_t resolution = 1u << shape.levels;
    const uint32_t leafParentSide = shape.side(shape.leafParentDepth());
    if (!std::has_single_bit(side) || side < leafParentSide || side > resolution)
      throw std::invalid_argument(
          fmt::format("VOAA node side {} must be a power of two from {} to {}", side,
                      leafParentSide, resolution));
    const uint32_t depth = shape.levels - uint32_t(std::countr_zero(side));
    if (depth < dag_.gridLevels)
      throw std::invalid_argument(fmt::format(
          "VOAA node side {} is depth {}, which the top-level grid ({} levels) replaces", side,
          depth, dag_.gridLevels));
    return depth;
  }

  void litFraction(std::span<const Query> queries, uint32_t depth,
                   std::span<float> fraction) const override {
    const uint32_t resolution = 1u << dag_.shape.levels;
    for (size_t q = 0; q < queries.size(); ++q) {
      const int64_t i = texelOf(queries[q].x, resolution), j = texelOf(queries[q].y, resolution);
      fraction[q] =
          insideMap(i, j, resolution)
              ? occupancy(uint32_t(i), uint32_t(j), voxelOf(queries[q].z, resolution), depth)
              : 1.0f;
    }
  }

  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    checkLookupArguments(queries, k, visibility);
    const uint32_t resolution = 1u << dag_.shape.levels;
    for (size_t q = 0; q < queries.size(); ++q) {
      const int64_t i = texelOf(queries[q].x, resolution), j = texelOf(queries[q].y, resolution);
      const uint32_t z = voxelOf(queries[q].z, resolution);
      visibility[q] =
          k == 1
              ? (insideMap(i, j, resolution) ? float(pointLit(uint32_t(i), uint32_t(j), z)) : 1.0f)
              : float(pcfLit(i, j, z, k / 2)) / float(k * k);
    }
  }

  SizeBreakdown size() const override {
    return {{"top grid", dag_.grid.size() * sizeof(DagRef)},
            {"nodes", dag_.nodes.size() * sizeof(uint32_t)},
            {"leafmasks", dag_.leafmasks.size() * sizeof(uint64_t)}};
  }

  void save(ByteWriter& out) const override {
    out.put<uint32_t>(dag_.gridLevels);
    out.putArray<uint32_t>(dag_.depthBegin);
    out.putArray<DagRef>(dag_.grid);
    out.putArray<uint32_t>(dag_.nodes);
    out.putArray<uint64_t>(dag_.leafmasks);
  }

  // The lit fraction of the node at `depth` around voxel (x, y, z) (VOAA, Sintorn §5). Depths
  // above the grid have no nodes left and answer at the grid's depth.
  float occupancy(uint32_t x, uint32_t y, uint32_t z, uint32_t depth) const {
    const VoxelDagShape& shape = dag_.shape;
    DagRef ref = dag_.grid[cellOf(dag_, x, y, z)];
    for (uint32_t d = dag_.gridLevels;; ++d) {
      if (!isNodeRef(ref)) return ref == kLitRef ? 1.0f : 0.0f;
      const uint32_t header = dag_.nodes[ref];
      if (d >= depth) return float(header >> 16) / 65535.0f;
      const uint32_t c = shape.childIndex(x, y, z, d), code = childCode(header, c);
      if (code != kChildPartial) return code == kChildLit ? 1.0f : 0.0f;
      const uint32_t pointer = dag_.nodes[ref + pointerSlot(header, c)];
      if (d == shape.leafParentDepth())
        return float(std::popcount(dag_.leafmasks[pointer])) / 64.0f;
      ref = pointer;
    }
  }

 private:
  // What a walk reaches: a homogeneous volume, or the leafmask holding the voxel.
  struct Reached {
    bool isLeafmask;
    bool lit;
    uint64_t leafmask;
  };

  // A walk from the grid to the volume holding a voxel. Consecutive walks of one PCF kernel
  // resume from the deepest node both paths share instead of the top (Sintorn §6.2).
  class Walk {
   public:
    explicit Walk(const VoxelDag& dag) : dag_(dag) {}

    Reached to(uint32_t x, uint32_t y, uint32_t z) {
      const VoxelDagShape& shape = dag_.shape;
      const uint32_t gridDepth = dag_.gridLevels, leafParent = shape.leafParentDepth();
      uint32_t depth = gridDepth;
      if (started_) {
        // Cubes at depth d hold both voxels while their coordinates agree above bit levels − d.
        const uint32_t diff = (x ^ x_) | (y ^ y_) | (z ^ z_);
        depth = std::min(shape.levels - uint32_t(std::bit_width(diff)), reached_);
      }
      if (!started_ || depth < gridDepth) {
        depth = gridDepth;
        path_[gridDepth] = dag_.grid[cellOf(dag_, x, y, z)];
      }
      started_ = true;
      x_ = x, y_ = y, z_ = z;
      for (;;) {
        const DagRef ref = path_[depth];
        if (!isNodeRef(ref)) {
          reached_ = depth;
          return {false, ref == kLitRef, 0};
        }
        const uint32_t header = dag_.nodes[ref];
        const uint32_t c = shape.childIndex(x, y, z, depth), code = childCode(header, c);
        const uint32_t next = code == kChildPartial ? dag_.nodes[ref + pointerSlot(header, c)] : 0;
        if (depth == leafParent) {
          // Leafmasks are not cubes in the slab8 layout, so the path stops at their parent.
          reached_ = depth;
          if (code != kChildPartial) return {false, code == kChildLit, 0};
          return {true, false, dag_.leafmasks[next]};
        }
        path_[depth + 1] = code == kChildLit        ? kLitRef
                           : code == kChildShadowed ? kShadowedRef
                                                    : next;
        ++depth;
      }
    }

   private:
    const VoxelDag& dag_;
    std::array<DagRef, 24> path_{};
    uint32_t x_ = 0, y_ = 0, z_ = 0, reached_ = 0;
    bool started_ = false;
  };

  static size_t cellOf(const VoxelDag& dag, uint32_t x, uint32_t y, uint32_t z) {
    const uint32_t shift = dag.shape.levels - dag.gridLevels, cells = 1u << dag.gridLevels;
    return (size_t(z >> shift) * cells + (y >> shift)) * cells + (x >> shift);
  }

  bool pointLit(uint32_t x, uint32_t y, uint32_t z) const {
    Walk walk(dag_);
    const Reached reached = walk.to(x, y, z);
    return reached.isLeafmask ? (reached.leafmask >> dag_.shape.leafBit(x, y, z)) & 1 : reached.lit;
  }

  // Lit taps of the kernel of `radius` around texel (ci, cj) at slice z. Sintorn §6.2: each
  // leafmask the kernel touches is ANDed with the kernel's footprint and its bits counted; taps
  // off the map count as lit.
  uint32_t pcfLit(int64_t ci, int64_t cj, uint32_t z, int64_t radius) const {
    const int64_t resolution = int64_t(1) << dag_.shape.levels;
    const int64_t i0 = std::max<int64_t>(ci - radius, 0),
                  i1 = std::min(ci + radius, resolution - 1);
    const int64_t j0 = std::max<int64_t>(cj - radius, 0),
                  j1 = std::min(cj + radius, resolution - 1);
    const int64_t side = 2 * radius + 1;
    if (i0 > i1 || j0 > j1) return uint32_t(side * side);
    uint32_t lit = uint32_t(side * side - (i1 - i0 + 1) * (j1 - j0 + 1));
    const uint32_t leafSide = dag_.shape.leafSide();
    // In the cube4 layout the kernel's slice is one 16-bit layer of the leafmask.
    const uint32_t layerShift = dag_.shape.layout == LeafLayout::Cube4 ? 16 * (z & 3) : 0;
    Walk walk(dag_);
    for (uint32_t by = uint32_t(j0) / leafSide; by <= uint32_t(j1) / leafSide; ++by)
      for (uint32_t bx = uint32_t(i0) / leafSide; bx <= uint32_t(i1) / leafSide; ++bx) {
        const uint32_t x0 = bx * leafSide, y0 = by * leafSide;
        const uint32_t rx0 = uint32_t(std::max<int64_t>(i0, x0)) - x0,
                       rx1 = uint32_t(std::min<int64_t>(i1, x0 + leafSide - 1)) - x0;
        const uint32_t ry0 = uint32_t(std::max<int64_t>(j0, y0)) - y0,
                       ry1 = uint32_t(std::min<int64_t>(j1, y0 + leafSide - 1)) - y0;
        const Reached reached = walk.to(x0, y0, z);
        if (!reached.isLeafmask) {
          if (reached.lit) lit += (rx1 - rx0 + 1) * (ry1 - ry0 + 1);
          continue;
        }
        const uint64_t row = ((uint64_t(1) << (rx1 - rx0 + 1)) - 1) << rx0;
        uint64_t footprint = 0;
        for (uint32_t ry = ry0; ry <= ry1; ++ry) footprint |= row << (leafSide * ry);
        lit += uint32_t(std::popcount(reached.leafmask & (footprint << layerShift)));
      }
    return lit;
  }

  VoxelDag dag_;
};

}  // namespace

std::unique_ptr<Decoder> makeVoxelDagDecoder(VoxelDag dag) {
  return std::make_unique<VoxelDagDecoder>(std::move(dag));
}

std::unique_ptr<Decoder> finishVoxelDag(VoxelDagBuilder& dag, DagRef root, uint32_t gridLevels,
                                        BuildContext& context) {
  context.count("dag nodes", dag.nodeCount());
  context.count("dag leafmasks", dag.leafmaskCount());
  return makeVoxelDagDecoder(dag.finish(root, gridLevels));
}

std::unique_ptr<Decoder> loadVoxelDag(ByteReader& in, const VoxelDagShape& shape,
                                      uint32_t gridLevels) {
  VoxelDag dag;
  dag.shape = shape;
  dag.gridLevels = in.get<uint32_t>("CPVS grid levels");
  if (dag.gridLevels != gridLevels)
    throw FormatError(fmt::format("CPVS: {} grid levels stored, the parameters give {}",
                                  dag.gridLevels, gridLevels));
  const uint32_t leafParent = shape.leafParentDepth(), cells = 1u << gridLevels;
  dag.depthBegin = in.getArray<uint32_t>("CPVS depth offsets", leafParent - gridLevels + 2);
  dag.grid = in.getArray<DagRef>("CPVS top grid", uint64_t(cells) * cells * cells);
  dag.nodes = in.getArray<uint32_t>("CPVS nodes");
  dag.leafmasks = in.getArray<uint64_t>("CPVS leafmasks");

  // Every node must parse within its depth's range, and every pointer must name a node of the
  // next depth (or a leafmask): then no lookup can leave the arrays or loop.
  if (dag.depthBegin.front() != 0 || dag.depthBegin.back() != dag.nodes.size() ||
      !std::is_sorted(dag.depthBegin.begin(), dag.depthBegin.end()))
    throw FormatError("CPVS: depth offsets do not partition the node array");
  std::vector<bool> nodeStart(dag.nodes.size() + 1, false);
  for (uint32_t level = 0; level + 1 < dag.depthBegin.size(); ++level)
    for (uint64_t w = dag.depthBegin[level]; w < dag.depthBegin[level + 1];) {
      const uint32_t header = dag.nodes[w];
      for (uint32_t c = 0; c < 8; ++c)
        if (childCode(header, c) == 3)
          throw FormatError(fmt::format("CPVS: invalid child code in the node at word {}", w));
      nodeStart[w] = true;
      w += nodeWordCount(header);
      if (w > dag.depthBegin[level + 1])
        throw FormatError(
            fmt::format("CPVS: a node at depth {} overruns its depth", gridLevels + level));
    }
  auto checkNode = [&](uint32_t ref, uint32_t depth, const char* what) {
    const uint32_t level = depth - gridLevels;
    if (!isNodeRef(ref)) return;
    if (ref < dag.depthBegin[level] || ref >= dag.depthBegin[level + 1] || !nodeStart[ref])
      throw FormatError(fmt::format("CPVS: {} {} is not a node of depth {}", what, ref, depth));
  };
  for (const DagRef ref : dag.grid) checkNode(ref, gridLevels, "grid entry");
  for (uint32_t level = 0; level + 1 < dag.depthBegin.size(); ++level) {
    const uint32_t depth = gridLevels + level;
    for (uint64_t w = dag.depthBegin[level]; w < dag.depthBegin[level + 1];) {
      const uint32_t words = nodeWordCount(dag.nodes[w]);
      for (uint32_t p = 1; p < words; ++p) {
        const uint32_t pointer = dag.nodes[w + p];
        if (depth == leafParent) {
          if (pointer >= dag.leafmasks.size())
            throw FormatError(fmt::format("CPVS: leafmask pointer {} out of range", pointer));
        } else {
          if (!isNodeRef(pointer))
            throw FormatError("CPVS: a child pointer holds a reserved value");
          checkNode(pointer, depth + 1, "child pointer");
        }
      }
      w += words;
    }
  }
  return makeVoxelDagDecoder(std::move(dag));
}

}  // namespace sb
