#include "harness/many_lights.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <CLI/CLI.hpp>
#include <glm/gtc/constants.hpp>

#include "harness/cell.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "schemes/interface/splitmix.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

// The highest point of the triangles whose ground plan overlaps the square of half-width `half`
// around `centre`; `floor` where there are none.
double highestOver(const Scene& scene, glm::dvec2 centre, double half, double floor) {
  double top = floor;
  for (const Mesh& mesh : scene.meshes)
    for (const glm::uvec3& t : mesh.triangles) {
      const glm::vec3 &a = mesh.vertices[t.x], &b = mesh.vertices[t.y], &c = mesh.vertices[t.z];
      const glm::dvec2 lo(glm::min(glm::min(a, b), c)), hi(glm::max(glm::max(a, b), c));
      if (hi.x >= centre.x - half && lo.x <= centre.x + half && hi.y >= centre.y - half &&
          lo.y <= centre.y + half)
        top = std::max<double>(top, std::max({a.z, b.z, c.z}));
    }
  return top;
}

CellSpec cellOf(const ManyLightsConfig& config, uint32_t index) {
  return {config.sceneSpec,  index,          config.mode, config.scheme, config.params,
          config.resolution, config.tileSize};
}

std::string cellName(const Scene& litScene, const ManyLightsConfig& config, uint32_t index) {
  return cellKey(cellIdentity(cellOf(config, index), litScene));
}

std::string number(double value) {
  return formatSignificant(value, 3);
}

}  // namespace

std::vector<LightSpec> placeSpotLights(const Scene& scene, const SpotLightPlacement& placement) {
  if (placement.count == 0) throw std::invalid_argument("many lights: at least one light");
  if (!(placement.minFovDegrees > 0 && placement.minFovDegrees <= placement.maxFovDegrees &&
        placement.maxFovDegrees < 179))
    throw std::invalid_argument("many lights: fov range must be within (0, 179) degrees");
  if (!(placement.maxTiltDegrees >= 0 && placement.maxTiltDegrees <= placement.minFovDegrees / 2))
    throw std::invalid_argument("many lights: the tilt must not exceed half the smallest fov");
  const Bounds bounds = scene.bounds();
  const glm::dvec2 lo(bounds.min), extent = glm::dvec2(bounds.max) - lo;
  // Lights this far apart cover the ground plan about once; each stands at least half a
  // spacing inside the plan, so that its footprint stays over the scene.
  const double spacing = std::max(extent.x, extent.y) / std::sqrt(double(placement.count));
  const glm::dvec2 margin = glm::min(glm::dvec2(spacing / 2), extent / 4.0);

  uint64_t state = placement.seed;
  const glm::dvec2 shift(unitFloat(nextRandom(state)), unitFloat(nextRandom(state)));
  std::vector<LightSpec> lights;
  for (uint32_t i = 0; i < placement.count; ++i) {
    // The R2 sequence (Roberts 2018, steps 1/g and 1/g², g the plastic number) spreads any
    // number of lights evenly; the seed shifts it.
    const glm::dvec2 u =
        glm::fract(shift + double(i + 1) * glm::dvec2(0.7548776662466927, 0.5698402909980532));
    const glm::dvec2 xy = lo + margin + u * (extent - 2.0 * margin);
    // Above everything under the light's cell, so never inside a closed object (DESIGN §3).
    const double height = highestOver(scene, xy, spacing / 2, bounds.min.z) +
                          spacing * (0.5 + 0.5 * unitFloat(nextRandom(state)));
    const double tilt =
        glm::radians(double(placement.maxTiltDegrees)) * unitFloat(nextRandom(state));
    const double azimuth = 2 * glm::pi<double>() * unitFloat(nextRandom(state));
    LightSpec light;
    light.kind = LightKind::Spot;
    light.position = glm::vec3(xy.x, xy.y, height);
    light.direction = glm::vec3(std::sin(tilt) * std::cos(azimuth),
                                std::sin(tilt) * std::sin(azimuth), -std::cos(tilt));
    light.fovDegrees =
        placement.minFovDegrees +
        (placement.maxFovDegrees - placement.minFovDegrees) * unitFloat(nextRandom(state));
    light.depth = DepthDistribution::Logarithmic;  // Kämpe eq. 1
    lights.push_back(light);
  }
  return lights;
}

