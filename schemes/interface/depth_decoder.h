// Point and exact PCF lookups for depth schemes (DESIGN §4), written once, and hierarchical PCF
// for those whose structure holds the coarser levels. A depth scheme's
// decoder derives from DepthDecoder<Self> and supplies
//     uint32_t resolution() const;
//     float depth(uint32_t i, uint32_t j) const;   // the stored d of texel (i, j)
// and gets batch lookups that call depth() directly: no virtual call per query or tap.
#pragma once

#include <bit>
#include <stdexcept>
#include <string>

#include "schemes/interface/capabilities.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/scheme.h"

namespace sb {

// Point (k = 1) and exact k×k PCF over an R×R map whose texel (i, j) stores depthAt(i, j).
template <class DepthAt>
void pcfLookup(uint32_t resolution, const DepthAt& depthAt, std::span<const Query> queries, int k,
               std::span<float> visibility) {
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

template <class Self>
class DepthDecoder : public Decoder {
 public:
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const final {
    checkLookupArguments(queries, k, visibility);
    const Self& self = static_cast<const Self&>(*this);
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
