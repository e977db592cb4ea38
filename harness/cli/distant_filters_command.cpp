// `shadowbench distant-filters`: builds the structure and its MRAA levels, evaluates the
// distant-shadow filters on view or uniform queries, prints the Markdown table and writes it with
// a JSON file to --out.
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cell_key.h"
#include "harness/cli/commands.h"
#include "harness/distant_filters.h"
#include "harness/machine.h"
#include "harness/record.h"
#include "harness/source_commit.h"
#include "harness/table.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct CommandOptions {
  std::string scene = "city", mode = "closed", resolution = "4K", scheme = "cpvs-fast";
  std::string queries = "view", out = "results/distant-filters";
};

Table reportTable(const DistantFiltersReport& report) {
  Table table;
  table.title = "Distant filters against exact PCF (Sintorn 2014 §5, Scandolo 2016a)";
  table.unit_note =
      "absolute error in visibility (0–1) per query; ns/query single thread, median; MiB = 2²⁰ "
      "bytes of the structure the filter reads";
  table.header = {"filter", "answer",      "exact PCF", "mean |err|",     "RMS",
                  "max",    "err > 0.1 %", "ns/query",  "exact ns/query", "MiB"};
  for (const DistantFilterRow& r : report.rows) {
    const std::string k = fmt::format("{}×{}", r.referenceK, r.referenceK);
    table.rows.push_back({r.filter, r.answer, k, fmt::format("{:.4f}", r.error.meanAbs),
                          fmt::format("{:.4f}", r.error.rms), fmt::format("{:.4f}", r.error.max),
                          fmt::format("{:.2f}", 100 * r.error.overTenth),
                          fmt::format("{:.1f}", r.nsPerQuery),
                          fmt::format("{:.1f}", r.exactNsPerQuery),
                          fmt::format("{:.3f}", double(r.bytes) / (1 << 20))});
  }
  return table;
}

void runDistantFilters(const CommandOptions& o) {
  const Scene scene = openScene(o.scene);
  const SchemeInfo& scheme = findScheme(o.scheme);
  const DepthMode mode = depthModeFromString(o.mode);
  const uint32_t resolution = parseResolution(o.resolution);
  const Light light = sceneLight(scene, 0);
  const DepthSource source(scene, light, mode, resolution);
  constexpr uint32_t kMraaLevels = 4;  // R/2 … R/16: exact kernels 3×3 … 17×17

  fmt::print("building {} on {} ({}) at {} and its MRAA levels down to {}\n", scheme.name,
             scene.name, o.mode, resolutionHeading(resolution),
             resolutionHeading(resolution >> kMraaLevels));
  const ParamValues params = scheme.resolve({});
  const BuildOutcome full =
      buildStructure(source, scheme, params, BuildShape{defaultTileSize(resolution)});
  const std::vector<BuildOutcome> mraa =
      buildMraaLevels(scene, light, mode, scheme, params, resolution, kMraaLevels);
  // The query sets and sizes of the lookup benchmark (cell.cpp).
  const QuerySet set =
      o.queries == "view" ? standardViewQueries(scene, source) : standardUniformQueries();
  DistantFiltersOptions options;
  fmt::print("evaluating {} {} queries\n", set.queries.size(), set.name);
  const DistantFiltersReport report = evaluateDistantFilters(full, mraa, set, options);
  const bool hasVoaa = full.decoder->voxelOccupancy() != nullptr;

  std::string markdown = fmt::format(
      "# Distant filters: {} on `{}`, {}, {}\n\n"
      "Scene `{}`: {} triangles, hash {}; light 0. {} {} queries. Machine: {}.\n\n",
      scheme.name, o.scene, o.mode, resolutionHeading(resolution), scene.name,
      scene.triangleCount(), scene.hash(), set.queries.size(), set.name,
      machineInfo()["cpu"].get<std::string>());
  markdown += toMarkdown({reportTable(report)});
  markdown += fmt::format(
      "MRAA memory: levels R/2 … R/{} take {:.3f} MiB, {:.2f}× the full structure's {:.3f} MiB "
      "(all levels together {:.2f}×; Sintorn §5 says about twice the full structure).\n\n",
      1u << kMraaLevels, report.mraaExtra() * double(report.fullBytes) / (1 << 20),
      report.mraaExtra(), double(report.fullBytes) / (1 << 20), 1 + report.mraaExtra());
  if (hasVoaa)
    markdown +=
        "VOAA is a volume filter (Sintorn §5): the occupancy of the aligned s³ node holding the "
        "query's voxel, against an area kernel centred on the query texel at its depth. s = 32 "
        "is compared with 17×17, the largest exact kernel, which covers 17² of the node's 32² "
        "texels: its error also holds that difference in footprint.\n\n";
  if (scheme.kind == SchemeKind::Voxel)
    markdown +=
        "MRAA level L also quantises depth to R/2^L slices, so its answers are at the coarse "
        "voxel's centre.\n";
  else
    markdown +=
        "HPCF (hierarchical PCF, Scandolo et al. 2016a) reads level L of the structure's own "
        "hierarchy, a complete R/2^L map: the footprint of MRAA level L with no extra memory.\n";

  const fs::path base =
      fs::path(o.out) / fmt::format("{}_{}_{}_{}_{}", fileNamePart(scene.name), o.mode, scheme.name,
                                    fileNamePart(resolutionLabel(resolution)), set.name);
  nlohmann::json json = report.toJson();
  nlohmann::json paramsJson = nlohmann::json::object();
  for (const auto& [name, value] : full.params.text()) paramsJson[name] = value;
  json.update({{"format", "shadowbench-distant-filters/1"},
               {"scene",
                {{"name", scene.name},
                 {"spec", o.scene},
                 {"triangles", scene.triangleCount()},
                 {"hash", scene.hash()}}},
               {"light_index", 0},
               {"mode", o.mode},
               {"scheme", {{"name", scheme.name}, {"params", paramsJson}}},
               {"resolution", resolution},
               {"query_set", set.name},
               {"machine", machineInfo()},
               {"commit", sourceCommit(SHADOWBENCH_SOURCE_DIR)}});
  writeFileAtomically(fs::path(base) += ".md", markdown);
  writeJsonAtomically(fs::path(base) += ".json", json);
  fmt::print("\n{}\nwrote {}.md and .json\n", markdown, base.string());
}

}  // namespace

void addDistantFiltersCommand(CLI::App& app) {
  auto o = std::make_shared<CommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "distant-filters",
      "Sintorn 2014 §5 VOAA and MRAA, and hierarchical PCF of the MH schemes: distant-shadow "
      "filters, error against exact PCF");
  sub->add_option("--scene,-s", o->scene, "generator, scene .json or model file")
      ->capture_default_str();
  sub->add_option("--mode,-m", o->mode, "dual depth mode: open, closed or static")
      ->capture_default_str();
  sub->add_option("--resolution,-r", o->resolution, "texels per side: 512, 4K, …")
      ->capture_default_str();
  sub->add_option("--scheme", o->scheme, "scheme name (VOAA rows for CPVS-format schemes)")
      ->capture_default_str();
  sub->add_option("--queries", o->queries, "query set: view (camera orbit samples) or uniform")
      ->capture_default_str()
      ->check(CLI::IsMember({"view", "uniform"}));
  sub->add_option("--out", o->out, "folder for <scene>_<mode>_<scheme>_<R>_<queries>.md/.json")
      ->capture_default_str();
  sub->callback([o] { runDistantFilters(*o); });
}

}  // namespace sb::cli
