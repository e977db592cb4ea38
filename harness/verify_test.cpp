// The verifier must catch wrong structures, or the correctness matrix proves nothing: decoders
// broken on purpose (a depth one float too far, a texel shifted, PCF off by one tap) are
// reported, and a correct one is not.
#include <catch2/catch.hpp>

#include <cmath>

#include "harness/depth_source.h"
#include "harness/verify.h"
#include "schemes/interface/depth_decoder.h"

using namespace sb;

namespace {

constexpr uint32_t kResolution = 128;

// A depth map of every texel, with a fault injected.
enum class Fault { None, BeyondHi, ShiftedTexel, PcfOffByOne };

class FaultyDecoder final : public DepthDecoder<FaultyDecoder> {
 public:
  FaultyDecoder(const DepthSource& source, Fault fault)
      : fault_(fault), depth_(size_t(kResolution) * kResolution) {
    streamDualDepth(source, kResolution, [&](const DualDepthTile& tile) {
      for (size_t t = 0; t < tile.lo.size(); ++t) {
        const bool point = tile.hi[t] == tile.lo[t];
        // One float past hi: shadowed queries at hi's successor would be reported lit.
        depth_[t] = fault == Fault::BeyondHi && point && t % 97 == 0
                        ? std::nextafter(tile.hi[t], 2.0f)
                        : tile.lo[t];
      }
    });
  }
  uint32_t resolution() const { return kResolution; }
  float depth(uint32_t i, uint32_t j) const {
    if (fault_ == Fault::ShiftedTexel) i = std::min(i + 1, kResolution - 1);
    return depth_[size_t(j) * kResolution + i];
  }
  SizeBreakdown size() const override { return {{"depths", depth_.size() * 4}}; }
  void save(ByteWriter&) const override {}

 private:
  Fault fault_;
  std::vector<float> depth_;
};

// Wraps a correct decoder and adds one lit tap to every PCF answer that has room for it.
class PcfOffByOne final : public Decoder {
 public:
  explicit PcfOffByOne(const Decoder& exact) : exact_(exact) {}
  void lookup(std::span<const Query> q, int k, std::span<float> out) const override {
    exact_.lookup(q, k, out);
    if (k > 1)
      for (size_t n = 0; n < q.size(); ++n) out[n] = std::min(1.0f, out[n] + 1.0f / float(k * k));
  }
  SizeBreakdown size() const override { return exact_.size(); }
  void save(ByteWriter&) const override {}

 private:
  const Decoder& exact_;
};

}  // namespace

TEST_CASE("the verifier passes a correct structure and catches broken ones", "[verify]") {
  const Scene scene = openScene("city");
  const DepthSource source(scene, Light::fit(scene.lights[0], scene), DepthMode::Open, kResolution);
  const MapInfo map{kResolution, 0, DepthMode::Open};
  for (uint32_t exhaustiveUpTo : {kResolution, kResolution / 2}) {
    VerifyOptions options;
    options.exhaustiveUpTo = exhaustiveUpTo;  // exhaustive, then sampled
    options.sampledQueries = 100'000;
    INFO("exhaustive up to " << exhaustiveUpTo);

    const FaultyDecoder exact(source, Fault::None);
    const VerifyReport good = verify(exact, SchemeKind::Depth, map, source, options);
    CHECK(good.queries > 0);
    CHECK(good.mismatches == 0);

    for (Fault fault : {Fault::BeyondHi, Fault::ShiftedTexel}) {
      const FaultyDecoder broken(source, fault);
      const VerifyReport bad = verify(broken, SchemeKind::Depth, map, source, options);
      CHECK(bad.mismatches > 0);
      CHECK(!bad.examples.empty());
    }
    const PcfOffByOne pcf(exact);
    CHECK(verify(pcf, SchemeKind::Depth, map, source, options).mismatches > 0);
  }
}
