// openvdb — the voxelized shadow volume of CPVS stored in an OpenVDB tree (Museth 2013, "VDB:
// High-resolution sparse volumes with dynamic topology"), the structure a reviewer would reach
// for before a custom DAG. The voxels are those of cpvs: DESIGN §4's rule, with undefined voxels
// decided by Sintorn §6.1's parent rule, applied here to VDB's own nodes instead of an octree's.
// The tree is a mask tree (one bit per voxel) whose active voxels are the shadowed ones: a
// homogeneously shadowed node becomes an active tile, lit space is the inactive background, and
// nothing is shared between identical subtrees, which is exactly what the comparison measures.
#include <algorithm>
#include <map>
#include <memory>
#include <unordered_map>

#include <fmt/format.h>
#include <openvdb/tree/Tree.h>
#include <openvdb/tree/ValueAccessor.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/slice_interval.h"
#include "schemes/shared/svo.h"

namespace sb {
namespace {

constexpr const char* kScheme = "openvdb";

// VDB's standard configuration (Museth §3, "5-4-3"): a root table of upper internal nodes of
// 32³ children (4096³ voxels), lower internal nodes of 16³ children (128³ voxels) and leaves of
// 8³ voxels. An internal node holds a dense table of child pointers or tile values.
using ShadowTree = openvdb::tree::Tree4<openvdb::ValueMask, 5, 4, 3>::Type;
using RootNode = ShadowTree::RootNodeType;
using UpperNode = RootNode::ChildNodeType;
using LowerNode = UpperNode::ChildNodeType;
using Leaf = ShadowTree::LeafNodeType;
using openvdb::Coord;
using Volume = BlockPyramid::Volume;

// The voxels per side of each node, as values (OpenVDB's DIM members are declared, not defined,
// so std::min could not take them by reference).
constexpr uint32_t kLeafSide = Leaf::DIM, kLowerSide = LowerNode::DIM, kUpperSide = UpperNode::DIM;

Coord voxelCoord(uint32_t x, uint32_t y, uint32_t z) {
  return Coord(int32_t(x), int32_t(y), int32_t(z));
}

// Bytes of one std::map entry of the root table in libstdc++: a 32-byte red-black node header
// and the (Coord, child pointer, tile) pair, 32 bytes. RootNode::memUsage() leaves them out.
constexpr uint64_t kRootEntryBytes = 64;

// The nodes of a tree and the bytes they occupy, as OpenVDB's memUsage() counts them (each
// node's sizeof, the internal nodes' dense tables included) plus the root table's entries.
struct NodeCensus {
  uint64_t rootEntries = 0, upperNodes = 0, lowerNodes = 0, leaves = 0;

  static uint64_t upperBytes() { return UpperNode(Coord(), false).memUsage(); }
  static uint64_t lowerBytes() { return LowerNode(Coord(), false).memUsage(); }

  SizeBreakdown breakdown() const {
    return {{"root table", sizeof(RootNode) + rootEntries * kRootEntryBytes},
            {"upper internal nodes", upperNodes * upperBytes()},
            {"lower internal nodes", lowerNodes * lowerBytes()},
            {"leaves", leaves * sizeof(Leaf)}};
  }
};

// A tree in its file form: the origins of its active tiles by level (root tiles of 4096³, upper
// node tiles of 128³, lower node tiles of 8³) and of its leaves, with each leaf's eight 64-bit
// mask words, in the tree's own order (root table by coordinate, children by table offset).
struct TreeListing {
  std::vector<uint32_t> rootTiles, upperTiles, lowerTiles, leafOrigins;  // x, y, z per entry
  std::vector<uint64_t> leafMasks;

  static void put(std::vector<uint32_t>& origins, const Coord& origin) {
    origins.insert(origins.end(),
                   {uint32_t(origin.x()), uint32_t(origin.y()), uint32_t(origin.z())});
  }

  static TreeListing of(const ShadowTree& tree) {
    TreeListing listing;
    const RootNode& root = tree.root();
    for (auto tile = root.cbeginValueOn(); tile; ++tile) put(listing.rootTiles, tile.getCoord());
    for (auto upper = root.cbeginChildOn(); upper; ++upper) {
      for (auto tile = upper->cbeginValueOn(); tile; ++tile)
        put(listing.upperTiles, tile.getCoord());
      for (auto lower = upper->cbeginChildOn(); lower; ++lower) {
        for (auto tile = lower->cbeginValueOn(); tile; ++tile)
          put(listing.lowerTiles, tile.getCoord());
        for (auto leaf = lower->cbeginChildOn(); leaf; ++leaf) {
          put(listing.leafOrigins, leaf->origin());
          for (openvdb::Index w = 0; w < Leaf::NodeMaskType::WORD_COUNT; ++w)
            listing.leafMasks.push_back(leaf->getValueMask().getWord<uint64_t>(w));
        }
      }
    }
    return listing;
  }

