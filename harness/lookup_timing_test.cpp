// Lookup timings: how many queries a run takes, what a decoder with a block cache adds — whole
// frames per batch and the hit rate of the single-thread runs — and decoders timed in turn.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <utility>
#include <vector>

#include "harness/lookup_timing.h"
#include "schemes/interface/capabilities.h"

namespace sb {
namespace {

// Each batch a decoder answered, in order: the decoder and the batch's size.
using BatchLog = std::vector<std::pair<const Decoder*, size_t>>;

// Answers every query lit after `pace` a query (100 ns: a tenth of a second is a million queries,
// under half a frame); with a cache, each batch counts one miss and a hit for every other query,
// in the calling thread. Logs each batch if given a log.
class PacedDecoder final : public Decoder, public BlockCacheStatistics {
 public:
  explicit PacedDecoder(bool cached, std::chrono::nanoseconds pace = std::chrono::nanoseconds(100),
                        BatchLog* log = nullptr)
      : cached_(cached), pace_(pace), log_(log) {}
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    checkLookupArguments(queries, k, visibility);
    if (log_) log_->emplace_back(this, queries.size());
    const auto until = std::chrono::steady_clock::now() + queries.size() * pace_;
    while (std::chrono::steady_clock::now() < until) {
    }
    std::fill_n(visibility.begin(), queries.size(), 1.0f);
    if (queries.empty()) return;
    ++counts().misses;
    counts().hits += queries.size() - 1;
    size_t largest = largestBatch_;
    while (largest < queries.size() &&
           !largestBatch_.compare_exchange_weak(largest, queries.size())) {
    }
  }
  SizeBreakdown size() const override { return {}; }
  void save(ByteWriter&) const override {}
  const BlockCacheStatistics* blockCacheStatistics() const override {
    return cached_ ? this : nullptr;
  }
  Counts threadCounts() const override { return counts(); }
  size_t largestBatch() const { return largestBatch_; }

 private:
  static Counts& counts() {
    thread_local Counts perThread;
    return perThread;
  }
  bool cached_;
  std::chrono::nanoseconds pace_;
  BatchLog* log_;
  mutable std::atomic<size_t> largestBatch_{0};
};

}  // namespace

TEST_CASE("a decoder with a block cache is timed on whole frames, with its hit rate", "[lookup]") {
  const QuerySet set = uniformQueries(3'000'000, 5);
  constexpr size_t frame = 1920 * 1080;
  const PacedDecoder plain(false), cached(true);
  const LookupTiming plainTiming = timeLookups(plain, set, 1, 3);
  CHECK(plainTiming.queries >= 4096);
  CHECK(plainTiming.queries < frame);
  CHECK(!plainTiming.cacheHitRate);

  const LookupTiming cachedTiming = timeLookups(cached, set, 3, 3);
  CHECK(cachedTiming.queries >= frame);
  REQUIRE(cachedTiming.cacheHitRate);
  // One batch per single-thread run: one miss in `queries`.
  CHECK(*cachedTiming.cacheHitRate ==
        Approx(double(cachedTiming.queries - 1) / double(cachedTiming.queries)));
  // All threads take a contiguous share each, not chunks of a few thousand.
  CHECK(cached.largestBatch() >= cachedTiming.queries / size_t(cachedTiming.threads));
}

TEST_CASE("decoders timed in turn run one prefix, sized for the slowest, in alternating order",
          "[lookup]") {
  const QuerySet set = uniformQueries(3'000'000, 5);
  BatchLog log;
  const PacedDecoder fast(false, std::chrono::nanoseconds(5), &log),
      slow(false, std::chrono::nanoseconds(100), &log);
  const Decoder* decoders[] = {&fast, &slow};
  const InTurnTimings timings = timeLookupsInTurn(decoders, set, 1, 3);
  // A tenth of a second of the slow decoder, about a million queries; the fast one alone would
  // take the whole set.
  CHECK(timings.queries >= 4096);
  CHECK(timings.queries < set.queries.size());
  REQUIRE(timings.nsPerQuery.size() == 2);
  for (const std::vector<double>& runs : timings.nsPerQuery) {
    CHECK(runs.size() == 3);
    CHECK(std::ranges::all_of(runs, [](double ns) { return ns > 0; }));
  }
  // After each decoder's probes, the rounds: fast, slow; slow, fast; fast, slow.
  REQUIRE(log.size() >= 6);
  const size_t q = timings.queries;
  const BatchLog rounds(log.end() - 6, log.end());
  CHECK(rounds == BatchLog{{&fast, q}, {&slow, q}, {&slow, q}, {&fast, q}, {&fast, q}, {&slow, q}});
}

}  // namespace sb
