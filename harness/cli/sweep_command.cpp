#include <memory>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/sweep.h"

namespace sb::cli {

namespace {

struct SweepOptions {
  std::string scenes = "city", modes = "closed", schemes = "all";
  std::string resolutions = "1K,2K,4K,8K", out = "results/sweep";
  std::vector<std::string> params;
  PartOptions parts;
  bool noBench = false;
  uint64_t sampledQueries = 10'000'000;
};

int sweep(const SweepOptions& o) {
  SweepSpec spec;
  spec.scenes = splitList(o.scenes);
  spec.modes = splitList(o.modes);
  spec.schemes = splitList(o.schemes);
  spec.resolutions = splitList(o.resolutions);
  spec.params = parseParams(o.params);
  spec.out = o.out;
  spec.partSize = o.parts.partSizeValue();
  spec.cellOptions.partsRoot = o.parts.partsRoot;
  spec.cellOptions.benchLookups = !o.noBench;
  spec.cellOptions.verifyOptions.sampledQueries = o.sampledQueries;
  SweepEvents events;
  events.built = [](const Record& record) { printCellSummary(nlohmann::json(record)); };
  events.warning = [](const std::string& message) { fmt::print(stderr, "{}\n", message); };
  const SweepOutcome outcome = runSweep(spec, events);
  fmt::print("sweep: {} cells built, {} already done, {} failed or mismatched", outcome.built,
             outcome.reused, outcome.failed);
  if (outcome.superseded) fmt::print(", {} older records moved aside", outcome.superseded);
  fmt::print("\n{}", toMarkdown(outcome.tables));
  return outcome.failed ? 1 : 0;
}

}  // namespace

void addSweepCommand(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* sub =
      app.add_subcommand("sweep", "build every cell of a matrix, resuming finished cells");
  sub->add_option("--scenes", o->scenes, "comma-separated scene specs")->capture_default_str();
  sub->add_option("--modes", o->modes, "comma-separated modes")->capture_default_str();
  sub->add_option("--schemes", o->schemes, "comma-separated schemes, or all")
      ->capture_default_str();
  sub->add_option("--resolutions", o->resolutions, "comma-separated resolutions")
      ->capture_default_str();
  sub->add_option("--param,-p", o->params,
                  "scheme parameter name=value for the swept schemes that declare it "
                  "(repeatable); it names the cells' records");
  sub->add_option("--out", o->out,
                  "records folder (cells with a record there are reused; other sweeps may share "
                  "it)")
      ->capture_default_str();
  o->parts.addTo(sub, false);
  sub->add_flag("--no-bench", o->noBench, "skip lookup timings");
  addSampledQueries(sub, o->sampledQueries);
  sub->callback([o] { setExitStatus(sweep(*o)); });
}

}  // namespace sb::cli