  bool operator==(const TreeListing&) const = default;
};

NodeCensus censusOf(const ShadowTree& tree) {
  NodeCensus census;
  const RootNode& root = tree.root();
  census.rootEntries = root.getTableSize();
  for (auto upper = root.cbeginChildOn(); upper; ++upper) {
    ++census.upperNodes;
    for (auto lower = upper->cbeginChildOn(); lower; ++lower) {
      ++census.lowerNodes;
      census.leaves += lower->getChildMask().countOn();
    }
  }
  return census;
}

class ShadowGridDecoder final : public Decoder {
 public:
  ShadowGridDecoder(uint32_t resolution, std::unique_ptr<ShadowTree> tree)
      : resolution_(resolution), tree_(std::move(tree)), census_(censusOf(*tree_)) {}

  // A ValueAccessor per batch caches the nodes of the previous query (Museth §4.2), so that
  // coherent queries and a kernel's taps skip the root table; not registered with the tree,
  // which never changes after the build.
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    checkLookupArguments(queries, k, visibility);
    openvdb::tree::ValueAccessor<const ShadowTree, false> accessor(*tree_);
    const int64_t radius = k / 2;
    for (size_t q = 0; q < queries.size(); ++q) {
      const int64_t i = texelOf(queries[q].x, resolution_), j = texelOf(queries[q].y, resolution_);
      const int32_t z = int32_t(voxelOf(queries[q].z, resolution_));
      uint32_t lit = 0;
      for (int64_t y = j - radius; y <= j + radius; ++y)
        for (int64_t x = i - radius; x <= i + radius; ++x)
          lit += !insideMap(x, y, resolution_) ||
                 !accessor.isValueOn(Coord(int32_t(x), int32_t(y), z));
      visibility[q] = float(lit) / float(k * k);
    }
  }

  SizeBreakdown size() const override { return census_.breakdown(); }

  void save(ByteWriter& out) const override {
    const TreeListing listing = TreeListing::of(*tree_);
    out.putArray<uint32_t>(listing.rootTiles);
    out.putArray<uint32_t>(listing.upperTiles);
    out.putArray<uint32_t>(listing.lowerTiles);
    out.putArray<uint32_t>(listing.leafOrigins);
    out.putArray<uint64_t>(listing.leafMasks);
  }

