#include "schemes/dag-mh/value_chunks.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "schemes/interface/serial.h"

namespace sb::dag_mh {

namespace {

inline constexpr uint32_t kInfinityKey = 0x7f800000u;

// §3.3: the value covered by the most intervals of a chunk. Some interval's lower bound is such
// a value (intervals are closed), so a sweep over the sorted bounds, counting the intervals
// opened at or before each lower bound and closed before it, finds the best.
uint32_t chooseRepresentative(std::span<const KeyInterval> chunk) {
  std::vector<uint32_t> lows, highs;
  for (const KeyInterval& interval : chunk)
    lows.push_back(interval.lo), highs.push_back(interval.hi);
  std::sort(lows.begin(), lows.end());
  std::sort(highs.begin(), highs.end());
  uint32_t best = lows[0];
  size_t bestCovered = 0, closed = 0;
  for (size_t opened = 1; opened <= lows.size(); ++opened) {
    if (opened < lows.size() && lows[opened] == lows[opened - 1]) continue;
    const uint32_t point = lows[opened - 1];
    while (closed < highs.size() && highs[closed] < point) ++closed;
    if (opened - closed > bestCovered) best = point, bestCovered = opened - closed;
  }
  return best;
}

// §3.3: the smallest factor i ≤ maxFactor whose value is ≥ lo — the value closest to the interval
// from above — if that value is also ≤ hi. factorValue is non-decreasing in i (c_f ≥ 0 and
// rounding is monotone), so the smallest such i is a lower bound: the estimate from the exact
// quotient is checked with factorValue itself, and a binary search decides where rounding moves
// it (c_f far below the float spacing near lo).
std::optional<uint32_t> findFactor(float cl, float cf, uint32_t maxFactor, float lo, float hi) {
  const auto atLeastLo = [&](uint32_t i) { return factorValue(cl, cf, i) >= lo; };
  uint32_t i = 0;
  if (cf > 0.0f) {
    const double estimate = std::ceil((double(lo) - double(cl)) / double(cf));
    i = uint32_t(std::clamp(estimate, 0.0, double(maxFactor)));
  }
  if (!atLeastLo(i) || (i > 0 && atLeastLo(i - 1))) {
    uint32_t low = 0, high = maxFactor;  // the answer is in [low, high], or none at all
    if (!atLeastLo(high)) return std::nullopt;
    while (low < high) {
      const uint32_t middle = low + (high - low) / 2;
      if (atLeastLo(middle))
        high = middle;
      else
        low = middle + 1;
    }
    i = low;
  }
  if (factorValue(cl, cf, i) > hi) return std::nullopt;
  return i;
}

}  // namespace

ValueChunks::ValueChunks(uint32_t chunkSize)
    : chunkSize_(chunkSize), chunkShift_(uint32_t(std::countr_zero(chunkSize))) {
  if (!std::has_single_bit(chunkSize) || chunkSize < 16 || chunkSize > 128)
    throw std::invalid_argument(
        fmt::format("dag-mh: chunk size {} is not 16, 32, 64 or 128", chunkSize));
}

ValueChunks::ValueChunks(std::span<const KeyInterval> intervals, uint32_t chunkSize,
                         ValueChunkStats* stats)
    : ValueChunks(chunkSize) {
  if (intervals.size() > kMaxValues)
    throw std::runtime_error(fmt::format(
        "dag-mh: {} values exceed what 32-bit value indices address", intervals.size()));
  for (size_t first = 0; first < intervals.size(); first += chunkSize)
    encodeChunk(intervals.subspan(first, std::min<size_t>(chunkSize, intervals.size() - first)),
                stats);
}

void ValueChunks::append(const KeyInterval& interval, ValueChunkStats* stats) {
  filling_.push_back(interval);
  if (filling_.size() == chunkSize_) close(stats);
}

void ValueChunks::close(ValueChunkStats* stats) {
  if (!filling_.empty()) encodeChunk(filling_, stats);
  filling_.clear();
}

void ValueChunks::encodeChunk(std::span<const KeyInterval> chunk, ValueChunkStats* stats) {
  if (valueCount_ + chunk.size() > kMaxValues)
    throw std::runtime_error(fmt::format(
        "dag-mh: more than {} values exceed what 32-bit value indices address", kMaxValues));
  valueCount_ += uint32_t(chunk.size());
  infos_.resize(infos_.size() + infoBytes(), 0);
  std::vector<uint32_t> factors;
  uint8_t* info = infos_.data() + infos_.size() - infoBytes();
  const uint32_t representative = chooseRepresentative(chunk);
  std::memcpy(info + kRepresentativeAt, &representative, 4);

  // The values the representative does not cover; the lowest lower bound v_l and the highest
  // upper bound v_h among them span the factors. An open-ended interval (hi = +inf, the empty
  // sky) is bounded at max(lo, 1) instead: still inside it, and it keeps c_f finite.
  std::vector<KeyInterval> uncovered;
  float vl = std::numeric_limits<float>::infinity(), vh = 0.0f;
  for (uint32_t v = 0; v < chunk.size(); ++v) {
    const KeyInterval& interval = chunk[v];
    if (interval.lo <= representative && representative <= interval.hi) {
      info[kCoverageAt + v / 8] |= uint8_t(1u << (v % 8));
      continue;
    }
    uncovered.push_back(interval);
    const float lo = depthOfKey(interval.lo);
    vl = std::min(vl, lo);
    vh = std::max(vh, std::min(depthOfKey(interval.hi), std::max(lo, 1.0f)));
  }

  // §3.3: c_l = v_l and c_f = (v_h − v_l)/(2^b − 1) for b = 8, 16, 24 in turn, until every
  // uncovered interval holds a value c_l + c_f · i_v; else b = 32, the raw floats (a lower
  // bound each).
  float cl = 0.0f, cf = 0.0f;
  uint32_t bytes = 4;
  if (uncovered.empty()) {
    bytes = 1;
  } else {
    for (uint32_t b = 8; b <= 24 && bytes == 4; b += 8) {
      const uint32_t maxFactor = (1u << b) - 1;
      cl = vl;
      cf = float((double(vh) - double(vl)) / double(maxFactor));
      factors.clear();
      for (const KeyInterval& interval : uncovered) {
        const auto factor =
            findFactor(cl, cf, maxFactor, depthOfKey(interval.lo), depthOfKey(interval.hi));
        if (!factor) break;
        factors.push_back(*factor);
      }
      if (factors.size() == uncovered.size()) bytes = b / 8;
    }
    if (bytes == 4) {
      cl = cf = 0.0f;
      factors.clear();
      for (const KeyInterval& interval : uncovered) factors.push_back(interval.lo);
    }
  }
  std::memcpy(info + kFactorLowAt, &cl, 4);
  std::memcpy(info + kFactorStepAt, &cf, 4);
  if (factors_.size() + factors.size() * bytes > kMaxFactorBytes)
    throw std::runtime_error(fmt::format(
        "dag-mh: the factors exceed the {} bytes 30-bit offsets address", kMaxFactorBytes));
  const uint32_t reference = uint32_t(factors_.size()) | (bytes - 1) << kFactorBytesShift;
  std::memcpy(info + kFactorReferenceAt, &reference, 4);
  for (const uint32_t factor : factors)
    factors_.insert(factors_.end(), reinterpret_cast<const uint8_t*>(&factor),
                    reinterpret_cast<const uint8_t*>(&factor) + bytes);
  if (stats) {
    stats->covered += chunk.size() - uncovered.size();
    stats->factors += uncovered.size();
    stats->factorBits += uncovered.size() * bytes * 8;
  }
}

void ValueChunks::save(ByteWriter& out) const {
  out.putArray<uint8_t>(infos_);
  out.putArray<uint8_t>(factors_);
}

ValueChunks ValueChunks::load(ByteReader& in, uint32_t chunkSize, uint32_t valueCount) {
  ValueChunks chunks;
  chunks.chunkSize_ = chunkSize;
  chunks.chunkShift_ = uint32_t(std::countr_zero(chunkSize));
  chunks.valueCount_ = valueCount;
  const uint64_t count = (uint64_t(valueCount) + chunkSize - 1) / chunkSize;
  chunks.infos_ = in.getArray<uint8_t>("dag-mh chunk infos", count * chunks.infoBytes());
  chunks.factors_ = in.getArray<uint8_t>("dag-mh chunk factors");

  // Every chunk's factors must start where the previous chunk's end and fit the factor array,
  // with one factor per uncovered value: then no lookup reads outside it.
  uint64_t offset = 0;
  for (uint64_t c = 0; c < count; ++c) {
    const uint8_t* info = chunks.infos_.data() + c * chunks.infoBytes();
    const uint32_t values = uint32_t(std::min<uint64_t>(chunkSize, valueCount - c * chunkSize));
    uint32_t covered = 0;
    for (uint32_t v = 0; v < chunkSize; ++v) {
      const bool bit = (info[kCoverageAt + v / 8] >> (v % 8)) & 1;
      if (bit && v >= values)
        throw FormatError(
            fmt::format("dag-mh: chunk {} covers value {} but holds only {} values", c, v, values));
      covered += bit;
    }
    const uint32_t reference = read<uint32_t>(info + kFactorReferenceAt),
                   bytes = (reference >> kFactorBytesShift) + 1;
    if ((reference & kOffsetMask) != offset)
      throw FormatError(fmt::format("dag-mh: chunk {} factor offset {} where {} was expected", c,
                                    reference & kOffsetMask, offset));
    offset += uint64_t(values - covered) * bytes;
    if (offset > chunks.factors_.size())
      throw FormatError(fmt::format("dag-mh: chunk {} factors end at byte {} of {}", c, offset,
                                    chunks.factors_.size()));
    // Stored floats are depths (non-negative, not NaN), so every answer is one too.
    for (const auto& [at, field] :
         {std::pair{kRepresentativeAt, "representative"}, std::pair{kFactorLowAt, "c_l"},
          std::pair{kFactorStepAt, "c_f"}})
      if (read<uint32_t>(info + at) > kInfinityKey)
        throw FormatError(fmt::format("dag-mh: chunk {} {} is not a depth", c, field));
    if (bytes == 4)
      for (uint64_t f = offset - uint64_t(values - covered) * 4; f < offset; f += 4)
        if (read<uint32_t>(chunks.factors_.data() + f) > kInfinityKey)
          throw FormatError(
              fmt::format("dag-mh: chunk {} raw value at byte {} is not a depth", c, f));
  }
  if (offset != chunks.factors_.size())
    throw FormatError(fmt::format("dag-mh: the chunks' factors take {} of the {} factor bytes",
                                  offset, chunks.factors_.size()));
  return chunks;
}

}  // namespace sb::dag_mh
