// compressed-sm's builds in parts (parts.h, scanlines.h).
#include <bit>
#include <limits>

#include <fmt/format.h>

#include "schemes/compressed-sm/scanlines.h"

namespace sb::compressed_sm {

// Builds in parts (parts.h). A part whose side is a multiple of the span starts every row at a
// multiple of it, where the whole build closes its segments too: the part fits its rows on its
// own, and its payload is their segments (Rows of its P scanlines, first columns counted from its
// left border). A part smaller than the span cannot know the segment that enters it from the
// left, so its payload is its texels (lo, then hi, P² each, row-major), and the merger fits them
// continuing each scanline's open segment exactly as the whole build does.
bool fitsOnItsOwn(uint32_t partSize, uint64_t span) {
  return partSize % span == 0;
}

namespace {

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

}  // namespace

std::unique_ptr<PartEncoder> makePartEncoder(const MapPart& part, uint64_t span) {
  return std::make_unique<CompressedSmPartEncoder>(part, span);
}

std::unique_ptr<PartMerger> makePartMerger(const MapInfo& map, uint32_t partSize, uint64_t span) {
  return std::make_unique<CompressedSmMerger>(map, partSize, span);
}

}  // namespace sb::compressed_sm
