// `shadowbench soak`: the soak test (harness/soak.h) of a saved structure or of one built in
// memory, resumable through a state file; exit status 1 on any mismatch.
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "harness/build.h"
#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/progress.h"
#include "harness/record.h"
#include "harness/soak.h"
#include "schemes/interface/serial.h"

namespace sb::cli {

namespace {

struct SoakCommandOptions {
  std::string structure, scene = "city", scheme, mode = "closed", resolution = "1K";
  std::vector<std::string> params;
  uint32_t light = 0, tile = 0;
  ThreadOptions threads;
  uint64_t seed = 1;
  double queries = 1e9;
  std::string state, json;
};

// The structure file's own checksum (its last 8 bytes, XXH3-64 of all before: serial.h), which
// loadStructure has validated: the file's identity without hashing gigabytes again.
std::string structureChecksum(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t checksum = 0;
  in.seekg(-int64_t(sizeof checksum), std::ios::end);
  in.read(reinterpret_cast<char*>(&checksum), sizeof checksum);
  if (!in) throw std::runtime_error(fmt::format("cannot read the checksum of '{}'", path));
  return fmt::format("{:016x}", checksum);
}

// The scheme, map and identity of what is soaked, known before any work.
struct Subject {
  const SchemeInfo* scheme = nullptr;
  MapInfo map;
  ParamValues params;
  nlohmann::json identity;
  std::unique_ptr<Decoder> decoder;  // loaded now from a file, built later otherwise
};

Subject subjectOf(const SoakCommandOptions& o, const Scene& scene) {
  Subject s;
  nlohmann::json params = nlohmann::json::object();
  if (!o.structure.empty()) {
    StructureHeader header;
    s.decoder = loadStructure(o.structure, &header);
    s.scheme = &findScheme(header.scheme);
    s.map = header.map;
    s.params = s.scheme->resolve(header.params);
    for (const auto& [name, value] : s.params.text()) params[name] = value;
    s.identity = {{"file_checksum", structureChecksum(o.structure)}};
  } else {
    if (o.scheme.empty())
      throw std::invalid_argument("give a structure file, or --scheme to build one in memory");
    s.scheme = &findScheme(o.scheme);
    s.params = s.scheme->resolve(parseParams(o.params));
    s.map = mapFor(*s.scheme, depthModeFromString(o.mode), parseResolution(o.resolution));
    for (const auto& [name, value] : s.params.text()) params[name] = value;
    s.identity = {{"built_with_tile_size", defaultTileSize(s.map.resolution)}};
    checkBuildFits(*s.scheme, s.map, s.params, BuildShape{defaultTileSize(s.map.resolution)});
  }
  s.identity["scheme"] = s.scheme->name;
  s.identity["params"] = params;
  s.identity["scene_hash"] = scene.hash();
  s.identity["light"] = o.light;
  return s;
}

void printReport(const SoakState& state, const std::string& label) {
  const VerifyReport& r = state.report;
  fmt::print("soak {}: {} queries in {} ({}), {} mismatches\n", label, r.queries,
             formatDuration(state.seconds),
             formatSi(double(r.queries) / state.seconds, "queries/s"), r.mismatches);
  for (const Mismatch& m : r.examples)
    fmt::print("  mismatch at x={} y={} z={} k={}: got {}, expected [{}, {}]\n", m.query.x,
               m.query.y, m.query.z, m.k, m.got, m.expected.min, m.expected.max);
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw std::runtime_error("cannot write the soak report to standard output");
}

void runSoak(const SoakCommandOptions& o) {
  if (!(o.queries >= 1 && o.queries <= 0x1p62))
    throw std::invalid_argument(fmt::format("--queries {} must be from 1 to 2^62", o.queries));
  const auto threadLimit = o.threads.apply();
  const Scene scene = openScene(o.scene);
  const Light light = sceneLight(scene, o.light);
  Subject subject = subjectOf(o, scene);
  const MapInfo& map = subject.map;

  SoakOptions options;
  options.seed = o.seed;
  options.tileSize = o.tile ? o.tile : defaultTileSize(map.resolution);
  const uint64_t tiles =
      uint64_t(map.resolution / options.tileSize) * (map.resolution / options.tileSize);
  options.queriesPerTile = (uint64_t(o.queries) + tiles - 1) / tiles;
  SoakState state = newSoakState(subject.identity, map, options);
  if (!o.state.empty() && std::filesystem::exists(o.state)) {
    std::ifstream in(o.state);
    nlohmann::json saved;
    try {
      in >> saved;
    } catch (const nlohmann::json::exception& error) {
      throw std::runtime_error(
          fmt::format("soak state '{}' is not JSON: {}", o.state, error.what()));
    }
    try {
      state = resumeSoakState(saved, state);
    } catch (const std::exception& error) {
      throw std::runtime_error(fmt::format("'{}': {}", o.state, error.what()));
    }
  }
  const std::string label = fmt::format("{} {} {} {}", subject.scheme->name, scene.name,
                                        toString(map.mode), resolutionLabel(map.resolution));
  if (!state.finished()) {
    const DepthSource source(scene, light, map.mode, map.resolution);
    if (!subject.decoder) {
      Progress building("build " + label, map.texelCount(), "texels");
      subject.decoder = buildStructure(source, *subject.scheme, subject.params,
                                       BuildShape{defaultTileSize(map.resolution)},
                                       [&](uint64_t done) { building.set(done); })
                            .decoder;
    }
    const uint64_t queriesBefore = state.report.queries;
    Progress progress("soak " + label,
                      (state.tilesTotal - state.tilesDone) *
                          ((options.queriesPerTile + kSoakBatchQueries - 1) / kSoakBatchQueries) *
                          kSoakBatchQueries,
                      "queries");
    soak(*subject.decoder, subject.scheme->kind, map, source, options, state,
         [&](const SoakState& now) {
           if (!o.state.empty()) writeJsonAtomically(o.state, now.toJson());
           progress.set(now.report.queries - queriesBefore);
         });
    progress.finish();
  }
  printReport(state, label);
  if (!o.json.empty()) {
    nlohmann::json summary = state.toJson();
    summary["scene"] = o.scene;
    summary["queries_per_second"] = double(state.report.queries) / state.seconds;
    writeJsonAtomically(o.json, summary);
  }
  if (state.report.mismatches) throw CLI::RuntimeError(1);
}

}  // namespace

void addSoakCommand(CLI::App& app) {
  auto o = std::make_shared<SoakCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "soak",
      "check ~1e9 random and boundary queries (points and PCF) of a structure against the "
      "reference, tile by tile; resumable with --state");
  CLI::Option* structure =
      sub->add_option("structure", o->structure, "structure file (or build one with --scheme)");
  sub->add_option("--scene,-s", o->scene, "generator, scene .json or model file")
      ->capture_default_str();
  sub->add_option("--light,-l", o->light, "index of the scene's light")->capture_default_str();
  for (CLI::Option* buildOnly :
       {sub->add_option("--scheme", o->scheme, "build this scheme in memory instead of loading"),
        sub->add_option("--param,-p", o->params, "scheme parameter name=value (repeatable)"),
        sub->add_option("--mode,-m", o->mode, "dual depth mode of the build")
            ->capture_default_str(),
        sub->add_option("--resolution,-r", o->resolution, "resolution of the build")
            ->capture_default_str()})
    buildOnly->excludes(structure);
  sub->add_option("--queries", o->queries, "queries in all (rounded up to whole batches per tile)")
      ->capture_default_str();
  sub->add_option("--seed", o->seed, "seed of the queries")->capture_default_str();
  sub->add_option("--tile", o->tile, "tile size of the soak (default min(R, 512))");
  o->threads.addTo(sub);
  sub->add_option("--state", o->state, "state file: resumed when it exists, saved after each tile");
  sub->add_option("--json", o->json, "write the summary as JSON");
  sub->callback([o] { runSoak(*o); });
}

}  // namespace sb::cli
