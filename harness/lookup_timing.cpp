#include "harness/lookup_timing.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

template <class F>
double secondsOf(F&& f) {
  const auto start = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

nlohmann::json LookupTiming::toJson() const {
  return {{"query_set", querySet},
          {"filter", filter},
          {"queries", queries},
          {"ns_per_query_1t", nsPerQuerySingleThread},
          {"mqueries_per_s_all", mqueriesPerSecondAllThreads},
          {"threads", threads}};
}

LookupTiming timeLookups(const Decoder& decoder, const QuerySet& set, int k, int repeats) {
  LookupTiming timing;
  timing.querySet = set.name;
  timing.filter = k;
  timing.threads = tbb::this_task_arena::max_concurrency();
  if (set.queries.empty()) return timing;
  constexpr size_t kChunk = 4096;
  std::vector<float> answers(set.queries.size());
  auto run = [&](size_t count) {
    decoder.lookup(std::span(set.queries).first(count), k, std::span(answers).first(count));
  };

  // Size the run from a probe so that slow filters do not take minutes.
  const size_t probe = std::min(set.queries.size(), kChunk);
  const double probeSeconds = std::max(secondsOf([&] { run(probe); }), 1e-9);
  const size_t count =
      std::clamp<size_t>(size_t(0.1 / probeSeconds * double(probe)), probe, set.queries.size());
  timing.queries = count;

  std::vector<double> single, all;
  for (int r = 0; r < repeats; ++r) {
    single.push_back(secondsOf([&] { run(count); }));
    all.push_back(secondsOf([&] {
      tbb::parallel_for(size_t(0), (count + kChunk - 1) / kChunk, [&](size_t c) {
        const size_t begin = c * kChunk, n = std::min(kChunk, count - begin);
        decoder.lookup(std::span(set.queries).subspan(begin, n), k,
                       std::span(answers).subspan(begin, n));
      });
    }));
  }
  timing.nsPerQuerySingleThread = median(single) * 1e9 / double(count);
  timing.mqueriesPerSecondAllThreads = double(count) / median(all) * 1e-6;
  return timing;
}

}  // namespace sb
