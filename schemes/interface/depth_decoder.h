// Point and exact PCF lookups for depth schemes (DESIGN §4), written once. A depth scheme's
// decoder derives from DepthDecoder<Self> and supplies
//     uint32_t resolution() const;
//     float depth(uint32_t i, uint32_t j) const;   // the stored d of texel (i, j)
// and gets batch lookups that call depth() directly: no virtual call per query or tap.
#pragma once

#include <stdexcept>
#include <string>

#include "schemes/interface/lightspace.h"
#include "schemes/interface/scheme.h"

namespace sb {

template <class Self>
class DepthDecoder : public Decoder {
 public:
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const final {
    checkLookupArguments(queries, k, visibility);
    const Self& self = static_cast<const Self&>(*this);
    const uint32_t resolution = self.resolution();
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
            lit += query.z <= self.depth(i, j);
      } else {
        for (int64_t j = cj - radius; j <= cj + radius; ++j)
          for (int64_t i = ci - radius; i <= ci + radius; ++i)
            lit += !insideMap(i, j, resolution) || query.z <= self.depth(uint32_t(i), uint32_t(j));
      }
      visibility[q] = float(lit) / taps;
    }
  }
};

}  // namespace sb
