// compressed-sm — compressed shadow maps (Arvo & Hirvikorpi 2005): every scanline of the dual
// depth map becomes a piecewise-linear function of the column that stays inside every texel's
// [lo, hi] interval; only its segments are stored.
#pragma once

#include <array>
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

// A segment being fitted from its first texel: for each start value tried, the range of slopes
// of the lines from it through every interval seen so far (Arvo & Hirvikorpi 2005, §3).
struct OpenSegment {
  struct Candidate {
    float start;
    double slopeMin, slopeMax;
    size_t end;  // texels before `end` have narrowed the range (counted from the segment's first)
    bool ended;  // texel `end` emptied it
  };
  std::array<Candidate, 3> candidates;
  uint32_t count = 0;  // 0: no segment started
};

// The same fit over the texels of a scanline known so far, from column `firstColumn` on: appends
// the segments these texels decide and returns how many texels they cover. A segment that no
// texel so far has ended could grow with the next ones, so the fit stops before it unless
// `complete` (the scanline's last texel is among them) and keeps its candidates in `open`, to
// go on from there. Calling again with the texels from the returned one on, more appended, and
// the same `open` gives exactly the segments of fitScanline over the whole scanline.
size_t fitDecided(std::span<const float> lo, std::span<const float> hi, uint32_t firstColumn,
                  bool complete, Segments& out, OpenSegment& open);

}  // namespace sb::compressed_sm
