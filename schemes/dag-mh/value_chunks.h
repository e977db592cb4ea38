// The chunked factor value list of DAG-MH (Scandolo & Eisemann 2021 §3.3, §3.4, §3.6, Alg. 2):
// the depth values in depth-first order, split into chunks; per chunk a representative value
// with a coverage bitmask, and for the values it does not cover, b-bit factors i_v giving
// c_l + c_f · i_v (b = 8, 16, 24), or the raw float32 (b = 32).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "schemes/shared/multires_hierarchy.h"

namespace sb {
class ByteReader;
class ByteWriter;
}  // namespace sb

namespace sb::dag_mh {

// §3.6: the one reconstruction of a factor, shared by the encoder's check and every lookup, so
// a factor the encoder accepted gives the same float bit for bit (float(i) is exact: i < 2^24).
inline float factorValue(float cl, float cf, uint32_t factor) {
  return std::fma(cf, float(factor), cl);
}

// What the encoder reports (BuildContext counters).
struct ValueChunkStats {
  uint64_t covered = 0;     // values the representative covers
  uint64_t factors = 0;     // values with a factor (or a raw float)
  uint64_t factorBits = 0;  // Σ over factors of their bit count, 32 for raw floats
};

// The value list. Chunk c holds values [c·S, min((c + 1)·S, n)); its info is `infoBytes()`
// bytes at c·infoBytes() in `infos`, little-endian:
//   [0, 4)   representative, float32
//   [4, 8)   c_l, float32
//   [8, 12)  c_f, float32
//   [12, 16) factor reference: bits 0–29 the byte offset of the chunk's factors in `factors`,
//            bits 30–31 the factor byte count minus one (1, 2, 3 bytes: b = 8, 16, 24; 4: raw)
//   [16, 16 + S/8) coverage bitmask: bit v (byte v/8, bit v%8) set = value v of the chunk is the
//            representative; value v ≥ the chunk's count has bit 0.
// The factors of the uncovered values follow each other in `factors`, each factor in b/8 bytes
// little-endian; chunk c's start where chunk c − 1's end.
class ValueChunks {
 public:
  static constexpr uint32_t kMaxValues = ~uint32_t(0);              // 32-bit value indices
  static constexpr uint64_t kMaxFactorBytes = (uint64_t(1) << 30);  // 30-bit factor offsets

  ValueChunks() = default;
  // §3.3: chunks of `chunkSize` (16, 32, 64 or 128) values, each value inside its interval.
  ValueChunks(std::span<const KeyInterval> intervals, uint32_t chunkSize, ValueChunkStats* stats);
  // An empty list grown value by value (a merge of parts): each chunk is encoded once it fills,
  // the last one by close(); the result is the span constructor's.
  explicit ValueChunks(uint32_t chunkSize);
  void append(const KeyInterval& interval, ValueChunkStats* stats);
  void close(ValueChunkStats* stats);

  uint32_t chunkSize() const { return chunkSize_; }
  uint32_t valueCount() const { return valueCount_; }
  uint32_t infoBytes() const { return kCoverageAt + chunkSize_ / 8; }
  uint64_t infoSize() const { return infos_.size(); }
  uint64_t factorSize() const { return factors_.size(); }

  // Alg. 2: value `index` (< valueCount()).
  float value(uint32_t index) const {
    const uint8_t* info = infos_.data() + size_t(index >> chunkShift_) * infoBytes();
    const uint32_t v = index & (chunkSize_ - 1);
    const uint8_t* mask = info + kCoverageAt;
    if ((mask[v / 8] >> (v % 8)) & 1) return read<float>(info + kRepresentativeAt);
    uint32_t coveredBefore = 0;
    for (uint32_t w = 0; w < v / 64; ++w)
      coveredBefore += std::popcount(read<uint64_t>(mask + 8 * w));
    coveredBefore += std::popcount(readBits(mask + 8 * (v / 64), v % 64));
    const uint32_t reference = read<uint32_t>(info + kFactorReferenceAt);
    const uint32_t bytes = (reference >> kFactorBytesShift) + 1;
    const uint8_t* at =
        factors_.data() + (reference & kOffsetMask) + size_t(v - coveredBefore) * bytes;
    const uint32_t factor = uint32_t(loadBytes(at, bytes));
    if (bytes == 4) return std::bit_cast<float>(factor);
    return factorValue(read<float>(info + kFactorLowAt), read<float>(info + kFactorStepAt), factor);
  }

  void save(ByteWriter& out) const;
  // Reads what save() wrote for `valueCount` values in chunks of `chunkSize`, checking every
  // chunk's bitmask, factor reference and stored floats; throws FormatError naming "dag-mh".
  static ValueChunks load(ByteReader& in, uint32_t chunkSize, uint32_t valueCount);

 private:
  // The chunk info's fields, by byte offset (the layout above).
  static constexpr uint32_t kRepresentativeAt = 0, kFactorLowAt = 4, kFactorStepAt = 8,
                            kFactorReferenceAt = 12, kCoverageAt = 16;
  static constexpr uint32_t kFactorBytesShift = 30;  // the factor reference's byte-count bits
  static constexpr uint32_t kOffsetMask = (1u << kFactorBytesShift) - 1;

  template <class T>
  static T read(const uint8_t* at) {
    T value;
    std::memcpy(&value, at, sizeof(T));
    return value;
  }
  // The `n` (1 to 8) bytes at `at` as a little-endian number (little-endian machines only, like
  // the whole file format). Two fixed-size loads that may overlap, not a copy of `n` bytes: a
  // copy of a run-time length becomes a byte loop whose stores stall the load that follows.
  static uint64_t loadBytes(const uint8_t* at, uint32_t n) {
    if (n >= 4) {
      const uint64_t low = read<uint32_t>(at), high = read<uint32_t>(at + n - 4);
      return low | high << (8 * (n - 4));
    }
    return uint64_t(at[0]) | uint64_t(at[n / 2]) << (8 * (n / 2)) |
           uint64_t(at[n - 1]) << (8 * (n - 1));
  }
  // The low `count` (< 64) bits of the bitmask word at `at`, reading only the bytes they need.
  static uint64_t readBits(const uint8_t* at, uint32_t count) {
    if (count == 0) return 0;
    return loadBytes(at, (count + 7) / 8) & ((uint64_t(1) << count) - 1);
  }

  // Encodes the next chunk (at most chunkSize_ values).
  void encodeChunk(std::span<const KeyInterval> chunk, ValueChunkStats* stats);

  uint32_t chunkSize_ = 0, chunkShift_ = 0, valueCount_ = 0;
  std::vector<uint8_t> infos_, factors_;
  std::vector<KeyInterval> filling_;  // append(): the values of the chunk not yet encoded
};

}  // namespace sb::dag_mh
