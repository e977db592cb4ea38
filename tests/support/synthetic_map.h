// A seeded random dual depth map held whole in memory, for tests of schemes and file formats
// that need no ray casting: plateaus of shared depth (like roofs), noisy slopes, empty texels,
// and intervals of every kind the modes produce (points, bands, open-ended bands).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "schemes/interface/morton.h"
#include "schemes/interface/parts.h"
#include "schemes/interface/scheme.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"

namespace sb::testing {

class NullBuildContext final : public BuildContext {
 public:
  void phase(std::string_view) override {}
  void count(std::string_view, uint64_t) override {}
  void reserve(uint64_t, std::string_view) override {}
};

// Merges part payloads as the harness does: every part in index order, once per pass the merger
// asks for, each payload read to its end; then finish.
inline std::unique_ptr<Decoder> mergePayloads(
    PartMerger& merger, uint64_t count, uint32_t partSize,
    const std::function<std::span<const uint8_t>(uint64_t index)>& payloadOf,
    BuildContext& context) {
  do {
    for (uint64_t index = 0; index < count; ++index) {
      ByteReader in(payloadOf(index));
      merger.add(MapPart::of(index, partSize), in, context);
      in.expectEnd();
    }
  } while (merger.anotherPass(context));
  return merger.finish(context);
}

struct SyntheticMap {
  uint32_t resolution = 0;
  DepthMode mode = DepthMode::Open;
  std::vector<float> lo, hi;

  static SyntheticMap random(uint32_t resolution, DepthMode mode, uint64_t seed) {
    SyntheticMap map{resolution, mode, {}, {}};
    map.lo.resize(size_t(resolution) * resolution);
    map.hi.resize(map.lo.size());
    uint64_t state = seed;
    auto next = [&] { return nextRandom(state); };
    auto unit = [&] { return unitFloat(next()); };
    const uint32_t block = std::max(1u, resolution / 8);
    std::vector<float> plateau(64), slope(64);
    for (size_t b = 0; b < 64; ++b) plateau[b] = unit() * 0.9f, slope[b] = (unit() - 0.5f) * 0.01f;
    for (uint32_t j = 0; j < resolution; ++j)
      for (uint32_t i = 0; i < resolution; ++i) {
        const size_t b = size_t(j / block % 8) * 8 + i / block % 8;
        const size_t at = size_t(j) * resolution + i;
        const uint64_t kind = next() % 16;
        float l = kind < 10 ? plateau[b]
                            : std::clamp(plateau[b] + slope[b] * float(i % block), 0.0f, 0.99f);
        if (kind == 15) l = 1.0f;  // the ray hit nothing
        float h = l;
        if (l == 1.0f)
          h = std::numeric_limits<float>::infinity();
        else if (mode != DepthMode::Open)
          h = kind % 4 == 0 ? std::numeric_limits<float>::infinity()
                            : std::min(1.0f, l + unit() * 0.2f);
        map.lo[at] = l, map.hi[at] = h;
      }
    return map;
  }

  // random()'s map with each square of `block`² texels taking the depths of its first texel, so
  // that subtrees of that size repeat whole (parts whose trees are small below their roots).
  static SyntheticMap blocky(uint32_t resolution, DepthMode mode, uint64_t seed, uint32_t block) {
    SyntheticMap map = random(resolution, mode, seed);
    for (uint32_t j = 0; j < resolution; ++j)
      for (uint32_t i = 0; i < resolution; ++i) {
        const size_t at = size_t(j) * resolution + i,
                     first = size_t(j / block * block) * resolution + i / block * block;
        map.lo[at] = map.lo[first], map.hi[at] = map.hi[first];
      }
    return map;
  }

  // Every texel [lo, hi], closed mode.
  static SyntheticMap uniform(uint32_t resolution, float lo, float hi) {
    SyntheticMap map{resolution, DepthMode::Closed, {}, {}};
    map.lo.assign(size_t(resolution) * resolution, lo);
    map.hi.assign(map.lo.size(), hi);
    return map;
  }

  MapInfo info(SchemeKind kind) const {
    return {resolution, kind == SchemeKind::Voxel ? resolution : 0u, mode};
  }

  // Square tiles in Morton order, as the harness streams them; the tiles [first, end) of that
  // order only (a part's tiles are a run of it).
  template <class F>
  void stream(uint32_t tileSize, F&& consume, uint64_t first = 0, uint64_t end = ~0ull) const {
    const uint32_t perSide = resolution / tileSize;
    DualDepthTile tile;
    for (uint64_t m = first; m < std::min(end, uint64_t(perSide) * perSide); ++m) {
      tile.resize(mortonX(m) * tileSize, mortonY(m) * tileSize, tileSize, tileSize);
      for (uint32_t j = 0; j < tileSize; ++j)
        for (uint32_t i = 0; i < tileSize; ++i) {
          const size_t at = size_t(tile.y0 + j) * resolution + tile.x0 + i;
          tile.lo[size_t(j) * tileSize + i] = lo[at];
          tile.hi[size_t(j) * tileSize + i] = hi[at];
        }
      consume(tile);
    }
  }

  std::unique_ptr<Decoder> build(const SchemeInfo& scheme, const Params& params,
                                 uint32_t tileSize) const {
    NullBuildContext context;
    auto encoder =
        scheme.makeEncoder(info(scheme.kind), scheme.resolve(params), BuildShape{tileSize});
    stream(tileSize, [&](const DualDepthTile& tile) { encoder->consume(tile, context); });
    return encoder->finish(context);
  }

  // The payload of every part in parts of side `partSize` (parts.h), in part order, each
  // encoded from its own run of tiles as the harness streams them.
  std::vector<std::vector<uint8_t>> partPayloads(const SchemeInfo& scheme, const Params& params,
                                                 uint32_t tileSize, uint32_t partSize) const {
    NullBuildContext context;
    const MapInfo map = info(scheme.kind);
    const ParamValues values = scheme.resolve(params);
    const uint64_t tilesPerPart = uint64_t(partSize / tileSize) * (partSize / tileSize);
    std::vector<std::vector<uint8_t>> payloads;
    for (uint64_t index = 0; index < MapPart::countFor(map, partSize); ++index) {
      auto encoder = scheme.makePartEncoder(map, MapPart::of(index, partSize), values,
                                            BuildShape{tileSize, partSize});
      stream(
          tileSize, [&](const DualDepthTile& tile) { encoder->consume(tile, context); },
          index * tilesPerPart, (index + 1) * tilesPerPart);
      ByteWriter payload;
      encoder->finish(payload, context);
      payloads.push_back(payload.release());
    }
    return payloads;
  }

  // The build in parts: every part's payload read back as a part file's would be and merged in
  // part order.
  std::unique_ptr<Decoder> buildInParts(const SchemeInfo& scheme, const Params& params,
                                        uint32_t tileSize, uint32_t partSize) const {
    NullBuildContext context;
    auto merger =
        scheme.makePartMerger(info(scheme.kind), scheme.resolve(params), {tileSize, partSize});
    const auto payloads = partPayloads(scheme, params, tileSize, partSize);
    return mergePayloads(
        *merger, payloads.size(), partSize,
        [&](uint64_t index) -> std::span<const uint8_t> { return payloads[index]; }, context);
  }
};

}  // namespace sb::testing
