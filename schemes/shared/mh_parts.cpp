#include "schemes/shared/mh_parts.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace sb {

void expectPart(const std::string& scheme, uint64_t next, uint32_t partSize, const MapPart& part) {
  const MapPart expected = MapPart::of(next, partSize);
  if (part.index != expected.index || part.size != expected.size || part.x0 != expected.x0 ||
      part.y0 != expected.y0)
    throw std::invalid_argument(
        fmt::format("{}: part {} ({}² at ({}, {})) given where part {} ({}² at ({}, {})) is next",
                    scheme, part.index, part.size, part.x0, part.y0, expected.index, expected.size,
                    expected.x0, expected.y0));
}

void expectAllParts(const std::string& scheme, uint64_t merged, uint64_t count) {
  if (merged != count)
    throw std::logic_error(
        fmt::format("{}: {} of the {} parts were merged", scheme, merged, count));
}

uint32_t checkedPartSize(const std::string& scheme, uint32_t partSize, const MapInfo& map) {
  if (!std::has_single_bit(partSize) || partSize >= map.resolution)
    throw std::invalid_argument(fmt::format("{}: part size {} is not a power of two below {}",
                                            scheme, partSize, map.resolution));
  return partSize;
}

std::vector<MhNode> partTree(MhBuilder::PartHierarchy hierarchy) {
  const MhBuilder::Pending& root = hierarchy.root;
  hierarchy.nodes.push_back({root.interval, root.firstChild, root.childFlags});
  return std::move(hierarchy.nodes);
}

namespace {

// depthKey(+inf): the largest key a depth has (DESIGN §2: hi may be +inf, never NaN).
constexpr uint32_t kInfinityKey = 0x7f800000u;

struct NodeRecord {
  KeyInterval interval;
  uint32_t firstChild = 0;
  uint8_t childFlags = 0;
};

void putRecord(uint8_t* at, const NodeRecord& node) {
  std::memcpy(at, &node.interval.lo, 4);
  std::memcpy(at + 4, &node.interval.hi, 4);
  std::memcpy(at + 8, &node.firstChild, 4);
  at[12] = node.childFlags;
}

NodeRecord getRecord(ByteReader& in, const char* what) {
  NodeRecord node;
  node.interval.lo = in.get<uint32_t>(what);
  node.interval.hi = in.get<uint32_t>(what);
  node.firstChild = in.get<uint32_t>(what);
  node.childFlags = in.get<uint8_t>(what);
  return node;
}

int childCount(uint8_t flags) {
  int count = 0;
  for (int k = 0; k < kMhChildren; ++k) count += childFlag(flags, k) != uint32_t(MhChild::None);
  return count;
}

// Nodes a part of side 2^levels can store below its root: every node of the full quadtree.
uint64_t maxPartNodes(int levels) {
  uint64_t nodes = 0, level = 1;
  for (int d = 1; d <= levels && nodes <= UINT32_MAX; ++d) level *= 4, nodes += level;
  return std::min<uint64_t>(nodes, UINT32_MAX);
}

// Throws unless `interval` holds depths' keys, lo ≤ hi (`what` names its node).
void checkKeys(const KeyInterval& interval, const std::string& prefix, const std::string& what) {
  if (interval.lo > interval.hi || interval.hi > kInfinityKey)
    throw FormatError(
        fmt::format("{}: {} has the key interval [{:#x}, {:#x}], not depths with "
                    "lo ≤ hi",
                    prefix, what, interval.lo, interval.hi));
}

// The checks of readMhPart once the nodes are read.
class PartValidator {
 public:
  PartValidator(const MhBuilder::PartHierarchy& part, int levels, std::string prefix)
      : part_(part), levels_(levels), prefix_(std::move(prefix)), depth_(part.nodes.size(), 0) {}

