// compressed-sm — compressed shadow maps (J. Arvo, M. Hirvikorpi, "Compressed shadow maps",
// The Visual Computer 21(3), 2005), as summarised by Sintorn et al. 2014 §2 and Scandolo et al.
// 2016a §2.2: each scanline of the dual depth map becomes a piecewise-linear function of the
// column that passes through every texel's [lo, hi] interval, and only its segments are stored.
#include "schemes/compressed-sm/compressed_sm.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/serial.h"

namespace sb {
namespace compressed_sm {

namespace {

// The upper end used for fitting: an open-ended interval (the ray hit nothing, or the closed
// mode's open band) is bounded by max(lo, 1), which lies inside it and keeps slopes finite.
float upperBound(float lo, float hi) {
  return std::isinf(hi) ? std::max(lo, 1.0f) : hi;
}

// Half the gap to the neighbouring float: a real value that close to a bound rounds onto it or
// inside (round to nearest). The feasible cone is widened by it so that points that lie on a
// line only up to float rounding still join one segment; the float32 check decides.
double halfGapBelow(float x) {
  return (double(x) - double(std::nextafter(x, -std::numeric_limits<float>::infinity()))) / 2;
}
double halfGapAbove(float x) {
  return (double(std::nextafter(x, std::numeric_limits<float>::infinity())) - double(x)) / 2;
}

struct Line {
  float start, slope;
  size_t end;  // one past the segment's last column
};

// Narrows the candidate's range of slopes (Arvo & Hirvikorpi 2005, §3: the lines from its start
// value through every interval so far) by the texels after the ones it has seen, until a texel
// empties it. `first` is the segment's first texel.
void narrow(OpenSegment::Candidate& candidate, std::span<const float> lo, std::span<const float> hi,
            size_t first) {
  for (; candidate.end < lo.size(); ++candidate.end) {
    const double k = double(candidate.end - first);
    const float l = lo[candidate.end], h = upperBound(lo[candidate.end], hi[candidate.end]);
    const double low =
        std::max(candidate.slopeMin, (double(l) - halfGapBelow(l) - candidate.start) / k);
    const double high =
        std::min(candidate.slopeMax, (double(h) + halfGapAbove(h) - candidate.start) / k);
    if (low > high) {
      candidate.ended = true;
      return;
    }
    candidate.slopeMin = low, candidate.slopeMax = high;
  }
}

// The segment a candidate gives: the middle of its slope range, ended before the first texel
// that float32 rounding pushes out of its interval.
Line lineOf(const OpenSegment::Candidate& candidate, std::span<const float> lo,
            std::span<const float> hi, size_t first) {
  size_t end = candidate.end;
  const float slope =
      end == first + 1 ? 0.0f : float((candidate.slopeMin + candidate.slopeMax) / 2);
  // The range was found in double precision; the lookup evaluates in float32. Check every texel
  // exactly as the lookup computes it (the first texel is the start value itself).
  for (size_t i = first + 1; i < end; ++i) {
    const float d = segmentDepth(candidate.start, slope, uint32_t(i - first));
    if (!(d >= lo[i] && d <= upperBound(lo[i], hi[i]))) {
      end = i;
      break;
    }
  }
  return {candidate.start, end == first + 1 ? 0.0f : slope, end};
}

}  // namespace

size_t fitDecided(std::span<const float> lo, std::span<const float> hi, uint32_t firstColumn,
                  bool complete, Segments& out, OpenSegment& open) {
  const size_t n = lo.size();
  size_t first = 0;
  while (first < n) {
    if (open.count == 0) {
      // The segment's start value is free within its first interval. Try its middle (the most
      // room both ways) and both ends (a slope that leaves the interval from one end reaches
      // furthest), keep the longest segment, the middle on ties.
      const float l0 = lo[first], h0 = upperBound(lo[first], hi[first]);
      const float middle = std::clamp(float((double(l0) + double(h0)) / 2), l0, h0);
      for (float start : {middle, l0, h0}) {
        open.candidates[open.count++] = {start, -std::numeric_limits<double>::infinity(),
                                         std::numeric_limits<double>::infinity(), first + 1, false};
        if (l0 == h0) break;
      }
    }
    bool undecided = false;
    for (uint32_t c = 0; c < open.count; ++c) {
      narrow(open.candidates[c], lo, hi, first);
      undecided |= !open.candidates[c].ended;
    }
    // A candidate that no texel so far has ended may still become the longest.
    if (undecided && !complete) {
      for (uint32_t c = 0; c < open.count; ++c) open.candidates[c].end -= first;
      break;
    }
    Line best = lineOf(open.candidates[0], lo, hi, first);
    for (uint32_t c = 1; c < open.count; ++c) {
      const Line line = lineOf(open.candidates[c], lo, hi, first);
      if (line.end > best.end) best = line;
    }
    open.count = 0;
    out.firstColumns.push_back(firstColumn + uint32_t(first));
    out.starts.push_back(best.start);
    out.slopes.push_back(best.slope);
    first = best.end;
  }
  return first;
}

size_t fitScanline(std::span<const float> lo, std::span<const float> hi, Segments& out) {
  const size_t before = out.count();
  OpenSegment open;
  fitDecided(lo, hi, 0, true, out, open);
  return out.count() - before;
}

namespace {

class CompressedSmDecoder final : public DepthDecoder<CompressedSmDecoder> {
 public:
  CompressedSmDecoder(uint32_t resolution, std::vector<uint32_t> rowIndex, Segments segments)
      : resolution_(resolution), rowIndex_(std::move(rowIndex)), segments_(std::move(segments)) {}

