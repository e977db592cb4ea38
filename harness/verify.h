// The correctness matrix's check of one structure against the reference (DESIGN §4):
// exhaustive up to 2K², sampled (biased to shadow boundaries, plus uniform) above.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
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

// The range a correct answer to a k×k query at depth z centred on texel (ci, cj) must lie in
// (DESIGN §4, §5): [lit_defined/k², (lit_defined+undefined)/k²] over the taps, each tap's point
// test taken at the depth a scheme of `kind` tests; taps outside the map are lit. k = 1 is the
// point test: {1, 1} lit, {0, 0} shadowed, {0, 1} undefined. `intervalAt(i, j)` is the
// reference interval of a tap inside the map.
template <class IntervalAt>
VisibilityRange acceptedRange(SchemeKind kind, const MapInfo& map, int64_t ci, int64_t cj, int k,
                              float z, IntervalAt&& intervalAt) {
  const float tested = testedDepth(kind, map, z);
  const int64_t radius = k / 2;
  int lit = 0, undefined = 0;
  for (int64_t j = cj - radius; j <= cj + radius; ++j)
    for (int64_t i = ci - radius; i <= ci + radius; ++i) {
      if (!insideMap(i, j, map.resolution)) {
        ++lit;
        continue;
      }
      const PointAnswer answer = pointTest(intervalAt(i, j), tested);
      lit += answer == PointAnswer::Lit;
      undefined += answer == PointAnswer::Undefined;
    }
  const float taps = float(k * k);
  return {float(lit) / taps, float(lit + undefined) / taps};
}

// Checks `decoder` (a structure for `map`) against the reference re-traced from `source`,
// which must describe the same scene, light, mode and resolution. Never throws on a wrong
// answer: mismatches are counted and the caller decides.
VerifyReport verify(const Decoder& decoder, SchemeKind kind, const MapInfo& map,
                    const DepthSource& source, const VerifyOptions& options,
                    const std::function<void(uint64_t queriesSoFar)>& progress = {});

// Issue 13: a structure's k×k PCF (k of kStandardFilters above 1) against its own point lookups
// composed tap for tap, which is what the generic pcfLookup answers: exactly the same float,
// at the centre of every texel of the map, for every depth of `depths`. Kernel lookups that walk
// a structure once per kernel must agree with it bit for bit. Never throws on a wrong answer.
VerifyReport verifyKernels(const Decoder& decoder, const MapInfo& map,
                           std::span<const float> depths);

// `count` depths spread over the map's first hits (quantiles of the lo of every texel hit),
// where kernels cross shadow boundaries: the depths verifyKernels is run at.
std::vector<float> hitDepthQuantiles(const DepthSource& source, int count);

}  // namespace sb
