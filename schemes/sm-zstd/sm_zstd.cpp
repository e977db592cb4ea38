// sm-zstd — the float32 shadow map of sm32 cut into square blocks, each compressed on its own
// with zstd. A general-purpose lossless codec as a reference point for the structured schemes:
// lossless like sm32, and a lookup pays for decompressing the block its texel lies in.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <map>
#include <new>
#include <unordered_map>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <zstd.h>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/morton.h"
#include "schemes/interface/serial.h"

namespace sb {
namespace {

constexpr const char* kScheme = "sm-zstd";

// The block side a structure of resolution R uses: the `block` parameter, but never more than
// the map itself (a map smaller than a block is one block).
uint32_t blockSideOf(const ParamValues& params, uint32_t resolution) {
  return std::min<uint32_t>(uint32_t(params.integer("block")), resolution);
}

// Decompresses one block frame into `texels` (blockTexels floats) with `context`; false if the
// frame is not exactly one valid block.
bool decompressBlock(ZSTD_DCtx* context, std::span<const uint8_t> frame, std::span<float> texels) {
  const size_t expected = texels.size_bytes();
  if (ZSTD_getFrameContentSize(frame.data(), frame.size()) != expected) return false;
  const size_t written =
      ZSTD_decompressDCtx(context, texels.data(), expected, frame.data(), frame.size());
  return !ZSTD_isError(written) && written == expected;
}

// A zstd decompression context per thread: ZSTD_decompress would allocate and initialise one
// (over 100 KiB) on every cache miss, which costs about as much as decoding a 16 KiB block.
ZSTD_DCtx* threadContext() {
  struct Owner {
    ZSTD_DCtx* context = ZSTD_createDCtx();
    ~Owner() { ZSTD_freeDCtx(context); }
  };
  thread_local Owner owner;
  if (!owner.context) throw std::bad_alloc();
  return owner.context;
}

// Decoded blocks a thread keeps: lookups from several TBB threads each decompress into their own
// cache, so the decoder itself stays immutable. Keyed by decoder instance (ids are never reused,
// so a destroyed decoder's blocks cannot answer for a new one) and block index. Four entries so
// that a PCF kernel straddling a block corner does not decompress a block per kernel row.
struct BlockCache {
  static constexpr size_t kEntries = 4;
  struct Entry {
    uint64_t decoder = 0;  // 0: empty (instance ids start at 1)
    uint64_t block = 0;
    std::vector<float> texels;
  };
  std::array<Entry, kEntries> entries;
  size_t next = 0;  // round-robin replacement
};

std::atomic<uint64_t> nextDecoderId{1};

class SmZstdDecoder final : public DepthDecoder<SmZstdDecoder> {
 public:
  // `offsets` has a start per block plus the end of the last; validates everything so that
  // lookups never meet a bad frame. Throws FormatError.
  SmZstdDecoder(uint32_t resolution, uint32_t blockSide, std::vector<uint64_t> offsets,
                std::vector<uint8_t> blocks)
      : resolution_(resolution),
        blockSide_(blockSide),
        blocksPerRow_(resolution / blockSide),
        offsets_(std::move(offsets)),
        blocks_(std::move(blocks)),
        id_(nextDecoderId.fetch_add(1)) {
    const uint64_t blockCount = uint64_t(blocksPerRow_) * blocksPerRow_;
    if (offsets_.size() != blockCount + 1)
      throw FormatError(
          fmt::format("{}: {} block offsets for {} blocks", kScheme, offsets_.size(), blockCount));
    if (offsets_.front() != 0 || offsets_.back() != blocks_.size())
      throw FormatError(
          fmt::format("{}: block offsets do not span the compressed blocks", kScheme));
    std::vector<float> texels(blockTexels());
    for (uint64_t block = 0; block < blockCount; ++block) {
      if (offsets_[block] > offsets_[block + 1])
        throw FormatError(fmt::format("{}: block offsets decrease at block {}", kScheme, block));
      if (!decompressBlock(threadContext(), frame(block), texels))
        throw FormatError(fmt::format("{}: block {} does not decompress to {}² floats", kScheme,
                                      block, blockSide_));
      // The blocks hold each texel's lo as sm32 stores it: never NaN, infinite or outside
      // [0, 1] (DESIGN §3).
      if (!std::all_of(texels.begin(), texels.end(), [](float d) { return d >= 0 && d <= 1; }))
        throw FormatError(fmt::format("{}: block {} holds a depth outside [0, 1]", kScheme, block));
    }
  }

