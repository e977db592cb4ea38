#include <memory>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "schemes/interface/atomic_file.h"

namespace sb::cli {

namespace {

struct BuildOptions {
  MapOptions map;
  SchemeOptions schemes;
  PartOptions parts;
  RecordOptions record;
};

int buildCells(const BuildOptions& o) {
  // Everything the scene is not needed for is checked before it is opened, and the light (in
  // runCells) before the depth pass: a typo or an output that cannot be written must not cost a
  // build (issue 11 A2, A9).
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  o.record.checkOutputs(cells, o.map.scene);
  if (cells.front().partSize) checkWritableFolder(o.parts.partsRoot);
  const Scene scene = openScene(o.map.scene);
  bool mismatches = false;
  runCells(cells, scene, o.record.cellOptions(o.parts), [&](size_t, const Record& built) {
    mismatches = writeCellRecord(built, o.record.results) || mismatches;
  });
  return mismatches ? 1 : 0;
}

}  // namespace

void addBuildCommand(CLI::App& app) {
  auto o = std::make_shared<BuildOptions>();
  CLI::App* sub = app.add_subcommand(
      "build", "build schemes for a scene (one depth pass), verify, time lookups, record each");
  o->map.addTo(sub);
  o->schemes.addTo(sub, "sm32");
  o->parts.addTo(sub, false);
  o->record.addTo(sub);
  sub->callback([o] { setExitStatus(buildCells(*o)); });
}

}  // namespace sb::cli
