// shadowbench — one CLI for building, verifying, querying, sweeping, benchmarking and tabulating
// compressed shadow-map schemes (DESIGN §6).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "harness/cell.h"
#include "harness/distant_filters.h"
#include "harness/lookup_timing.h"
#include "harness/many_lights.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "harness/scene_export.h"
#include "harness/table.h"
#include "schemes/interface/serial.h"

namespace sb {
void addSoakCommand(CLI::App& app);
}

namespace fs = std::filesystem;
using namespace sb;

namespace {

// Options shared by the subcommands that need a scene, light, mode and resolution.
struct MapOptions {
  std::string scene = "city";
  uint32_t light = 0;
  std::string mode = "closed";
  std::string resolution = "1K";
  uint32_t tile = 0;

  void addTo(CLI::App* app, bool withMapShape = true) {
    app->add_option("--scene,-s", scene,
                    "generator (city, terrain, forest, tangle; ':full' or "
                    "':size=N,seed=S'), scene .json or model file")
        ->capture_default_str();
    app->add_option("--light,-l", light, "index of the scene's light")->capture_default_str();
    if (!withMapShape) return;
    app->add_option("--mode,-m", mode, "dual depth mode: open, closed or static")
        ->capture_default_str();
    app->add_option("--resolution,-r", resolution, "texels per side: 512, 4K, 64K, …")
        ->capture_default_str();
    app->add_option("--tile", tile, "tile size streamed to the encoder (default min(R, 512))");
  }
};

Params parseParams(const std::vector<std::string>& assignments) {
  Params params;
  for (const std::string& a : assignments) {
    const size_t eq = a.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument(fmt::format("parameter '{}' must be written name=value", a));
    params[a.substr(0, eq)] = a.substr(eq + 1);
  }
  return params;
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

void printVerification(const nlohmann::json& v) {
  fmt::print("verification ({}): {} queries, {} mismatches\n", v["method"].get<std::string>(),
             v["queries"].get<uint64_t>(), v["mismatches"].get<uint64_t>());
  for (const auto& m : v["examples"])
    fmt::print("  mismatch at x={} y={} z={} k={}: got {}, expected [{}, {}]\n",
               m["x"].get<float>(), m["y"].get<float>(), m["z"].get<float>(), m["k"].get<int>(),
               m["got"].get<float>(), m["expected"][0].get<float>(), m["expected"][1].get<float>());
}

void printCellSummary(const nlohmann::json& r) {
  fmt::print(
      "{} on {} ({}, {}²): {:.3f} MiB in {:.2f} s (depth {:.1f} Mtexels/s, peak RSS {:.0f} MiB)\n",
      r["scheme"]["name"].get<std::string>(), r["scene"]["name"].get<std::string>(),
      r["mode"].get<std::string>(), r["resolution"].get<uint32_t>(),
      r["size_bytes"]["total"].get<double>() / (1 << 20), r["time_s"]["total"].get<double>(),
      r["depth"]["mtexels_per_s"].get<double>(),
      r["memory"]["peak_rss_bytes"].get<double>() / (1 << 20));
  if (r.contains("verification")) printVerification(r["verification"]);
  if (r.contains("lookup"))
    for (const auto& t : r["lookup"])
      fmt::print(
          "  lookup {:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} "
          "threads)\n",
          t["query_set"].get<std::string>(), t["filter"].get<int>(), t["filter"].get<int>(),
          t["ns_per_query_1t"].get<double>(), t["mqueries_per_s_all"].get<double>(),
          t["threads"].get<int>());
}

bool hasMismatches(const nlohmann::json& record) {
  return record.contains("verification") &&
         record["verification"]["mismatches"].get<uint64_t>() > 0;
}

int listSchemes() {
  for (const SchemeInfo& s : schemes()) {
    fmt::print("{:12} {} scheme — {}\n", s.name, toString(s.kind), s.paper);
    for (const ParamSpec& p : s.params)
      fmt::print("    {}={} ({}{}) {}\n", p.name, p.defaultValue,
                 p.choices.empty() ? fmt::format("{}…{}", p.min, p.max)
                                   : fmt::format("{}", fmt::join(p.choices, "|")),
                 p.sweep.empty() ? "" : fmt::format("; sweep {}", fmt::join(p.sweep, ",")), p.help);
  }
  return 0;
}

// The options of every subcommand; each subcommand's callback reads its own part.
struct Options {
  MapOptions map;
  std::string output, exr, scheme = "sm32", results = "results/builds", structure;
  std::vector<std::string> params;
  bool rayCast = false, noVerify = false, noBench = false;
  uint64_t sampledQueries = 10'000'000;
  std::string sweepScenes = "city", sweepModes = "closed", sweepSchemes = "all";
  std::string sweepResolutions = "1K,2K,4K,8K", sweepOut = "results/sweep";
  std::string records = "results/sweep", tableOut;
};

int sceneList() {
  for (const GeneratorInfo& g : sceneGenerators())
    fmt::print("{:8} default size {}, full size {} — {}\n", g.name, g.defaultSize, g.fullSize,
               g.description);
  return 0;
}

int sceneInfo(const Options& o) {
  const Scene scene = openScene(o.map.scene);
  const Bounds b = scene.bounds();
  fmt::print("scene {}: {} triangles in {} meshes, hash {}\n", scene.name, scene.triangleCount(),
             scene.meshes.size(), scene.hash());
  fmt::print("bounds ({}, {}, {}) – ({}, {}, {})\n", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y,
             b.max.z);
  for (const Mesh& m : scene.meshes)
    fmt::print("  {:24} {:6} {:>10} triangles\n", m.name, m.closed ? "closed" : "open",
               m.triangles.size());
  for (size_t i = 0; i < scene.lights.size(); ++i)
    fmt::print("  light {}: {}\n", i, sceneLight(scene, uint32_t(i)).describe().dump());
  return 0;
}

int sceneExport(const Options& o) {
  const Scene scene = openScene(o.map.scene);
  std::ofstream out(o.output);
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", o.output));
  exportLightSpaceObj(scene, sceneLight(scene, o.map.light), out);
  fmt::print("wrote {} ({} triangles in light space)\n", o.output, scene.triangleCount());
  return 0;
}

int depth(const Options& o) {
  const Scene scene = openScene(o.map.scene);
  const uint32_t r = parseResolution(o.map.resolution);
  const DepthSource source(scene, sceneLight(scene, o.map.light), depthModeFromString(o.map.mode),
                           r, o.rayCast ? DepthMethod::RayCast : DepthMethod::Rasterize);
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
  return 0;
}

int build(const Options& o) {
  const Scene scene = openScene(o.map.scene);
  const CellSpec cell{o.map.scene, o.map.light,           depthModeFromString(o.map.mode),
                      o.scheme,    parseParams(o.params), parseResolution(o.map.resolution),
                      o.map.tile};
  CellOptions options;
  options.verify = !o.noVerify;
  options.benchLookups = !o.noBench;
  options.verifyOptions.sampledQueries = o.sampledQueries;
  if (!o.output.empty()) options.saveStructureTo = o.output;
  const nlohmann::json record = runCell(cell, scene, options);
  const fs::path recordPath = fs::path(o.results) / (cellKey(record) + ".json");
  writeJsonAtomically(recordPath, record);
  printCellSummary(record);
  fmt::print("record: {}\n", recordPath.string());
  return hasMismatches(record) ? 1 : 0;
}

// A saved structure with the scene it was built for: the reference re-traced for `verify`,
// view samples for `bench`.
struct LoadedStructure {
  StructureHeader header;
  std::unique_ptr<Decoder> decoder;
  Scene scene;
  std::unique_ptr<DepthSource> source;

  explicit LoadedStructure(const Options& o)
      : decoder(loadStructure(o.structure, &header)), scene(openScene(o.map.scene)) {
    source = std::make_unique<DepthSource>(scene, sceneLight(scene, o.map.light), header.map.mode,
                                           header.map.resolution);
  }
};

int verifyStructure(const Options& o) {
  const LoadedStructure loaded(o);
  VerifyOptions options;
  options.sampledQueries = o.sampledQueries;
  Progress progress("verify", 0, "queries");
  const VerifyReport report =
      verify(*loaded.decoder, findScheme(loaded.header.scheme).kind, loaded.header.map,
             *loaded.source, options, [&](uint64_t done) { progress.set(done); });
  progress.finish();
  printVerification(report.toJson());
  return report.mismatches ? 1 : 0;
}

int benchStructure(const Options& o) {
  const LoadedStructure loaded(o);
  const QuerySet sets[] = {uniformQueries(1 << 22, 7),
                           viewSamples(loaded.scene, *loaded.source, 1920, 1080, 2)};
  for (const QuerySet& set : sets)
    for (int k : {1, 3, 5, 9, 17}) {
      const LookupTiming t = timeLookups(*loaded.decoder, set, k);
      fmt::print("{:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} threads)\n",
                 t.querySet, k, k, t.nsPerQuerySingleThread, t.mqueriesPerSecondAllThreads,
                 t.threads);
    }
  return 0;
}

int query(const Options& o) {
  const auto decoder = loadStructure(o.structure, nullptr);
  std::string line;
  for (uint64_t number = 1; std::getline(std::cin, line); ++number) {
    std::istringstream in(line);
    Query q{};
    int k = 1;
    if (!(in >> q.x >> q.y >> q.z)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      throw std::invalid_argument(
          fmt::format("query line {}: expected 'x y z [k]', got '{}'", number, line));
    }
    in >> k;
    float visibility = 0;
    decoder->lookup(std::span(&q, 1), k, std::span(&visibility, 1));
    fmt::print("{}\n", visibility);
  }
  return 0;
}

// The --param assignments that `scheme` declares. A sweep's parameters go only to the schemes
// that have them, so one sweep can set a parameter of one scheme (culling=off) beside others.
Params declaredParams(const SchemeInfo& scheme, const Params& given) {
  Params own;
  for (const ParamSpec& spec : scheme.params)
    if (const auto it = given.find(spec.name); it != given.end()) own.insert(*it);
  return own;
}

int sweep(const Options& o) {
  std::vector<std::string> schemeNames = splitList(o.sweepSchemes);
  if (o.sweepSchemes == "all") {
    schemeNames.clear();
    for (const SchemeInfo& s : schemes()) schemeNames.push_back(s.name);
  }
  // Checked before the first build: a misspelt name or a bad value is an error, not a sweep of
  // default cells or of failed ones.
  const Params params = parseParams(o.params);
  std::set<std::string> declared;
  for (const std::string& name : schemeNames) {
    const SchemeInfo& scheme = findScheme(name);
    scheme.resolve(declaredParams(scheme, params));  // throws on a bad value
    for (const ParamSpec& spec : scheme.params) declared.insert(spec.name);
  }
  for (const auto& [name, value] : params)
    if (!declared.count(name))
      throw std::invalid_argument(
          fmt::format("no swept scheme has a parameter '{}' (see 'shadowbench schemes')", name));
  CellOptions options;
  options.benchLookups = !o.noBench;
  options.verifyOptions.sampledQueries = o.sampledQueries;
  size_t done = 0, skipped = 0, failed = 0;
  for (const std::string& spec : splitList(o.sweepScenes)) {
    const Scene scene = openScene(spec);
    for (const std::string& mode : splitList(o.sweepModes))
      for (const std::string& name : schemeNames) {
        const Params own = declaredParams(findScheme(name), params);
        for (const std::string& res : splitList(o.sweepResolutions)) {
          const CellSpec cell{spec, 0, depthModeFromString(mode), name, own, parseResolution(res),
                              0};
          const fs::path path =
              fs::path(o.sweepOut) / (cellKey(cellIdentity(cell, scene)) + ".json");
          if (readRecord(path)) {
            ++skipped;
            continue;
          }
          try {
            const nlohmann::json record = runCell(cell, scene, options);
            writeJsonAtomically(path, record);
            printCellSummary(record);
            failed += hasMismatches(record);
            ++done;
          } catch (const std::exception& error) {
            // One cell that cannot be built (e.g. too large for memory) does not stop the sweep.
            fmt::print(stderr, "cell {} skipped: {}\n", path.filename().string(), error.what());
            ++failed;
          }
        }
      }
  }
  fmt::print("sweep: {} cells built, {} already done, {} failed or mismatched\n", done, skipped,
             failed);
  const auto tables = makeTables(readRecords(o.sweepOut).records);
  writeTables(tables, fs::path(o.sweepOut) / "tables");
  fmt::print("{}", toMarkdown(tables));
  return failed ? 1 : 0;
}

int table(const Options& o) {
  const auto loaded = readRecords(o.records);
  if (loaded.records.empty())
    throw std::runtime_error(fmt::format("no complete records under '{}'", o.records));
  const auto tables = makeTables(loaded.records);
  writeTables(tables, o.tableOut.empty() ? fs::path(o.records) / "tables" : fs::path(o.tableOut));
  fmt::print("{}", toMarkdown(tables));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"shadowbench: build, verify and measure compressed precomputed shadow maps"};
  app.require_subcommand(1);
  Options o;
  int status = 0;
  // Each subcommand runs its function as its callback; the status is the process's exit code.
  auto command = [&](CLI::App* parent, const char* name, const char* help, auto run) {
    CLI::App* sub = parent->add_subcommand(name, help);
    sub->callback([&status, run] { status = run(); });
    return sub;
  };

  command(&app, "schemes", "list registered schemes and their parameters",
          [] { return listSchemes(); });

  CLI::App* scene = app.add_subcommand("scene", "inspect and export scenes");
  scene->require_subcommand(1);
  command(scene, "list", "list the procedural generators", [] { return sceneList(); });
  o.map.addTo(command(scene, "info", "triangles, meshes, closedness, bounds, lights, hash",
                      [&] { return sceneInfo(o); }),
              false);
  CLI::App* exporter = command(scene, "export", "write the scene in light space as OBJ",
                               [&] { return sceneExport(o); });
  o.map.addTo(exporter, false);
  exporter->add_option("--output,-o", o.output, "OBJ file to write")->required();

  CLI::App* depthCmd = command(&app, "depth", "stream the dual depth map and report its throughput",
                               [&] { return depth(o); });
  o.map.addTo(depthCmd);
  depthCmd->add_option("--exr", o.exr, "also write lo/hi as a float EXR (R ≤ 16K)");
  depthCmd->add_flag("--raycast", o.rayCast,
                     "ray cast with Embree instead of rasterising (directional lights)");

  auto sampled = [&](CLI::App* sub) {
    sub->add_option("--sampled-queries", o.sampledQueries, "queries checked above 2K²")
        ->capture_default_str();
  };
  CLI::App* buildCmd =
      command(&app, "build", "build a scheme for a scene, verify it, time lookups, record it",
              [&] { return build(o); });
  o.map.addTo(buildCmd);
  buildCmd->add_option("--scheme", o.scheme, "scheme name (see 'shadowbench schemes')")
      ->capture_default_str();
  buildCmd->add_option("--param,-p", o.params, "scheme parameter name=value (repeatable)");
  buildCmd->add_option("--output,-o", o.output, "save the structure to this file");
  buildCmd->add_option("--results", o.results, "folder for the JSON record")->capture_default_str();
  buildCmd->add_flag("--no-verify", o.noVerify, "skip the check against the reference");
  buildCmd->add_flag("--no-bench", o.noBench, "skip lookup timings");
  sampled(buildCmd);

  CLI::App* verifyCmd = command(&app, "verify", "check a saved structure against the reference",
                                [&] { return verifyStructure(o); });
  o.map.addTo(verifyCmd, false);
  verifyCmd->add_option("structure", o.structure, "structure file")->required();
  sampled(verifyCmd);

  command(&app, "query", "answer 'x y z [k]' lines from stdin with a saved structure",
          [&] { return query(o); })
      ->add_option("structure", o.structure, "structure file")
      ->required();

  CLI::App* benchCmd = command(&app, "bench", "time lookups of a saved structure",
                               [&] { return benchStructure(o); });
  o.map.addTo(benchCmd, false);
  benchCmd->add_option("structure", o.structure, "structure file")->required();

  CLI::App* sweepCmd =
      command(&app, "sweep", "build every cell of a matrix, resuming finished cells",
              [&] { return sweep(o); });
  sweepCmd->add_option("--scenes", o.sweepScenes, "comma-separated scene specs")
      ->capture_default_str();
  sweepCmd->add_option("--modes", o.sweepModes, "comma-separated modes")->capture_default_str();
  sweepCmd->add_option("--schemes", o.sweepSchemes, "comma-separated schemes, or all")
      ->capture_default_str();
  sweepCmd->add_option("--resolutions", o.sweepResolutions, "comma-separated resolutions")
      ->capture_default_str();
  sweepCmd->add_option("--param,-p", o.params,
                       "scheme parameter name=value for the swept schemes that declare it "
                       "(repeatable); it names the cells' records");
  sweepCmd->add_option("--out", o.sweepOut, "records folder (finished cells there are skipped)")
      ->capture_default_str();
  sweepCmd->add_flag("--no-bench", o.noBench, "skip lookup timings");
  sampled(sweepCmd);

  CLI::App* tableCmd = command(&app, "table", "regenerate Markdown and CSV tables from records",
                               [&] { return table(o); });
  tableCmd->add_option("records", o.records, "records folder")->capture_default_str();
  tableCmd->add_option("--out", o.tableOut,
                       "folder for tables.md and CSVs (default RECORDS/tables)");

  addManyLightsCommand(app);
  addDistantFiltersCommand(app);
  addSoakCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const std::exception& error) {
    fmt::print(stderr, "shadowbench: {}\n", error.what());
    return 2;
  }
  return status;
}
