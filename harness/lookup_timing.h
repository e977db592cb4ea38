// Lookup timings (DESIGN §6): single-thread ns per query and all-thread Mqueries/s, medians of
// repeated runs over a query set.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/query_sets.h"
#include "schemes/interface/scheme.h"

namespace sb {

// The median (the upper of the middle two of an even count) and the range of repeated timings.
struct Spread {
  double median, min, max;
  explicit Spread(std::vector<double> values);
};

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

// Single-thread timings of several decoders on the same queries, taken in turn: `rounds` rounds,
// each running every decoder once on one prefix of `set` (sized as timeLookups sizes it, for the
// slowest decoder), in the order given and reversed every other round, so that none always
// follows the same one. This machine's single runs spread by up to 2× with what else it runs,
// so a ratio of two separate runs does not resolve tens of percent; runs in turn share the load
// of their round, and the ratios within each round are what to compare. Returns the prefix's
// length and, per decoder, its ns per query round by round.
struct InTurnTimings {
  uint64_t queries = 0;  // per run
  std::vector<std::vector<double>> nsPerQuery;
};
InTurnTimings timeLookupsInTurn(std::span<const Decoder* const> decoders, const QuerySet& set,
                                int k, int rounds);

}  // namespace sb
