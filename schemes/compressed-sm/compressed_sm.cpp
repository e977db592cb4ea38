// compressed-sm — compressed shadow maps (J. Arvo, M. Hirvikorpi, "Compressed shadow maps",
// The Visual Computer 21(3), 2005), as summarised by Sintorn et al. 2014 §2 and Scandolo et al.
// 2016a §2.2: each scanline of the dual depth map becomes a piecewise-linear function of the
// column that passes through every texel's [lo, hi] interval, and only its segments are stored.
#include "schemes/compressed-sm/compressed_sm.h"

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

namespace {

// The scanline layout of a structure and of a part payload alike: the row index, then the
// segments' arrays.
void putScanlines(ByteWriter& out, std::span<const uint32_t> rowIndex, const Segments& segments) {
  out.putArray<uint32_t>(rowIndex);
  out.putArray<uint32_t>(segments.firstColumns);
  out.putArray<float>(segments.starts);
  out.putArray<float>(segments.slopes);
}

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
  void save(ByteWriter& out) const override { putScanlines(out, rowIndex_, segments_); }

 private:
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

// The segments of consecutive scanlines: scanline r's are [rowIndex[r], rowIndex[r + 1]).
struct Rows {
  std::vector<uint32_t> rowIndex;
  Segments segments;
};

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

std::unique_ptr<Decoder> load(ByteReader& in, const MapInfo& map) {
  Rows rows = readRows(in, map.resolution);
  if (const std::string error = rowsError(rows, map.resolution); !error.empty())
    throw FormatError("compressed-sm: " + error);
  return std::make_unique<CompressedSmDecoder>(map.resolution, std::move(rows.rowIndex),
                                               std::move(rows.segments));
}

// Builds in parts (parts.h). A part whose side is a multiple of the span starts every row at a
// multiple of it, where the whole build closes its segments too: the part fits its rows on its
// own, and its payload is their segments (Rows of its P scanlines, first columns counted from its
// left border). A part smaller than the span cannot know the segment that enters it from the
// left, so its payload is its texels (lo, then hi, P² each, row-major), and the merger fits them
// continuing each scanline's open segment exactly as the whole build does.
bool fitsOnItsOwn(uint32_t partSize, uint64_t span) {
  return partSize % span == 0;
}

class CompressedSmPartEncoder final : public PartEncoder {
 public:
  CompressedSmPartEncoder(const MapPart& part, uint64_t span)
      : part_(part), span_(span), ownFit_(fitsOnItsOwn(part.size, span)), arrived_(part.size) {
    if (ownFit_) {
      fits_.resize(part.size);
      rows_.resize(part.size);
      for (ScanlineFit& fit : fits_) fit.arrived = fit.first = part.x0;
    } else {
      lo_.resize(size_t(part.size) * part.size);
      hi_.resize(lo_.size());
    }
  }

  void consume(const DualDepthTile& tile, BuildContext& context) override {
    context.phase("fit scanlines");
    if (tile.x0 < part_.x0 || tile.y0 < part_.y0 || tile.x0 + tile.width > part_.x0 + part_.size ||
        tile.y0 + tile.height > part_.y0 + part_.size)
      throw std::invalid_argument(
          fmt::format("compressed-sm: a tile reaches outside part {}", part_.index));
    tbb::parallel_for(uint32_t(0), tile.height, [&](uint32_t row) {
      const uint32_t local = tile.y0 - part_.y0 + row;
      if (arrived_[local] != tile.x0 - part_.x0)
        throw std::invalid_argument(fmt::format(
            "compressed-sm: scanline {} received columns from {} after {} columns of part {}; "
            "tiles must deliver each scanline left to right",
            tile.y0 + row, tile.x0, arrived_[local], part_.index));
      arrived_[local] += tile.width;
      const size_t from = tile.index(tile.x0, tile.y0 + row);
      const auto lo = std::span(tile.lo).subspan(from, tile.width);
      const auto hi = std::span(tile.hi).subspan(from, tile.width);
      if (ownFit_) {
        fits_[local].append(lo, hi, span_, part_.x0 + part_.size, rows_[local]);
      } else {
        const size_t to = size_t(local) * part_.size + (tile.x0 - part_.x0);
        std::copy(lo.begin(), lo.end(), lo_.begin() + to);
        std::copy(hi.begin(), hi.end(), hi_.begin() + to);
      }
    });
  }

