#include <memory>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/lookup_timing.h"
#include "harness/query_sets.h"

namespace sb::cli {

namespace {

struct BenchOptions {
  MapOptions map;
  std::string structure;
};

void benchStructure(const BenchOptions& o) {
  const LoadedStructure loaded(o.structure, o.map);
  const QuerySet sets[] = {standardUniformQueries(),
                           standardViewQueries(loaded.scene, *loaded.source)};
  for (const QuerySet& set : sets)
    for (int k : kStandardFilters) {
      const LookupTiming t = timeLookups(*loaded.decoder, set, k);
      fmt::print("{:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} threads)",
                 t.querySet, k, k, t.nsPerQuerySingleThread, t.mqueriesPerSecondAllThreads,
                 t.threads);
      if (t.cacheHitRate) fmt::print(", cache hits {:.1f}%", 100 * *t.cacheHitRate);
      fmt::print("\n");
    }
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* sub = app.add_subcommand("bench", "time lookups of a saved structure");
  o->map.addTo(sub, false);
  sub->add_option("structure", o->structure, "structure file")->required();
  sub->callback([o] { benchStructure(*o); });
}

}  // namespace sb::cli
