// shadowbench — one CLI for building, verifying, querying, sweeping, benchmarking and tabulating
// compressed shadow-map schemes (DESIGN §6).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "harness/cell.h"
#include "harness/lookup_timing.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "harness/scene_export.h"
#include "harness/table.h"
#include "schemes/interface/serial.h"

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"shadowbench: build, verify and measure compressed precomputed shadow maps"};
  app.require_subcommand(1);

  auto* schemesCmd = app.add_subcommand("schemes", "list registered schemes and their parameters");

  auto* sceneCmd = app.add_subcommand("scene", "inspect and export scenes");
  sceneCmd->require_subcommand(1);
  auto* sceneList = sceneCmd->add_subcommand("list", "list the procedural generators");
  MapOptions sceneMap;
  auto* sceneInfo =
      sceneCmd->add_subcommand("info", "triangles, meshes, closedness, bounds, lights, hash");
  sceneMap.addTo(sceneInfo, false);
  auto* sceneExport = sceneCmd->add_subcommand("export", "write the scene in light space as OBJ");
  sceneMap.addTo(sceneExport, false);
  std::string exportPath;
  sceneExport->add_option("--output,-o", exportPath, "OBJ file to write")->required();

  MapOptions depthMap;
  auto* depthCmd =
      app.add_subcommand("depth", "stream the dual depth map and report its throughput");
  depthMap.addTo(depthCmd);
  std::string exrPath;
  bool rayCast = false;
  depthCmd->add_option("--exr", exrPath, "also write lo/hi as a float EXR (R ≤ 16K)");
  depthCmd->add_flag("--raycast", rayCast, "ray cast with Embree instead of rasterising (directional lights)");

  MapOptions buildMap;
  auto* buildCmd =
      app.add_subcommand("build", "build a scheme for a scene, verify it, time lookups, record it");
  buildMap.addTo(buildCmd);
  std::string schemeName = "sm32", outputPath, resultsDir = "results/builds";
  std::vector<std::string> paramList;
  bool noVerify = false, noBench = false;
  uint64_t sampled = 10'000'000;
  buildCmd->add_option("--scheme", schemeName, "scheme name (see 'shadowbench schemes')")
      ->capture_default_str();
  buildCmd->add_option("--param,-p", paramList, "scheme parameter name=value (repeatable)");
  buildCmd->add_option("--output,-o", outputPath, "save the structure to this file");
  buildCmd->add_option("--results", resultsDir, "folder for the JSON record")
      ->capture_default_str();
  buildCmd->add_flag("--no-verify", noVerify, "skip the check against the reference");
  buildCmd->add_flag("--no-bench", noBench, "skip lookup timings");
  buildCmd->add_option("--sampled-queries", sampled, "queries checked above 2K²")
      ->capture_default_str();

  MapOptions verifyMap;
  auto* verifyCmd = app.add_subcommand("verify", "check a saved structure against the reference");
  verifyMap.addTo(verifyCmd, false);
  std::string structurePath;
  verifyCmd->add_option("structure", structurePath, "structure file")->required();
  verifyCmd->add_option("--sampled-queries", sampled, "queries checked above 2K²")
      ->capture_default_str();

  auto* queryCmd =
      app.add_subcommand("query", "answer 'x y z [k]' lines from stdin with a saved structure");
  std::string queryStructure;
  queryCmd->add_option("structure", queryStructure, "structure file")->required();

  MapOptions benchMap;
  auto* benchCmd = app.add_subcommand("bench", "time lookups of a saved structure");
  benchMap.addTo(benchCmd, false);
  std::string benchStructure;
  benchCmd->add_option("structure", benchStructure, "structure file")->required();

  auto* sweepCmd =
      app.add_subcommand("sweep", "build every cell of a matrix, resuming finished cells");
  std::string sweepScenes = "city", sweepModes = "closed", sweepSchemes = "all",
              sweepResolutions = "1K,2K,4K,8K";
  std::string sweepOut = "results/sweep";
  bool sweepNoBench = false;
  sweepCmd->add_option("--scenes", sweepScenes, "comma-separated scene specs")
      ->capture_default_str();
  sweepCmd->add_option("--modes", sweepModes, "comma-separated modes")->capture_default_str();
  sweepCmd->add_option("--schemes", sweepSchemes, "comma-separated schemes, or all")
      ->capture_default_str();
  sweepCmd->add_option("--resolutions", sweepResolutions, "comma-separated resolutions")
      ->capture_default_str();
  sweepCmd->add_option("--out", sweepOut, "records folder (finished cells there are skipped)")
      ->capture_default_str();
  sweepCmd->add_option("--sampled-queries", sampled, "queries checked above 2K²")
      ->capture_default_str();
  sweepCmd->add_flag("--no-bench", sweepNoBench, "skip lookup timings");

  auto* tableCmd = app.add_subcommand("table", "regenerate Markdown and CSV tables from records");
  std::string tableIn = "results/sweep", tableOut;
  tableCmd->add_option("records", tableIn, "records folder")->capture_default_str();
  tableCmd->add_option("--out", tableOut, "folder for tables.md and CSVs (default RECORDS/tables)");

  CLI11_PARSE(app, argc, argv);

  try {
    if (*schemesCmd) return listSchemes();

    if (*sceneList) {
      for (const GeneratorInfo& g : sceneGenerators())
        fmt::print("{:8} default size {}, full size {} — {}\n", g.name, g.defaultSize, g.fullSize,
                   g.description);
      return 0;
    }
    if (*sceneInfo) {
      const Scene scene = openScene(sceneMap.scene);
      const Bounds b = scene.bounds();
      fmt::print("scene {}: {} triangles in {} meshes, hash {}\n", scene.name,
                 scene.triangleCount(), scene.meshes.size(), scene.hash());
      fmt::print("bounds ({}, {}, {}) – ({}, {}, {})\n", b.min.x, b.min.y, b.min.z, b.max.x,
                 b.max.y, b.max.z);
      for (const Mesh& m : scene.meshes)
        fmt::print("  {:24} {:6} {:>10} triangles\n", m.name, m.closed ? "closed" : "open",
                   m.triangles.size());
      for (size_t i = 0; i < scene.lights.size(); ++i)
        fmt::print("  light {}: {}\n", i, sceneLight(scene, uint32_t(i)).describe().dump());
      return 0;
    }
    if (*sceneExport) {
      const Scene scene = openScene(sceneMap.scene);
      std::ofstream out(exportPath);
      if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", exportPath));
      exportLightSpaceObj(scene, sceneLight(scene, sceneMap.light), out);
      fmt::print("wrote {} ({} triangles in light space)\n", exportPath, scene.triangleCount());
      return 0;
    }

    if (*depthCmd) {
      const Scene scene = openScene(depthMap.scene);
      const uint32_t r = parseResolution(depthMap.resolution);
      const DepthSource source(scene, sceneLight(scene, depthMap.light),
                               depthModeFromString(depthMap.mode), r,
                               rayCast ? DepthMethod::RayCast : DepthMethod::Rasterize);
      Progress progress("depth", uint64_t(r) * r, "texels");
      const StreamStats stats = streamDualDepth(
          source, depthMap.tile ? depthMap.tile : defaultTileSize(r), [](const DualDepthTile&) {},
          [&](uint64_t d) { progress.set(d); });
      progress.finish();
      fmt::print(
          "{} {} {}² ({}): {:.3f} s, {:.1f} Mtexels/s ({:.3f} thread-s tracing), {} closed fallbacks\n",
          scene.name, depthMap.mode, r, toString(source.method()), stats.wallSeconds, double(r) * r / stats.wallSeconds * 1e-6,
          stats.traceThreadSeconds, source.closedFallbacks());
      if (!exrPath.empty()) {
        writeDualDepthExr(source, exrPath);
        fmt::print("wrote {}\n", exrPath);
      }
      return 0;
    }

    if (*buildCmd) {
      const Scene scene = openScene(buildMap.scene);
      CellSpec cell{buildMap.scene, buildMap.light,         depthModeFromString(buildMap.mode),
                    schemeName,     parseParams(paramList), parseResolution(buildMap.resolution),
                    buildMap.tile};
      CellOptions options;
      options.verify = !noVerify;
      options.benchLookups = !noBench;
      options.verifyOptions.sampledQueries = sampled;
      if (!outputPath.empty()) options.saveStructureTo = outputPath;
      const nlohmann::json record = runCell(cell, scene, options);
      const fs::path recordPath = fs::path(resultsDir) / (cellKey(record) + ".json");
      writeJsonAtomically(recordPath, record);
      printCellSummary(record);
      fmt::print("record: {}\n", recordPath.string());
      return hasMismatches(record) ? 1 : 0;
    }

    if (*verifyCmd || *benchCmd) {
      MapOptions& map = *verifyCmd ? verifyMap : benchMap;
      StructureHeader header;
      const auto decoder = loadStructure(*verifyCmd ? structurePath : benchStructure, &header);
      const Scene scene = openScene(map.scene);
      const DepthSource source(scene, sceneLight(scene, map.light), header.map.mode,
                               header.map.resolution);
      if (*benchCmd) {
        const QuerySet sets[] = {uniformQueries(1 << 22, 7),
                                 viewSamples(scene, source, 1920, 1080, 2)};
        for (const QuerySet& set : sets)
          for (int k : {1, 3, 5, 9, 17}) {
            const LookupTiming t = timeLookups(*decoder, set, k);
            fmt::print(
                "{:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} threads)\n",
                t.querySet, k, k, t.nsPerQuerySingleThread, t.mqueriesPerSecondAllThreads,
                t.threads);
          }
        return 0;
      }
      VerifyOptions options;
      options.sampledQueries = sampled;
      const SchemeInfo& scheme = findScheme(header.scheme);
      Progress progress("verify", 0, "queries");
      const VerifyReport report = verify(*decoder, scheme.kind, header.map, source, options,
                                         [&](uint64_t d) { progress.set(d); });
      progress.finish();
      printVerification(report.toJson());
      return report.mismatches ? 1 : 0;
    }

    if (*queryCmd) {
      const auto decoder = loadStructure(queryStructure, nullptr);
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

    if (*sweepCmd) {
      std::vector<std::string> schemeNames = splitList(sweepSchemes);
      if (sweepSchemes == "all") {
        schemeNames.clear();
        for (const SchemeInfo& s : schemes()) schemeNames.push_back(s.name);
      }
      CellOptions options;
      options.benchLookups = !sweepNoBench;
      options.verifyOptions.sampledQueries = sampled;
      size_t done = 0, skipped = 0, failed = 0;
      for (const std::string& spec : splitList(sweepScenes)) {
        const Scene scene = openScene(spec);
        for (const std::string& mode : splitList(sweepModes))
          for (const std::string& name : schemeNames)
            for (const std::string& res : splitList(sweepResolutions)) {
              const CellSpec cell{
                  spec, 0, depthModeFromString(mode), name, {}, parseResolution(res), 0};
              const fs::path path =
                  fs::path(sweepOut) / (cellKey(cellIdentity(cell, scene)) + ".json");
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
                // One cell that cannot be built (e.g. too large for memory) does not stop the
                // sweep.
                fmt::print(stderr, "cell {} skipped: {}\n", path.filename().string(), error.what());
                ++failed;
              }
            }
      }
      fmt::print("sweep: {} cells built, {} already done, {} failed or mismatched\n", done, skipped,
                 failed);
      const auto tables = makeTables(readRecords(sweepOut).records);
      writeTables(tables, fs::path(sweepOut) / "tables");
      fmt::print("{}", toMarkdown(tables));
      return failed ? 1 : 0;
    }

    if (*tableCmd) {
      const auto loaded = readRecords(tableIn);
      if (loaded.records.empty())
        throw std::runtime_error(fmt::format("no complete records under '{}'", tableIn));
      const auto tables = makeTables(loaded.records);
      writeTables(tables, tableOut.empty() ? fs::path(tableIn) / "tables" : fs::path(tableOut));
      fmt::print("{}", toMarkdown(tables));
      return 0;
    }
  } catch (const std::exception& error) {
    fmt::print(stderr, "shadowbench: {}\n", error.what());
    return 2;
  }
  return 0;
}
