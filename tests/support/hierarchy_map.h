// A synthetic map's multiresolution hierarchy and the inside test the MH-family tests share.
#pragma once

#include "schemes/shared/multires_hierarchy.h"
#include "tests/support/synthetic_map.h"

namespace sb::testing {

inline MultiresHierarchy hierarchyOf(const SyntheticMap& map, uint32_t tileSize) {
  MhBuilder builder(map.info(SchemeKind::Depth));
  map.stream(tileSize, [&](const DualDepthTile& tile) { builder.consume(tile); });
  return builder.finish();
}

// Whether the depth of `key` lies in texel (i, j)'s interval, compared as float32 (DESIGN §4).
inline bool insideInterval(const SyntheticMap& map, uint32_t i, uint32_t j, uint32_t key) {
  const size_t at = size_t(j) * map.resolution + i;
  const float d = depthOfKey(key);
  return map.lo[at] <= d && d <= map.hi[at];
}

}  // namespace sb::testing