Scene withSpotLights(Scene scene, const SpotLightPlacement& placement) {
  scene.lights = placeSpotLights(scene, placement);
  return scene;
}

fs::path lightRecordPath(const fs::path& out, const Scene& litScene, const ManyLightsConfig& config,
                         uint32_t index) {
  return out / (cellName(litScene, config, index) + ".json");
}

fs::path lightStructurePath(const fs::path& out, const Scene& litScene,
                            const ManyLightsConfig& config, uint32_t index) {
  return out / "structures" / (cellName(litScene, config, index) + ".sb");
}

std::vector<nlohmann::json> buildManyLights(
    const Scene& litScene, const ManyLightsConfig& config, const fs::path& out,
    const std::function<void(uint32_t, const nlohmann::json&, bool)>& done) {
  CellOptions options;
  options.verify = config.verify;
  // One light of hundreds: sampled at every resolution, never exhaustive.
  options.verifyOptions.exhaustiveUpTo = 0;
  options.verifyOptions.sampledQueries = config.sampledQueries;
  options.benchLookups = false;
  const nlohmann::json placement = {
      {"lights", litScene.lights.size()},
      {"seed", config.placement.seed},
      {"fov_degrees", {config.placement.minFovDegrees, config.placement.maxFovDegrees}},
      {"max_tilt_degrees", config.placement.maxTiltDegrees}};

  std::vector<nlohmann::json> records;
  for (uint32_t index = 0; index < litScene.lights.size(); ++index) {
    const fs::path recordPath = lightRecordPath(out, litScene, config, index);
    const fs::path structurePath = lightStructurePath(out, litScene, config, index);
    if (const auto existing = readRecord(recordPath)) {
      if (existing->value("light", nlohmann::json()) != sceneLight(litScene, index).describe())
        throw std::runtime_error(
            fmt::format("'{}' holds a record of another light {}: the folder belongs to another "
                        "placement; choose another --out",
                        recordPath.string(), index));
      if (!config.saveStructures || fs::exists(structurePath)) {
        records.push_back(*existing);
        if (done) done(index, records.back(), false);
        continue;
      }
    }
    options.saveStructureTo = std::nullopt;
    if (config.saveStructures) {
      fs::create_directories(structurePath.parent_path());
      options.saveStructureTo = structurePath;
    }
    nlohmann::json record = runCell(cellOf(config, index), litScene, options);
    record["many_lights"] = placement;
    // The record comes last: a structure without its record is rebuilt on resuming.
    writeJsonAtomically(recordPath, record);
    records.push_back(std::move(record));
    if (done) done(index, records.back(), true);
  }
  return records;
}

Distribution distributionOf(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  d.min = values.front();
  d.max = values.back();
  d.median = n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
  for (double v : values) d.total += v;
  d.mean = d.total / double(n);
  return d;
}

Histogram histogramOf(std::span<const double> values, uint32_t bins) {
  Histogram h;
  if (values.empty() || bins == 0) return h;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  h.lo = *lo;
  h.binWidth = (*hi - *lo) / bins;
  // Equal values (a scheme of fixed size) make one bin of width 0.
  h.counts.assign(h.binWidth > 0 ? bins : 1, 0);
  for (double v : values)
    ++h.counts[h.binWidth > 0 ? std::min<size_t>(size_t((v - h.lo) / h.binWidth), bins - 1) : 0];
  return h;
}

