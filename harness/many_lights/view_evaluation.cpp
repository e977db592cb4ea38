#include "harness/many_lights/view_evaluation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "harness/cell.h"
#include "harness/machine.h"
#include "harness/many_lights/statistics.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "schemes/interface/serial.h"

namespace fs = std::filesystem;

namespace sb {

uint64_t evaluateShadows(const ViewSurface& view, std::span<const ShadowedLight> lights,
                         const TileLightLists& lists, int k, bool parallel,
                         std::vector<float>& visibility) {
  visibility.assign(size_t(view.width) * view.height, 0.0f);
  std::atomic<uint64_t> lookups{0};
  forTiles(lists.lights.size(), parallel, [&](size_t begin, size_t end) {
    std::vector<Query> queries;
    std::vector<size_t> pixels;
    std::vector<float> answers;
    uint64_t done = 0;
    for (size_t tile = begin; tile < end; ++tile)
      for (uint32_t l : lists.lights[tile]) {
        // One batch per tile and light: the decoder is called once, not once per pixel.
        queries.clear();
        pixels.clear();
        forCoveredPixels(view, lists, tile, [&](size_t p) {
          if (const auto q = lightSpaceQuery(lights[l], view.position[p], view.normal[p], k)) {
            queries.push_back(*q);
            pixels.push_back(p);
          }
        });
        if (queries.empty()) continue;
        answers.resize(queries.size());
        lights[l].decoder->lookup(queries, k, answers);
        for (size_t i = 0; i < pixels.size(); ++i) visibility[pixels[i]] += answers[i];
        done += queries.size();
      }
    lookups += done;
  });
  return lookups;
}

namespace {

using Clock = std::chrono::steady_clock;

template <class F>
double medianMilliseconds(uint32_t repeats, F&& f) {
  std::vector<double> ms;
  for (uint32_t r = 0; r < std::max(repeats, 1u); ++r) {
    const auto start = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return distributionOf(ms).median;
}

}  // namespace

Table evaluateViews(const Scene& litScene, const std::vector<nlohmann::json>& records,
                    const ManyLightsConfig& config, const ViewOptions& o, const fs::path& out) {
  Table table{fmt::format("Many lights: shadows of all lights in a {}×{} view, {}×{} PCF", o.width,
                          o.height, o.filter, o.filter),
              fmt::format("milliseconds, medians of {} runs; tiles of {}×{} pixels; lights per "
                          "tile over tiles with samples; lookups only where the light reaches",
                          o.repeats, o.tilePixels, o.tilePixels),
              {"frame", "lights per tile", "lights per pixel", "lookups", "light lists 1 thread",
               fmt::format("light lists {} threads", tbb::this_task_arena::max_concurrency()),
               "shadows 1 thread",
               fmt::format("shadows {} threads", tbb::this_task_arena::max_concurrency())},
              {},
              "view"};
  uint64_t needed = 0;
  for (const nlohmann::json& r : records) needed += r["size_bytes"]["total"].get<uint64_t>();
  if (const uint64_t available = availableMemoryBytes(); available && needed > available)
    throw std::runtime_error(fmt::format(
        "the {} structures need {:.2f} GiB but only {:.2f} GiB is available; use --no-view",
        records.size(), needed / double(1ull << 30), available / double(1ull << 30)));

  std::vector<std::unique_ptr<Decoder>> decoders;
  std::vector<ShadowedLight> lights;
  for (uint32_t i = 0; i < records.size(); ++i) {
    decoders.push_back(loadStructure(lightStructurePath(out, litScene, config, i), nullptr));
    lights.emplace_back(sceneLight(litScene, i), *decoders.back(), config.resolution);
  }
  // Primary rays need any light's view of the scene; the map itself is never traced.
  const DepthSource camera(litScene, lights.front().light, DepthMode::Open, kMinResolution,
                           DepthMethod::RayCast);

  for (uint32_t frame = 0; frame < o.frames; ++frame) {
    const ViewSurface view = captureView(litScene, camera, o.width, o.height, frame, o.frames);
    TileLightLists lists;
    const double listsSingle = medianMilliseconds(
        o.repeats, [&] { lists = buildLightLists(view, lights, o.tilePixels, o.filter, false); });
    const double listsAll = medianMilliseconds(
        o.repeats, [&] { lists = buildLightLists(view, lights, o.tilePixels, o.filter, true); });
    std::vector<float> visibility;
    uint64_t lookups = 0;
    const double shadowsSingle = medianMilliseconds(o.repeats, [&] {
      lookups = evaluateShadows(view, lights, lists, o.filter, false, visibility);
    });
    const double shadowsAll = medianMilliseconds(o.repeats, [&] {
      lookups = evaluateShadows(view, lights, lists, o.filter, true, visibility);
    });

    uint64_t listed = 0, tilesWithSamples = 0, covered = 0;
    for (const auto& list : lists.lights) listed += list.size();
    for (size_t t = 0; t < lists.lights.size(); ++t) {
      bool any = false;
      forCoveredPixels(view, lists, t, [&](size_t) { any = true, ++covered; });
      tilesWithSamples += any;
    }
    table.rows.push_back(
        {fmt::format("{}/{}", frame + 1, o.frames),
         formatSignificant(double(listed) / double(std::max<uint64_t>(tilesWithSamples, 1))),
         formatSignificant(double(lookups) / double(std::max<uint64_t>(covered, 1))),
         fmt::format("{}", lookups), formatSignificant(listsSingle), formatSignificant(listsAll),
         formatSignificant(shadowsSingle), formatSignificant(shadowsAll)});
    fmt::print("view {}/{}: {} lookups, shadows {} ms (1 thread), {} ms (all threads)\n", frame + 1,
               o.frames, lookups, formatSignificant(shadowsSingle), formatSignificant(shadowsAll));
  }
  // Kämpe Fig. 1 and §5.3: 1920×1080, 165 lights, 9×9 PCF, one CUDA thread per pixel.
  table.rows.push_back(
      {"Kämpe 2015 (paper, GTX Titan)", "–", "–", "–", "–", "–", "–", "3.2 (GPU)"});
  return table;
}

uint64_t viewEvaluationBytes(const ViewOptions& view) {
  const uint64_t pixels = uint64_t{view.width} * view.height;
  const uint64_t tiles = ((uint64_t{view.width} + view.tilePixels - 1) / view.tilePixels) *
                         ((uint64_t{view.height} + view.tilePixels - 1) / view.tilePixels);
  constexpr uint64_t kBytesPerPixel =
      2 * sizeof(glm::vec3) + sizeof(uint8_t) + sizeof(float);  // ViewSurface, visibility
  return pixels * kBytesPerPixel + tiles * sizeof(std::vector<uint32_t>);
}

}  // namespace sb