  uint32_t resolution() const { return resolution_; }

  float depth(uint32_t i, uint32_t j) const {
    const uint64_t block = mortonCode(i / blockSide_, j / blockSide_);
    const std::vector<float>& texels = decodedBlock(block);
    return texels[size_t(j % blockSide_) * blockSide_ + i % blockSide_];
  }

  SizeBreakdown size() const override {
    return {{"blocks", blocks_.size()}, {"block offsets", offsets_.size() * sizeof(uint64_t)}};
  }

  void save(ByteWriter& out) const override {
    out.putArray<uint64_t>(offsets_);
    out.putArray<uint8_t>(blocks_);
  }

 private:
  size_t blockTexels() const { return size_t(blockSide_) * blockSide_; }

  std::span<const uint8_t> frame(uint64_t block) const {
    return std::span(blocks_).subspan(offsets_[block], offsets_[block + 1] - offsets_[block]);
  }

  const std::vector<float>& decodedBlock(uint64_t block) const {
    thread_local BlockCache cache;
    for (const BlockCache::Entry& entry : cache.entries)
      if (entry.decoder == id_ && entry.block == block) return entry.texels;
    BlockCache::Entry& entry = cache.entries[cache.next];
    cache.next = (cache.next + 1) % BlockCache::kEntries;
    entry.texels.resize(blockTexels());
    // Every frame was decompressed once at load, so this cannot fail short of memory corruption.
    if (!decompressBlock(threadContext(), frame(block), entry.texels)) {
      entry.decoder = 0;
      throw std::logic_error(fmt::format("{}: block {} failed to decompress", kScheme, block));
    }
    entry.decoder = id_;
    entry.block = block;
    return entry.texels;
  }

  uint32_t resolution_, blockSide_, blocksPerRow_;
  // Blocks in Morton order of their (column, row): block m's frame is
  // blocks_[offsets_[m], offsets_[m + 1]).
  std::vector<uint64_t> offsets_;
  std::vector<uint8_t> blocks_;
  uint64_t id_;
};

// The frames are laid out in Morton order of the blocks, the order in which the harness's
// Morton-ordered tiles complete them, so each frame is appended to the final array as soon as
// its block is compressed: the build holds the compressed map once, never a copy of it.
class SmZstdEncoder final : public Encoder {
 public:
  SmZstdEncoder(const MapInfo& map, uint32_t blockSide, int level)
      : map_(map), blockSide_(blockSide), blocksPerRow_(map.resolution / blockSide), level_(level) {
    offsets_.reserve(uint64_t(blocksPerRow_) * blocksPerRow_ + 1);
    offsets_.push_back(0);
    // Frames never exceed the bound of the raw map, and pages reserved but never written cost
    // no memory: with no reallocation, no copy of the frames ever exists.
    blocks_.reserve(ZSTD_compressBound(map.texelCount() * sizeof(float)));
  }

  // A tile may hold several blocks or part of one: texels gather in a block's buffer, and the
  // blocks complete are compressed at the end of the tile (in parallel) and laid out in Morton
  // order. A block that
  // completes before one earlier in Morton order (another tiling) waits for it, compressed.
  void consume(const DualDepthTile& tile, BuildContext&) override {
    std::vector<uint64_t> completed;
    for (uint32_t row = 0; row < tile.height; ++row) {
      const uint32_t j = tile.y0 + row;
      for (uint32_t i = tile.x0; i < tile.x0 + tile.width;) {
        const uint32_t end = std::min(tile.x0 + tile.width, (i / blockSide_ + 1) * blockSide_);
        const uint64_t block = mortonCode(i / blockSide_, j / blockSide_);
        PartialBlock& partial = partials_[block];
        if (partial.texels.empty()) partial.texels.resize(size_t(blockSide_) * blockSide_);
        std::copy_n(tile.lo.begin() + tile.index(i, j), end - i,
                    partial.texels.begin() + size_t(j % blockSide_) * blockSide_ + i % blockSide_);
        partial.arrived += end - i;
        if (partial.arrived == partial.texels.size()) completed.push_back(block);
        i = end;
      }
    }
    std::sort(completed.begin(), completed.end());
    std::vector<std::vector<uint8_t>> frames(completed.size());
    tbb::parallel_for(size_t(0), completed.size(), [&](size_t b) {
      frames[b] = compress(completed[b], partials_.at(completed[b]).texels);
    });
    for (size_t b = 0; b < completed.size(); ++b) {
      waiting_[completed[b]] = std::move(frames[b]);
      partials_.erase(completed[b]);
    }
    while (!waiting_.empty() && waiting_.begin()->first == offsets_.size() - 1) {
      const std::vector<uint8_t>& frame = waiting_.begin()->second;
      blocks_.insert(blocks_.end(), frame.begin(), frame.end());
      offsets_.push_back(blocks_.size());
      waiting_.erase(waiting_.begin());
    }
  }

