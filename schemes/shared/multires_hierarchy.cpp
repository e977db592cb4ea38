#include "schemes/shared/multires_hierarchy.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "schemes/interface/morton.h"

namespace sb {

uint32_t depthKey(float d) {
  if (!(d >= 0.0f))
    throw std::invalid_argument(
        fmt::format("depth {} is negative or NaN: not a light-space depth", d));
  return d == 0.0f ? 0u : std::bit_cast<uint32_t>(d);
}

int MultiresHierarchy::childCount(const MhNode& node) {
  int count = 0;
  for (int k = 0; k < kMhChildren; ++k) count += node.child(k) != MhChild::None;
  return count;
}

uint32_t MultiresHierarchy::childNode(const MhNode& node, int k) {
  uint32_t index = node.firstChild;
  for (int m = 0; m < k; ++m) index += node.child(m) != MhChild::None;
  return index;
}

KeyInterval MultiresHierarchy::texelInterval(uint32_t i, uint32_t j) const {
  const MhNode* node = &nodes[root()];
  KeyInterval deepest = node->interval;
  for (int bit = levels - 1; bit >= 0; --bit) {
    const int k = mhChildIndex(i, j, bit);
    const MhChild type = node->child(k);
    if (type == MhChild::None) break;
    node = &nodes[childNode(*node, k)];
    if (type != MhChild::Empty) deepest = node->interval;
    if (type == MhChild::Leaf) break;
  }
  return deepest;
}

std::map<uint32_t, uint64_t> MultiresHierarchy::nodesAtLevel(int level) const {
  std::map<uint32_t, uint64_t> found;
  const auto visit = [&](const auto& self, uint32_t n, int at, uint32_t x, uint32_t y) -> void {
    if (at == level) {
      found[n] = mortonCode(x, y);
      return;
    }
    for (int k = 0; k < kMhChildren; ++k)
      if (nodes[n].child(k) != MhChild::None)
        self(self, childNode(nodes[n], k), at + 1, 2 * x + (k & 1), 2 * y + (k >> 1));
  };
  visit(visit, root(), 0, 0, 0);
  return found;
}

namespace {

// SBE16a §3: of four children, the largest group whose intervals share a point moves up. Among
// equally large groups, prefer the one that leaves fewer empty inner nodes behind (children
// with descendants stay as empty nodes, childless ones vanish), then the widest intersection,
// which gives the parent's own group more room one level up. A shared point of a group can
// always be taken at one member's lower bound, so the four lower bounds are the candidates.
MhBuilder::Pending chooseGroup(const MhBuilder::Pending (&children)[kMhChildren]) {
  int bestMask = 0, bestCount = -1, bestChildless = -1;
  KeyInterval best;
  for (int candidate = 0; candidate < kMhChildren; ++candidate) {
    const uint32_t point = children[candidate].interval.lo;
    int mask = 0;
    KeyInterval shared{0, ~0u};
    for (int k = 0; k < kMhChildren; ++k) {
      const KeyInterval& interval = children[k].interval;
      if (interval.lo <= point && point <= interval.hi) {
        mask |= 1 << k;
        shared.lo = std::max(shared.lo, interval.lo);
        shared.hi = std::min(shared.hi, interval.hi);
      }
    }
    int childless = 0;
    for (int k = 0; k < kMhChildren; ++k) childless += (mask >> k & 1) && !children[k].childFlags;
    const int count = std::popcount(unsigned(mask));
    if (count > bestCount || (count == bestCount && childless > bestChildless) ||
        (count == bestCount && childless == bestChildless &&
         shared.hi - shared.lo > best.hi - best.lo)) {
      bestMask = mask, bestCount = count, bestChildless = childless, best = shared;
    }
  }
  MhBuilder::Pending parent;
  parent.interval = best;
  for (int k = 0; k < kMhChildren; ++k) {
    const bool represented = bestMask >> k & 1, hasChildren = children[k].childFlags != 0;
    const MhChild type = represented ? (hasChildren ? MhChild::Empty : MhChild::None)
                                     : (hasChildren ? MhChild::Full : MhChild::Leaf);
    parent.childFlags |= uint8_t(uint8_t(type) << (2 * k));
  }
  return parent;
}

}  // namespace

namespace {

int levelsOf(uint32_t resolution) {
  if (resolution == 0 || !std::has_single_bit(resolution))
    throw std::invalid_argument(
        fmt::format("multiresolution hierarchy: resolution {} is not a power of two", resolution));
  return std::countr_zero(resolution);
}

}  // namespace

MhBuilder::MhBuilder(const MapInfo& map) {
  hierarchy_.resolution = map.resolution;
  hierarchy_.levels = levelsOf(map.resolution);
  regionSize_ = map.resolution;
}

MhBuilder::MhBuilder(const MapInfo& map, const MapPart& part) : MhBuilder(map) {
  if (part.size == 0 || !std::has_single_bit(part.size) || part.size > map.resolution ||
      part.x0 % part.size || part.y0 % part.size || part.x0 > map.resolution - part.size ||
      part.y0 > map.resolution - part.size)
    throw std::invalid_argument(fmt::format(
        "multiresolution hierarchy: part {} ({}² at ({}, {})) is not an aligned square of the "
        "{}² map",
        part.index, part.size, part.x0, part.y0, map.resolution));
  regionX0_ = part.x0, regionY0_ = part.y0, regionSize_ = part.size;
  regionLevel_ = hierarchy_.levels - std::countr_zero(part.size);
}

uint64_t MhBuilder::workingBytes(uint32_t tileSize) {
  return uint64_t(tileSize) * tileSize * sizeof(Pending) * 5 / 4;
}

uint64_t MhBuilder::hierarchyFloorBytes(const MapInfo& map) {
  return map.texelCount() / 64 * sizeof(MhNode);
}

void MhBuilder::expectNext(uint32_t x0, uint32_t y0, uint32_t size, const char* what) {
  if (size == 0 || !std::has_single_bit(size) || size > regionSize_ || x0 < regionX0_ ||
      y0 < regionY0_ || x0 - regionX0_ > regionSize_ - size || y0 - regionY0_ > regionSize_ - size)
    throw std::invalid_argument(fmt::format(
        "multiresolution hierarchy: {} {}² at ({}, {}) is not a power-of-two square within the "
        "{}² at ({}, {})",
        what, size, x0, y0, regionSize_, regionX0_, regionY0_));
  // Roots are combined in fours as they arrive, so the order must be Morton order.
  const uint32_t x = x0 - regionX0_, y = y0 - regionY0_;
  if (x % size || y % size || mortonCode(x, y) != nextTexel_)
    throw std::invalid_argument(fmt::format(
        "multiresolution hierarchy: {} at ({}, {}) arrived out of Morton order", what, x0, y0));
  nextTexel_ += uint64_t(size) * size;
}

MhBuilder::Pending MhBuilder::store(Pending parent, const Pending (&children)[kMhChildren]) {
  if (parent.childFlags) {
    parent.firstChild = uint32_t(hierarchy_.nodes.size());
    for (int k = 0; k < kMhChildren; ++k)
      if (childFlag(parent.childFlags, k) != uint32_t(MhChild::None))
        hierarchy_.nodes.push_back(
            MhNode{children[k].interval, children[k].firstChild, children[k].childFlags});
  }
  return parent;
}

void MhBuilder::join(int level, Pending root) {
  while (level > regionLevel_ && waiting_.size() >= 3 && waiting_.back().first == level &&
         waiting_[waiting_.size() - 3].first == level) {
    const Pending group[kMhChildren] = {waiting_[waiting_.size() - 3].second,
                                        waiting_[waiting_.size() - 2].second,
                                        waiting_.back().second, root};
    waiting_.resize(waiting_.size() - 3);
    root = store(chooseGroup(group), group);
    --level;
  }
  waiting_.emplace_back(level, root);
}

void MhBuilder::consume(const DualDepthTile& tile) {
  const uint32_t size = tile.width;
  if (tile.height != size)
    throw std::invalid_argument(
        fmt::format("multiresolution hierarchy: tile {}×{} at ({}, {}) is not square", tile.width,
                    tile.height, tile.x0, tile.y0));
  expectNext(tile.x0, tile.y0, size, "tile");
  level_.resize(size_t(size) * size);
  tbb::parallel_for(uint32_t(0), size, [&](uint32_t row) {
    for (uint32_t column = 0; column < size; ++column) {
      const size_t texel = size_t(row) * size + column;
      const uint32_t lo = depthKey(tile.lo[texel]), hi = depthKey(tile.hi[texel]);
      if (hi < lo)
        throw std::invalid_argument(
            fmt::format("multiresolution hierarchy: texel ({}, {}) has hi {} below lo {}",
                        tile.x0 + column, tile.y0 + row, tile.hi[texel], tile.lo[texel]));
      level_[texel] = Pending{{lo, hi}, 0, 0};
    }
  });

  // Bottom-up over the tile's levels: choosing the groups is independent per parent and runs in
  // parallel; storing the kept children is a serial pass, so node order is deterministic.
  for (uint32_t width = size; width > 1; width /= 2) {
    const uint32_t half = width / 2;
    next_.resize(size_t(half) * half);
    const auto children = [&](uint32_t x, uint32_t y, Pending(&out)[kMhChildren]) {
      for (int k = 0; k < kMhChildren; ++k)
        out[k] = level_[size_t(2 * y + (k >> 1)) * width + 2 * x + (k & 1)];
    };
    tbb::parallel_for(uint32_t(0), half, [&](uint32_t y) {
      Pending group[kMhChildren];
      for (uint32_t x = 0; x < half; ++x) {
        children(x, y, group);
        next_[size_t(y) * half + x] = chooseGroup(group);
      }
    });
    for (uint32_t y = 0; y < half; ++y)
      for (uint32_t x = 0; x < half; ++x) {
        Pending& parent = next_[size_t(y) * half + x];
        if (!parent.childFlags) continue;
        Pending group[kMhChildren];
        children(x, y, group);
        parent = store(parent, group);
      }
    std::swap(level_, next_);
  }

  join(hierarchy_.levels - std::countr_zero(size), level_[0]);
}

void MhBuilder::consume(const MapPart& part, const PartHierarchy& hierarchy) {
  expectNext(part.x0, part.y0, part.size, "part");
  // Child indices are 32-bit, as in a whole build.
  const uint64_t offset = hierarchy_.nodes.size();
  if (offset + hierarchy.nodes.size() + 1 > uint64_t(UINT32_MAX))
    throw std::length_error(fmt::format(
        "multiresolution hierarchy: part {} takes the nodes beyond 32-bit indices", part.index));
  const auto shifted = [&](auto node) {
    if (node.childFlags) node.firstChild += uint32_t(offset);
    return node;
  };
  for (const MhNode& node : hierarchy.nodes) hierarchy_.nodes.push_back(shifted(node));
  join(hierarchy_.levels - std::countr_zero(part.size), shifted(hierarchy.root));
}

MultiresHierarchy MhBuilder::finish() {
  if (regionLevel_ != 0)
    throw std::logic_error("multiresolution hierarchy: a part's builder finishes with finishPart");
  if (waiting_.size() != 1 || waiting_[0].first != 0)
    throw std::logic_error("multiresolution hierarchy: the map's tiles did not all arrive");
  const Pending& root = waiting_[0].second;
  hierarchy_.nodes.push_back(MhNode{root.interval, root.firstChild, root.childFlags});
  waiting_.clear();
  level_ = {}, next_ = {};
  return std::move(hierarchy_);
}

MhBuilder::PartHierarchy MhBuilder::finishPart() {
  if (waiting_.size() != 1 || waiting_[0].first != regionLevel_)
    throw std::logic_error("multiresolution hierarchy: the part's tiles did not all arrive");
  PartHierarchy part{std::move(hierarchy_.nodes), waiting_[0].second};
  hierarchy_.nodes = {}, waiting_.clear();
  level_ = {}, next_ = {};
  return part;
}

}  // namespace sb