std::string histogramText(const Histogram& h, int digits) {
  constexpr uint32_t kBarWidth = 40;
  const uint32_t most = h.counts.empty() ? 0 : *std::max_element(h.counts.begin(), h.counts.end());
  std::string text;
  for (size_t b = 0; b < h.counts.size(); ++b) {
    const uint32_t bar = most ? (h.counts[b] * kBarWidth + most - 1) / most : 0;
    std::string bars;
    for (uint32_t i = 0; i < bar; ++i) bars += "█";
    text += fmt::format(
        "{:>10} – {:<10} {:<{}} {}\n", formatSignificant(h.lo + double(b) * h.binWidth, digits),
        formatSignificant(h.lo + double(b + 1) * h.binWidth, digits), bars, kBarWidth, h.counts[b]);
  }
  return text;
}

BuildSummary summariseBuilds(const std::vector<nlohmann::json>& records, uint32_t bins) {
  constexpr double kMiB = 1 << 20;
  std::vector<double> sizes, builds, depths;
  std::vector<std::pair<std::string, std::vector<double>>> phases;  // in order of appearance
  BuildSummary summary;
  summary.perLight = {
      "Many lights: per light",
      "bytes and milliseconds; build = depth map and encoding, wall clock",
      {"light", "x", "y", "z", "dx", "dy", "dz", "fov_degrees", "size_bytes", "build_ms",
       "depth_ms", "closed_fallbacks", "verified_queries", "mismatches"},
      {},
      "lights"};
  for (const nlohmann::json& r : records) {
    sizes.push_back(r["size_bytes"]["total"].get<double>() / kMiB);
    builds.push_back(r["time_s"]["total"].get<double>() * 1e3);
    depths.push_back(r["time_s"]["depth"].get<double>() * 1e3);
    for (const auto& [name, seconds] : r["time_s"]["phases"].items()) {
      auto phase = std::find_if(phases.begin(), phases.end(),
                                [&](const auto& p) { return p.first == name; });
      if (phase == phases.end()) phase = phases.insert(phase, {name, {}});
      phase->second.push_back(seconds.get<double>() * 1e3);
    }
    const nlohmann::json& light = r["light"];
    const bool verified = r.contains("verification");
    summary.perLight.rows.push_back(
        {fmt::format("{}", r["light_index"].get<uint32_t>()),
         number(light["position"][0].get<double>()), number(light["position"][1].get<double>()),
         number(light["position"][2].get<double>()), number(light["direction"][0].get<double>()),
         number(light["direction"][1].get<double>()), number(light["direction"][2].get<double>()),
         number(light["fov_degrees"].get<double>()),
         fmt::format("{}", r["size_bytes"]["total"].get<uint64_t>()), number(builds.back()),
         number(depths.back()), fmt::format("{}", r["depth"]["closed_fallbacks"].get<uint64_t>()),
         verified ? fmt::format("{}", r["verification"]["queries"].get<uint64_t>()) : "–",
         verified ? fmt::format("{}", r["verification"]["mismatches"].get<uint64_t>()) : "–"});
  }

  // Kämpe §5.3 and Fig. 1: 165 lights at 8192³ on a GTX Titan with a Core i5-2500K; the
  // paper writes MB and gives no median.
  summary.distribution = {
      fmt::format("Many lights: {} structures (Kämpe 2015 Fig. 3)", records.size()),
      "MiB (2²⁰ bytes) and milliseconds, ours; the paper's rows as printed there (MB), 165 "
      "lights at 8192³; build = depth map and encoding, wall clock; depth map = tracing "
      "thread-seconds over threads, overlapping the encoder's phases",
      {"", "min", "median", "mean", "max", "total"},
      {},
      "distribution"};
  const auto row = [&](std::string label, const std::vector<double>& values) {
    const Distribution d = distributionOf(values);
    summary.distribution.rows.push_back({std::move(label), number(d.min), number(d.median),
                                         number(d.mean), number(d.max), number(d.total)});
  };
  row("size (MiB)", sizes);
  summary.distribution.rows.push_back(
      {"size (MB), Kämpe 2015 (paper)", "0.3", "–", "0.5", "1.7", "96"});
  row("build (ms)", builds);
  summary.distribution.rows.push_back(
      {"build (ms), Kämpe 2015 (paper)", "–", "–", "114", "–", "19000"});
  row("depth map (ms)", depths);
  for (const auto& [name, values] : phases) row(fmt::format("phase {} (ms)", name), values);

  summary.histograms = {"Many lights: histograms",
                        "lights per bin [from, to) (the last bin includes its end)",
                        {"quantity", "from", "to", "lights"},
                        {},
                        "histogram"};
  const std::pair<const char*, const std::vector<double>*> quantities[] = {{"size (MiB)", &sizes},
                                                                           {"build (ms)", &builds}};
  for (const auto& [label, values] : quantities) {
    const Histogram h = histogramOf(*values, bins);
    for (size_t b = 0; b < h.counts.size(); ++b)
      summary.histograms.rows.push_back({label, number(h.lo + double(b) * h.binWidth),
                                         number(h.lo + double(b + 1) * h.binWidth),
                                         fmt::format("{}", h.counts[b])});
    summary.histogramText += fmt::format("{}:\n{}\n", label, histogramText(h));
  }
  return summary;
}

