// `shadowbench many-lights`: its options, the checks made before any work, and the run that
// places, builds, summarises and evaluates the lights.
#include "harness/cli/many_lights_command.h"

#include <memory>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "harness/cell.h"
#include "harness/machine.h"
#include "harness/many_lights/placement.h"
#include "harness/many_lights/statistics.h"
#include "harness/progress.h"
#include "harness/record.h"

namespace fs = std::filesystem;

namespace sb {

void checkManyLightsFits(const ManyLightsCommandOptions& o, uint64_t availableBytes) {
  if (availableBytes == 0) return;
  constexpr double kGiB = 1ull << 30;
  const uint64_t histograms = summaryBytes(o.bins);
  if (histograms > availableBytes)
    throw std::runtime_error(fmt::format(
        "many lights: --bins {} needs at least {:.2f} GiB for the histograms but only {:.2f} GiB "
        "is available; choose fewer bins",
        o.bins, histograms / kGiB, availableBytes / kGiB));
  const uint64_t view = o.noView ? 0 : viewEvaluationBytes(o.view);
  if (view > availableBytes)
    throw std::runtime_error(fmt::format(
        "many lights: a {}×{} view needs at least {:.2f} GiB but only {:.2f} GiB is available; "
        "choose a smaller --view-width or --view-height, or --no-view",
        o.view.width, o.view.height, view / kGiB, availableBytes / kGiB));
}

namespace {

void runManyLights(ManyLightsCommandOptions o) {
  if (!validFilterSize(o.view.filter))
    throw std::invalid_argument(
        fmt::format("filter size {} must be odd and in [1, 17]", o.view.filter));
  o.config.mode = depthModeFromString(o.mode);
  o.config.resolution = parseResolution(o.resolution);
  o.config.saveStructures = !o.noView;
  checkManyLightsFits(o, availableMemoryBytes());
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
                   formatSignificant(r["size_bytes"]["total"].get<double>() / (1 << 20)),
                   formatSignificant(r["time_s"]["total"].get<double>() * 1e3),
                   formatSignificant(r["time_s"]["depth"].get<double>() * 1e3), checked,
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
    const Table view = evaluateViews(litScene, records, o.config, o.view, out);
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
  auto o = std::make_shared<ManyLightsCommandOptions>();
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
      {"--view-width", &o->view.width, "view width in pixels"},
      {"--view-height", &o->view.height, "view height in pixels"},
      {"--tile-pixels", &o->view.tilePixels, "screen tile side in pixels"},
      {"--frames", &o->view.frames, "views along the camera orbit"},
      {"--repeats", &o->view.repeats, "timed runs per measurement (median)"},
      {"--bins", &o->bins, "histogram bins"}};
  for (const auto& [name, value, help] : counts)
    sub->add_option(name, *value, help)->capture_default_str()->check(CLI::PositiveNumber);
  sub->add_option("--filter,-k", o->view.filter, "PCF filter size k (odd, ≤ 17)")
      ->capture_default_str();
  sub->callback([o] { runManyLights(*o); });
}

}  // namespace sb
