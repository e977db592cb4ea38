// What several subcommands share: the map options, parameter assignments, the checks of
// outputs before any work, the exit status and the printed summaries of a cell.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "harness/cell.h"
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

// --scheme (repeatable, or a comma-separated list: schemes built from one depth pass) and --param:
// NAME=VALUE for a single scheme, SCHEME:NAME=VALUE to address one of several.
struct SchemeOptions {
  std::vector<std::string> schemes;
  std::vector<std::string> params;

  void addTo(CLI::App* app, const std::string& defaultScheme);
  // Each scheme with its parameters, checked against its registry row (throws naming the scheme
  // and parameter, or a scheme:parameter that names no listed scheme).
  std::vector<std::pair<std::string, Params>> resolve() const;
};

// --part-size (a resolution such as 16K; none for a whole build) and --parts (the folder of the
// part files, one subfolder per scheme cell).
struct PartOptions {
  std::string partSize;
  std::string partsRoot = "results/parts";

  void addTo(CLI::App* app, bool partSizeRequired);
  uint32_t partSizeValue() const;  // 0 when none was given
};

// The cells of one depth pass: every scheme of `schemes` on the map, whole or in parts. Checks
// resolution, tile and part size before anything is opened.
std::vector<CellSpec> cellsOf(const MapOptions& map, const SchemeOptions& schemes,
                              const PartOptions& parts);

// What `build` and `merge` do with a structure once built: --output (one scheme), --results,
// --no-verify, --no-bench, --sampled-queries.
struct RecordOptions {
  std::string output, results = "results/builds";
  bool noVerify = false, noBench = false;
  uint64_t sampledQueries = 10'000'000;

  void addTo(CLI::App* app);
  // Checks the outputs before any work (issue 11 A9): --output with one cell only, not one of the
  // scene's files; the results folder writable.
  void checkOutputs(const std::vector<CellSpec>& cells, const std::string& sceneSpec) const;
  CellOptions cellOptions(const PartOptions& parts) const;
};

// Writes a built cell's record atomically into the results folder and prints its summary;
// returns whether it has mismatches.
bool writeCellRecord(const Record& record, const std::string& results);

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
