// The correctness matrix in CI: every registered scheme, on every generator scene at its
// default size, in every mode, checked against the reference exhaustively at small
// resolutions and by sampling at a larger one (not under the sanitizers, see kSampledCells). A
// scheme added to the registry is picked up here with no edit.
#include <fmt/format.h>
#include <catch2/catch.hpp>

#include "harness/build.h"
#include "harness/cell.h"
#include "harness/verify.h"
#include "scenes/scene.h"

using namespace sb;

namespace {

const Scene& cachedScene(const std::string& name) {
  static std::map<std::string, Scene> scenes;
  auto it = scenes.find(name);
  if (it == scenes.end()) it = scenes.emplace(name, openScene(name)).first;
  return it->second;
}

// The city under a spot light with logarithmic depth (Kämpe eq. 1): the ray-cast path.
const Scene& spotLitCity() {
  static const Scene scene = [] {
    Scene s = openScene("city");
    const Bounds b = s.bounds();
    LightSpec spot;
    spot.kind = LightKind::Spot;
    spot.position = glm::vec3((b.min.x + b.max.x) / 2, (b.min.y + b.max.y) / 2, b.max.z * 3);
    spot.direction = {0.1f, 0.05f, -1.0f};
    spot.fovDegrees = 70;
    spot.depth = DepthDistribution::Logarithmic;
    s.lights = {spot};
    return s;
  }();
  return scene;
}

#ifdef __SANITIZE_ADDRESS__
constexpr bool kUnderSanitizers = true;  // CI's second run
#else
constexpr bool kUnderSanitizers = false;
#endif
// Under the sanitizers the sampled 1024² cells are left to the Release run: they run the code
// the 256² cells run (several tiles, every level), at 16 times the cost.
constexpr bool kSampledCells = !kUnderSanitizers;

// Kernels are checked against taps at every texel up to this resolution.
constexpr uint32_t kKernelCheckUpTo = 256;

void checkCell(const SchemeInfo& scheme, const std::string& sceneName, DepthMode mode,
               uint32_t resolution, const VerifyOptions& options, const Params& params = {}) {
  const Scene& scene = sceneName == "spot-city" ? spotLitCity() : cachedScene(sceneName);
  const DepthSource source(scene, sceneLight(scene, 0), mode, resolution);
  const BuildOutcome built = buildStructure(source, scheme, scheme.resolve(params),
                                            BuildShape{defaultTileSize(resolution) / 2});
  const VerifyReport report = verify(*built.decoder, scheme.kind, built.map, source, options);
  INFO(fmt::format("{} on {} ({}, {}²): {} of {} queries wrong", scheme.name, sceneName,
                   toString(mode), resolution, report.mismatches, report.queries));
  for (const Mismatch& m : report.examples)
    INFO(fmt::format("  x={} y={} z={} k={} got {} expected [{}, {}]", m.query.x, m.query.y,
                     m.query.z, m.k, m.got, m.expected.min, m.expected.max));
  CHECK(report.queries > 0);
  CHECK(report.mismatches == 0);
  if (resolution > kKernelCheckUpTo) return;
  // Issue 13: kernel lookups that walk a structure once agree with its taps, bit for bit; under
  // the sanitizers the 256² cells at one depth (their 64² cells at 16 run the same code).
  const int kernelDepths = resolution <= 64 ? 16 : kUnderSanitizers ? 1 : 4;
  const std::vector<float> depths = hitDepthQuantiles(source, kernelDepths);
  const VerifyReport kernels = verifyKernels(*built.decoder, built.map, depths);
  INFO(fmt::format("{} on {} ({}, {}²): {} of {} kernels differ from their taps", scheme.name,
                   sceneName, toString(mode), resolution, kernels.mismatches, kernels.queries));
  for (const Mismatch& m : kernels.examples)
    INFO(fmt::format("  x={} y={} z={} k={} got {} taps give {}", m.query.x, m.query.y, m.query.z,
                     m.k, m.got, m.expected.min));
  CHECK(kernels.queries > 0);
  CHECK(kernels.mismatches == 0);
}

// Parameter values that change what a scheme stores, checked beside its defaults: the scheme,
// the values, and a name for the sections.
struct Variant {
  std::string scheme;
  Params params;
  std::string name;
};
const std::vector<Variant>& variants() {
  static const std::vector<Variant> list{
      {"mmh", {{"relative-values", "float-differences"}}, "mmh float-differences"},
      {"cpvs-fast", {{"coarse-classification", "depth-hierarchy"}}, "cpvs-fast depth-hierarchy"},
      // With the depth hierarchy, culling may change the structure (cpvs-fast README): both are
      // checked.
      {"cpvs-fast",
       {{"coarse-classification", "depth-hierarchy"}, {"culling", "off"}},
       "cpvs-fast depth-hierarchy culling-off"}};
  return list;
}

// Every scheme on one scene, in every mode.
void checkScene(const std::string& sceneName) {
  const DepthMode mode = GENERATE(DepthMode::Open, DepthMode::Closed, DepthMode::Static);
  const auto check = [&](const SchemeInfo& scheme, const std::string& name, const Params& params) {
    SECTION(name + " exhaustive") {
      for (uint32_t resolution : {64u, 256u})
        checkCell(scheme, sceneName, mode, resolution, {}, params);
    }
    if (kSampledCells) {
      SECTION(name + " sampled") {
        VerifyOptions sampled;
        sampled.exhaustiveUpTo = 256;
        sampled.sampledQueries = 200'000;
        checkCell(scheme, sceneName, mode, 1024, sampled, params);
      }
    }
  };
  for (const SchemeInfo& scheme : schemes()) {
    check(scheme, scheme.name, {});
    for (const Variant& variant : variants())
      if (variant.scheme == scheme.name) check(scheme, variant.name, variant.params);
  }
}

}  // namespace

// One test case per scene, so that CTest runs the scenes side by side.
TEST_CASE("every scheme is lossless on the city in every mode", "[matrix]") {
  checkScene("city");
}
TEST_CASE("every scheme is lossless on the terrain in every mode", "[matrix]") {
  checkScene("terrain");
}
TEST_CASE("every scheme is lossless on the forest in every mode", "[matrix]") {
  checkScene("forest");
}
TEST_CASE("every scheme is lossless on the tangle in every mode", "[matrix]") {
  checkScene("tangle");
}
TEST_CASE("every scheme is lossless on the spot-lit city in every mode", "[matrix]") {
  checkScene("spot-city");
}
