// A cell of the matrix — scene × light × mode × scheme (+ parameters) × resolution — built,
// verified, benchmarked and recorded: the unit of work of `build` and `sweep`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "harness/build.h"
#include "harness/parts_build.h"
#include "harness/query_sets.h"
#include "harness/record_type.h"
#include "harness/resolution.h"
#include "harness/verify.h"
#include "scenes/scene.h"

namespace sb {

struct CellSpec {
  std::string sceneSpec = "city";
  uint32_t lightIndex = 0;
  DepthMode mode = DepthMode::Closed;
  std::string scheme = "sm32";
  Params params;
  uint32_t resolution = 1024;
  uint32_t tileSize = 0;  // 0: defaultTileSize, or the part size when that is smaller
  uint32_t partSize = 0;  // a build in parts of this side (DESIGN §5); 0: a whole build

  uint32_t effectiveTileSize() const;
  BuildShape shape() const { return {effectiveTileSize(), partSize}; }
};

struct CellOptions {
  bool verify = true;
  VerifyOptions verifyOptions;
  bool benchLookups = true;
  std::vector<int> filters{std::begin(kStandardFilters), std::end(kStandardFilters)};
  std::optional<std::filesystem::path> saveStructureTo;
  // Builds in parts keep their part files in partsFolder(partsRoot, identity).
  std::filesystem::path partsRoot = "results/parts";
};

// The record's identifying fields (scene, light, mode, scheme, params, resolution, tile size),
// not yet complete: enough for cellKey() to name the cell before it is built and for a sweep to
// tell whether a record answers it. Throws on an unknown scheme, a bad parameter or light index.
Record cellIdentity(const CellSpec& cell, const Scene& scene);

// Builds the cell and returns its complete record (DESIGN §6). Throws on bad input; a wrong
// answer is not an exception but a record with mismatches.
Record runCell(const CellSpec& cell, const Scene& scene, const CellOptions& options);

// Cells that differ only in scheme and parameters (the same scene, light, mode, resolution, tile
// and part size) built from one depth pass (issue 12): whole, every tile feeds every encoder; in
// parts, every part's depth feeds every scheme's part encoder, and each scheme is then merged.
// Each cell is verified, timed and handed to `done` (with its index in `cells`) as soon as it is
// complete, so that a failure later loses nothing finished. Throws std::invalid_argument for cells
// that do not share the map.
void runCells(std::span<const CellSpec> cells, const Scene& scene, const CellOptions& options,
              const std::function<void(size_t cell, const Record& record)>& done);

// A cell's part files: <partsRoot>/<cellKey>, one folder per scheme cell.
std::filesystem::path partsFolder(const std::filesystem::path& partsRoot, const Record& identity);

// Only the part files of cells built in parts (one depth pass per part for all of them): every
// part, or part `only`; parts already there are kept. For the cluster workflow's part jobs.
PartsEncoded encodeCellParts(std::span<const CellSpec> cells, const Scene& scene,
                             const CellOptions& options, std::optional<uint64_t> only);

// A cell built in parts, from its part files alone (a missing part is named): merged, verified,
// timed, recorded. For the cluster workflow's merge jobs.
Record mergeCell(const CellSpec& cell, const Scene& scene, const CellOptions& options);

// mergeCell for each cell, handing each record to `done` as it is complete. A merge that fails
// (a missing or damaged part, a merge that does not fit in memory) does not stop the others:
// afterwards one std::runtime_error names every cell that failed and why.
void mergeCells(std::span<const CellSpec> cells, const Scene& scene, const CellOptions& options,
                const std::function<void(size_t cell, const Record& record)>& done);

// The light at `index` in the scene, fitted; throws naming the scene's light count.
Light sceneLight(const Scene& scene, uint32_t index);

}  // namespace sb