ShadowedLight::ShadowedLight(Light l, const Decoder& d, uint32_t r)
    : light(std::move(l)), decoder(&d), resolution(r) {
  if (light.kind() != LightKind::Spot)
    throw std::invalid_argument("many lights: only spot lights are evaluated");
  // The fitted near and far planes are the Light's own; describe() is where it reports them.
  const nlohmann::json frustum = light.describe();
  tanHalfFov = std::tan(glm::radians(double(light.spec().fovDegrees)) / 2);
  near = frustum["near"].get<double>();
  far = frustum["far"].get<double>();
}

std::optional<Query> lightSpaceQuery(const ShadowedLight& s, const glm::dvec3& position,
                                     const glm::dvec3& normal, int k) {
  // A texel at view depth z is 2·tan(fov/2)·z/R wide; half of k texels along the normal.
  const double z = std::clamp(s.light.toView(position).z, 0.0, s.far);
  const double offset = k * s.tanHalfFov * z / s.resolution;
  const glm::dvec3 p = s.light.toLightSpace(position + offset * normal);
  if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1 && p.z >= 0 && p.z <= 1)) return std::nullopt;
  return Query{float(p.x), float(p.y), float(p.z)};
}

namespace {

// A light's frustum as six world-space planes dot(n, p) ≤ w (n unit), each pushed out by the
// largest normal offset of lightSpaceQuery plus rounding slack, so that every view sample whose
// query it accepts lies inside: the light's bounding volume for the light lists.
struct LightVolume {
  std::array<glm::dvec4, 6> planes;

  explicit LightVolume(const ShadowedLight& s, int k) {
    const double padding = k * s.tanHalfFov * s.far / s.resolution + 1e-6 * s.far;
    const double t = s.tanHalfFov, c = 1 / std::sqrt(1 + t * t);
    // View space: |x| ≤ t·z, |y| ≤ t·z, near ≤ z ≤ far.
    const glm::dvec4 view[6] = {{c, 0, -t * c, 0},  {-c, 0, -t * c, 0},  {0, c, -t * c, 0},
                                {0, -c, -t * c, 0}, {0, 0, -1, -s.near}, {0, 0, 1, s.far}};
    // toView is a rotation and a shift: n·view(p) = normalToWorld(n)·p + n·view(0).
    const glm::dvec3 viewOfOrigin = s.light.toView(glm::dvec3(0));
    for (size_t i = 0; i < 6; ++i) {
      const glm::dvec3 n(view[i]);
      planes[i] =
          glm::dvec4(s.light.normalToWorld(n), view[i].w + padding - glm::dot(n, viewOfOrigin));
    }
  }

