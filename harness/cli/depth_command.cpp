#include <memory>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/progress.h"
#include "harness/scene_export.h"

namespace sb::cli {

namespace {

struct DepthOptions {
  MapOptions map;
  std::string exr;
  bool rayCast = false;
};

void streamDepth(const DepthOptions& o) {
  // Checked before the depth pass, which at the sizes refused here takes minutes (issue 11 A9).
  const DepthMode mode = depthModeFromString(o.map.mode);
  const uint32_t r = parseResolution(o.map.resolution);
  checkTileSize(o.map.tile, r);
  if (!o.exr.empty()) {
    if (r > kMaxExrResolution)
      throw std::invalid_argument(fmt::format("--exr is limited to {}² maps; {}² asked",
                                              resolutionLabel(kMaxExrResolution),
                                              resolutionLabel(r)));
    checkOutputFile(o.exr, sceneSourceFiles(o.map.scene));
  }
  const Scene scene = openScene(o.map.scene);
  const DepthSource source(scene, sceneLight(scene, o.map.light), mode, r,
                           o.rayCast ? DepthMethod::RayCast : DepthMethod::Rasterize);
  Progress progress("depth", uint64_t(r) * r, "texels");
  const StreamStats stats = streamDualDepth(
      source, o.map.tile ? o.map.tile : defaultTileSize(r), [](const DualDepthTile&) {},
      [&](uint64_t done) { progress.set(done); });
  progress.finish();
  fmt::print(
      "{} {} {}² ({}): {:.3f} s, {:.1f} Mtexels/s ({:.3f} thread-s tracing), {} closed "
      "fallbacks\n",
      scene.name, o.map.mode, r, toString(source.method()), stats.wallSeconds,
      double(r) * r / stats.wallSeconds * 1e-6, stats.traceThreadSeconds, source.closedFallbacks());
  if (!o.exr.empty()) {
    writeDualDepthExr(source, o.exr);
    fmt::print("wrote {}\n", o.exr);
  }
}

}  // namespace

void addDepthCommand(CLI::App& app) {
  auto o = std::make_shared<DepthOptions>();
  CLI::App* sub =
      app.add_subcommand("depth", "stream the dual depth map and report its throughput");
  o->map.addTo(sub);
  sub->add_option("--exr", o->exr, "also write lo/hi as a float EXR (R ≤ 16K)");
  sub->add_flag("--raycast", o->rayCast,
                "ray cast with Embree instead of rasterising (directional lights)");
  sub->callback([o] { streamDepth(*o); });
}

}  // namespace sb::cli
