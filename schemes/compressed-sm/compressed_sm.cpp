// compressed-sm — compressed shadow maps (J. Arvo, M. Hirvikorpi, "Compressed shadow maps",
// The Visual Computer 21(3), 2005), as summarised by Sintorn et al. 2014 §2 and Scandolo et al.
// 2016a §2.2: each scanline of the dual depth map becomes a piecewise-linear function of the
// column that passes through every texel's [lo, hi] interval, and only its segments are stored.
#include "schemes/compressed-sm/compressed_sm.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

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

// The longest segment from column `first` whose line starts at `start` (Arvo & Hirvikorpi 2005,
// §3): the slopes of the lines from the start value that pass through every interval so far form
// a range; each texel narrows it, and the segment ends where it becomes empty.
Line extend(std::span<const float> lo, std::span<const float> hi, size_t first, float start) {
  double slopeMin = -std::numeric_limits<double>::infinity();
  double slopeMax = std::numeric_limits<double>::infinity();
  size_t end = first + 1;
  for (; end < lo.size(); ++end) {
    const double k = double(end - first);
    const float l = lo[end], h = upperBound(lo[end], hi[end]);
    const double low = std::max(slopeMin, (double(l) - halfGapBelow(l) - start) / k);
    const double high = std::min(slopeMax, (double(h) + halfGapAbove(h) - start) / k);
    if (low > high) break;
    slopeMin = low, slopeMax = high;
  }
  const float slope = end == first + 1 ? 0.0f : float((slopeMin + slopeMax) / 2);
  // The range was found in double precision; the lookup evaluates in float32. Check every texel
  // exactly as the lookup computes it and end the segment before the first one that rounding
  // pushes out of its interval (the first texel is the start value itself).
  for (size_t i = first + 1; i < end; ++i) {
    const float d = segmentDepth(start, slope, uint32_t(i - first));
    if (!(d >= lo[i] && d <= upperBound(lo[i], hi[i]))) {
      end = i;
      break;
    }
  }
  return {start, end == first + 1 ? 0.0f : slope, end};
}

}  // namespace