  uint32_t resolution() const { return resolution_; }
  float depth(uint32_t i, uint32_t j) const {
    // Binary search for the segment of column i among the first columns of scanline j; the
    // first one of a scanline is column 0, so the search never falls off its front.
    const uint32_t* columns = segments_.firstColumns.data();
    const uint32_t* found =
        std::upper_bound(columns + rowIndex_[j] + 1, columns + rowIndex_[j + 1], i) - 1;
    const size_t at = size_t(found - columns);
    return segmentDepth(segments_.starts[at], segments_.slopes[at], i - *found);
  }

  SizeBreakdown size() const override {
    return {{"segments", segments_.count() * (sizeof(uint32_t) + 2 * sizeof(float))},
            {"row index", rowIndex_.size() * sizeof(uint32_t)}};
  }
  void save(ByteWriter& out) const override {
    out.putArray<uint32_t>(rowIndex_);
    out.putArray<uint32_t>(segments_.firstColumns);
    out.putArray<float>(segments_.starts);
    out.putArray<float>(segments_.slopes);
  }

 private:
  uint32_t resolution_;
  std::vector<uint32_t> rowIndex_;  // R + 1 entries: scanline j's segments are [j], [j + 1])
  Segments segments_;
};

// Tiles arrive in Morton order, which hands every scanline its texels left to right, a tile's
// width at a time. Each scanline keeps the texels from the first column of its open segment on:
// a new piece extends them, the segments they decide are fitted (fitDecided) and their texels
// dropped. So what waits in memory is each scanline's open segment, not the map, and the
// segments are those of fitting whole scanlines.
class CompressedSmEncoder final : public Encoder {
 public:
  explicit CompressedSmEncoder(const MapInfo& map) : map_(map), scanlines_(map.resolution) {}

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("fit scanlines");
    if (tile.x0 + tile.width > map_.resolution || tile.y0 + tile.height > map_.resolution)
      throw std::invalid_argument("compressed-sm: a tile reaches outside the map");
    std::vector<int64_t> pendingChange(tile.height);
    tbb::parallel_for(uint32_t(0), tile.height, [&](uint32_t row) {
      Scanline& scanline = scanlines_[tile.y0 + row];
      if (scanline.arrived != tile.x0)
        throw std::invalid_argument(fmt::format(
            "compressed-sm: scanline {} received columns from {} after {} columns; tiles must "
            "deliver each scanline left to right",
            tile.y0 + row, tile.x0, scanline.arrived));
      const int64_t before = int64_t(scanline.lo.size());
      const size_t from = tile.index(tile.x0, tile.y0 + row);
      scanline.lo.insert(scanline.lo.end(), tile.lo.begin() + from,
                         tile.lo.begin() + from + tile.width);
      scanline.hi.insert(scanline.hi.end(), tile.hi.begin() + from,
                         tile.hi.begin() + from + tile.width);
      scanline.arrived += tile.width;
      const bool complete = scanline.arrived == map_.resolution;
      const size_t fitted = fitDecided(scanline.lo, scanline.hi, scanline.first, complete,
                                       scanline.segments, scanline.open);
      scanline.lo.erase(scanline.lo.begin(), scanline.lo.begin() + fitted);
      scanline.hi.erase(scanline.hi.begin(), scanline.hi.begin() + fitted);
      scanline.first += uint32_t(fitted);
      if (complete) {
        std::vector<float>().swap(scanline.lo);
        std::vector<float>().swap(scanline.hi);
      }
      pendingChange[row] = int64_t(scanline.lo.size()) - before;
    });
    for (int64_t change : pendingChange) pendingTexels_ += change;
    peakPendingTexels_ = std::max(peakPendingTexels_, pendingTexels_);
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    context.phase("concatenate scanlines");
    std::vector<uint32_t> rowIndex{0};
    rowIndex.reserve(size_t(map_.resolution) + 1);
    // Reserved exactly: growing by doubling would hold up to twice the segments while copying.
    size_t total = 0;
    for (const Scanline& scanline : scanlines_) total += scanline.segments.count();
    Segments all;
    all.firstColumns.reserve(total);
    all.starts.reserve(total);
    all.slopes.reserve(total);
    for (Scanline& scanline : scanlines_) {
      if (scanline.arrived != map_.resolution)
        throw std::logic_error("compressed-sm: the map did not arrive whole");
      const Segments& row = scanline.segments;
      if (uint64_t(rowIndex.back()) + row.count() > std::numeric_limits<uint32_t>::max())
        throw std::length_error("compressed-sm: more segments than a 32-bit row index holds");
      rowIndex.push_back(rowIndex.back() + uint32_t(row.count()));
      all.firstColumns.insert(all.firstColumns.end(), row.firstColumns.begin(),
                              row.firstColumns.end());
      all.starts.insert(all.starts.end(), row.starts.begin(), row.starts.end());
      all.slopes.insert(all.slopes.end(), row.slopes.begin(), row.slopes.end());
      scanline = {};
    }
    context.count("segments", all.count());
    context.count("peak pending texels", uint64_t(peakPendingTexels_));
    return std::make_unique<CompressedSmDecoder>(map_.resolution, std::move(rowIndex),
                                                 std::move(all));
  }

