// Lookup timings (DESIGN §6): single-thread ns per query and all-thread Mqueries/s, medians of
// repeated runs over a query set.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "harness/query_sets.h"
#include "schemes/interface/scheme.h"

namespace sb {

struct LookupTiming {
  std::string querySet;
  int filter = 1;
  uint64_t queries = 0;  // per run
  double nsPerQuerySingleThread = 0;
  double mqueriesPerSecondAllThreads = 0;
  int threads = 1;
  // Of a decoder with a block cache: the share of the single-thread runs' block reads it answered.
  std::optional<double> cacheHitRate;
  nlohmann::json toJson() const;
};

// Times `decoder` on (a prefix of) `set` with a k×k filter; the prefix is sized so that one run
// lasts about a tenth of a second (at least a 1920×1080 frame's queries, one batch, for a decoder
// with a block cache), and the median of `repeats` runs is kept.
LookupTiming timeLookups(const Decoder& decoder, const QuerySet& set, int k, int repeats = 5);

}  // namespace sb
