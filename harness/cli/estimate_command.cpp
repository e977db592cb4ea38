#include <algorithm>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "harness/build.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/depth_source.h"
#include "harness/parts_build.h"

namespace sb::cli {

namespace {

struct EstimateOptions {
  MapOptions map;
  SchemeOptions schemes;
  PartOptions parts;
};

// The declared build memory a scheduler reserves for a job. A whole build from one depth pass
// holds every scheme's build at once ("build_bytes"); a part job holds one part encoder of every
// scheme ("part_bytes", the sum, one encoder for schemes that share a part payload); a merge job
// one scheme's merge ("merge_bytes", the largest, before the part files exist).
void printEstimate(const EstimateOptions& o) {
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  nlohmann::json perScheme = nlohmann::json::object();
  uint64_t build = 0, merge = 0;
  std::vector<SchemeBuild> builds;
  for (const CellSpec& cell : cells) {
    const SchemeInfo& scheme = findScheme(cell.scheme);
    const MapInfo map = mapFor(scheme, cell.mode, cell.resolution);
    const ParamValues params = scheme.resolve(cell.params);
    const auto bytes = [&](BuildShape::Step step) -> uint64_t {
      BuildShape shape = cell.shape();
      shape.step = step;
      return scheme.buildBytes ? scheme.buildBytes(map, params, shape) : 0;
    };
    nlohmann::json own = {{"build_bytes", bytes(BuildShape::Step::Whole)}};
    build += own["build_bytes"].get<uint64_t>();
    if (cell.partSize) {
      own["part_bytes"] = bytes(BuildShape::Step::EncodePart);
      own["merge_bytes"] = bytes(BuildShape::Step::Merge);
      builds.push_back({&scheme, params});
      merge = std::max(merge, own["merge_bytes"].get<uint64_t>());
    }
    perScheme[cell.scheme] = own;
  }
  nlohmann::json estimate = {{"build_bytes", build}, {"schemes", perScheme}};
  if (cells.front().partSize)
    estimate["part_bytes"] =
        partPassBytes(builds, cells.front().mode, cells.front().resolution, cells.front().shape()),
    estimate["merge_bytes"] = merge;
  fmt::print("{}\n", estimate.dump());
  flushStandardOutput();
}

}  // namespace

void addEstimateCommand(CLI::App& app) {
  auto o = std::make_shared<EstimateOptions>();
  CLI::App* sub = app.add_subcommand(
      "estimate",
      "print the declared build memory as JSON: build_bytes (every scheme's whole build at once, "
      "as one depth pass needs), with --part-size part_bytes (one part of every scheme) and "
      "merge_bytes (the largest merge), and each scheme's own under \"schemes\"");
  o->map.addTo(sub);
  o->schemes.addTo(sub, "mh");
  o->parts.addTo(sub, false);
  sub->callback([o] { printEstimate(*o); });
}

}  // namespace sb::cli