  void check() {
    const uint64_t root = part_.nodes.size();
    checkNode(root, {part_.root.interval, part_.root.firstChild, part_.root.childFlags});
    if (part_.root.childFlags) claimChildren(root, part_.root.firstChild, part_.root.childFlags, 0);
    // Parents lie after their packs: walking down from the last node, every node's pack is
    // claimed before the node is reached, so one pass finds nodes in no pack or in two.
    for (uint64_t n = root; n-- > 0;) {
      if (!depth_[n]) fail(fmt::format("{} lies in no sibling pack", name(n)));
      const MhNode& node = part_.nodes[n];
      checkNode(n, {node.interval, node.firstChild, node.childFlags});
      if (node.childFlags) claimChildren(n, node.firstChild, node.childFlags, depth_[n]);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw FormatError(fmt::format("{}: {}", prefix_, what));
  }
  std::string name(uint64_t n) const {
    return n == part_.nodes.size() ? "the part's root" : fmt::format("node {}", n);
  }

  void checkNode(uint64_t n, const NodeRecord& node) const {
    checkKeys(node.interval, prefix_, name(n));
    if (!node.childFlags && node.firstChild != 0)
      fail(fmt::format("{} has no children but a first child {}", name(n), node.firstChild));
  }

  void claimChildren(uint64_t parent, uint32_t first, uint8_t flags, int parentDepth) {
    if (parentDepth >= levels_)
      fail(fmt::format("{} has children below the texel level", name(parent)));
    const uint64_t end = uint64_t(first) + childCount(flags);
    if (end > parent)
      fail(fmt::format("{}'s children [{}, {}) do not lie before it", name(parent), first, end));
    uint64_t child = first;
    for (int k = 0; k < kMhChildren; ++k) {
      const MhChild type = MhChild(childFlag(flags, k));
      if (type == MhChild::None) continue;
      if (depth_[child])
        fail(fmt::format("{} lies in two sibling packs ({}'s and another)", name(child),
                         name(parent)));
      depth_[child] = uint8_t(parentDepth + 1);
      const bool hasChildren = part_.nodes[child].childFlags != 0;
      if (hasChildren != (type != MhChild::Leaf))
        fail(fmt::format("{} is child {} of {} as {}, but has{} children", name(child), k,
                         name(parent), type == MhChild::Leaf ? "a leaf" : "an inner node",
                         hasChildren ? "" : " no"));
      ++child;
    }
  }

  const MhBuilder::PartHierarchy& part_;
  int levels_;
  std::string prefix_;
  std::vector<uint8_t> depth_;  // levels below the part's root; 0 until a pack claims the node
};

// The nodes a hierarchy of side `side` keeps at least, for the estimates of builds in parts: a
// node per 64 texels (MhBuilder::hierarchyFloorBytes) up to 16K², 256 per texel row beyond.
// Past the scene's detail, nodes follow the depth discontinuities and slopes, curves whose texels
// grow as R, not R²: the full city closed keeps 6.9 M nodes at 16K² (419 R), and dag-mh's 4.0 GiB
// peak at 256K² (issue 12) fits that rate, not R²/64 (1.1 G nodes, 17 GiB of hierarchy alone).
uint64_t nodesAtFloor(uint32_t side) {
  return std::min(MhBuilder::hierarchyFloorBytes({side, 0, DepthMode::Open}) / sizeof(MhNode),
                  uint64_t(side) * 256);
}

class MhPartEncoder final : public PartEncoder {
 public:
  MhPartEncoder(const MapInfo& map, const MapPart& part) : part_(part), builder_(map, part) {}
  void consume(const DualDepthTile& tile, BuildContext& context) override {
    if (!started_) context.phase("mh"), started_ = true;
    builder_.consume(tile);
  }
  void finish(ByteWriter& out, BuildContext&) override {
    writeMhPart(out, part_, builder_.finishPart());
  }

 private:
  MapPart part_;
  MhBuilder builder_;
  bool started_ = false;
};

class MhPartMerger final : public PartMerger {
 public:
  MhPartMerger(const MapInfo& map, std::string scheme, const BuildShape& shape,
               HierarchyEncode encode)
      : map_(map),
        scheme_(std::move(scheme)),
        partSize_(checkedPartSize(scheme_, shape.partSize, map)),
        builder_(map),
        encode_(std::move(encode)) {
    // The part files' records count the parts' nodes; the levels above add fewer than two nodes
    // a part.
    builder_.reserve(shape.partFiles.totalBytes / kMhPartNodeBytes +
                     2 * MapPart::countFor(map, partSize_));
  }

  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override {
    expectPart(scheme_, nextPart_, partSize_, part);
    if (nextPart_ == 0) context.phase("merge");
    builder_.consume(part, readMhPart(payload, part, scheme_));
    ++nextPart_;
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    expectAllParts(scheme_, nextPart_, MapPart::countFor(map_, partSize_));
    return encode_(builder_.finish(), context);
  }