  std::unique_ptr<Decoder> finish(BuildContext& context) override {
    if (!partials_.empty() || !waiting_.empty() ||
        offsets_.size() != uint64_t(blocksPerRow_) * blocksPerRow_ + 1)
      throw std::logic_error(fmt::format("{}: not every block received all its texels", kScheme));
    context.count("compressed bytes", blocks_.size());
    return std::make_unique<SmZstdDecoder>(map_.resolution, blockSide_, std::move(offsets_),
                                           std::move(blocks_));
  }

 private:
  struct PartialBlock {
    std::vector<float> texels;
    size_t arrived = 0;
  };

  std::vector<uint8_t> compress(uint64_t block, std::span<const float> texels) const {
    std::vector<uint8_t> frame(ZSTD_compressBound(texels.size_bytes()));
    const size_t bytes =
        ZSTD_compress(frame.data(), frame.size(), texels.data(), texels.size_bytes(), level_);
    if (ZSTD_isError(bytes))
      throw std::runtime_error(
          fmt::format("{}: zstd failed on block {}: {}", kScheme, block, ZSTD_getErrorName(bytes)));
    frame.resize(bytes);
    return frame;
  }

  MapInfo map_;
  uint32_t blockSide_, blocksPerRow_;
  int level_;
  std::unordered_map<uint64_t, PartialBlock> partials_;  // by Morton index
  std::map<uint64_t, std::vector<uint8_t>> waiting_;     // compressed, awaiting earlier blocks
  std::vector<uint64_t> offsets_;
  std::vector<uint8_t> blocks_;
};

SchemeInfo smZstd() {
  SchemeInfo info;
  info.name = kScheme;
  info.paper = "float32 shadow map in square blocks, each compressed with zstd (reference codec)";
  info.kind = SchemeKind::Depth;
  info.params = {ParamSpec::integer("block", "texels per side of a block compressed on its own", 64,
                                    8, 1024, {32, 64, 128, 256})
                     .satisfying("a power of two",
                                 [](int64_t side) { return std::has_single_bit(uint64_t(side)); }),
                 ParamSpec::integer("level", "zstd compression level", 3, 1, 19, {1, 3, 9, 19})};
  // The blocks in flight, at most a row of them, and the frames' array, which the encoder
  // reserves at the raw map's compression bound: the frames depend on the data (below the raw
  // map; 57% of it on the city), and the kernel commits a reservation it cannot back only at
  // the cost of refusing it (std::bad_alloc at 128K²).
  info.buildBytes = [](const MapInfo& map, const ParamValues& params, const BuildShape&) {
    const uint64_t side = blockSideOf(params, map.resolution);
    return uint64_t(map.resolution) * side * sizeof(float) +
           ZSTD_compressBound(map.texelCount() * sizeof(float));
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues& params,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<SmZstdEncoder>(map, blockSideOf(params, map.resolution),
                                           int(params.integer("level")));
  };
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues& params) -> std::unique_ptr<Decoder> {
    const uint32_t side = blockSideOf(params, map.resolution);
    const uint64_t perRow = map.resolution / side;
    auto offsets = in.getArray<uint64_t>("sm-zstd block offsets", perRow * perRow + 1);
    auto blocks = in.getArray<uint8_t>("sm-zstd blocks");
    return std::make_unique<SmZstdDecoder>(map.resolution, side, std::move(offsets),
                                           std::move(blocks));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(smZstd);

}  // namespace sb
