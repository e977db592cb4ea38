#include <memory>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"

namespace sb::cli {

namespace {

struct MergeOptions {
  MapOptions map;
  SchemeOptions schemes;
  PartOptions parts;
  RecordOptions record;
};

int mergeCells(const MergeOptions& o) {
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  o.record.checkOutputs(cells, o.map.scene);
  const Scene scene = openScene(o.map.scene);
  const CellOptions options = o.record.cellOptions(o.parts);
  bool mismatches = false;
  for (const CellSpec& cell : cells)
    mismatches = writeCellRecord(mergeCell(cell, scene, options), o.record.results) || mismatches;
  return mismatches ? 1 : 0;
}

}  // namespace

void addMergeCommand(CLI::App& app) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* sub = app.add_subcommand(
      "merge",
      "merge the part files of a build in parts into its structure, verify, time lookups, record");
  o->map.addTo(sub);
  o->schemes.addTo(sub, "mh");
  o->parts.addTo(sub, true);
  o->record.addTo(sub);
  sub->callback([o] { setExitStatus(mergeCells(*o)); });
}

}  // namespace sb::cli