 private:
  uint32_t resolution_;
  std::unique_ptr<ShadowTree> tree_;
  NodeCensus census_;
};

// The lower internal nodes of one column of texels (`side`² texels at (x0, y0), side = 128 or
// the whole map when smaller), nearest the light first, each Lit, Shadowed or Undefined, or
// Mixed with its node.
struct LowerVolume {
  Volume kind;
  std::unique_ptr<LowerNode> node;
};

std::vector<LowerVolume> lowerColumn(uint32_t x0, uint32_t y0, uint32_t side,
                                     const std::vector<SliceInterval>& intervals,
                                     uint32_t depthResolution) {
  const BlockPyramid pyramid = BlockPyramid::over(intervals, side);
  const uint32_t lowerSide = std::min<uint32_t>(kLowerSide, depthResolution);
  std::vector<LowerVolume> column(depthResolution / lowerSide);
  for (uint32_t n = 0; n < column.size(); ++n) {
    const uint32_t z0 = n * lowerSide;
    column[n].kind = pyramid.classify(0, 0, side, z0, z0 + lowerSide - 1);
    if (column[n].kind != Volume::Mixed) continue;
    // A mixed volume holds both lit and shadowed voxels, so by the parent rule its undefined
    // children become shadowed, and so do the undefined voxels of its mixed leaves.
    auto node = std::make_unique<LowerNode>(voxelCoord(x0, y0, z0), false);
    for (uint32_t ly = 0; ly < side; ly += kLeafSide)
      for (uint32_t lx = 0; lx < side; lx += kLeafSide)
        for (uint32_t lz = z0; lz < z0 + lowerSide; lz += kLeafSide) {
          const Coord origin = voxelCoord(x0 + lx, y0 + ly, lz);
          const Volume kind = pyramid.classify(lx, ly, kLeafSide, lz, lz + kLeafSide - 1);
          if (kind == Volume::Lit) continue;
          if (kind != Volume::Mixed) {
            node->addTile(LowerNode::coordToOffset(origin), true, true);
            continue;
          }
          // Leaf offsets are x·64 + y·8 + z: mask word dx holds a byte of slices per dy.
          auto leaf = std::make_unique<Leaf>(origin, false);
          for (uint32_t dx = 0; dx < kLeafSide; ++dx) {
            uint64_t word = 0;
            for (uint32_t dy = 0; dy < kLeafSide; ++dy) {
              const SliceInterval& interval = intervals[size_t(ly + dy) * side + lx + dx];
              const int64_t litSlices = std::clamp<int64_t>(int64_t(interval.litEnd) - lz, 0, 8);
              word |= uint64_t((0xffu << litSlices) & 0xffu) << (8 * dy);
            }
            leaf->getValueMask().getWord<uint64_t>(dx) = word;
          }
          node->addLeaf(leaf.release());
        }
    column[n].node = std::move(node);
  }
  return column;
}

// The build: texels gather into columns of 128² (lower node footprints), a finished column
// becomes its lower nodes, and the lower nodes of one upper node wait until all of its columns
// have arrived, when the parent rule decides its homogeneous children and the node joins the
// root (or becomes a root tile).
class ShadowGridEncoder final : public Encoder {
 public:
  explicit ShadowGridEncoder(const MapInfo& map)
      : resolution_(map.resolution),
        columnSide_(std::min<uint32_t>(kLowerSide, map.resolution)),
        upperSide_(std::min<uint32_t>(kUpperSide, map.resolution)),
        memoryLimit_(uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE)) / 4 * 3),
        tree_(std::make_unique<ShadowTree>(false)) {
    if (!validResolution(map.resolution) || map.depthResolution != map.resolution)
      throw std::invalid_argument(
          fmt::format("{}: needs a cube of voxels, got resolution {} with {} depth slices", kScheme,
                      map.resolution, map.depthResolution));
  }

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("slice intervals");
    std::vector<std::pair<uint64_t, ColumnTexels>> finished;
    for (uint32_t j = tile.y0; j < tile.y0 + tile.height; ++j)
      for (uint32_t i = tile.x0; i < tile.x0 + tile.width;) {
        const uint32_t end = std::min(tile.x0 + tile.width, (i / columnSide_ + 1) * columnSide_);
        const uint64_t key = uint64_t(j / columnSide_) << 32 | i / columnSide_;
        ColumnTexels& column = columns_[key];
        column.intervals.resize(size_t(columnSide_) * columnSide_);
        for (uint32_t x = i; x < end; ++x) {
          const size_t at = tile.index(x, j);
          column.intervals[size_t(j % columnSide_) * columnSide_ + x % columnSide_] = {
              firstSliceBeyond(tile.lo[at], resolution_),
              firstSliceBeyond(tile.hi[at], resolution_)};
        }
        column.arrived += end - i;
        if (column.arrived == column.intervals.size()) {
          finished.emplace_back(key, std::move(column));
          columns_.erase(key);
        }
        i = end;
      }

    context.phase("lower nodes");
    std::vector<std::vector<LowerVolume>> built(finished.size());
    tbb::parallel_for(size_t(0), finished.size(), [&](size_t c) {
      const uint64_t key = finished[c].first;
      built[c] = lowerColumn(uint32_t(key) * columnSide_, uint32_t(key >> 32) * columnSide_,
                             columnSide_, finished[c].second.intervals, resolution_);
    });

    context.phase("upper nodes");
    for (size_t c = 0; c < finished.size(); ++c) {
      const uint32_t x0 = uint32_t(finished[c].first) * columnSide_,
                     y0 = uint32_t(finished[c].first >> 32) * columnSide_;
      addColumn(x0, y0, built[c]);
      const uint64_t upperColumn = uint64_t(y0 / upperSide_) << 32 | x0 / upperSide_;
      const uint32_t columnsPerUpper = (upperSide_ / columnSide_) * (upperSide_ / columnSide_);
      if (++upperColumnsArrived_[upperColumn] == columnsPerUpper) {
        upperColumnsArrived_.erase(upperColumn);
        finishUpperColumn(x0 / upperSide_ * upperSide_, y0 / upperSide_ * upperSide_);
      }
    }
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    if (!columns_.empty() || !uppers_.empty())
      throw std::logic_error(fmt::format("{}: not every texel arrived", kScheme));
    const NodeCensus census = censusOf(*tree_);
    context.count("upper internal nodes", census.upperNodes);
    context.count("lower internal nodes", census.lowerNodes);
    context.count("leaves", census.leaves);
    context.count("active tiles", tree_->activeTileCount());
    return std::make_unique<ShadowGridDecoder>(resolution_, std::move(tree_));
  }

 private:
  struct ColumnTexels {
    std::vector<SliceInterval> intervals;
    size_t arrived = 0;
  };
  // The children of one upper node gathered so far: its mixed lower nodes (in `node`), and the
  // origins of its homogeneous shadowed and undefined ones, which wait for the parent rule.
  struct UpperChildren {
    std::unique_ptr<UpperNode> node;
    std::vector<Coord> shadowed, undefined;
    bool lit = false;
  };

  static uint64_t upperKey(uint32_t x, uint32_t y, uint32_t z) {
    return uint64_t(z / kUpperSide) << 40 | uint64_t(y / kUpperSide) << 20 | x / kUpperSide;
  }

  void addColumn(uint32_t x0, uint32_t y0, std::vector<LowerVolume>& column) {
    const uint32_t lowerSide = std::min<uint32_t>(kLowerSide, resolution_);
    for (uint32_t n = 0; n < column.size(); ++n) {
      const uint32_t z0 = n * lowerSide;
      UpperChildren& upper = uppers_[upperKey(x0, y0, z0)];
      const Coord origin = voxelCoord(x0, y0, z0);
      switch (column[n].kind) {
        case Volume::Lit:
          upper.lit = true;
          break;
        case Volume::Shadowed:
          upper.shadowed.push_back(origin);
          break;
        case Volume::Undefined:
          upper.undefined.push_back(origin);
          break;
        case Volume::Mixed:
          if (!upper.node) {
            upper.node = std::make_unique<UpperNode>(origin & ~(kUpperSide - 1), false);
            census_.upperNodes++;
          }
          census_.leaves += column[n].node->getChildMask().countOn();
          census_.lowerNodes++;
          upper.node->addChild(column[n].node.release());
          break;
      }
    }
    checkMemory();
  }

  // Sintorn §6.1 at the upper nodes over the column (x0, y0): a node with only shadowed (or
  // only lit) children becomes a root tile (or background); otherwise its undefined children
  // become shadowed tiles. Upper nodes of undefined voxels alone are the top of the tree, taken
  // as lit, as the CPVS root is.
  void finishUpperColumn(uint32_t x0, uint32_t y0) {
    for (uint32_t z0 = 0; z0 < resolution_; z0 += upperSide_) {
      auto found = uppers_.find(upperKey(x0, y0, z0));
      if (found == uppers_.end()) continue;
      UpperChildren upper = std::move(found->second);
      uppers_.erase(found);
      const Coord origin = voxelCoord(x0, y0, z0);
      switch (parentKind(upper.lit, !upper.shadowed.empty(), upper.node != nullptr)) {
        case SvoChild::Shadowed:
          tree_->root().addTile(origin, true, true);
          continue;
        case SvoChild::Local:
          break;
        default:
          continue;
      }
      if (!upper.node) {
        upper.node = std::make_unique<UpperNode>(origin, false);
        census_.upperNodes++;
      }
      for (const auto* tiles : {&upper.shadowed, &upper.undefined})
        for (const Coord& tile : *tiles)
          upper.node->addTile(UpperNode::coordToOffset(tile), true, true);
      tree_->root().addChild(upper.node.release());
    }
  }

  // The grid is the build's output and has no bound but the scene's: stop with an error that
  // names the resolution before the machine starts swapping.
  void checkMemory() const {
    const uint64_t bytes = totalBytes(census_.breakdown());
    if (bytes > memoryLimit_)
      throw std::runtime_error(fmt::format(
          "{}: the grid has grown to {:.1f} GiB, over 3/4 of this machine's memory, before "
          "every tile of the {}² map arrived; choose a smaller resolution",
          kScheme, double(bytes) / double(1ull << 30), resolution_));
  }

  uint32_t resolution_, columnSide_, upperSide_;
  uint64_t memoryLimit_;
  std::unique_ptr<ShadowTree> tree_;
  std::unordered_map<uint64_t, ColumnTexels> columns_;  // by (column y, column x)
  std::unordered_map<uint64_t, uint32_t> upperColumnsArrived_;
  std::map<uint64_t, UpperChildren> uppers_;  // by upperKey
  NodeCensus census_;                         // nodes built so far, for checkMemory
};