 private:
  MapInfo map_;
  std::string scheme_;
  uint32_t partSize_;
  MhBuilder builder_;
  HierarchyEncode encode_;
  uint64_t nextPart_ = 0;
};

// partwiseMhMerger: the first pass feeds the parts' roots to the builder of the levels above
// them and measures every part's block; each further pass measures again until the scales
// settle, and the last writes every part's block into the structure.
class PartwiseMhMerger final : public PartMerger {
 public:
  using Decoding =
      std::function<std::unique_ptr<Decoder>(OffsetQuadtree, const MhNodeCounts&, BuildContext&)>;
  PartwiseMhMerger(const MapInfo& map, std::string scheme, uint32_t partSize, int offsetBits,
                   Decoding decoder)
      : map_(map),
        scheme_(std::move(scheme)),
        partSize_(checkedPartSize(scheme_, partSize, map)),
        decoder_(std::move(decoder)),
        upperBuilder_(map),
        layout_(std::countr_zero(map.resolution),
                std::countr_zero(map.resolution) - std::countr_zero(partSize_),
                MapPart::countFor(map, partSize_), offsetBits, scheme_.c_str()) {}

  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override {
    expectPart(scheme_, nextPart_, partSize_, part);
    if (nextPart_ == 0) context.phase(upper_ ? writing_ ? "serialise" : "layout" : "merge");
    MhBuilder::PartHierarchy hierarchy = readMhPart(payload, part, scheme_);
    if (!upper_) upperBuilder_.consume(part, {{}, hierarchy.root});
    if (writing_)
      for (const MhNode& node : hierarchy.nodes) counts_.addChildrenOf(node);
    const MultiresHierarchy tree{map_.resolution, std::countr_zero(map_.resolution),
                                 partTree(std::move(hierarchy))};
    if (writing_)
      layout_.write(part.index, tree);
    else
      layout_.measure(part.index, tree);
    ++nextPart_;
  }

  bool anotherPass(BuildContext& context) override {
    expectAllParts(scheme_, nextPart_, MapPart::countFor(map_, partSize_));
    if (writing_) return false;
    if (!upper_) upper_ = upperBuilder_.finish();
    context.phase("layout");
    writing_ = layout_.settle(*upper_);
    nextPart_ = 0;
    ++passes_;
    return true;
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    expectAllParts(scheme_, nextPart_, MapPart::countFor(map_, partSize_));
    if (!writing_)
      throw std::logic_error(fmt::format("{}: the merge finished before its last pass", scheme_));
    for (const MhNode& node : upper_->nodes) counts_.addChildrenOf(node);
    counts_.addRoot(upper_->nodes.back());
    context.count("passes over the parts", passes_);
    return decoder_(layout_.finish(), counts_, context);
  }

