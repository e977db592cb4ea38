// The correctness matrix's check of one structure against the reference (DESIGN §4):
// exhaustive up to 2K², sampled (biased to shadow boundaries, plus uniform) above.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/depth_source.h"
#include "harness/reference.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct Mismatch {
  Query query;
  int k;
  float got;
  VisibilityRange expected;
};

struct VerifyReport {
  std::string method;  // "exhaustive" or "sampled"
  uint64_t queries = 0, mismatches = 0;
  std::vector<Mismatch> examples;  // the first few, for the record and the error message
  nlohmann::json toJson() const;
};

struct VerifyOptions {
  uint32_t exhaustiveUpTo = 2048;        // every texel checked at resolutions up to this
  uint64_t sampledQueries = 10'000'000;  // at least this many above it
  uint64_t seed = 1;
};

// Checks `decoder` (a structure for `map`) against the reference re-traced from `source`,
// which must describe the same scene, light, mode and resolution. Never throws on a wrong
// answer: mismatches are counted and the caller decides.
VerifyReport verify(const Decoder& decoder, SchemeKind kind, const MapInfo& map,
                    const DepthSource& source, const VerifyOptions& options,
                    const std::function<void(uint64_t queriesSoFar)>& progress = {});

}  // namespace sb