  // False only when the box lies wholly outside one of the planes.
  bool mayIntersect(const glm::dvec3& lo, const glm::dvec3& hi) const {
    const glm::dvec3 centre = (lo + hi) * 0.5, half = (hi - lo) * 0.5;
    for (const glm::dvec4& plane : planes) {
      const glm::dvec3 n(plane);
      if (glm::dot(n, centre) - glm::dot(glm::abs(n), half) > plane.w) return false;
    }
    return true;
  }
};

TileLightLists emptyLists(const ViewSurface& view, uint32_t tilePixels) {
  if (tilePixels == 0) throw std::invalid_argument("many lights: tiles need at least one pixel");
  TileLightLists lists;
  lists.tilePixels = tilePixels;
  lists.tilesX = (view.width + tilePixels - 1) / tilePixels;
  lists.tilesY = (view.height + tilePixels - 1) / tilePixels;
  lists.lights.resize(size_t(lists.tilesX) * lists.tilesY);
  return lists;
}

// Calls body(firstTile, endTile) over all tiles: on this thread, or split over all threads.
template <class Body>
void forTiles(size_t tiles, bool parallel, Body&& body) {
  if (!parallel) return body(size_t(0), tiles);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles),
                    [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

// Calls f(pixel) for every covered pixel of tile `tile`.
template <class F>
void forCoveredPixels(const ViewSurface& view, const TileLightLists& lists, size_t tile, F&& f) {
  const uint32_t x0 = uint32_t(tile % lists.tilesX) * lists.tilePixels;
  const uint32_t y0 = uint32_t(tile / lists.tilesX) * lists.tilePixels;
  for (uint32_t y = y0; y < std::min(y0 + lists.tilePixels, view.height); ++y)
    for (uint32_t x = x0; x < std::min(x0 + lists.tilePixels, view.width); ++x)
      if (view.covered[view.pixel(x, y)]) f(view.pixel(x, y));
}

}  // namespace

TileLightLists buildLightLists(const ViewSurface& view, std::span<const ShadowedLight> lights,
                               uint32_t tilePixels, int k, bool parallel) {
  TileLightLists lists = emptyLists(view, tilePixels);
  std::vector<LightVolume> volumes;
  for (const ShadowedLight& light : lights) volumes.emplace_back(light, k);
  forTiles(lists.lights.size(), parallel, [&](size_t begin, size_t end) {
    for (size_t tile = begin; tile < end; ++tile) {
      // The tile's three-dimensional bounds over its view samples (Olsson & Assarsson 2011).
      constexpr double inf = std::numeric_limits<double>::infinity();
      glm::dvec3 lo(inf), hi(-inf);
      forCoveredPixels(view, lists, tile, [&](size_t p) {
        lo = glm::min(lo, glm::dvec3(view.position[p]));
        hi = glm::max(hi, glm::dvec3(view.position[p]));
      });
      if (!(lo.x <= hi.x)) continue;
      for (uint32_t l = 0; l < volumes.size(); ++l)
        if (volumes[l].mayIntersect(lo, hi)) lists.lights[tile].push_back(l);
    }
  });
  return lists;
}

TileLightLists allLightsEverywhere(const ViewSurface& view, size_t lightCount,
                                   uint32_t tilePixels) {
  TileLightLists lists = emptyLists(view, tilePixels);
  std::vector<uint32_t> all(lightCount);
  for (uint32_t l = 0; l < lightCount; ++l) all[l] = l;
  std::fill(lists.lights.begin(), lists.lights.end(), all);
  return lists;
}

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

struct CommandOptions {
  ManyLightsConfig config;
  std::string mode = "closed", resolution = "8K", out = "results/many-lights";
  bool noView = false;
  uint32_t viewWidth = 1920, viewHeight = 1080, tilePixels = 8, frames = 1, repeats = 3, bins = 12;
  int filter = 9;
};

// The view evaluation of Kämpe §5.3 for each frame of the orbit, beside the paper's 3.2 ms.
Table evaluateViews(const Scene& litScene, const std::vector<nlohmann::json>& records,
                    const CommandOptions& o, const fs::path& out) {
  Table table{fmt::format("Many lights: shadows of all lights in a {}×{} view, {}×{} PCF",
                          o.viewWidth, o.viewHeight, o.filter, o.filter),
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
    decoders.push_back(loadStructure(lightStructurePath(out, litScene, o.config, i), nullptr));
    lights.emplace_back(sceneLight(litScene, i), *decoders.back(), o.config.resolution);
  }
  // Primary rays need any light's view of the scene; the map itself is never traced.
  const DepthSource camera(litScene, lights.front().light, DepthMode::Open, kMinResolution,
                           DepthMethod::RayCast);

  for (uint32_t frame = 0; frame < o.frames; ++frame) {
    const ViewSurface view =
        captureView(litScene, camera, o.viewWidth, o.viewHeight, frame, o.frames);
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
    table.rows.push_back({fmt::format("{}/{}", frame + 1, o.frames),
                          number(double(listed) / double(std::max<uint64_t>(tilesWithSamples, 1))),
                          number(double(lookups) / double(std::max<uint64_t>(covered, 1))),
                          fmt::format("{}", lookups), number(listsSingle), number(listsAll),
                          number(shadowsSingle), number(shadowsAll)});
    fmt::print("view {}/{}: {} lookups, shadows {} ms (1 thread), {} ms (all threads)\n", frame + 1,
               o.frames, lookups, number(shadowsSingle), number(shadowsAll));
  }
  // Kämpe Fig. 1 and §5.3: 1920×1080, 165 lights, 9×9 PCF, one CUDA thread per pixel.
  table.rows.push_back(
      {"Kämpe 2015 (paper, GTX Titan)", "–", "–", "–", "–", "–", "–", "3.2 (GPU)"});
  return table;
}

void runManyLights(CommandOptions o) {
  if (!validFilterSize(o.filter))
    throw std::invalid_argument(fmt::format("filter size {} must be odd and in [1, 17]", o.filter));
  o.config.mode = depthModeFromString(o.mode);
  o.config.resolution = parseResolution(o.resolution);
  o.config.saveStructures = !o.noView;
  const fs::path out = o.out;
  const Scene litScene = withSpotLights(openScene(o.config.sceneSpec), o.config.placement);
  const SchemeInfo& scheme = findScheme(o.config.scheme);
  fmt::print("many lights: {} spot lights over {} ({} triangles), {} {} {}³ → {}\n",
             litScene.lights.size(), litScene.name, litScene.triangleCount(), scheme.name, o.mode,
             resolutionLabel(o.config.resolution), out.string());

  const auto records = buildManyLights(
      litScene, o.config, out, [&](uint32_t index, const nlohmann::json& r, bool built) {
        std::string checked;
        if (r.contains("verification"))
          checked = fmt::format(", verified {} queries, {} mismatches",
                                r["verification"]["queries"].get<uint64_t>(),
                                r["verification"]["mismatches"].get<uint64_t>());
        fmt::print("light {:>3}/{}: {} MiB, build {} ms (depth {} ms){}{}\n", index + 1,
                   litScene.lights.size(),
                   number(r["size_bytes"]["total"].get<double>() / (1 << 20)),
                   number(r["time_s"]["total"].get<double>() * 1e3),
                   number(r["time_s"]["depth"].get<double>() * 1e3), checked,
                   built ? "" : " (from an earlier run)");
      });

  const BuildSummary summary = summariseBuilds(records, o.bins);
  writeFileAtomically(out / "lights.csv", toCsv(summary.perLight));
  writeFileAtomically(out / "histogram.csv", toCsv(summary.histograms));
  std::string markdown = fmt::format(
      "# Many local lights (Kämpe 2015 §4, §5.3)\n\n"
      "{} spot lights over `{}` ({} triangles, hash {}): seed {}, fov {}–{}°, tilt ≤ {}°, "
      "logarithmic depth (eq. 1). Scheme `{}`, {} mode, {}² ({}). Machine: {}.\n\n",
      litScene.lights.size(), o.config.sceneSpec, litScene.triangleCount(), litScene.hash(),
      o.config.placement.seed, o.config.placement.minFovDegrees, o.config.placement.maxFovDegrees,
      o.config.placement.maxTiltDegrees, scheme.name, o.mode, resolutionLabel(o.config.resolution),
      scheme.kind == SchemeKind::Voxel ? "voxel scheme, Rz = R" : "depth scheme",
      machineInfo()["cpu"].get<std::string>());
  markdown += toMarkdown({summary.distribution});
  markdown +=
      fmt::format("Histograms (lights per bin):\n\n```text\n{}```\n\n", summary.histogramText);
  if (!o.noView) {
    const Table view = evaluateViews(litScene, records, o, out);
    writeFileAtomically(out / "view.csv", toCsv(view));
    markdown += toMarkdown({view});
  }
  writeFileAtomically(out / "summary.md", markdown);
  fmt::print("\n{}wrote {}\n", markdown, (out / "summary.md").string());

  size_t mismatched = 0;
  for (const nlohmann::json& r : records)
    mismatched += r.contains("verification") && r["verification"]["mismatches"].get<uint64_t>();
  if (mismatched)
    throw std::runtime_error(
        fmt::format("{} of {} lights have mismatches", mismatched, records.size()));
}

}  // namespace