 private:
  MapInfo map_;
  std::string scheme_;
  uint32_t partSize_;
  Decoding decoder_;
  MhBuilder upperBuilder_;
  std::optional<MultiresHierarchy> upper_;  // the levels above the parts, after the first pass
  PartwiseLayout layout_;
  bool writing_ = false;
  MhNodeCounts counts_;
  uint64_t nextPart_ = 0;
  uint64_t passes_ = 1;
};

}  // namespace

std::unique_ptr<PartMerger> partwiseMhMerger(
    const MapInfo& map, std::string scheme, uint32_t partSize, int offsetBits,
    std::function<std::unique_ptr<Decoder>(OffsetQuadtree, const MhNodeCounts&, BuildContext&)>
        decoder) {
  return std::make_unique<PartwiseMhMerger>(map, std::move(scheme), partSize, offsetBits,
                                            std::move(decoder));
}

void writeMhPart(ByteWriter& out, const MapPart& part, const MhBuilder::PartHierarchy& hierarchy) {
  out.put<uint64_t>(part.index);
  out.put<uint32_t>(part.size);
  const MhBuilder::Pending& root = hierarchy.root;
  out.put<uint32_t>(root.interval.lo);
  out.put<uint32_t>(root.interval.hi);
  out.put<uint32_t>(root.firstChild);
  out.put<uint8_t>(root.childFlags);
  out.put<uint64_t>(hierarchy.nodes.size());
  // In blocks: a payload holds a tenth of the part's texels or so, too many for a put each.
  constexpr size_t kBlock = 4096;
  uint8_t block[kBlock * kMhPartNodeBytes];
  for (size_t first = 0; first < hierarchy.nodes.size(); first += kBlock) {
    const size_t count = std::min(kBlock, hierarchy.nodes.size() - first);
    for (size_t n = 0; n < count; ++n) {
      const MhNode& node = hierarchy.nodes[first + n];
      putRecord(block + n * kMhPartNodeBytes, {node.interval, node.firstChild, node.childFlags});
    }
    out.append(block, count * kMhPartNodeBytes);
  }
}

namespace {

// A payload's header up to its node count: the part it belongs to, its root and how many nodes
// follow (at most what the part holds, and all of them there).
struct PartHeader {
  MhBuilder::Pending root;
  uint64_t count = 0;
};
PartHeader readPartHeader(ByteReader& in, const MapPart& part, const std::string& prefix) {
  const uint64_t index = in.get<uint64_t>("MH part index");
  const uint32_t size = in.get<uint32_t>("MH part size");
  if (index != part.index || size != part.size)
    throw FormatError(fmt::format("{}: the payload belongs to part {} of side {}, not of side {}",
                                  prefix, index, size, part.size));
  const NodeRecord root = getRecord(in, "MH part root");
  const uint64_t count = in.get<uint64_t>("MH part node count");
  if (count > maxPartNodes(std::countr_zero(part.size)))
    throw FormatError(
        fmt::format("{}: {} nodes, more than a {}² part holds", prefix, count, part.size));
  if (count > in.remaining() / kMhPartNodeBytes)
    throw FormatError(fmt::format("{}: {} nodes take {} bytes, {} follow", prefix, count,
                                  count * kMhPartNodeBytes, in.remaining()));
  return {{root.interval, root.firstChild, root.childFlags}, count};
}

}  // namespace

MhBuilder::Pending readMhPartRoot(ByteReader& in, const MapPart& part, const std::string& scheme) {
  const std::string prefix = fmt::format("{} part {}", scheme, part.index);
  const PartHeader header = readPartHeader(in, part, prefix);
  checkKeys(header.root.interval, prefix, "the part's root");
  in.skip(header.count * kMhPartNodeBytes, "MH part nodes");
  return header.root;
}

MhBuilder::PartHierarchy readMhPart(ByteReader& in, const MapPart& part,
                                    const std::string& scheme) {
  const std::string prefix = fmt::format("{} part {}", scheme, part.index);
  const PartHeader header = readPartHeader(in, part, prefix);
  const int levels = std::countr_zero(part.size);
  const uint64_t count = header.count;
  MhBuilder::PartHierarchy hierarchy;
  hierarchy.root = header.root;
  hierarchy.nodes.resize(count);
  for (MhNode& node : hierarchy.nodes) {
    const NodeRecord record = getRecord(in, "MH part node");
    node = {record.interval, record.firstChild, record.childFlags};
  }
  PartValidator(hierarchy, levels, prefix).check();
  return hierarchy;
}

void setMhBuilds(SchemeInfo& info, MhEncoding encoding) {
  info.buildBytes = [wholeBuildBytes = encoding.wholeBuildBytes, merging = encoding.merge](
                        const MapInfo& map, const ParamValues&, const BuildShape& shape) {
    if (!shape.inParts(map))
      return MhBuilder::workingBytes(std::min(map.resolution, shape.tileSize)) +
             wholeBuildBytes(map);
    constexpr uint64_t kPartNodeBytes = sizeof(MhNode) + kMhPartNodeBytes;  // read and held
    const uint64_t partBytes = nodesAtFloor(shape.partSize) * kPartNodeBytes;
    const uint64_t encoder =
        MhBuilder::workingBytes(std::min(shape.partSize, shape.tileSize)) + partBytes;
    // Once the parts exist their payloads count the nodes: a part file is its nodes' records
    // (kMhPartNodeBytes each) and a header.
    const BuildShape::PartFiles& files = shape.partFiles;
    const uint64_t partPerNode = kPartNodeBytes + merging.partBytesPerNode;
    const uint64_t merge =
        files.totalBytes
            ? files.totalBytes / kMhPartNodeBytes * merging.bytesPerNode +
                  files.largestBytes / kMhPartNodeBytes * partPerNode
            : nodesAtFloor(map.resolution) * (merging.bytesPerNode + merging.reservedBytesPerNode) +
                  nodesAtFloor(shape.partSize) * partPerNode;
    return shape.partsBytes(encoder, merge);
  };
  const auto encodeFor = encoding.encodeFor;
  info.makeEncoder = [encodeFor](const MapInfo& map, const ParamValues& params,
                                 const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<HierarchyEncoder>(map, encodeFor(map, params));
  };
  info.makePartEncoder = [](const MapInfo& map, const MapPart& part, const ParamValues&,
                            const BuildShape&) -> std::unique_ptr<PartEncoder> {
    return std::make_unique<MhPartEncoder>(map, part);
  };
  info.partPayload = "mh-part-hierarchy";
  info.makePartMerger = [encodeFor, merging = encoding.merge, scheme = info.name](
                            const MapInfo& map, const ParamValues& params,
                            const BuildShape& shape) -> std::unique_ptr<PartMerger> {
    if (merging.makeMerger) return merging.makeMerger(map, params, shape.partSize);
    return std::make_unique<MhPartMerger>(map, scheme, shape, encodeFor(map, params));
  };
}

}  // namespace sb
