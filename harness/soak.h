// The soak test (issue 11): far more queries than `verify` — random and boundary point queries
// and PCF kernels in every tile of a large map — checked against the reference by the same
// acceptance rule (DESIGN §4, §5), resumable tile by tile.
//
// The dual depth map is traced once, tile by tile in Morton order (DESIGN §3); each tile's
// queries are answered by the decoder and judged against that tile's own intervals, so the
// reference costs one depth pass however many queries are checked. PCF kernels are centred so that
// every tap inside the map falls inside the tile (taps outside the map are lit).
#pragma once

#include <cstdint>
#include <functional>

#include <nlohmann/json.hpp>

#include "harness/depth_source.h"
#include "harness/verify.h"
#include "schemes/interface/scheme.h"

namespace sb {

inline constexpr std::string_view kSoakStateFormat = "shadowbench-soak-state/1";

// Queries are drawn and looked up in batches of this many: kSoakPcfPerBatch PCF queries of one
// filter size (3, 5, 9, 17 in turn) and point queries for the rest.
inline constexpr uint64_t kSoakBatchQueries = 4096, kSoakPcfPerBatch = 32;
inline constexpr size_t kSoakMaxExamples = 10;

struct SoakOptions {
  uint64_t seed = 1;
  uint64_t queriesPerTile = 1 << 20;  // rounded up to whole batches
  uint32_t tileSize = 512;            // a power of two in [32, R]
};

// What a soak run has done so far. Tiles are checked in Morton order, so the tiles done are the
// first `tilesDone` of that order.
struct SoakState {
  // What is checked: the structure (file checksum or build description), scene, light, map, seed,
  // queries per tile and tile size. A resumed run must have exactly the same.
  nlohmann::json identity;
  uint64_t tilesTotal = 0, tilesDone = 0;
  double seconds = 0;   // wall time spent checking, over every session
  VerifyReport report;  // method "soak"; the first kSoakMaxExamples mismatches in tile order

  bool finished() const { return tilesDone == tilesTotal; }
  nlohmann::json toJson() const;
  // Throws std::invalid_argument naming the field that is missing or of the wrong type.
  static SoakState fromJson(const nlohmann::json& json);
};

// A fresh state for soaking a structure of `map` described by `structure` (whatever identifies
// it: the file's checksum, or the scheme, parameters and scene it is built from) with `options`.
// Throws std::invalid_argument for a tile size that is not a power of two in [32, R].
SoakState newSoakState(const nlohmann::json& structure, const MapInfo& map,
                       const SoakOptions& options);

// `saved` (a state file's contents) when it is a run of `fresh`'s identity, to be continued;
// throws std::runtime_error naming the first field that differs otherwise.
SoakState resumeSoakState(const nlohmann::json& saved, const SoakState& fresh);

// Checks the remaining tiles of `state` (made for `map` and `options`) and adds to it;
// `tileDone(state)` runs after each tile, on one thread, so the caller can save the state and
// report progress. Stopping early (an exception from `tileDone`, or the process killed) loses at
// most the tile in flight. Never throws on a wrong answer: mismatches are counted.
void soak(const Decoder& decoder, SchemeKind kind, const MapInfo& map, const DepthSource& source,
          const SoakOptions& options, SoakState& state,
          const std::function<void(const SoakState&)>& tileDone = {});

}  // namespace sb