size_t fitScanline(std::span<const float> lo, std::span<const float> hi, Segments& out) {
  const size_t n = lo.size(), before = out.count();
  size_t first = 0;
  while (first < n) {
    // The segment's start value is free within its first interval. Try its middle (the most
    // room both ways) and both ends (a slope that leaves the interval from one end reaches
    // furthest), keep the longest segment, the middle on ties.
    const float l0 = lo[first], h0 = upperBound(lo[first], hi[first]);
    const float middle = std::clamp(float((double(l0) + double(h0)) / 2), l0, h0);
    Line best = extend(lo, hi, first, middle);
    if (l0 != h0)
      for (float start : {l0, h0}) {
        const Line line = extend(lo, hi, first, start);
        if (line.end > best.end) best = line;
      }
    out.firstColumns.push_back(uint32_t(first));
    out.starts.push_back(best.start);
    out.slopes.push_back(best.slope);
    first = best.end;
  }
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

// Tiles arrive square and in Morton order, so a scanline is complete only when every tile of its
// band (a row of tiles) has arrived. The encoder buffers lo/hi of each band until then, fits its
// scanlines and frees it. In Morton order at most R / 2 rows are buffered at once (after the
// top-left quadrant every band of the top half is half full): 4 R² bytes, half of the map.
class CompressedSmEncoder final : public Encoder {
 public:
  explicit CompressedSmEncoder(const MapInfo& map) : map_(map) {}

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("buffer and fit scanlines");
    if (bandHeight_ == 0) {
      bandHeight_ = tile.height;
      fitted_.resize((map_.resolution + bandHeight_ - 1) / bandHeight_);
    }
    if (tile.height != bandHeight_ || tile.y0 % bandHeight_ != 0 ||
        tile.x0 + tile.width > map_.resolution || tile.y0 + tile.height > map_.resolution)
      throw std::invalid_argument("compressed-sm: tiles must be equal, aligned and in the map");
    const uint32_t bandIndex = tile.y0 / bandHeight_;
    Band& band = open_[bandIndex];
    if (band.lo.empty()) {
      band.lo.resize(size_t(bandHeight_) * map_.resolution);
      band.hi.resize(band.lo.size());
    }
    peakBands_ = std::max<uint64_t>(peakBands_, open_.size());
    for (uint32_t row = 0; row < tile.height; ++row) {
      const size_t from = size_t(row) * tile.width, to = size_t(row) * map_.resolution + tile.x0;
      std::copy_n(tile.lo.begin() + from, tile.width, band.lo.begin() + to);
      std::copy_n(tile.hi.begin() + from, tile.width, band.hi.begin() + to);
    }
    band.columnsArrived += tile.width;
    if (band.columnsArrived == map_.resolution) {
      fitBand(band, fitted_[bandIndex]);
      open_.erase(bandIndex);
    }
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    context.phase("concatenate scanlines");
    if (!open_.empty() || bandHeight_ == 0)
      throw std::logic_error("compressed-sm: the map did not arrive whole");
    std::vector<uint32_t> rowIndex{0};
    rowIndex.reserve(size_t(map_.resolution) + 1);
    Segments all;
    for (FittedBand& band : fitted_) {
      for (uint32_t count : band.rowCounts) {
        if (uint64_t(rowIndex.back()) + count > std::numeric_limits<uint32_t>::max())
          throw std::length_error("compressed-sm: more segments than a 32-bit row index holds");
        rowIndex.push_back(rowIndex.back() + count);
      }
      all.firstColumns.insert(all.firstColumns.end(), band.segments.firstColumns.begin(),
                              band.segments.firstColumns.end());
      all.starts.insert(all.starts.end(), band.segments.starts.begin(), band.segments.starts.end());
      all.slopes.insert(all.slopes.end(), band.segments.slopes.begin(), band.segments.slopes.end());
      band = {};
    }
    if (rowIndex.size() != size_t(map_.resolution) + 1)
      throw std::logic_error("compressed-sm: the map did not arrive whole");
    context.count("segments", all.count());
    context.count("peak buffered bands", peakBands_);
    return std::make_unique<CompressedSmDecoder>(map_.resolution, std::move(rowIndex),
                                                 std::move(all));
  }

 private:
  struct Band {
    std::vector<float> lo, hi;
    uint32_t columnsArrived = 0;
  };
  struct FittedBand {
    std::vector<uint32_t> rowCounts;
    Segments segments;
  };

  void fitBand(const Band& band, FittedBand& fitted) const {
    const uint32_t rows = bandHeight_;
    const size_t width = map_.resolution;
    std::vector<Segments> perRow(rows);
    tbb::parallel_for(uint32_t(0), rows, [&](uint32_t row) {
      fitScanline(std::span(band.lo).subspan(row * width, width),
                  std::span(band.hi).subspan(row * width, width), perRow[row]);
    });
    for (Segments& row : perRow) {
      fitted.rowCounts.push_back(uint32_t(row.count()));
      fitted.segments.firstColumns.insert(fitted.segments.firstColumns.end(),
                                          row.firstColumns.begin(), row.firstColumns.end());
      fitted.segments.starts.insert(fitted.segments.starts.end(), row.starts.begin(),
                                    row.starts.end());
      fitted.segments.slopes.insert(fitted.segments.slopes.end(), row.slopes.begin(),
                                    row.slopes.end());
    }
  }

  MapInfo map_;
  uint32_t bandHeight_ = 0;
  std::map<uint32_t, Band> open_;  // bands still waiting for tiles, by band index
  std::vector<FittedBand> fitted_;
  uint64_t peakBands_ = 0;
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
  info.buildBytes = [](const MapInfo& map, const Params&) {
    return map.texelCount() * 4;  // lo/hi of up to R / 2 buffered rows
  };
  info.makeEncoder = [](const MapInfo& map, const Params&) -> std::unique_ptr<Encoder> {
    return std::make_unique<CompressedSmEncoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map, const Params&) { return load(in, map); };
  return info;
}

}  // namespace
}  // namespace compressed_sm

using compressed_sm::compressedSm;
SHADOWBENCH_REGISTER_SCHEME(compressedSm);

}  // namespace sb
