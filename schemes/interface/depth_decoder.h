// Point and exact PCF lookups for depth schemes (DESIGN §4), written once, and hierarchical PCF
// for those whose structure holds the coarser levels. A depth scheme's
// decoder derives from DepthDecoder<Self> and supplies
//     uint32_t resolution() const;
//     float depth(uint32_t i, uint32_t j) const;   // the stored d of texel (i, j)
// and gets batch lookups that call depth() directly: no virtual call per query or tap. A
// structure that can answer a whole kernel in one walk supplies litTexels as well (see
// KernelWalk), and its PCF lookups walk it once per kernel instead of once per tap.
#pragma once

#include <algorithm>
#include <bit>
#include <concepts>
#include <stdexcept>
#include <string>
#include <vector>

#include "schemes/interface/capabilities.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/scheme.h"

namespace sb {

// Point (k = 1) and exact k×k PCF over an R×R map whose texel (i, j) stores depthAt(i, j).
template <class DepthAt>
void pcfLookup(uint32_t resolution, const DepthAt& depthAt, std::span<const Query> queries, int k,
               std::span<float> visibility) {
  // Point lookups get a loop of their own: inside the k×k loop's bookkeeping a deep walk (mh's 14
  // levels at 16K²) lost registers and reloaded its texel column and depth limit from the stack
  // each step, which cost mh and mmh 30 % on view queries.
  if (k == 1) {
    for (size_t q = 0; q < queries.size(); ++q) {
      const Query& query = queries[q];
      const int64_t i = texelOf(query.x, resolution), j = texelOf(query.y, resolution);
      visibility[q] = !insideMap(i, j, resolution) || query.z <= depthAt(uint32_t(i), uint32_t(j));
    }
    return;
  }
  const int64_t radius = k / 2;
  const float taps = float(k * k);
  for (size_t q = 0; q < queries.size(); ++q) {
    const Query& query = queries[q];
    const int64_t ci = texelOf(query.x, resolution), cj = texelOf(query.y, resolution);
    int lit = 0;
    if (insideMap(ci - radius, cj - radius, resolution) &&
        insideMap(ci + radius, cj + radius, resolution)) {
      // The whole kernel lies inside the map: no per-tap bounds test.
      for (uint32_t j = uint32_t(cj - radius); j <= uint32_t(cj + radius); ++j)
        for (uint32_t i = uint32_t(ci - radius); i <= uint32_t(ci + radius); ++i)
          lit += query.z <= depthAt(i, j);
    } else {
      for (int64_t j = cj - radius; j <= cj + radius; ++j)
        for (int64_t i = ci - radius; i <= ci + radius; ++i)
          lit += !insideMap(i, j, resolution) || query.z <= depthAt(uint32_t(i), uint32_t(j));
    }
    visibility[q] = float(lit) / taps;
  }
}

// The taps of a kernel that lie inside the map: texels [i0, i1] × [j0, j1].
struct TexelRect {
  uint32_t i0, j0, i1, j1;
  uint64_t texels() const { return uint64_t(i1 - i0 + 1) * (j1 - j0 + 1); }
};

// The texels a square of side `side` at (x0, y0) shares with `rect` (0 if none).
inline uint64_t overlap(const TexelRect& rect, uint32_t x0, uint32_t y0, uint32_t side) {
  const uint32_t i0 = std::max(rect.i0, x0), i1 = std::min(rect.i1, x0 + (side - 1));
  const uint32_t j0 = std::max(rect.j0, y0), j1 = std::min(rect.j1, y0 + (side - 1));
  return i0 > i1 || j0 > j1 ? 0 : uint64_t(i1 - i0 + 1) * (j1 - j0 + 1);
}

// Issue 13: a structure walked once per kernel. litTexels(rect, z) counts the texels (i, j) of
// `rect` with z ≤ depth(i, j), exactly as testing each would, but a block of texels that one
// node of the structure decides (the MH reference code's kernel lookup), or one line segment,
// is tested once.
template <class Self>
concept KernelWalk = requires(const Self& self, const TexelRect& rect, float z) {
  { self.litTexels(rect, z) } -> std::convertible_to<uint64_t>;
};

// Exact k×k PCF from a kernel walk: the answers of pcfLookup, tap for tap, since every texel is
// tested against the depth it stores.
template <KernelWalk Self>
void kernelLookup(const Self& self, std::span<const Query> queries, int k,
                  std::span<float> visibility) {
  const uint32_t resolution = self.resolution();
  const int64_t radius = k / 2, last = int64_t(resolution) - 1;
  const uint64_t taps = uint64_t(k) * uint64_t(k);
  for (size_t q = 0; q < queries.size(); ++q) {
    const Query& query = queries[q];
    const int64_t ci = texelOf(query.x, resolution), cj = texelOf(query.y, resolution);
    const int64_t i0 = std::max<int64_t>(ci - radius, 0), i1 = std::min(ci + radius, last);
    const int64_t j0 = std::max<int64_t>(cj - radius, 0), j1 = std::min(cj + radius, last);
    uint64_t lit = taps;
    if (i0 <= i1 && j0 <= j1) {
      // Taps off the map count as lit.
      lit -= uint64_t(i1 - i0 + 1) * uint64_t(j1 - j0 + 1);
      lit += self.litTexels(TexelRect{uint32_t(i0), uint32_t(j0), uint32_t(i1), uint32_t(j1)},
                            query.z);
    }
    visibility[q] = float(lit) / float(taps);
  }
}

// Issue 13: the positions of a batch's queries sorted by the Morton code of their texels (those
// off the map first), so that consecutive lookups share what they read.
std::vector<uint32_t> mortonOrder(std::span<const Query> queries, uint32_t resolution);

// A decoder declaring `static constexpr bool kMortonBatches = true` answers each batch in
// mortonOrder and writes the answers back in the caller's order: worth it where a lookup pays
// for what it brings in (sm-zstd decompresses a block on a cache miss), not where the sort costs
// more than it saves.
template <class Self>
concept SortsBatches = Self::kMortonBatches;

template <class Self>
class DepthDecoder : public Decoder {
 public:
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const final {
    checkLookupArguments(queries, k, visibility);
    if constexpr (SortsBatches<Self>) {
      const std::vector<uint32_t> order =
          mortonOrder(queries, static_cast<const Self&>(*this).resolution());
      std::vector<Query> sorted(queries.size());
      for (size_t q = 0; q < order.size(); ++q) sorted[q] = queries[order[q]];
      std::vector<float> answers(queries.size());
      lookupInOrder(sorted, k, answers);
      for (size_t q = 0; q < order.size(); ++q) visibility[order[q]] = answers[q];
    } else {
      lookupInOrder(queries, k, visibility);
    }
  }