  void finish(ByteWriter& out, BuildContext& context) override {
    context.phase("write part");
    for (uint32_t arrived : arrived_)
      if (arrived != part_.size)
        throw std::logic_error(
            fmt::format("compressed-sm: part {} did not arrive whole", part_.index));
    if (!ownFit_) {
      out.putArray<float>(lo_);
      out.putArray<float>(hi_);
      return;
    }
    std::vector<uint32_t> rowIndex{0};
    Segments all;
    for (const Segments& row : rows_) {
      rowIndex.push_back(rowIndex.back() + uint32_t(row.count()));
      for (uint32_t column : row.firstColumns) all.firstColumns.push_back(column - part_.x0);
      all.starts.insert(all.starts.end(), row.starts.begin(), row.starts.end());
      all.slopes.insert(all.slopes.end(), row.slopes.begin(), row.slopes.end());
    }
    putScanlines(out, rowIndex, all);
  }

 private:
  MapPart part_;
  uint64_t span_;
  bool ownFit_;
  std::vector<uint32_t> arrived_;  // columns each of the part's scanlines received
  std::vector<ScanlineFit> fits_;  // fitting on its own: the part's scanlines
  std::vector<Segments> rows_;
  std::vector<float> lo_, hi_;  // otherwise: the part's texels, row-major
};

// Joins the parts' rows into the structure. Parts arrive in Morton order, so the parts of one band
// of P scanlines arrive left to right but interleaved with other bands: each part's rows are kept
// as they came (Rows of P scanlines, first columns absolute), per band, and finish() interleaves
// them into the final scanline order band by band, freeing each band once copied, so that the
// peak holds the structure once plus one band.
class CompressedSmMerger final : public PartMerger {
 public:
  CompressedSmMerger(const MapInfo& map, uint32_t partSize, uint64_t span)
      : map_(map),
        partSize_(partSize),
        span_(span),
        ownFit_(partSize != 0 && fitsOnItsOwn(partSize, span)),
        bands_(partSize == 0 ? 0 : map.resolution / partSize) {
    if (!std::has_single_bit(partSize) || partSize > map.resolution)
      throw std::invalid_argument(fmt::format(
          "compressed-sm: parts of side {} do not cut a map of side {}", partSize, map.resolution));
    if (!ownFit_) scanlines_.resize(map.resolution);
  }

  void add(const MapPart& part, ByteReader& payload, BuildContext& context) override {
    context.phase("merge");
    const MapPart expected = MapPart::of(nextPart_, partSize_);
    if (part.index != expected.index || part.size != expected.size || part.x0 != expected.x0 ||
        part.y0 != expected.y0)
      throw std::invalid_argument(fmt::format(
          "compressed-sm: part {} of side {} at ({}, {}) arrived where part {} of side {} was due",
          part.index, part.size, part.x0, part.y0, expected.index, expected.size));
    Rows rows;
    try {
      rows = ownFit_ ? readPartRows(payload) : fitPartTexels(payload);
    } catch (const FormatError& error) {
      throw FormatError(fmt::format("compressed-sm part {}: {}", part.index, error.what()));
    }
    bands_[part.y0 / partSize_].push_back(std::move(rows));
    ++nextPart_;
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    context.phase("concatenate scanlines");
    const uint64_t parts = MapPart::countFor(map_, partSize_);
    if (nextPart_ != parts)
      throw std::logic_error(
          fmt::format("compressed-sm: {} of {} parts were merged", nextPart_, parts));
    uint64_t total = 0;
    for (const std::vector<Rows>& band : bands_)
      for (const Rows& rows : band) total += rows.segments.count();
    if (total > std::numeric_limits<uint32_t>::max())
      throw std::length_error("compressed-sm: more segments than a 32-bit row index holds");
    std::vector<uint32_t> rowIndex{0};
    rowIndex.reserve(size_t(map_.resolution) + 1);
    Segments all;
    all.firstColumns.reserve(total);
    all.starts.reserve(total);
    all.slopes.reserve(total);
    for (std::vector<Rows>& band : bands_) {
      for (uint32_t row = 0; row < partSize_; ++row) {
        for (const Rows& rows : band) {
          const auto from = rows.rowIndex[row], to = rows.rowIndex[row + 1];
          const Segments& piece = rows.segments;
          all.firstColumns.insert(all.firstColumns.end(), piece.firstColumns.begin() + from,
                                  piece.firstColumns.begin() + to);
          all.starts.insert(all.starts.end(), piece.starts.begin() + from,
                            piece.starts.begin() + to);
          all.slopes.insert(all.slopes.end(), piece.slopes.begin() + from,
                            piece.slopes.begin() + to);
        }
        rowIndex.push_back(uint32_t(all.count()));
      }
      std::vector<Rows>().swap(band);
    }
    context.count("segments", all.count());
    return std::make_unique<CompressedSmDecoder>(map_.resolution, std::move(rowIndex),
                                                 std::move(all));
  }

