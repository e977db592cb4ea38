// Sintorn 2014 §5 distant-shadow antialiasing, reported as an error against exact PCF (DESIGN §4:
// approximate filters are an error figure, not a lossless check). VOAA answers with the
// occupancy of the CPVS node of side s around the query's voxel; MRAA looks the query up in the
// same scheme built at R/2^L. Each is compared with the exact full-resolution k×k PCF of about
// the same footprint.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/build.h"
#include "harness/query_sets.h"
#include "scenes/scene.h"
#include "schemes/interface/scheme.h"

namespace sb {

// How far approximate answers are from the exact ones, query by query.
struct FilterError {
  double meanAbs = 0, rms = 0, max = 0;
  double overTenth = 0;  // fraction of queries off by more than 0.1
};
FilterError filterError(std::span<const float> approximate, std::span<const float> exact);

// MRAA (Sintorn §5): `scheme` built with the same light, mode and parameters at R/2, R/4, …,
// R/2^levels (levels ≤ 4, so that the matching exact kernel 2^L + 1 is at most 17×17).
std::vector<BuildOutcome> buildMraaLevels(const Scene& scene, const Light& light, DepthMode mode,
                                          const SchemeInfo& scheme, const ParamValues& params,
                                          uint32_t resolution, uint32_t levels);

// The exact kernel an MRAA level L answer stands for: 2^L + 1, the odd kernel covering one
// coarse texel (1 at L = 0).
inline int mraaReferenceK(uint32_t level) {
  return int(1u << level) | 1;
}

struct DistantFilterRow {
  std::string filter;  // "VOAA", "MRAA" or "HPCF"
  std::string answer;  // what answers: "s = 8 (depth 9)", "L = 2 (1K²), 3×3"
  int referenceK = 1;  // the exact full-resolution k×k PCF it is compared with
  FilterError error;
  double nsPerQuery = 0, exactNsPerQuery = 0;  // single thread, median; 0 when not timed
  uint64_t bytes = 0;                          // the structure its lookups read
};

struct DistantFiltersOptions {
  std::vector<uint32_t> voaaSides{8, 16, 32};  // VOAA node sides; empty for no VOAA rows
  bool time = true;                            // time every filter (timeLookups)
};

struct DistantFiltersReport {
  std::vector<DistantFilterRow> rows;  // VOAA by side, MRAA by level, HPCF by level; 1×1, 3×3
  uint64_t queries = 0;
  uint64_t fullBytes = 0;
  std::vector<uint64_t> mraaBytes;  // levels 1, 2, …
  double mraaExtra() const;         // the coarse levels' bytes relative to the full structure
  nlohmann::json toJson() const;
};

// Answers `set` with every filter and with the exact PCF each is compared with. VOAA rows come
// from a `full` whose decoder offers voxelOccupancy(); `mraa` holds levels 1, 2, …
// (buildMraaLevels), level 0 being `full`. HPCF rows, at the same levels, come from a `full`
// whose decoder offers hierarchicalLookup().
DistantFiltersReport evaluateDistantFilters(const BuildOutcome& full,
                                            std::span<const BuildOutcome> mraa, const QuerySet& set,
                                            const DistantFiltersOptions& options = {});

}  // namespace sb
