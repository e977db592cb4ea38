// A cell of the matrix — scene × light × mode × scheme (+ parameters) × resolution — built,
// verified, benchmarked and recorded: the unit of work of `build` and `sweep`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "harness/build.h"
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
  uint32_t tileSize = 0;  // 0: defaultTileSize
};

struct CellOptions {
  bool verify = true;
  VerifyOptions verifyOptions;
  bool benchLookups = true;
  std::vector<int> filters{std::begin(kStandardFilters), std::end(kStandardFilters)};
  std::optional<std::filesystem::path> saveStructureTo;
};

// The record's identifying fields (scene, light, mode, scheme, params, resolution, tile size),
// not yet complete: enough for cellKey() to name the cell before it is built and for a sweep to
// tell whether a record answers it. Throws on an unknown scheme, a bad parameter or light index.
Record cellIdentity(const CellSpec& cell, const Scene& scene);

// Builds the cell and returns its complete record (DESIGN §6). Throws on bad input; a wrong
// answer is not an exception but a record with mismatches.
Record runCell(const CellSpec& cell, const Scene& scene, const CellOptions& options);

// The light at `index` in the scene, fitted; throws naming the scene's light count.
Light sceneLight(const Scene& scene, uint32_t index);

}  // namespace sb
