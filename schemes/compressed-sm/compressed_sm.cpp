// compressed-sm — compressed shadow maps (J. Arvo, M. Hirvikorpi, "Compressed shadow maps",
// The Visual Computer 21(3), 2005), as summarised by Sintorn et al. 2014 §2 and Scandolo et al.
// 2016a §2.2: each scanline of the dual depth map becomes a piecewise-linear function of the
// column that passes through every texel's [lo, hi] interval, and only its segments are stored.
#include "schemes/compressed-sm/compressed_sm.h"
#include "schemes/compressed-sm/scanlines.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/parts.h"
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

// The scanline layout of a structure and of a part payload alike: the row index, then the
// segments' arrays.
void putScanlines(ByteWriter& out, std::span<const uint32_t> rowIndex, const Segments& segments) {
  out.putArray<uint32_t>(rowIndex);
  out.putArray<uint32_t>(segments.firstColumns);
  out.putArray<float>(segments.starts);
  out.putArray<float>(segments.slopes);
}

// Reads the four arrays of Rows (the structure's payload and a part's), `rows` scanlines.
Rows readRows(ByteReader& in, uint32_t rows) {
  Rows read;
  read.rowIndex = in.getArray<uint32_t>("compressed-sm row index", size_t(rows) + 1);
  read.segments.firstColumns = in.getArray<uint32_t>("compressed-sm first columns");
  const uint64_t count = read.segments.count();
  read.segments.starts = in.getArray<float>("compressed-sm start values", count);
  read.segments.slopes = in.getArray<float>("compressed-sm slopes", count);
  return read;
}

// What is wrong with Rows of `width` columns, or "" where nothing is. Every scanline owns a
// non-empty run of segments, the runs tile the segment arrays, and within a run the first columns
// start at 0 and strictly increase below `width`: the lookup's binary search then always lands on
// a segment of its own scanline.
std::string rowsError(const Rows& rows, uint32_t width) {
  const std::vector<uint32_t>& index = rows.rowIndex;
  const Segments& segments = rows.segments;
  const size_t count = segments.count(), scanlines = index.size() - 1;
  if (index[0] != 0) return "the row index does not start at 0";
  if (index[scanlines] != count) return "the row index does not end at the segment count";
  for (size_t j = 0; j < scanlines; ++j) {
    if (index[j + 1] <= index[j] || index[j + 1] > count)
      return fmt::format("scanline {} has no segments or runs past them", j);
    if (segments.firstColumns[index[j]] != 0)
      return fmt::format("scanline {} does not start at column 0", j);
    for (uint32_t s = index[j] + 1; s < index[j + 1]; ++s)
      if (segments.firstColumns[s] <= segments.firstColumns[s - 1] ||
          segments.firstColumns[s] >= width)
        return fmt::format("scanline {} has first columns out of order or past {}", j, width);
  }
  for (size_t s = 0; s < count; ++s)
    if (!std::isfinite(segments.starts[s]) || !std::isfinite(segments.slopes[s]))
      return "a segment's start value or slope is not finite";
  return "";
}

