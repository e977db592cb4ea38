// sm32 — the plain float32 shadow map (Williams 1978), storing each texel's first-hit depth lo.
// Lossless by definition and the baseline every size table divides by.
#include <algorithm>

#include <fmt/format.h>

#include "schemes/interface/depth_decoder.h"
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

class Sm32Encoder final : public Encoder {
 public:
  explicit Sm32Encoder(const MapInfo& map) : map_(map), depths_(map.texelCount()) {}

  void consume(const DualDepthTile& tile, BuildContext&) override {
    for (uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(tile.lo.begin() + size_t(row) * tile.width, tile.width,
                  depths_.begin() + size_t(tile.y0 + row) * map_.resolution + tile.x0);
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
  info.buildBytes = [](const MapInfo& map, const ParamValues&, const BuildShape&) {
    return map.texelCount() * sizeof(float);
  };
  info.makeEncoder = [](const MapInfo& map, const ParamValues&,
                        const BuildShape&) -> std::unique_ptr<Encoder> {
    return std::make_unique<Sm32Encoder>(map);
  };
  info.load = [](ByteReader& in, const MapInfo& map,
                 const ParamValues&) -> std::unique_ptr<Decoder> {
    std::vector<float> depths = in.getArray<float>("sm32 depths", map.texelCount());
    // The encoder stores each texel's lo: a first hit inside the frustum, or 1 for a ray that
    // hit nothing (DESIGN §2, §3), so never NaN, infinite or outside [0, 1].
    for (size_t t = 0; t < depths.size(); ++t)
      if (!(depths[t] >= 0.0f && depths[t] <= 1.0f))
        throw FormatError(fmt::format("sm32 depths: texel ({}, {}) holds {}, outside [0, 1]",
                                      t % map.resolution, t / map.resolution, depths[t]));
    return std::make_unique<Sm32Decoder>(map.resolution, std::move(depths));
  };
  return info;
}

}  // namespace

SHADOWBENCH_REGISTER_SCHEME(sm32);

}  // namespace sb