 private:
  void lookupInOrder(std::span<const Query> queries, int k, std::span<float> visibility) const {
    const Self& self = static_cast<const Self&>(*this);
    if constexpr (KernelWalk<Self>) {
      if (k > 1) return kernelLookup(self, queries, k, visibility);
    }
    pcfLookup(
        self.resolution(), [&](uint32_t i, uint32_t j) { return self.depth(i, j); }, queries, k,
        visibility);
  }
};

// A DepthDecoder that also answers hierarchical PCF; Self supplies, besides resolution() and
// depth(), float coarseDepth(uint32_t i, uint32_t j, int coarser) for texel (i, j) of the map
// `coarser` levels up.
template <class Self>
class HierarchicalDepthDecoder : public DepthDecoder<Self>, public HierarchicalLookup {
 public:
  const HierarchicalLookup* hierarchicalLookup() const final { return this; }
  int levels() const final {
    return std::countr_zero(static_cast<const Self&>(*this).resolution());
  }
  void lookupCoarse(std::span<const Query> queries, int coarser, int k,
                    std::span<float> visibility) const final {
    checkLookupArguments(queries, k, visibility);
    if (coarser < 0 || coarser > levels())
      throw std::invalid_argument("a coarse level must lie between 0 and log2 R");
    const Self& self = static_cast<const Self&>(*this);
    pcfLookup(
        self.resolution() >> coarser,
        [&](uint32_t i, uint32_t j) { return self.coarseDepth(i, j, coarser); }, queries, k,
        visibility);
  }
};

}  // namespace sb