 private:
  struct Scanline {
    uint32_t arrived = 0;       // columns received
    uint32_t first = 0;         // the column of lo[0], hi[0]: the open segment's first
    std::vector<float> lo, hi;  // texels [first, arrived), not yet in a segment
    OpenSegment open;           // the fit of the segment from column `first`
    Segments segments;          // the segments fitted so far
  };

  MapInfo map_;
  std::vector<Scanline> scanlines_;
  int64_t pendingTexels_ = 0, peakPendingTexels_ = 0;
};

[[noreturn]] void invalid(const std::string& what) {
  throw FormatError("compressed-sm: " + what);
}

std::unique_ptr<Decoder> load(ByteReader& in, const MapInfo& map) {
  const uint32_t r = map.resolution;
  std::vector<uint32_t> rowIndex = in.getArray<uint32_t>("compressed-sm row index", size_t(r) + 1);
  Segments segments;
  segments.firstColumns = in.getArray<uint32_t>("compressed-sm first columns");
  const uint64_t count = segments.count();
  segments.starts = in.getArray<float>("compressed-sm start values", count);
  segments.slopes = in.getArray<float>("compressed-sm slopes", count);
  // Every scanline owns a non-empty run of segments, the runs tile the segment arrays, and
  // within a run the first columns start at 0 and strictly increase below R: the lookup's
  // binary search then always lands on a segment of its own scanline.
  if (rowIndex[0] != 0) invalid("the row index does not start at 0");
  if (rowIndex[r] != count) invalid("the row index does not end at the segment count");
  for (uint32_t j = 0; j < r; ++j) {
    if (rowIndex[j + 1] <= rowIndex[j] || rowIndex[j + 1] > count)
      invalid(fmt::format("scanline {} has no segments or runs past them", j));
    if (segments.firstColumns[rowIndex[j]] != 0)
      invalid(fmt::format("scanline {} does not start at column 0", j));
    for (uint32_t s = rowIndex[j] + 1; s < rowIndex[j + 1]; ++s)
      if (segments.firstColumns[s] <= segments.firstColumns[s - 1] || segments.firstColumns[s] >= r)
        invalid(fmt::format("scanline {} has first columns out of order or past R", j));
  }
  for (uint64_t s = 0; s < count; ++s)
    if (!std::isfinite(segments.starts[s]) || !std::isfinite(segments.slopes[s]))
      invalid("a segment's start value or slope is not finite");
  return std::make_unique<CompressedSmDecoder>(r, std::move(rowIndex), std::move(segments));
}

SchemeInfo compressedSm() {
  SchemeInfo info;
  info.name = "compressed-sm";
  info.paper =
      "Arvo & Hirvikorpi 2005, compressed shadow maps: scanlines as piecewise-linear "
      "functions through the depth intervals";
  info.kind = SchemeKind::Depth;
  // The open segments' texels: a row of tiles' worth when segments are as short as tiles (long
  // segments keep more, up to the texels of a scanline that has arrived); and the segments, at
  // least one per scanline (start and slope) with its row index entry.
  info.buildBytes = [](const MapInfo& map, const ParamValues&, const BuildShape& shape) {
    return uint64_t(map.resolution) * std::min(map.resolution, shape.tileSize) * 2 * sizeof(float) +
           uint64_t(map.resolution) * (2 * sizeof(float) + sizeof(uint64_t));
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues&,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<CompressedSmEncoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map, const ParamValues&) { return load(in, map); };
  return info;
}

}  // namespace
}  // namespace compressed_sm

using compressed_sm::compressedSm;
SHADOWBENCH_REGISTER_SCHEME(compressedSm);

}  // namespace sb
