#include <algorithm>
#include <charconv>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/lookup_timing.h"
#include "harness/query_sets.h"

namespace sb::cli {

namespace {

struct BenchOptions {
  MapOptions map;
  std::vector<std::string> structures;
  std::vector<int> filters{std::begin(kStandardFilters), std::end(kStandardFilters)};
  int rounds = 5;
};

void benchOne(const LoadedStructure& loaded, std::span<const QuerySet> sets,
              const BenchOptions& o) {
  for (const QuerySet& set : sets)
    for (int k : o.filters) {
      const LookupTiming t = timeLookups(*loaded.decoder, set, k, o.rounds);
      fmt::print("{:8} {:2}×{:<2}: {:8.1f} ns/query (1 thread), {:8.1f} Mqueries/s ({} threads)",
                 t.querySet, k, k, t.nsPerQuerySingleThread, t.mqueriesPerSecondAllThreads,
                 t.threads);
      if (t.cacheHitRate) fmt::print(", cache hits {:.1f}%", 100 * *t.cacheHitRate);
      fmt::print("\n");
    }
}

// Several structures of one map, timed in turn (timeLookupsInTurn): each one's ns per query, and
// the others' over the first's, round by round.
void benchInTurn(const LoadedStructure& first, std::span<const QuerySet> sets,
                 const BenchOptions& o) {
  std::vector<std::unique_ptr<Decoder>> others;
  std::vector<const Decoder*> decoders{first.decoder.get()};
  for (size_t s = 1; s < o.structures.size(); ++s) {
    StructureHeader header;
    others.push_back(loadStructure(o.structures[s], &header));
    const MapInfo& map = first.header.map;
    const bool sameScene = header.sceneHash == first.header.sceneHash;
    if (header.map.resolution != map.resolution || header.map.mode != map.mode || !sameScene)
      throw std::runtime_error(fmt::format(
          "structure '{}' is of another map than '{}' ({}, {}² against {}, {}²{}): structures "
          "timed in turn must answer the same queries",
          o.structures[s], o.structures[0], toString(header.map.mode), header.map.resolution,
          toString(map.mode), map.resolution, sameScene ? "" : ", and another scene"));
    decoders.push_back(others.back().get());
  }
  const size_t width = std::max_element(o.structures.begin(), o.structures.end(),
                                        [](const std::string& a, const std::string& b) {
                                          return a.size() < b.size();
                                        })
                           ->size();
  for (const QuerySet& set : sets)
    for (int k : o.filters) {
      const InTurnTimings t = timeLookupsInTurn(decoders, set, k, o.rounds);
      fmt::print(
          "{} {}×{}, {} rounds of {} queries in turn: ns/query (1 thread), median and range; "
          "over the first, the median and range of the rounds' ratios\n",
          set.name, k, k, o.rounds, t.queries);
      for (size_t d = 0; d < decoders.size(); ++d) {
        const Spread ns(t.nsPerQuery[d]);
        fmt::print("  {:{}}  {:8.1f}  {:8.1f}–{:<8.1f}", o.structures[d], width, ns.median, ns.min,
                   ns.max);
        if (d > 0) {
          std::vector<double> ratios;
          for (int r = 0; r < o.rounds; ++r)
            ratios.push_back(t.nsPerQuery[d][r] / t.nsPerQuery[0][r]);
          const Spread ratio(ratios);
          fmt::print("  {:.2f}×  {:.2f}–{:.2f}", ratio.median, ratio.min, ratio.max);
        }
        fmt::print("\n");
      }
    }
}

void bench(const BenchOptions& o) {
  const LoadedStructure first(o.structures[0], o.map);
  const QuerySet sets[] = {standardUniformQueries(),
                           standardViewQueries(first.scene, *first.source)};
  if (o.structures.size() == 1) return benchOne(first, sets, o);
  benchInTurn(first, sets, o);
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* sub = app.add_subcommand(
      "bench",
      "time lookups of saved structures: one alone (single thread and all threads), or several "
      "of one map in turn, round by round, with their ratios to the first");
  o->map.addTo(sub, false);
  sub->add_option("structures", o->structures, "structure files")->required();
  sub->add_option("--filters", o->filters, "filter sizes k (k×k PCF; 1 = point lookups)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& value) {
            int k = 0;
            const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), k);
            const bool odd = error == std::errc() && end == value.data() + value.size() && k >= 1 &&
                             k <= 17 && k % 2 == 1;
            return odd ? std::string()
                       : fmt::format("'{}' is not a filter size: odd, from 1 to 17 (DESIGN §4)",
                                     value);
          },
          "ODD 1..17"));
  sub->add_option("--rounds", o->rounds, "runs of each structure (their median is reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  sub->callback([o] { bench(*o); });
}

}  // namespace sb::cli
