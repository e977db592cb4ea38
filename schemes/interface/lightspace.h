// Light-space addressing shared by every lookup and by the reference (DESIGN §2, §4), so the
// texel or voxel a query falls in is decided by one piece of code.
#pragma once

#include <cmath>
#include <cstdint>

namespace sb {

// Resolutions are powers of two — tiles, Morton order and quadtrees need it — from 8 to 2^20.
inline constexpr uint32_t kMinResolution = 8, kMaxResolution = 1u << 20;
inline bool validResolution(uint64_t r) {
  return r >= kMinResolution && r <= kMaxResolution && (r & (r - 1)) == 0;
}

// The texel coordinate ⌊x·R⌋; anything outside [0, R) (including NaN) means "outside the map".
inline int64_t texelOf(float x, uint32_t resolution) {
  const float scaled = std::floor(x * float(resolution));  // exact: R is a power of two
  if (!(scaled >= 0.0f)) return -1;
  if (scaled >= float(resolution)) return int64_t(resolution);
  return int64_t(scaled);
}

inline bool insideMap(int64_t i, int64_t j, uint32_t resolution) {
  return i >= 0 && j >= 0 && i < int64_t(resolution) && j < int64_t(resolution);
}

// DESIGN §4 voxel rule: slice k = ⌊z·Rz⌋ clamped to [0, Rz − 1], answered at its centre.
inline uint32_t voxelOf(float z, uint32_t depthResolution) {
  const float scaled = std::floor(z * float(depthResolution));
  if (!(scaled >= 0.0f)) return 0;
  if (scaled >= float(depthResolution)) return depthResolution - 1;
  return uint32_t(scaled);
}
inline float voxelCentre(uint32_t k, uint32_t depthResolution) {
  return (float(k) + 0.5f) / float(depthResolution);
}

// The widest PCF kernel a lookup answers (k × k taps).
inline constexpr int kMaxFilterSize = 17;
inline bool validFilterSize(int k) {
  return k >= 1 && k <= kMaxFilterSize && k % 2 == 1;
}

}  // namespace sb
