#include "harness/lookup_timing.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "schemes/interface/capabilities.h"

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

// The queries of one 1920×1080 frame.
constexpr size_t kFrameQueries = size_t(1920) * 1080;

template <class F>
double secondsOf(F&& f) {
  const auto start = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr size_t kChunk = 4096;

// The seconds `decoder` takes to answer the first `count` queries of `set` in one batch.
double secondsOfPrefix(const Decoder& decoder, const QuerySet& set, int k, size_t count,
                       std::span<float> answers) {
  return secondsOf(
      [&] { decoder.lookup(std::span(set.queries).first(count), k, answers.first(count)); });
}

// The queries of one run of `decoder` on `set` with a k×k filter: as many as take about a tenth
// of a second by a probe, so that slow filters do not take minutes, and for a decoder with a block
// cache at least a 1920×1080 frame (issue 13: a frame's queries arrive as one batch). The probe is
// timed on its second run: the first pays for the pages and cache lines it touches first, which
// sized the terrain's point lookups at 16K² to runs of 4 ms.
size_t queriesPerRun(const Decoder& decoder, const QuerySet& set, int k, std::span<float> answers) {
  const size_t probe = std::min(set.queries.size(), kChunk);
  secondsOfPrefix(decoder, set, k, probe, answers);
  const double probeSeconds = std::max(secondsOfPrefix(decoder, set, k, probe, answers), 1e-9);
  const size_t count =
      std::clamp<size_t>(size_t(0.1 / probeSeconds * double(probe)), probe, set.queries.size());
  if (!decoder.blockCacheStatistics()) return count;
  return std::max(count, std::min(set.queries.size(), kFrameQueries));
}

}  // namespace

Spread::Spread(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  median = values[values.size() / 2], min = values.front(), max = values.back();
}

nlohmann::json LookupTiming::toJson() const {
  nlohmann::json j = {{"query_set", querySet},
                      {"filter", filter},
                      {"queries", queries},
                      {"ns_per_query_1t", nsPerQuerySingleThread},
                      {"mqueries_per_s_all", mqueriesPerSecondAllThreads},
                      {"threads", threads}};
  if (cacheHitRate) j["cache_hit_rate"] = *cacheHitRate;
  return j;
}

LookupTiming timeLookups(const Decoder& decoder, const QuerySet& set, int k, int repeats) {
  LookupTiming timing;
  timing.querySet = set.name;
  timing.filter = k;
  timing.threads = tbb::this_task_arena::max_concurrency();
  if (set.queries.empty()) return timing;
  std::vector<float> answers(set.queries.size());
  const size_t count = queriesPerRun(decoder, set, k, answers);
  // A decoder with a block cache answers a batch in an order of its own, so that each block is
  // decompressed once per batch: all threads take a contiguous share of each frame.
  const BlockCacheStatistics* cache = decoder.blockCacheStatistics();
  const size_t chunk =
      cache ? (count + size_t(timing.threads) - 1) / size_t(timing.threads) : kChunk;
  timing.queries = count;

  // Single-thread runs use the calling thread's cache; TBB's runs share it among threads.
  BlockCacheStatistics::Counts cached;
  std::vector<double> single, all;
  for (int r = 0; r < repeats; ++r) {
    const BlockCacheStatistics::Counts before = cache ? cache->threadCounts() : cached;
    single.push_back(secondsOfPrefix(decoder, set, k, count, answers));
    if (cache) {
      const BlockCacheStatistics::Counts after = cache->threadCounts();
      cached.hits += after.hits - before.hits;
      cached.misses += after.misses - before.misses;
    }
    all.push_back(secondsOf([&] {
      tbb::parallel_for(size_t(0), (count + chunk - 1) / chunk, [&](size_t c) {
        const size_t begin = c * chunk, n = std::min(chunk, count - begin);
        decoder.lookup(std::span(set.queries).subspan(begin, n), k,
                       std::span(answers).subspan(begin, n));
      });
    }));
  }
  timing.nsPerQuerySingleThread = Spread(single).median * 1e9 / double(count);
  timing.mqueriesPerSecondAllThreads = double(count) / Spread(all).median * 1e-6;
  if (cached.hits + cached.misses != 0)
    timing.cacheHitRate = double(cached.hits) / double(cached.hits + cached.misses);
  return timing;
}

InTurnTimings timeLookupsInTurn(std::span<const Decoder* const> decoders, const QuerySet& set,
                                int k, int rounds) {
  InTurnTimings timings;
  timings.nsPerQuery.resize(decoders.size());
  if (set.queries.empty() || decoders.empty()) return timings;
  std::vector<float> answers(set.queries.size());
  size_t count = set.queries.size();
  for (const Decoder* decoder : decoders)
    count = std::min(count, queriesPerRun(*decoder, set, k, answers));
  timings.queries = count;
  for (int r = 0; r < rounds; ++r)
    for (size_t turn = 0; turn < decoders.size(); ++turn) {
      const size_t d = r % 2 ? decoders.size() - 1 - turn : turn;
      timings.nsPerQuery[d].push_back(secondsOfPrefix(*decoders[d], set, k, count, answers) * 1e9 /
                                      double(count));
    }
  return timings;
}

}  // namespace sb
