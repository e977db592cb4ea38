// The soak test must pass every correct scheme, catch wrong answers (including those only a
// boundary query finds), and give the same totals resumed as in one run.
#include <catch2/catch.hpp>

#include <cmath>

#include "harness/build.h"
#include "harness/soak.h"
#include "schemes/interface/depth_decoder.h"

using namespace sb;

namespace {

constexpr uint32_t kResolution = 256, kTile = 64;

SoakOptions smallSoak() {
  SoakOptions options;
  options.tileSize = kTile;
  options.queriesPerTile = 4 * kSoakBatchQueries;
  return options;
}

const nlohmann::json kStructure = {{"test", "soak_test"}};

// Wraps a correct decoder and inverts its point answers on one texel in 97.
class WrongOnSomeTexels final : public Decoder {
 public:
  explicit WrongOnSomeTexels(const Decoder& exact) : exact_(exact) {}
  static bool wrongAt(int64_t i, int64_t j) { return (i * 31 + j) % 97 == 0; }
  void lookup(std::span<const Query> q, int k, std::span<float> out) const override {
    exact_.lookup(q, k, out);
    if (k == 1)
      for (size_t n = 0; n < q.size(); ++n)
        if (wrongAt(texelOf(q[n].x, kResolution), texelOf(q[n].y, kResolution)))
          out[n] = 1.0f - out[n];
  }
  SizeBreakdown size() const override { return exact_.size(); }
  void save(ByteWriter&) const override {}

 private:
  const Decoder& exact_;
};

// A shadow map storing one float beyond hi where lo = hi: only a query at exactly that float
// (the "just above hi" boundary depth) is answered lit when it is shadowed.
class OneFloatBeyondHi final : public DepthDecoder<OneFloatBeyondHi> {
 public:
  explicit OneFloatBeyondHi(const DepthSource& source) : depth_(size_t(kResolution) * kResolution) {
    streamDualDepth(source, kResolution, [&](const DualDepthTile& tile) {
      for (size_t t = 0; t < tile.lo.size(); ++t)
        depth_[t] = tile.hi[t] == tile.lo[t] ? std::nextafter(tile.hi[t], 2.0f) : tile.lo[t];
    });
  }
  uint32_t resolution() const { return kResolution; }
  float depth(uint32_t i, uint32_t j) const { return depth_[size_t(j) * kResolution + i]; }
  SizeBreakdown size() const override { return {{"depths", depth_.size() * 4}}; }
  void save(ByteWriter&) const override {}

 private:
  std::vector<float> depth_;
};

struct Interrupted {};

}  // namespace

TEST_CASE("the soak passes every registered scheme at 256² and catches wrong answers", "[soak]") {
  const Scene scene = openScene("city");
  const DepthSource source(scene, Light::fit(scene.lights[0], scene), DepthMode::Closed,
                           kResolution);
  const SoakOptions options = smallSoak();
  const uint64_t expectedQueries =
      (kResolution / kTile) * (kResolution / kTile) * 4 * kSoakBatchQueries;
  for (const SchemeInfo& scheme : schemes()) {
    INFO("scheme " << scheme.name);
    const BuildOutcome built =
        buildStructure(source, scheme, scheme.resolve({}), BuildShape{kTile});
    SoakState state = newSoakState(kStructure, built.map, options);
    soak(*built.decoder, scheme.kind, built.map, source, options, state);
    CHECK(state.finished());
    CHECK(state.report.queries == expectedQueries);
    CHECK(state.report.mismatches == 0);

    if (scheme.name != "sm32") continue;
    const WrongOnSomeTexels wrong(*built.decoder);
    SoakState bad = newSoakState(kStructure, built.map, options);
    soak(wrong, scheme.kind, built.map, source, options, bad);
    CHECK(bad.report.mismatches > 0);
    REQUIRE(bad.report.examples.size() == kSoakMaxExamples);
    for (const Mismatch& m : bad.report.examples) {
      CHECK(m.k == 1);
      CHECK(WrongOnSomeTexels::wrongAt(texelOf(m.query.x, kResolution),
                                       texelOf(m.query.y, kResolution)));
    }
  }
}

TEST_CASE("the soak's boundary depths find an error one float wide", "[soak]") {
  const Scene scene = openScene("city");
  const DepthSource source(scene, Light::fit(scene.lights[0], scene), DepthMode::Open, kResolution);
  const MapInfo map{kResolution, 0, DepthMode::Open};
  const OneFloatBeyondHi decoder(source);
  SoakState state = newSoakState(kStructure, map, smallSoak());
  soak(decoder, SchemeKind::Depth, map, source, smallSoak(), state);
  CHECK(state.report.mismatches > 0);
  for (const Mismatch& m : state.report.examples) CHECK(m.expected.max < m.got);
}

TEST_CASE("a resumed soak gives the totals of one uninterrupted run", "[soak]") {
  const Scene scene = openScene("city");
  const DepthSource source(scene, Light::fit(scene.lights[0], scene), DepthMode::Closed,
                           kResolution);
  const BuildOutcome built =
      buildStructure(source, findScheme("sm32"), findScheme("sm32").resolve({}), BuildShape{kTile});
  const WrongOnSomeTexels wrong(*built.decoder);
  const SoakOptions options = smallSoak();

  SoakState whole = newSoakState(kStructure, built.map, options);
  soak(wrong, SchemeKind::Depth, built.map, source, options, whole);
  REQUIRE(whole.report.mismatches > 0);

  // Stopped after 5 tiles, with only what a state file holds carried over.
  SoakState first = newSoakState(kStructure, built.map, options);
  std::string saved;
  CHECK_THROWS_AS(soak(wrong, SchemeKind::Depth, built.map, source, options, first,
                       [&](const SoakState& now) {
                         saved = now.toJson().dump();
                         if (now.tilesDone == 5) throw Interrupted{};
                       }),
                  Interrupted);
  SoakState resumed =
      resumeSoakState(nlohmann::json::parse(saved), newSoakState(kStructure, built.map, options));
  CHECK(resumed.tilesDone == 5);
  soak(wrong, SchemeKind::Depth, built.map, source, options, resumed);
  CHECK(resumed.finished());
  CHECK(resumed.report.queries == whole.report.queries);
  CHECK(resumed.report.mismatches == whole.report.mismatches);
  REQUIRE(resumed.report.examples.size() == whole.report.examples.size());
  for (size_t e = 0; e < whole.report.examples.size(); ++e) {
    CHECK(resumed.report.examples[e].query.x == whole.report.examples[e].query.x);
    CHECK(resumed.report.examples[e].query.y == whole.report.examples[e].query.y);
    CHECK(resumed.report.examples[e].query.z == whole.report.examples[e].query.z);
    CHECK(resumed.report.examples[e].got == whole.report.examples[e].got);
  }

  SECTION("a state of another run is refused, naming what differs") {
    SoakOptions otherSeed = options;
    otherSeed.seed = 2;
    CHECK_THROWS_WITH(
        resumeSoakState(whole.toJson(), newSoakState(kStructure, built.map, otherSeed)),
        Catch::Contains("seed"));
    CHECK_THROWS_WITH(
        resumeSoakState(whole.toJson(), newSoakState({{"test", "another"}}, built.map, options)),
        Catch::Contains("structure"));
    CHECK_THROWS_WITH(SoakState::fromJson(nlohmann::json::object()), Catch::Contains("format"));
  }
}
