#include "harness/cli/options.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cell_key.h"
#include "harness/record.h"
#include "harness/resolution.h"
#include "schemes/interface/atomic_file.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {
int status = 0;
}  // namespace

int exitStatus() {
  return status;
}
void setExitStatus(int value) {
  status = value;
}

void MapOptions::addTo(CLI::App* app, bool withMapShape) {
  app->add_option("--scene,-s", scene,
                  "generator (city, terrain, forest, tangle; ':full', a preset such as "
                  "':cityscape' or ':size=N,seed=S'; 'shadowbench scene list'), scene .json or "
                  "model file")
      ->capture_default_str();
  app->add_option("--light,-l", light, "index of the scene's light")->capture_default_str();
  if (!withMapShape) return;
  app->add_option("--mode,-m", mode, "dual depth mode: open, closed or static")
      ->capture_default_str();
  app->add_option("--resolution,-r", resolution, "texels per side: 512, 4K, 64K, …")
      ->capture_default_str();
  app->add_option("--tile", tile, "tile size streamed to the encoder (default min(R, 512))");
}

void addSampledQueries(CLI::App* app, uint64_t& sampledQueries) {
  app->add_option("--sampled-queries", sampledQueries, "queries checked above 2K²")
      ->capture_default_str();
}

Params parseParams(const std::vector<std::string>& assignments) {
  Params params;
  for (const std::string& a : assignments) {
    const size_t eq = a.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument(fmt::format("parameter '{}' must be written name=value", a));
    const auto [previous, added] = params.emplace(a.substr(0, eq), a.substr(eq + 1));
    if (!added)
      throw std::invalid_argument(fmt::format("parameter '{}' given twice ('{}' and '{}')",
                                              previous->first, previous->second, a.substr(eq + 1)));
  }
  return params;
}

void SchemeOptions::addTo(CLI::App* app, const std::string& defaultScheme) {
  schemes = {defaultScheme};
  app->add_option("--scheme", schemes,
                  "scheme name (see 'shadowbench schemes'); several (repeated or a,b,c) share one "
                  "depth pass")
      ->delimiter(',')
      ->capture_default_str();
  app->add_option("--param,-p", params,
                  "scheme parameter name=value, or scheme:name=value with several schemes "
                  "(repeatable)");
}

std::vector<std::pair<std::string, Params>> SchemeOptions::resolve() const {
  std::vector<std::pair<std::string, Params>> resolved;
  for (const std::string& name : schemes) {
    findScheme(name);
    for (const auto& [other, params] : resolved)
      if (other == name) throw std::invalid_argument(fmt::format("scheme '{}' given twice", name));
    resolved.emplace_back(name, Params{});
  }
  std::vector<std::vector<std::string>> assignments(resolved.size());
  for (const std::string& assignment : params) {
    const size_t colon = assignment.find(':'), eq = assignment.find('=');
    if (colon != std::string::npos && colon < eq) {
      const std::string scheme = assignment.substr(0, colon);
      const auto it = std::find_if(resolved.begin(), resolved.end(),
                                   [&](const auto& entry) { return entry.first == scheme; });
      if (it == resolved.end())
        throw std::invalid_argument(fmt::format(
            "parameter '{}' names scheme '{}', which is not among --scheme", assignment, scheme));
      assignments[size_t(it - resolved.begin())].push_back(assignment.substr(colon + 1));
    } else if (resolved.size() == 1) {
      assignments[0].push_back(assignment);
    } else {
      throw std::invalid_argument(fmt::format(
          "parameter '{}' must name its scheme (scheme:name=value) when several are built",
          assignment));
    }
  }
  for (size_t s = 0; s < resolved.size(); ++s) {
    resolved[s].second = parseParams(assignments[s]);
    findScheme(resolved[s].first).resolve(resolved[s].second);
  }
  return resolved;
}

void PartOptions::addTo(CLI::App* app, bool partSizeRequired) {
  auto* option = app->add_option(
      "--part-size", partSize,
      "build in square parts of this side (a power of two such as 16K), each saved as a part file "
      "and merged; a killed build resumes from its part files");
  if (partSizeRequired) option->required();
  app->add_option("--parts", partsRoot, "folder of the part files (one subfolder per cell)")
      ->capture_default_str();
}

uint32_t PartOptions::partSizeValue() const {
  return partSize.empty() ? 0 : parseResolution(partSize);
}

