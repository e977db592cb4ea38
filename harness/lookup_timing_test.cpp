// Lookup timings: how many queries a run takes, and what a decoder with a block cache adds — whole
// frames per batch and the hit rate of the single-thread runs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>

#include "harness/lookup_timing.h"
#include "schemes/interface/capabilities.h"

namespace sb {
namespace {

// Answers every query lit after 100 ns a query, so that a tenth of a second is a million
// queries, under half a frame; with a cache, each batch counts one miss and a hit for every other
// query, in the calling thread.
class PacedDecoder final : public Decoder, public BlockCacheStatistics {
 public:
  explicit PacedDecoder(bool cached) : cached_(cached) {}
  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    checkLookupArguments(queries, k, visibility);
    const auto until =
        std::chrono::steady_clock::now() + queries.size() * std::chrono::nanoseconds(100);
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

}  // namespace sb
