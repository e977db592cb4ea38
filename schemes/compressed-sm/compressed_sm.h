// compressed-sm — compressed shadow maps (Arvo & Hirvikorpi 2005): every scanline of the dual
// depth map becomes a piecewise-linear function of the column that stays inside every texel's
// [lo, hi] interval; only its segments are stored.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace sb::compressed_sm {

// The depth a segment gives `offset` columns after its first column. The encoder checks every
// texel with this very expression, and the lookup evaluates it: the build is -ffp-contract=off,
// so no fused multiply-add makes the two differ.
inline float segmentDepth(float start, float slope, uint32_t offset) {
  return start + slope * float(offset);
}

// The segments of one or more scanlines (structure of arrays, segments in column order).
struct Segments {
  std::vector<uint32_t> firstColumns;
  std::vector<float> starts, slopes;
  size_t count() const { return firstColumns.size(); }
};

// Greedy exact fit of one scanline (Arvo & Hirvikorpi 2005, §3): appends segments whose depths,
// evaluated with segmentDepth in float32, lie in [lo[i], bound(hi[i])] for every column i.
// An infinite hi is bounded by max(lo, 1), which lies inside the interval. Returns how many
// segments were appended.
size_t fitScanline(std::span<const float> lo, std::span<const float> hi, Segments& out);

}  // namespace sb::compressed_sm