namespace {

uint64_t segmentSpanOf(const ParamValues& params) {
  return uint64_t(params.integer("segment-span"));
}

// Tiles arrive in Morton order, which hands every scanline its texels left to right, a tile's
// width at a time. Each scanline keeps the texels from the first column of its open segment on:
// a new piece extends them, the segments they decide are fitted (fitDecided) and their texels
// dropped. So what waits in memory is each scanline's open segment, not the map, and the
// segments are those of fitting whole scanlines closed at every multiple of the span.
class CompressedSmEncoder final : public Encoder {
 public:
  CompressedSmEncoder(const MapInfo& map, uint64_t span)
      : map_(map), span_(span), scanlines_(map.resolution) {}

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("fit scanlines");
    if (tile.x0 + tile.width > map_.resolution || tile.y0 + tile.height > map_.resolution)
      throw std::invalid_argument("compressed-sm: a tile reaches outside the map");
    std::vector<int64_t> pendingChange(tile.height);
    tbb::parallel_for(uint32_t(0), tile.height, [&](uint32_t row) {
      Scanline& scanline = scanlines_[tile.y0 + row];
      if (scanline.fit.arrived != tile.x0)
        throw std::invalid_argument(fmt::format(
            "compressed-sm: scanline {} received columns from {} after {} columns; tiles must "
            "deliver each scanline left to right",
            tile.y0 + row, tile.x0, scanline.fit.arrived));
      const int64_t before = int64_t(scanline.fit.lo.size());
      const size_t from = tile.index(tile.x0, tile.y0 + row);
      scanline.fit.append(std::span(tile.lo).subspan(from, tile.width),
                          std::span(tile.hi).subspan(from, tile.width), span_, map_.resolution,
                          scanline.segments);
      pendingChange[row] = int64_t(scanline.fit.lo.size()) - before;
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
      if (scanline.fit.arrived != map_.resolution)
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
    ScanlineFit fit;
    Segments segments;  // the segments fitted so far
  };

  MapInfo map_;
  uint64_t span_;
  std::vector<Scanline> scanlines_;
  int64_t pendingTexels_ = 0, peakPendingTexels_ = 0;
};

std::unique_ptr<Decoder> load(ByteReader& in, const MapInfo& map) {
  Rows rows = readRows(in, map.resolution);
  if (const std::string error = rowsError(rows, map.resolution); !error.empty())
    throw FormatError("compressed-sm: " + error);
  return std::make_unique<CompressedSmDecoder>(map.resolution, std::move(rows.rowIndex),
                                               std::move(rows.segments));
}

SchemeInfo compressedSm() {
  SchemeInfo info;
  info.name = "compressed-sm";
  info.paper =
      "Arvo & Hirvikorpi 2005, compressed shadow maps: scanlines as piecewise-linear "
      "functions through the depth intervals";
  info.kind = SchemeKind::Depth;
  info.params = {
      ParamSpec::integer("segment-span",
                         "every scanline's segments close at the multiples of this column; a "
                         "build in parts fits parts of a multiple of it on their own",
                         16384, 16, int64_t(1) << 30, {1024, 16384})
          .satisfying("a power of two",
                      [](int64_t span) { return std::has_single_bit(uint64_t(span)); })};
  // What a fit holds is its scanlines' open segments: every texel from the first column of the
  // open one on (up to the span, the vector's capacity kept between segments). Tiles arrive in
  // Morton order, so the top half's scanlines are all open before the first of them ends: half
  // a map's (or a part's) side of scanlines, each holding up to min(side, span) texels. Measured
  // on 32K² parts with span 16K, against this 2 GiB: terrain closed 2.1 GiB, city closed 1.2,
  // forest static 1.1 (issue 12). Beside them the segments, at least one a scanline with its
  // row index entry. In parts (shape.inParts), one part's encoding (fitting its scanlines, or
  // holding its texels when it is smaller than the span), the merge (the parts' rows and the
  // structure they are copied into, which the part files bound once they exist, and for parts
  // smaller than the span every scanline's open segment), or the larger, by shape.step.
  info.buildBytes = [](const MapInfo& map, const ParamValues& params, const BuildShape& shape) {
    constexpr uint64_t kTexelBytes = 2 * sizeof(float);
    const uint64_t span = segmentSpanOf(params);
    auto fitting = [&](uint64_t side) {
      return side / 2 * std::min(side, span) * kTexelBytes +
             side * (kTexelBytes + sizeof(uint64_t));
    };
    const uint64_t r = map.resolution;
    if (!shape.inParts(map)) return fitting(r);
    const uint64_t p = shape.partSize;
    const BuildShape::PartFiles& files = shape.partFiles;
    // The parts' rows and the concatenated structure, both: the rows of the bands already copied
    // are freed to the allocator, which keeps most of them (measured: the merge peaks at 2.0×
    // the part files above the baseline, city closed 256K² and forest static 128K²).
    const uint64_t structure = 2 * files.totalBytes + files.largestBytes;
    if (fitsOnItsOwn(shape.partSize, span))
      return shape.partsBytes(fitting(p), structure + r * (kTexelBytes + sizeof(uint64_t)));
    return shape.partsBytes(2 * p * p * kTexelBytes, structure + fitting(r) + p * p * kTexelBytes);
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues& params,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<CompressedSmEncoder>(map, segmentSpanOf(params));
  };
  info.load = [](ByteReader& in, const MapInfo& map, const ParamValues&) { return load(in, map); };
  info.makePartEncoder = [](const MapInfo&, const MapPart& part, const ParamValues& params,
                            const BuildShape&) -> std::unique_ptr<PartEncoder> {
    return makePartEncoder(part, segmentSpanOf(params));
  };
  info.makePartMerger = [](const MapInfo& map, const ParamValues& params,
                           const BuildShape& shape) -> std::unique_ptr<PartMerger> {
    return makePartMerger(map, shape.partSize, segmentSpanOf(params));
  };
  return info;
}

}  // namespace
}  // namespace compressed_sm

using compressed_sm::compressedSm;
SHADOWBENCH_REGISTER_SCHEME(compressedSm);

}  // namespace sb
