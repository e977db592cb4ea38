// sm32 — the plain float32 shadow map (Williams 1978), storing each texel's first-hit depth lo.
// Lossless by definition and the baseline every size table divides by.
#include <algorithm>

#include <fmt/format.h>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"

namespace sb {
namespace {

class Sm32Decoder final : public DepthDecoder<Sm32Decoder> {
 public:
  Sm32Decoder(uint32_t resolution, std::vector<float> depths)
      : resolution_(resolution), depths_(std::move(depths)) {}

  uint32_t resolution() const { return resolution_; }
  float depth(uint32_t i, uint32_t j) const { return depths_[size_t(j) * resolution_ + i]; }

  SizeBreakdown size() const override { return {{"depths", depths_.size() * sizeof(float)}}; }
  void save(ByteWriter& out) const override { out.putArray<float>(depths_); }

 private:
  uint32_t resolution_;
  std::vector<float> depths_;
};

// The first-hit depths of a square region of the map: the whole map, or one part of a build in
// parts (DESIGN §5).
class RegionDepths {
 public:
  RegionDepths(uint32_t x0, uint32_t y0, uint32_t side)
      : x0_(x0), y0_(y0), side_(side), depths_(size_t(side) * side) {}

  void consume(const DualDepthTile& tile) {
    for (uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(tile.lo.begin() + size_t(row) * tile.width, tile.width,
                  depths_.begin() + size_t(tile.y0 - y0_ + row) * side_ + (tile.x0 - x0_));
  }
  std::vector<float>& depths() { return depths_; }

 private:
  uint32_t x0_, y0_, side_;
  std::vector<float> depths_;
};

// The encoder stores each texel's lo: a first hit inside the frustum, or 1 for a ray that hit
// nothing (DESIGN §2, §3), so never NaN, infinite or outside [0, 1].
std::vector<float> readDepths(ByteReader& in, const char* what, uint32_t x0, uint32_t y0,
                              uint32_t side) {
  std::vector<float> depths = in.getArray<float>(what, uint64_t(side) * side);
  for (size_t t = 0; t < depths.size(); ++t)
    if (!(depths[t] >= 0.0f && depths[t] <= 1.0f))
      throw FormatError(fmt::format("{}: texel ({}, {}) holds {}, outside [0, 1]", what,
                                    x0 + t % side, y0 + t / side, depths[t]));
  return depths;
}

class Sm32Encoder final : public Encoder {
 public:
  explicit Sm32Encoder(const MapInfo& map) : map_(map), region_(0, 0, map.resolution) {}

  void consume(const DualDepthTile& tile, BuildContext&) override { region_.consume(tile); }
  std::unique_ptr<Decoder> finish(BuildContext&) override {
    return std::make_unique<Sm32Decoder>(map_.resolution, std::move(region_.depths()));
  }

 private:
  MapInfo map_;
  RegionDepths region_;
};

// A part's payload is its depths, row-major within the part.
class Sm32PartEncoder final : public PartEncoder {
 public:
  explicit Sm32PartEncoder(const MapPart& part) : region_(part.x0, part.y0, part.size) {}

  void consume(const DualDepthTile& tile, BuildContext&) override { region_.consume(tile); }
  void finish(ByteWriter& out, BuildContext&) override { out.putArray<float>(region_.depths()); }

 private:
  RegionDepths region_;
};

class Sm32PartMerger final : public PartMerger {
 public:
  explicit Sm32PartMerger(const MapInfo& map) : map_(map), depths_(map.texelCount()) {}

  void add(const MapPart& part, ByteReader& payload, BuildContext&) override {
    const std::vector<float> depths =
        readDepths(payload, "sm32 part depths", part.x0, part.y0, part.size);
    for (uint32_t row = 0; row < part.size; ++row)
      std::copy_n(depths.begin() + size_t(row) * part.size, part.size,
                  depths_.begin() + size_t(part.y0 + row) * map_.resolution + part.x0);
  }
  std::unique_ptr<Decoder> finish(BuildContext&) override {
    return std::make_unique<Sm32Decoder>(map_.resolution, std::move(depths_));
  }

 private:
  MapInfo map_;
  std::vector<float> depths_;
};

SchemeInfo sm32() {
  SchemeInfo info;
  info.name = "sm32";
  info.paper = "Williams 1978, plain float32 shadow map (baseline)";
  info.kind = SchemeKind::Depth;
  // The merge, like the whole build, holds the whole map; a part encoder holds its part.
  info.buildBytes = [](const MapInfo& map, const ParamValues&, const BuildShape& shape) {
    const uint64_t whole = map.texelCount() * sizeof(float);
    if (!shape.inParts(map)) return whole;
    return shape.partsBytes(uint64_t(shape.partSize) * shape.partSize * sizeof(float), whole);
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues&,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<Sm32Encoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues&) -> std::unique_ptr<Decoder> {
    return std::make_unique<Sm32Decoder>(map.resolution,
                                         readDepths(in, "sm32 depths", 0, 0, map.resolution));
  };
  info.makePartEncoder = [](const MapInfo&, const MapPart& part, const ParamValues&,
                            const BuildShape&) -> std::unique_ptr<PartEncoder> {
    return std::make_unique<Sm32PartEncoder>(part);
  };
  info.makePartMerger = [](const MapInfo& map, const ParamValues&,
                           const BuildShape&) -> std::unique_ptr<PartMerger> {
    return std::make_unique<Sm32PartMerger>(map);
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(sm32);

}  // namespace sb