// Rebuilds the tree from its listing and lists it again: a listing that is not exactly the
// canonical form of the tree it builds (misaligned or out-of-map origins, overlapping or
// repeated entries, another order) is rejected, so a loaded tree is one the encoder could
// have built.
std::unique_ptr<Decoder> loadShadowGrid(ByteReader& in, const MapInfo& map) {
  TreeListing listing;
  listing.rootTiles = in.getArray<uint32_t>("openvdb root tiles");
  listing.upperTiles = in.getArray<uint32_t>("openvdb upper node tiles");
  listing.lowerTiles = in.getArray<uint32_t>("openvdb lower node tiles");
  listing.leafOrigins = in.getArray<uint32_t>("openvdb leaf origins");
  listing.leafMasks = in.getArray<uint64_t>("openvdb leaf masks");
  const uint64_t leafCount = listing.leafOrigins.size() / 3;
  if (listing.leafMasks.size() != leafCount * Leaf::NodeMaskType::WORD_COUNT)
    throw FormatError(fmt::format("{}: {} leaf mask words for {} leaves", kScheme,
                                  listing.leafMasks.size(), leafCount));

  auto tree = std::make_unique<ShadowTree>(false);
  auto origins = [&](const std::vector<uint32_t>& coordinates, uint32_t dim, const char* what,
                     auto&& add) {
    if (coordinates.size() % 3 != 0)
      throw FormatError(fmt::format("{}: {} are not coordinate triples", kScheme, what));
    for (size_t e = 0; e < coordinates.size(); e += 3) {
      const uint32_t x = coordinates[e], y = coordinates[e + 1], z = coordinates[e + 2];
      if (x >= map.resolution || y >= map.resolution || z >= map.resolution ||
          (x | y | z) % dim != 0)
        throw FormatError(
            fmt::format("{}: {} entry ({}, {}, {}) is outside the {}³ volume or "
                        "off its {}³ grid",
                        kScheme, what, x, y, z, map.resolution, dim));
      add(voxelCoord(x, y, z), e / 3);
    }
  };
  origins(listing.rootTiles, kUpperSide, "root tile",
          [&](const Coord& c, size_t) { tree->root().addTile(c, true, true); });
  origins(listing.upperTiles, kLowerSide, "upper node tile",
          [&](const Coord& c, size_t) { tree->root().addTile(2, c, true, true); });
  origins(listing.lowerTiles, kLeafSide, "lower node tile",
          [&](const Coord& c, size_t) { tree->root().addTile(1, c, true, true); });
  origins(listing.leafOrigins, kLeafSide, "leaf", [&](const Coord& c, size_t l) {
    auto leaf = std::make_unique<Leaf>(c, false);
    for (openvdb::Index w = 0; w < Leaf::NodeMaskType::WORD_COUNT; ++w)
      leaf->getValueMask().getWord<uint64_t>(w) =
          listing.leafMasks[l * Leaf::NodeMaskType::WORD_COUNT + w];
    tree->root().addLeaf(leaf.release());
  });
  if (!(TreeListing::of(*tree) == listing))
    throw FormatError(fmt::format(
        "{}: the tiles and leaves overlap, repeat or are out of the tree's order", kScheme));
  return std::make_unique<ShadowGridDecoder>(map.resolution, std::move(tree));
}

SchemeInfo openvdbScheme() {
  SchemeInfo info;
  info.name = kScheme;
  info.paper =
      "Museth 2013, VDB: the CPVS shadow volume (Sintorn et al. 2014 voxels) in an OpenVDB mask "
      "tree (reference library)";
  info.kind = SchemeKind::Voxel;
  // Columns of texels in flight: at most a row of 128² columns across the map, as slice
  // intervals. The tree is the build's output, guarded as it grows.
  info.buildBytes = [](const MapInfo& map, const ParamValues&, const BuildShape&) {
    return uint64_t(map.resolution) * kLowerSide * sizeof(SliceInterval) + (uint64_t(64) << 20);
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues&,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<ShadowGridEncoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map, const ParamValues&) {
    return loadShadowGrid(in, map);
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(openvdbScheme);

}  // namespace sb
