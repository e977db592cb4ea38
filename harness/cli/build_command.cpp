#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cell_key.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/record.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct BuildOptions {
  MapOptions map;
  std::string scheme = "sm32", output, results = "results/builds";
  std::vector<std::string> params;
  bool noVerify = false, noBench = false;
  uint64_t sampledQueries = 10'000'000;
};

int buildCell(const BuildOptions& o) {
  // Everything the scene is not needed for is checked before it is opened, and the light (in
  // runCell) before the depth pass: a typo or an output that cannot be written must not cost a
  // build (issue 11 A2, A9).
  const SchemeInfo& scheme = findScheme(o.scheme);
  const Params params = parseParams(o.params);
  scheme.resolve(params);
  const DepthMode mode = depthModeFromString(o.map.mode);
  const uint32_t resolution = parseResolution(o.map.resolution);
  checkTileSize(o.map.tile, resolution);
  if (!o.output.empty()) checkOutputFile(o.output, sceneSourceFiles(o.map.scene));
  checkWritableFolder(o.results);

  const Scene scene = openScene(o.map.scene);
  const CellSpec cell{o.map.scene, o.map.light, mode, o.scheme, params, resolution, o.map.tile};
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

}  // namespace

void addBuildCommand(CLI::App& app) {
  auto o = std::make_shared<BuildOptions>();
  CLI::App* sub =
      app.add_subcommand("build", "build a scheme for a scene, verify it, time lookups, record it");
  o->map.addTo(sub);
  sub->add_option("--scheme", o->scheme, "scheme name (see 'shadowbench schemes')")
      ->capture_default_str();
  sub->add_option("--param,-p", o->params, "scheme parameter name=value (repeatable)");
  sub->add_option("--output,-o", o->output, "save the structure to this file");
  sub->add_option("--results", o->results, "folder for the JSON record")->capture_default_str();
  sub->add_flag("--no-verify", o->noVerify, "skip the check against the reference");
  sub->add_flag("--no-bench", o->noBench, "skip lookup timings");
  addSampledQueries(sub, o->sampledQueries);
  sub->callback([o] { setExitStatus(buildCell(*o)); });
}

}  // namespace sb::cli
