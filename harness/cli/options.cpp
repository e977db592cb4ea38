#include "harness/cli/options.h"

#include <cerrno>
#include <cstdio>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "harness/cell.h"
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