std::vector<CellSpec> cellsOf(const MapOptions& map, const SchemeOptions& schemes,
                              const PartOptions& parts) {
  const DepthMode mode = depthModeFromString(map.mode);
  const uint32_t resolution = parseResolution(map.resolution);
  checkTileSize(map.tile, resolution);
  const uint32_t partSize = parts.partSizeValue();
  // An explicit tile must fit in a part; the default tile shrinks to the part (CellSpec).
  const uint32_t tile = std::max(map.tile, 8u);
  if (partSize && (partSize >= resolution || partSize < tile))
    throw std::invalid_argument(
        fmt::format("part size {} must lie from the tile size {} to below the resolution {}",
                    resolutionLabel(partSize), tile, resolutionLabel(resolution)));
  std::vector<CellSpec> cells;
  for (const auto& [scheme, params] : schemes.resolve())
    cells.push_back({map.scene, map.light, mode, scheme, params, resolution, map.tile, partSize});
  return cells;
}

void ThreadOptions::addTo(CLI::App* app) {
  app->add_option("--threads", threads, "threads to use (default: all)");
}

std::optional<tbb::global_control> ThreadOptions::apply() const {
  std::optional<tbb::global_control> limit;
  if (threads) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
  return limit;
}

void RecordOptions::addTo(CLI::App* app) {
  app->add_option("--output,-o", output, "save the structure to this file (one scheme)");
  app->add_option("--results", results, "folder for the JSON records")->capture_default_str();
  app->add_flag("--no-verify", noVerify, "skip the check against the reference");
  app->add_flag("--no-bench", noBench, "skip lookup timings");
  addSampledQueries(app, sampledQueries);
}

void RecordOptions::checkOutputs(const std::vector<CellSpec>& cells,
                                 const std::string& sceneSpec) const {
  if (!output.empty() && cells.size() > 1)
    throw std::invalid_argument("--output saves one structure: give one --scheme with it");
  if (!output.empty()) checkOutputFile(output, sceneSourceFiles(sceneSpec));
  checkWritableFolder(results);
}

CellOptions RecordOptions::cellOptions(const PartOptions& parts) const {
  CellOptions options;
  options.verify = !noVerify;
  options.benchLookups = !noBench;
  options.verifyOptions.sampledQueries = sampledQueries;
  if (!output.empty()) options.saveStructureTo = output;
  options.partsRoot = parts.partsRoot;
  return options;
}

bool writeCellRecord(const Record& built, const std::string& results) {
  const nlohmann::json record = built;
  const fs::path recordPath = fs::path(results) / (cellKey(built) + ".json");
  writeJsonAtomically(recordPath, record);
  printCellSummary(record);
  fmt::print("record: {}\n", recordPath.string());
  return hasMismatches(record);
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

void checkOutputFile(const fs::path& output, const std::vector<fs::path>& inputs) {
  if (!output.has_filename())
    throw std::runtime_error(
        fmt::format("output '{}' names a folder, not a file", output.string()));
  checkReplaceable(output);
  std::error_code error;
  for (const fs::path& input : inputs)
    if (fs::equivalent(output, input, error))
      throw std::runtime_error(fmt::format("refusing to write '{}': it is the input '{}'",
                                           output.string(), input.string()));
  checkWritableFolder(output.parent_path());
}

void flushStandardOutput() {
  errno = 0;
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return;
  if (errno == 0) throw std::runtime_error("cannot write standard output: an earlier write failed");
  throw std::system_error(errno, std::generic_category(), "cannot write standard output");
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
    for (const auto& t : r["lookup"]) {
      fmt::print(
          "  lookup {:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} "
          "threads)",
          t["query_set"].get<std::string>(), t["filter"].get<int>(), t["filter"].get<int>(),
          t["ns_per_query_1t"].get<double>(), t["mqueries_per_s_all"].get<double>(),
          t["threads"].get<int>());
      if (t.contains("cache_hit_rate"))
        fmt::print(", cache hits {:.1f}%", 100 * t["cache_hit_rate"].get<double>());
      fmt::print("\n");
    }
}

bool hasMismatches(const nlohmann::json& record) {
  return record.contains("verification") &&
         record["verification"]["mismatches"].get<uint64_t>() > 0;
}

LoadedStructure::LoadedStructure(const std::string& structurePath, const MapOptions& map)
    : decoder(loadStructure(structurePath, &header)), scene(openScene(map.scene)) {
  // The structure remembers its scene (structure file version 2); "" is a structure built from
  // no scene, which any scene may check.
  if (!header.sceneHash.empty() && header.sceneHash != scene.hash())
    throw std::runtime_error(fmt::format(
        "structure '{}' was built from another scene (hash {}), not from '{}' (hash {})",
        structurePath, header.sceneHash, map.scene, scene.hash()));
  source = std::make_unique<DepthSource>(scene, sceneLight(scene, map.light), header.map.mode,
                                         header.map.resolution);
}

}  // namespace sb::cli
