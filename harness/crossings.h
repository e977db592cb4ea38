// The crossings of one texel's ray with the scene's surfaces, and the interval [lo, hi] they
// define in each mode (DESIGN §3). Shared by both depth paths — the Embree ray caster and the
// light-space rasteriser — so that the modes are decided by one piece of code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "schemes/interface/scheme.h"

namespace sb {

// Closed mode follows at most this many crossings per ray; a ray that has not left the union
// of closed objects by then falls back to hi = lo.
inline constexpr int kMaxCrossings = 24;

// One crossing of a ray with a surface at light-space depth z: +1 entering a closed mesh (a
// front face), −1 leaving it (a back face), 0 for an open mesh.
struct Crossing {
  float z;
  int8_t sign;
  uint32_t mesh;
};

// Robust ray casting reports a ray through a shared edge or vertex once per triangle: the same
// mesh, the same facing, (almost) the same depth. Counted twice, one surface would unbalance
// the front/back counter, so such reports are one crossing.
inline bool sameCrossing(const Crossing& a, const Crossing& b) {
  return a.mesh == b.mesh && a.sign == b.sign &&
         std::abs(a.z - b.z) <= 1e-6f * std::max(std::abs(a.z), std::abs(b.z));
}

// The nearest crossings of a ray (at most kMaxCrossings), in order. At equal depth an entry sorts
// before an exit, so that touching closed objects (a building standing on the ground slab) count as
// one union.
struct CrossingList {
  Crossing nearest[kMaxCrossings];
  int count = 0;
  int capacity = kMaxCrossings;

  // Empties the list for a texel in `mode`: static mode needs only the two nearest crossings,
  // which spares deep scenes most of the insertion work.
  void clear(DepthMode mode) {
    count = 0;
    capacity = mode == DepthMode::Static ? 2 : kMaxCrossings;
  }

  // For ray casting, whose reports of one surface may repeat (sameCrossing).
  void insertOnce(Crossing c) {
    for (int k = 0; k < count; ++k)
      if (sameCrossing(nearest[k], c)) return;
    insert(c);
  }

  void insert(Crossing c) {
    auto before = [](const Crossing& a, const Crossing& b) {
      return a.z < b.z || (a.z == b.z && a.sign > b.sign);
    };
    if (count == capacity) {
      if (!before(c, nearest[count - 1])) return;
      --count;
    }
    int at = count++;
    while (at > 0 && before(c, nearest[at - 1])) nearest[at] = nearest[at - 1], --at;
    nearest[at] = c;
  }
};

struct ResolvedInterval {
  float lo, hi;
  bool closedFallback;  // closed mode could not find the exit: hi = lo, which is always correct
};

// DESIGN §3 for static and closed mode (open mode needs only the nearest crossing).
inline ResolvedInterval resolveCrossings(const CrossingList& list, DepthMode mode) {
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  if (list.count == 0) return {1.0f, kInfinity, false};
  const float lo = list.nearest[0].z;
  if (mode == DepthMode::Open) return {lo, lo, false};
  if (mode == DepthMode::Static)
    // Arvo & Hirvikorpi; Sintorn §6.1: no receiver lies between the first and second layer.
    return {lo, list.count > 1 ? list.nearest[1].z : kInfinity, false};
  if (list.nearest[0].sign == 0) return {lo, lo, false};  // an open first hit promises nothing
  // Sintorn §6.1, Kämpe §3.3: undefined from the first hit until the front/back counter over
  // closed meshes returns to zero.
  int inside = 0;
  for (int c = 0; c < list.count && inside >= 0; ++c) {
    inside += list.nearest[c].sign;
    if (inside == 0 && list.nearest[c].sign < 0) return {lo, list.nearest[c].z, false};
  }
  return {lo, lo, true};
}

}  // namespace sb
