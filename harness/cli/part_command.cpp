#include <memory>
#include <optional>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "schemes/interface/atomic_file.h"

namespace sb::cli {

namespace {

struct PartCommandOptions {
  MapOptions map;
  SchemeOptions schemes;
  PartOptions parts;
  std::optional<uint64_t> part;
};

void encodePart(const PartCommandOptions& o) {
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  checkWritableFolder(o.parts.partsRoot);
  const Scene scene = openScene(o.map.scene);
  CellOptions options;
  options.partsRoot = o.parts.partsRoot;
  const PartsEncoded encoded = encodeCellParts(cells, scene, options, o.part);
  fmt::print("parts encoded: {}, already there: {}\n", encoded.encoded, encoded.kept);
}

}  // namespace

void addPartCommand(CLI::App& app) {
  auto o = std::make_shared<PartCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "part",
      "encode parts of a build in parts (one depth pass per part for every scheme), saving a "
      "part file per scheme; parts already there are kept");
  o->map.addTo(sub);
  o->schemes.addTo(sub, "mh");
  o->parts.addTo(sub, true);
  sub->add_option("--part", o->part, "only this part (0 to (R / part size)² − 1); default all");
  sub->callback([o] { encodePart(*o); });
}

}  // namespace sb::cli
