// sm-zstd — the float32 shadow map of sm32 cut into square blocks, each compressed on its own
// with zstd. A general-purpose lossless codec as a reference point for the structured schemes:
// lossless like sm32, and a lookup pays for decompressing the block its texel lies in.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <map>
#include <new>
#include <unordered_map>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <zstd.h>

#include "schemes/interface/capabilities.h"
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

uint64_t cacheBytesOf(const ParamValues& params) {
  return uint64_t(params.integer("cache")) << 20;
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

// Decoded blocks a thread keeps, as a block codec's user configures them (issue 13): lookups
// from several TBB threads each decompress into their own cache, so the decoder itself stays
// immutable. The cache serves one decoder at a time, keyed by instance (ids are never reused, so
// a destroyed decoder's blocks cannot answer for a new one), and is 4-way set associative over
// the blocks' Morton indices with the least recently used way replaced: neighbouring blocks
// fall in different sets, and a PCF kernel across a block corner keeps its four blocks.
struct BlockCache {
  static constexpr uint32_t kWays = 4;
  uint64_t decoder = 0;  // 0: none (instance ids start at 1)
  uint64_t setMask = 0;
  std::vector<uint64_t> blocks;  // per set, its ways' block indices, most recently used first
  std::vector<uint32_t> slots;   // the slot in `texels` of each of those ways
  std::vector<float> texels;
  BlockCacheStatistics::Counts counts;

  // For `decoder` with blocks of `blockTexels` floats, `bytes` in all (at least a set).
  void reset(uint64_t id, size_t blockTexels, uint64_t bytes) {
    const uint64_t sets =
        std::bit_floor(std::max<uint64_t>(1, bytes / (blockTexels * sizeof(float)) / kWays));
    decoder = id;
    setMask = sets - 1;
    blocks.assign(sets * kWays, ~uint64_t(0));
    slots.resize(sets * kWays);
    for (uint32_t w = 0; w < slots.size(); ++w) slots[w] = w;
    texels.assign(sets * kWays * blockTexels, 0.0f);
    counts = {};
  }
};

thread_local BlockCache threadCache;

std::atomic<uint64_t> nextDecoderId{1};

class SmZstdDecoder final : public DepthDecoder<SmZstdDecoder>, public BlockCacheStatistics {
 public:
  // `offsets` has a start per block plus the end of the last; validates everything so that
  // lookups never meet a bad frame. Throws FormatError. Each thread caches `cacheBytes` of
  // decoded blocks (at least four blocks).
  SmZstdDecoder(uint32_t resolution, uint32_t blockSide, std::vector<uint64_t> offsets,
                std::vector<uint8_t> blocks, uint64_t cacheBytes)
      : resolution_(resolution),
        blockSide_(blockSide),
        blocksPerRow_(resolution / blockSide),
        offsets_(std::move(offsets)),
        blocks_(std::move(blocks)),
        cacheBytes_(cacheBytes),
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

  // A uniform batch would otherwise decompress a block per query.
  static constexpr bool kMortonBatches = true;

  uint32_t resolution() const { return resolution_; }

  float depth(uint32_t i, uint32_t j) const {
    const float* texels = decodedBlock(mortonCode(i / blockSide_, j / blockSide_));
    return texels[size_t(j % blockSide_) * blockSide_ + i % blockSide_];
  }
  // Issue 13: a kernel reads each block it overlaps from the cache once, not once per tap.
  uint64_t litTexels(const TexelRect& rect, float z) const {
    uint64_t lit = 0;
    for (uint32_t by = rect.j0 / blockSide_; by <= rect.j1 / blockSide_; ++by)
      for (uint32_t bx = rect.i0 / blockSide_; bx <= rect.i1 / blockSide_; ++bx) {
        const float* texels = decodedBlock(mortonCode(bx, by));
        const uint32_t x0 = bx * blockSide_, y0 = by * blockSide_;
        const uint32_t i0 = std::max(rect.i0, x0), i1 = std::min(rect.i1, x0 + blockSide_ - 1);
        const uint32_t j0 = std::max(rect.j0, y0), j1 = std::min(rect.j1, y0 + blockSide_ - 1);
        for (uint32_t j = j0; j <= j1; ++j)
          for (uint32_t i = i0; i <= i1; ++i)
            lit += z <= texels[size_t(j - y0) * blockSide_ + (i - x0)];
      }
    return lit;
  }

  const BlockCacheStatistics* blockCacheStatistics() const override { return this; }
  Counts threadCounts() const override {
    return threadCache.decoder == id_ ? threadCache.counts : Counts{};
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

  // The decoded texels of `block` (Morton index), from this thread's cache or decompressed into
  // it.
  const float* decodedBlock(uint64_t block) const {
    BlockCache& cache = threadCache;
    if (cache.decoder != id_) cache.reset(id_, blockTexels(), cacheBytes_);
    const size_t set = size_t(block & cache.setMask) * BlockCache::kWays;
    uint64_t* ways = cache.blocks.data() + set;
    uint32_t* slots = cache.slots.data() + set;
    uint32_t way = 0;
    while (way < BlockCache::kWays && ways[way] != block) ++way;
    const bool hit = way < BlockCache::kWays;
    if (!hit) way = BlockCache::kWays - 1;
    // Most recently used first: the way moves to the front, the others down one.
    const uint32_t slot = slots[way];
    std::rotate(ways, ways + way, ways + way + 1);
    std::rotate(slots, slots + way, slots + way + 1);
    float* texels = cache.texels.data() + size_t(slot) * blockTexels();
    if (hit) {
      ++cache.counts.hits;
      return texels;
    }
    ++cache.counts.misses;
    ways[0] = ~uint64_t(0);
    // Every frame was decompressed once at load, so this cannot fail short of memory corruption.
    if (!decompressBlock(threadContext(), frame(block), std::span(texels, blockTexels())))
      throw std::logic_error(fmt::format("{}: block {} failed to decompress", kScheme, block));
    ways[0] = block;
    return texels;
  }

  uint32_t resolution_, blockSide_, blocksPerRow_;
  // Blocks in Morton order of their (column, row): block m's frame is
  // blocks_[offsets_[m], offsets_[m + 1]).
  std::vector<uint64_t> offsets_;
  std::vector<uint8_t> blocks_;
  uint64_t cacheBytes_;
  uint64_t id_;
};

// The frames are laid out in Morton order of the blocks, the order in which the harness's
// Morton-ordered tiles complete them, so each frame is appended to the final array as soon as
// its block is compressed: the build holds the compressed map once, never a copy of it.
class SmZstdEncoder final : public Encoder {
 public:
  SmZstdEncoder(const MapInfo& map, uint32_t blockSide, int level, uint64_t cacheBytes)
      : map_(map),
        blockSide_(blockSide),
        blocksPerRow_(map.resolution / blockSide),
        level_(level),
        cacheBytes_(cacheBytes) {
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
                                           std::move(blocks_), cacheBytes_);
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
  uint64_t cacheBytes_;
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
                 ParamSpec::integer("level", "zstd compression level", 3, 1, 19, {1, 3, 9, 19}),
                 ParamSpec::integer("cache",
                                    "MiB of decoded blocks each looking-up thread keeps (at least "
                                    "four blocks); lookups only, the structure is the same",
                                    4, 1, 4096, {1, 4, 16, 64})};
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
                                           int(params.integer("level")), cacheBytesOf(params));
  };
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues& params) -> std::unique_ptr<Decoder> {
    const uint32_t side = blockSideOf(params, map.resolution);
    const uint64_t perRow = map.resolution / side;
    auto offsets = in.getArray<uint64_t>("sm-zstd block offsets", perRow * perRow + 1);
    auto blocks = in.getArray<uint8_t>("sm-zstd blocks");
    return std::make_unique<SmZstdDecoder>(map.resolution, side, std::move(offsets),
                                           std::move(blocks), cacheBytesOf(params));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(smZstd);

}  // namespace sb
