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
  ThreadOptions threads;
  RecordOptions record;
};

int mergeCells(const MergeOptions& o) {
  const auto threadLimit = o.threads.apply();
  const std::vector<CellSpec> cells = cellsOf(o.map, o.schemes, o.parts);
  o.record.checkOutputs(cells, o.map.scene);
  const Scene scene = openScene(o.map.scene);
  const CellOptions options = o.record.cellOptions(o.parts);
  bool mismatches = false;
  mergeCells(cells, scene, options, [&](size_t, const Record& record) {
    mismatches = writeCellRecord(record, o.record.results) || mismatches;
  });
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
  o->threads.addTo(sub);
  o->parts.addTo(sub, true);
  o->record.addTo(sub);
  sub->callback([o] { setExitStatus(mergeCells(*o)); });
}

}  // namespace sb::cli
