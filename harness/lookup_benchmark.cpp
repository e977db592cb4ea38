// Google Benchmark micro-benchmarks of lookups: every registered scheme built once for the
// default city (closed, 2K²), queried with uniform and view query sets at every filter size.
//   build/harness/lookup_benchmark [--benchmark_filter=sm32]
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "harness/build.h"
#include "harness/cell.h"
#include "harness/query_sets.h"

using namespace sb;

namespace {

constexpr uint32_t kResolution = 2048;
constexpr size_t kBatch = 4096;

struct Fixture {
  Scene scene = openScene("city");
  DepthSource source{scene, sceneLight(scene, 0), DepthMode::Closed, kResolution};
  QuerySet sets[2] = {uniformQueries(1 << 20, 7), viewSamples(scene, source, 960, 540, 1)};
  std::map<std::string, std::unique_ptr<Decoder>> built;

  const Decoder& decoder(const SchemeInfo& scheme) {
    auto& slot = built[scheme.name];
    if (!slot)
      slot = buildStructure(source, scheme, scheme.resolve({}),
                            BuildShape{defaultTileSize(kResolution)})
                 .decoder;
    return *slot;
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void lookups(benchmark::State& state, const SchemeInfo* scheme, int set, int k) {
  const Decoder& decoder = fixture().decoder(*scheme);
  const std::vector<Query>& queries = fixture().sets[set].queries;
  std::vector<float> answers(kBatch);
  size_t at = 0;
  for (auto _ : state) {
    if (at + kBatch > queries.size()) at = 0;
    decoder.lookup(std::span(queries).subspan(at, kBatch), k, answers);
    benchmark::DoNotOptimize(answers.data());
    at += kBatch;
  }
  state.SetItemsProcessed(int64_t(state.iterations() * kBatch));
}

}  // namespace

int main(int argc, char** argv) {
  for (const SchemeInfo& scheme : schemes())
    for (int set = 0; set < 2; ++set)
      for (int k : kStandardFilters)
        benchmark::RegisterBenchmark(
            (scheme.name + "/" + (set == 0 ? "uniform" : "view") + "/k" + std::to_string(k))
                .c_str(),
            lookups, &scheme, set, k);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
