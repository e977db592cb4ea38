// What compressed-sm's whole builds (compressed_sm.cpp) and builds in parts
// (compressed_sm_parts.cpp) share: the structure's scanline layout and its decoder, and a
// scanline's fit in progress.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "schemes/compressed-sm/compressed_sm.h"
#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"

namespace sb::compressed_sm {

// The scanline layout of a structure and of a part payload alike: the row index, then the
// segments' arrays.
void putScanlines(ByteWriter& out, std::span<const uint32_t> rowIndex, const Segments& segments);

class CompressedSmDecoder final : public DepthDecoder<CompressedSmDecoder> {
 public:
  CompressedSmDecoder(uint32_t resolution, std::vector<uint32_t> rowIndex, Segments segments)
      : resolution_(resolution), rowIndex_(std::move(rowIndex)), segments_(std::move(segments)) {}

  uint32_t resolution() const { return resolution_; }
  float depth(uint32_t i, uint32_t j) const {
    const size_t at = segmentOf(i, j);
    return segmentDepth(segments_.starts[at], segments_.slopes[at], i - segments_.firstColumns[at]);
  }
  // Issue 13: a kernel row is one search for its first column, then a walk along its segments;
  // a flat segment's taps are tested once. (Counting a sloped segment's lit taps from where its
  // line crosses z instead of tap by tap measured slower: the searches dominate.) Every row is
  // searched before any is walked, and the found segments' start and slope are fetched then, so
  // that the rows' cache misses overlap instead of coming one row after another.
  uint64_t litTexels(const TexelRect& rect, float z) const {
    const uint32_t* columns = segments_.firstColumns.data();
    uint64_t lit = 0;
    for (uint32_t top = rect.j0; top <= rect.j1; top += kMaxFilterSize) {
      const uint32_t rows = std::min<uint32_t>(kMaxFilterSize, rect.j1 - top + 1);
      size_t first[kMaxFilterSize];
      for (uint32_t r = 0; r < rows; ++r) {
        first[r] = segmentOf(rect.i0, top + r);
        __builtin_prefetch(segments_.starts.data() + first[r]);
        __builtin_prefetch(segments_.slopes.data() + first[r]);
      }
      for (uint32_t r = 0; r < rows; ++r) {
        const size_t end = rowIndex_[top + r + 1];
        for (size_t at = first[r], i = rect.i0; i <= rect.i1; ++at) {
          const uint32_t last = std::min(rect.i1, at + 1 == end ? rect.i1 : columns[at + 1] - 1);
          const float start = segments_.starts[at], slope = segments_.slopes[at];
          if (slope == 0.0f) {
            lit += z <= segmentDepth(start, slope, 0) ? last - i + 1 : 0;
            i = last + 1;
          } else {
            for (; i <= last; ++i)
              lit += z <= segmentDepth(start, slope, uint32_t(i) - columns[at]);
          }
        }
      }
    }
    return lit;
  }

  SizeBreakdown size() const override {
    return {{"segments", segments_.count() * (sizeof(uint32_t) + 2 * sizeof(float))},
            {"row index", rowIndex_.size() * sizeof(uint32_t)}};
  }
  void save(ByteWriter& out) const override { putScanlines(out, rowIndex_, segments_); }

 private:
  // The segment of column i in scanline j, by binary search among the scanline's first columns;
  // the first is column 0, so the search never falls off its front.
  size_t segmentOf(uint32_t i, uint32_t j) const {
    const uint32_t* columns = segments_.firstColumns.data();
    return size_t(std::upper_bound(columns + rowIndex_[j] + 1, columns + rowIndex_[j + 1], i) -
                  columns) -
           1;
  }

  uint32_t resolution_;
  std::vector<uint32_t> rowIndex_;  // R + 1 entries: scanline j's segments are [j], [j + 1])
  Segments segments_;
};

// One scanline's fit in progress: the texels from the first column of its open segment on, and
// the candidates' slope ranges so far. Segments close at every multiple of the span and at the
// scanline's end, in whole builds and in parts alike, so that a part whose left border is a
// multiple of the span fits its rows exactly as the whole build does.
struct ScanlineFit {
  uint32_t arrived = 0;       // columns received
  uint32_t first = 0;         // the column of lo[0], hi[0]: the open segment's first
  std::vector<float> lo, hi;  // texels [first, arrived), not yet in a segment
  OpenSegment open;           // the fit of the segment from column `first`

  // Appends the texels of columns [arrived, arrived + pieceLo.size()) and the segments they decide
  // to `out`; `end` is the scanline's last column plus one.
  void append(std::span<const float> pieceLo, std::span<const float> pieceHi, uint64_t span,
              uint32_t end, Segments& out) {
    size_t at = 0;
    while (at < pieceLo.size()) {
      const uint64_t boundary = (arrived / span + 1) * span;
      const size_t width = size_t(std::min<uint64_t>(pieceLo.size() - at, boundary - arrived));
      lo.insert(lo.end(), pieceLo.begin() + at, pieceLo.begin() + at + width);
      hi.insert(hi.end(), pieceHi.begin() + at, pieceHi.begin() + at + width);
      arrived += uint32_t(width), at += width;
      const bool closed = arrived % span == 0 || arrived == end;
      const size_t fitted = fitDecided(lo, hi, first, closed, out, open);
      lo.erase(lo.begin(), lo.begin() + fitted);
      hi.erase(hi.begin(), hi.begin() + fitted);
      first += uint32_t(fitted);
    }
    if (arrived == end) {
      std::vector<float>().swap(lo);
      std::vector<float>().swap(hi);
    }
  }
};

// The segments of consecutive scanlines: scanline r's are [rowIndex[r], rowIndex[r + 1]).
struct Rows {
  std::vector<uint32_t> rowIndex;
  Segments segments;
};

// Reads the four arrays of Rows (the structure's payload and a part's), `rows` scanlines.
Rows readRows(ByteReader& in, uint32_t rows);

// What is wrong with Rows of `width` columns, or "" where nothing is. Every scanline owns a
// non-empty run of segments, the runs tile the segment arrays, and within a run the first columns
// start at 0 and strictly increase below `width`: the lookup's binary search then always lands on
// a segment of its own scanline.
std::string rowsError(const Rows& rows, uint32_t width);

// Builds in parts (compressed_sm_parts.cpp): whether a part of side `partSize` fits its rows on
// its own, its encoder and the merger.
bool fitsOnItsOwn(uint32_t partSize, uint64_t span);
std::unique_ptr<PartEncoder> makePartEncoder(const MapPart& part, uint64_t span);
std::unique_ptr<PartMerger> makePartMerger(const MapInfo& map, uint32_t partSize, uint64_t span);

}  // namespace sb::compressed_sm
