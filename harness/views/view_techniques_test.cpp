// Cascaded and irregular adaptive shadow maps against closed forms and the plain shadow map
// (issue 15): the practical splits, the memory of the thesis's setups, one cascade or one tile
// over the scene equal to the plain map, every visible pixel covered by its cascade or tile, and
// §3.4's ranking.
#include <catch2/catch.hpp>

#include <algorithm>

#include "harness/depth_source.h"
#include "harness/views/cascaded_shadow_maps.h"
#include "harness/views/irregular_adaptive_shadow_maps.h"

using namespace sb;

namespace {

struct Frame {
  Scene scene = openScene("city:size=2");
  Light light = Light::fit(scene.lights[0], scene);
  SceneRays rays{scene};
  Camera camera;
  GroundTruth surface;

  explicit Frame(uint32_t width = 160, uint32_t height = 90) {
    const Bounds b = scene.bounds();
    const glm::dvec3 centre = (glm::dvec3(b.min) + glm::dvec3(b.max)) / 2.0;
    // Low over a street corner, looking across the city.
    camera.eye = glm::dvec3(b.min.x + 3, b.min.y + 3, 4.0);
    camera.target = glm::dvec3(centre.x, centre.y, 2.0);
    surface =
        traceGroundTruth(rays, scene.lights[0], camera, width, height, defaultNormalOffset(scene));
  }

  std::unique_ptr<ViewTechnique> make(const std::string& name, const Params& params) const {
    const ViewTechniqueRow& row = findViewTechnique(name);
    return row.make(scene, light, ParamValues::resolve(name, row.params, params));
  }
};

std::vector<float> shaded(ViewTechnique& technique, const Frame& frame) {
  std::vector<float> visibility;
  technique.prepare(frame.camera, frame.surface);
  technique.shade(frame.camera, frame.surface, visibility);
  return visibility;
}

}  // namespace

TEST_CASE("practical split distances", "[views][csm]") {
  const auto uniform = CascadedShadowMaps::splitDistances(1, 100, 3, 0.0);
  const auto logarithmic = CascadedShadowMaps::splitDistances(1, 100, 4, 1.0);
  const auto half = CascadedShadowMaps::splitDistances(1, 100, 2, 0.5);
  CHECK(uniform == std::vector<double>{1, 34, 67, 100});
  REQUIRE(logarithmic.size() == 5);
  CHECK(logarithmic[2] == Approx(10));
  CHECK(half[1] == Approx(0.5 * 10 + 0.5 * 50.5));
}

TEST_CASE("the memory of the thesis's setups", "[views]") {
  const Frame frame;
  auto csm = frame.make("csm", {});
  auto iasm = frame.make("iasm", {});
  shaded(*csm, frame);
  shaded(*iasm, frame);
  CHECK(csm->memoryBytes() == 3u * 1024u * 1024u * 4u);  // 12 MiB (Alecu §4.2)
  CHECK(iasm->memoryBytes() == 6'860'800u);              // 6.5 MB (Alecu §4.2)
}

TEST_CASE("one cascade or one tile over the scene is the plain shadow map", "[views]") {
  const Frame frame;
  auto csm = frame.make("csm", {{"cascades", "1"}, {"fit", "scene"}});
  auto iasm = frame.make(
      "iasm", {{"grid", "1"}, {"resolution-set", "single-1024"}, {"placement", "scene"}});
  const std::vector<float> a = shaded(*csm, frame), b = shaded(*iasm, frame);
  const DepthSource plain(frame.scene, frame.light, DepthMode::Open, 1024);
  DualDepthTile tile;
  plain.trace(0, 0, 1024, 1024, tile);
  CHECK(static_cast<CascadedShadowMaps&>(*csm).cascades().front().depth() == tile.lo);
  const auto& tiles = static_cast<IrregularAdaptiveShadowMaps&>(*iasm).tiles();
  REQUIRE(tiles.size() == 1);
  REQUIRE(tiles.front());
  CHECK(tiles.front()->depth() == tile.lo);
  CHECK(a == b);  // two lookup paths over one map
  CHECK(std::count(a.begin(), a.end(), 0.0f) >
        std::count(frame.surface.covered.begin(), frame.surface.covered.end(), 0));
}

TEST_CASE("cascades and tiles cover every visible pixel", "[views]") {
  const Frame frame;
  auto csm = frame.make("csm", {});
  auto iasm = frame.make("iasm", {});
  shaded(*csm, frame);
  shaded(*iasm, frame);
  const auto& c = static_cast<CascadedShadowMaps&>(*csm);
  const auto& i = static_cast<IrregularAdaptiveShadowMaps&>(*iasm);
  size_t covered = 0;
  for (size_t p = 0; p < frame.surface.covered.size(); ++p) {
    if (!frame.surface.covered[p]) continue;
    ++covered;
    const glm::dvec3 q = frame.light.toLightSpace(glm::dvec3(frame.surface.position[p]));
    REQUIRE(c.cascades()[c.cascadeOf(frame.surface.viewDepth[p])].covers(q));
    REQUIRE(i.tileOf(q).has_value());
  }
  CHECK(covered > frame.surface.covered.size() / 2);
}

TEST_CASE("IASM hands out its resolutions by importance rank", "[views][iasm]") {
  const Frame frame;
  auto technique = frame.make("iasm", {});
  auto& iasm = static_cast<IrregularAdaptiveShadowMaps&>(*technique);
  shaded(iasm, frame);
  // Eq. 3.1 recomputed here: the tile with the most importance gets 1024², and the resolutions
  // are the set's, each used as often as the set lists it.
  std::vector<double> importance(16, 0);
  const double k =
      0.5 * iasm.frameLayout()["square"][2].get<double>() * frame.light.worldPerUnitWidth();
  for (size_t p = 0; p < frame.surface.covered.size(); ++p)
    if (frame.surface.covered[p])
      if (const auto t =
              iasm.tileOf(frame.light.toLightSpace(glm::dvec3(frame.surface.position[p]))))
        importance[*t] += 1 + 4 * std::clamp(1 - frame.surface.viewDepth[p] / k, 0.0, 1.0);
  const size_t top =
      size_t(std::max_element(importance.begin(), importance.end()) - importance.begin());
  // The first frame is ranked by its own analysis; shading it again ranks by the same pixels.
  shaded(iasm, frame);
  CHECK(iasm.tileResolutions()[top] == 1024);
  std::vector<uint32_t> sorted = iasm.tileResolutions();
  std::sort(sorted.rbegin(), sorted.rend());
  CHECK(sorted == std::vector<uint32_t>{1024, 512, 512, 256, 128, 128, 128, 128, 64, 64, 32, 32, 16,
                                        16, 16, 16});
}

TEST_CASE("a resolution set that does not fit the grid names both parameters", "[views][iasm]") {
  const Frame frame(16, 9);
  CHECK_THROWS_WITH(frame.make("iasm", {{"grid", "2"}}),
                    Catch::Contains("resolution-set 'alecu'") && Catch::Contains("grid=2"));
  CHECK_THROWS_WITH(frame.make("csm", {{"lambda", "101"}}), Catch::Contains("lambda"));
}