 private:
  Rows readPartRows(ByteReader& payload) const {
    Rows rows = readRows(payload, partSize_);
    if (const std::string error = rowsError(rows, partSize_); !error.empty())
      throw FormatError(error);
    const uint32_t x0 = MapPart::of(nextPart_, partSize_).x0;
    for (uint32_t& column : rows.segments.firstColumns) column += x0;
    return rows;
  }

  // Continues every scanline's fit through the part's texels (validated first: a refused payload
  // leaves the scanlines as they were); the segments decided here become the part's rows.
  Rows fitPartTexels(ByteReader& payload) {
    const size_t texels = size_t(partSize_) * partSize_;
    const std::vector<float> lo = payload.getArray<float>("compressed-sm part lo", texels);
    const std::vector<float> hi = payload.getArray<float>("compressed-sm part hi", texels);
    // DESIGN §3: depths lie in [0, 1], and hi ≥ lo is a depth up to 1 or +inf.
    for (size_t t = 0; t < texels; ++t)
      if (!(lo[t] >= 0.0f && lo[t] <= 1.0f && hi[t] >= lo[t] &&
            (hi[t] <= 1.0f || std::isinf(hi[t]))))
        throw FormatError(
            fmt::format("texel {} of the part has no valid interval [{}, {}]", t, lo[t], hi[t]));
    const MapPart part = MapPart::of(nextPart_, partSize_);
    std::vector<Segments> decided(partSize_);
    tbb::parallel_for(uint32_t(0), partSize_, [&](uint32_t row) {
      const size_t from = size_t(row) * partSize_;
      scanlines_[part.y0 + row].append(std::span(lo).subspan(from, partSize_),
                                       std::span(hi).subspan(from, partSize_), span_,
                                       map_.resolution, decided[row]);
    });
    Rows rows;
    rows.rowIndex.push_back(0);
    for (const Segments& row : decided) {
      rows.rowIndex.push_back(rows.rowIndex.back() + uint32_t(row.count()));
      rows.segments.firstColumns.insert(rows.segments.firstColumns.end(), row.firstColumns.begin(),
                                        row.firstColumns.end());
      rows.segments.starts.insert(rows.segments.starts.end(), row.starts.begin(), row.starts.end());
      rows.segments.slopes.insert(rows.segments.slopes.end(), row.slopes.begin(), row.slopes.end());
    }
    return rows;
  }

  MapInfo map_;
  uint32_t partSize_;
  uint64_t span_;
  bool ownFit_;
  uint64_t nextPart_ = 0;
  std::vector<std::vector<Rows>> bands_;  // per band of P scanlines, its parts' rows in order
  std::vector<ScanlineFit> scanlines_;    // parts smaller than the span: every scanline's fit
};

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
    return std::make_unique<CompressedSmPartEncoder>(part, segmentSpanOf(params));
  };
  info.makePartMerger = [](const MapInfo& map, const ParamValues& params,
                           const BuildShape& shape) -> std::unique_ptr<PartMerger> {
    return std::make_unique<CompressedSmMerger>(map, shape.partSize, segmentSpanOf(params));
  };
  return info;
}

}  // namespace
}  // namespace compressed_sm

using compressed_sm::compressedSm;
SHADOWBENCH_REGISTER_SCHEME(compressedSm);

}  // namespace sb