void addManyLightsCommand(CLI::App& app) {
  auto o = std::make_shared<CommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "many-lights",
      "Kämpe 2015 §5.3: build one structure per spot light, summarise sizes and build times, "
      "evaluate all lights for a view");
  sub->add_option("--scene,-s", o->config.sceneSpec, "generator, scene .json or model file")
      ->capture_default_str();
  sub->add_option("--lights", o->config.placement.count, "number of spot lights")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--seed", o->config.placement.seed, "seed of the light placement")
      ->capture_default_str();
  sub->add_option("--scheme", o->config.scheme, "scheme name (see 'shadowbench schemes')")
      ->capture_default_str();
  sub->add_option("--mode,-m", o->mode, "dual depth mode: open, closed or static")
      ->capture_default_str();
  sub->add_option("--resolution,-r", o->resolution, "texels per side of each light")
      ->capture_default_str();
  sub->add_option("--tile", o->config.tileSize,
                  "tile size streamed to the encoder (default min(R, 512))");
  sub->add_option("--out", o->out, "folder for records, structures and summary.md (resumes)")
      ->capture_default_str();
  sub->add_flag("--verify", o->config.verify, "check each structure against the reference");
  sub->add_option("--sampled-queries", o->config.sampledQueries, "queries checked per light")
      ->capture_default_str();
  sub->add_flag("--no-view", o->noView, "skip the view evaluation (and keep no structure files)");
  const std::tuple<const char*, uint32_t*, const char*> counts[] = {
      {"--view-width", &o->viewWidth, "view width in pixels"},
      {"--view-height", &o->viewHeight, "view height in pixels"},
      {"--tile-pixels", &o->tilePixels, "screen tile side in pixels"},
      {"--frames", &o->frames, "views along the camera orbit"},
      {"--repeats", &o->repeats, "timed runs per measurement (median)"},
      {"--bins", &o->bins, "histogram bins"}};
  for (const auto& [name, value, help] : counts)
    sub->add_option(name, *value, help)->capture_default_str()->check(CLI::PositiveNumber);
  sub->add_option("--filter,-k", o->filter, "PCF filter size k (odd, ≤ 17)")->capture_default_str();
  sub->callback([o] { runManyLights(*o); });
}

}  // namespace sb
