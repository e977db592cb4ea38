#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "harness/build.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/depth_source.h"

namespace sb::cli {

namespace {

struct EstimateOptions {
  MapOptions map;
  SchemeOptions schemes;
  PartOptions parts;
};

// The declared build memory a scheduler reserves for a job: one part of every scheme of a part
// job at once, or one scheme's merge (the larger of the two is what buildBytes declares).
void printEstimate(const EstimateOptions& o) {
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  nlohmann::json perScheme = nlohmann::json::object();
  uint64_t together = 0;
  for (const CellSpec& cell : cells) {
    const SchemeInfo& scheme = findScheme(cell.scheme);
    const BuildShape shape{cell.tileSize ? cell.tileSize : defaultTileSize(cell.resolution),
                           cell.partSize};
    const MapInfo map = mapFor(scheme, cell.mode, cell.resolution);
    const uint64_t bytes =
        scheme.buildBytes ? scheme.buildBytes(map, scheme.resolve(cell.params), shape) : 0;
    perScheme[cell.scheme] = bytes;
    together += bytes;
  }
  fmt::print("{}\n", nlohmann::json{{"build_bytes", together}, {"schemes", perScheme}}.dump());
  flushStandardOutput();
}

}  // namespace

void addEstimateCommand(CLI::App& app) {
  auto o = std::make_shared<EstimateOptions>();
  CLI::App* sub = app.add_subcommand(
      "estimate",
      "print the declared build memory as JSON {\"build_bytes\": N, \"schemes\": {…}}: every "
      "scheme's at once, as a job building them from one depth pass needs");
  o->map.addTo(sub);
  o->schemes.addTo(sub, "mh");
  o->parts.addTo(sub, false);
  sub->callback([o] { printEstimate(*o); });
}

}  // namespace sb::cli
