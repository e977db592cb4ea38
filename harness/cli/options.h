// What several subcommands share: the map options, parameter assignments, the checks of
// outputs before any work, the exit status and the printed summaries of a cell.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "harness/depth_source.h"
#include "scenes/scene.h"
#include "schemes/interface/serial.h"

namespace sb::cli {

// The process's exit status: 0 unless the subcommand that ran says otherwise.
int exitStatus();
void setExitStatus(int status);

// --scene, --light and (withMapShape) --mode, --resolution, --tile.
struct MapOptions {
  std::string scene = "city";
  uint32_t light = 0;
  std::string mode = "closed";
  std::string resolution = "1K";
  uint32_t tile = 0;

  void addTo(CLI::App* app, bool withMapShape = true);
};

// --sampled-queries: queries checked above the exhaustive resolution.
void addSampledQueries(CLI::App* app, uint64_t& sampledQueries);

// "name=value" assignments of --param as Params; throws std::invalid_argument on another form
// and on a name given twice (which value was meant is unknown).
Params parseParams(const std::vector<std::string>& assignments);
std::vector<std::string> splitList(const std::string& text);

// Refuses, before any work, an output that would destroy something or fail only at the end: a
// path ending in '/', an existing file that is not a regular one (device node, FIFO, folder),
// one of `inputs` (the same file by fs::equivalent, however spelt), or a folder where no file
// can be created. Creates the output's folder. Throws std::runtime_error naming the path.
void checkOutputFile(const std::filesystem::path& output,
                     const std::vector<std::filesystem::path>& inputs);

// Flushes standard output; throws "cannot write standard output: <reason>" if that or an
// earlier write to it failed: output lost is a failed run (issue 11 A3).
void flushStandardOutput();

void printVerification(const nlohmann::json& verification);
void printCellSummary(const nlohmann::json& record);
bool hasMismatches(const nlohmann::json& record);

// A saved structure with the scene it was built for: the reference re-traced for `verify`,
// view samples for `bench`.
struct LoadedStructure {
  StructureHeader header;
  std::unique_ptr<Decoder> decoder;
  Scene scene;
  std::unique_ptr<DepthSource> source;

  LoadedStructure(const std::string& structurePath, const MapOptions& map);
};

}  // namespace sb::cli
