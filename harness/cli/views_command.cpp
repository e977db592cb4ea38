#include <algorithm>
#include <memory>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/progress.h"
#include "harness/resolution.h"
#include "harness/views/view_run.h"
#include "schemes/interface/atomic_file.h"
#include "schemes/interface/serial.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct ViewsCommandOptions {
  MapOptions map;
  std::string path, out;
  std::vector<std::string> techniques{"csm", "iasm"};
  std::vector<std::string> params, structures;
  uint32_t frames = 0;
  std::string images = "first,middle,last";
  bool noExr = false;
  int filter = 1;
  double offsetTexels = 0.75;
  uint32_t boundaryRadius = 2;
};

// "first,middle,last", "all", "none" or frame numbers, as frame indices of an n-frame path.
std::vector<uint32_t> pictureFrames(const std::string& text, uint32_t n) {
  std::vector<uint32_t> frames;
  for (const std::string& item : splitList(text)) {
    if (item == "none") continue;
    if (item == "all") {
      for (uint32_t f = 0; f < n; ++f) frames.push_back(f);
    } else if (item == "first") {
      frames.push_back(0);
    } else if (item == "middle") {
      frames.push_back(n / 2);
    } else if (item == "last") {
      frames.push_back(n - 1);
    } else {
      size_t used = 0;
      const unsigned long f = std::stoul(item, &used);
      if (used != item.size() || f >= n)
        throw std::invalid_argument(
            fmt::format("--images: '{}' is not a frame of the path's {} (0 … {})", item, n, n - 1));
      frames.push_back(uint32_t(f));
    }
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

// -p technique:name=value, per technique of --technique.
std::vector<Params> techniqueParams(const ViewsCommandOptions& o) {
  std::vector<std::vector<std::string>> assignments(o.techniques.size());
  for (const std::string& assignment : o.params) {
    const size_t colon = assignment.find(':'), eq = assignment.find('=');
    const std::string name = colon < eq ? assignment.substr(0, colon) : "";
    const auto it = std::find(o.techniques.begin(), o.techniques.end(), name);
    if (name.empty() || it == o.techniques.end())
      throw std::invalid_argument(fmt::format(
          "parameter '{}' must name one of --technique as technique:name=value", assignment));
    assignments[size_t(it - o.techniques.begin())].push_back(assignment.substr(colon + 1));
  }
  std::vector<Params> params;
  for (const auto& list : assignments) params.push_back(parseParams(list));
  return params;
}

int runViewsCommand(const ViewsCommandOptions& o) {
  // Everything a user can get wrong is checked before the first frame is traced.
  std::vector<Params> params = techniqueParams(o);
  std::vector<ParamValues> values;
  for (size_t t = 0; t < o.techniques.size(); ++t)
    values.push_back(ParamValues::resolve(o.techniques[t],
                                          findViewTechnique(o.techniques[t]).params, params[t]));
  if (o.filter < 1 || o.filter > 17 || o.filter % 2 == 0)
    throw std::invalid_argument(fmt::format("--filter {} must be odd, 1 … 17", o.filter));
  const Scene scene = openScene(o.map.scene);
  const Light light = sceneLight(scene, o.map.light);
  if (light.kind() != LightKind::Directional)
    throw std::invalid_argument(
        "views: cascaded and irregular adaptive shadow maps are orthographic; the scene's light "
        "must be directional");
  CameraPath path;
  const SceneRays rays(scene);
  if (o.path.empty()) {
    path = makeFlythrough(scene, o.map.scene, rays, o.frames ? o.frames : 24);
  } else {
    path = loadCameraPath(o.path);
    if (o.frames && o.frames < path.frames.size()) path.frames.resize(o.frames);
  }
  const std::string source = o.path.empty() ? "generated path" : o.path;
  checkCamerasOutside(path, scene, rays, source);
  // The ground truth, the boundary mask and one technique's visibility at a time, and the PNG rows.
  checkFrameFits(path, sizeof(glm::vec3) * 2 + sizeof(float) * 2 + 8, source);

  std::vector<std::unique_ptr<Decoder>> decoders;
  std::vector<ViewEntry> entries;
  for (const std::string& file : o.structures) {
    StructureHeader header;
    decoders.push_back(loadStructure(file, &header));
    if (!header.sceneHash.empty() && header.sceneHash != scene.hash())
      throw std::runtime_error(fmt::format(
          "structure '{}' was built from another scene (hash {}), not from '{}' (hash {})", file,
          header.sceneHash, o.map.scene, scene.hash()));
    const uint64_t bytes = totalBytes(decoders.back()->size());
    const nlohmann::json schemeParams(header.params);
    const std::string mode(toString(header.map.mode));
    const std::string suffix = fmt::format("{}² {}", resolutionLabel(header.map.resolution), mode);
    entries.push_back(
        {header.scheme,
         "precomputed",
         viewLabel(header.scheme, header.params, findScheme(header.scheme).params, suffix),
         schemeParams,
         {{"scheme", header.scheme},
          {"params", schemeParams},
          {"mode", mode},
          {"resolution", header.map.resolution},
          {"file", file}},
         makeStructureTechnique(light, *decoders.back(), header.map.resolution, bytes, o.filter,
                                o.offsetTexels)});
  }
  for (size_t t = 0; t < o.techniques.size(); ++t) {
    const ViewTechniqueRow& row = findViewTechnique(o.techniques[t]);
    const nlohmann::json text(values[t].text());
    entries.push_back({row.name, "view-dependent",
                       viewLabel(row.name, values[t].text(), row.params), text, nullptr,
                       row.make(scene, light, values[t])});
  }
  for (size_t a = 0; a < entries.size(); ++a)
    for (size_t b = a + 1; b < entries.size(); ++b)
      if (entries[a].label == entries[b].label)
        throw std::invalid_argument(fmt::format("'{}' is given twice", entries[a].label));

  ViewRunOptions options;
  options.out = o.out.empty() ? fs::path("results/views") / path.name : fs::path(o.out);
  checkWritableFolder(options.out);
  options.imageFrames = pictureFrames(o.images, uint32_t(path.frames.size()));
  options.exr = !o.noExr;
  options.boundaryRadius = o.boundaryRadius;
  options.normalOffset = defaultNormalOffset(scene);
  options.filter = o.filter;

  Progress progress("views", path.frames.size(), "frames");
  const std::vector<nlohmann::json> records =
      runViews({scene, o.map.scene, light}, path, o.path, entries, options,
               [&](uint32_t done) { progress.set(done); });
  progress.finish();
  fmt::print("{} frames of {} ({}×{}), records in {}\n", path.frames.size(), path.name, path.width,
             path.height, options.out.string());
  fmt::print(
      "| technique | error % | false lit | false shadow | boundary error % | memory MiB | "
      "build ms | shade ms |\n|---|---|---|---|---|---|---|---|\n");
  for (const nlohmann::json& r : records) {
    const nlohmann::json& t = r["totals"];
    fmt::print("| {} | {:.3f} | {} | {} | {:.2f} | {:.2f} | {:.1f} | {:.1f} |\n",
               r["technique"]["label"].get<std::string>(), 100 * t["error_rate"].get<double>(),
               t["false_lit"].get<uint64_t>(), t["false_shadow"].get<uint64_t>(),
               100 * t["boundary_error_rate"].get<double>(),
               t["memory_bytes"].get<uint64_t>() / 1048576.0, t["build_ms_median"].get<double>(),
               t["shade_ms_median"].get<double>());
  }
  flushStandardOutput();
  return 0;
}

struct PathCommandOptions {
  MapOptions map;
  std::string output;
  uint32_t frames = 24;
};

}  // namespace

void addViewsCommand(CLI::App& app) {
  auto o = std::make_shared<ViewsCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "views", "score shadow techniques on a camera path against ray-traced ground truth");
  o->map.addTo(sub, false);
  sub->add_option(
      "--path", o->path,
      "camera path file (scenes/paths/*.json); none: the scene's generated fly-through");
  sub->add_option("--frames", o->frames, "use the first N frames (a generated path: N frames)");
  sub->add_option("--technique,-t", o->techniques, "view-dependent techniques: csm, iasm")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option("--param,-p", o->params, "technique:name=value (repeatable)");
  sub->add_option("--structure", o->structures, "saved structure (build -o) to score as well")
      ->delimiter(',');
  sub->add_option("--filter", o->filter, "k of the structures' k×k lookups")->capture_default_str();
  sub->add_option("--offset-texels", o->offsetTexels,
                  "normal offset of structure lookups, in texels of the structure")
      ->capture_default_str();
  sub->add_option("--boundary-radius", o->boundaryRadius,
                  "pixels around a true shadow edge that count as near the boundary")
      ->capture_default_str();
  sub->add_option("--images", o->images,
                  "frames pictured: first,middle,last, all, none, or numbers")
      ->capture_default_str();
  sub->add_flag("--no-exr", o->noExr, "PNG pictures only");
  sub->add_option("--out,-o", o->out, "records folder (default results/views/<path name>)");
  sub->callback([o] { setExitStatus(runViewsCommand(*o)); });

  auto p = std::make_shared<PathCommandOptions>();
  CLI::App* pathSub = app.add_subcommand(
      "path", "write the scene's deterministic camera fly-through as a path file");
  p->map.addTo(pathSub, false);
  pathSub->add_option("--frames", p->frames, "frames")->capture_default_str();
  pathSub->add_option("--output,-o", p->output, "path file")->required();
  pathSub->callback([p] {
    const Scene scene = openScene(p->map.scene);
    const SceneRays rays(scene);
    if (p->frames == 0) throw std::invalid_argument("--frames must be at least 1");
    checkOutputFile(p->output, {});
    saveCameraPath(makeFlythrough(scene, p->map.scene, rays, p->frames), p->output);
    fmt::print("wrote {}\n", p->output);
  });
}

}  // namespace sb::cli
