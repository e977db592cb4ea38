#include <filesystem>
#include <memory>
#include <set>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/record.h"
#include "harness/table.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct SweepOptions {
  std::string scenes = "city", modes = "closed", schemes = "all";
  std::string resolutions = "1K,2K,4K,8K", out = "results/sweep";
  std::vector<std::string> params;
  bool noBench = false;
  uint64_t sampledQueries = 10'000'000;
};

// The --param assignments that `scheme` declares. A sweep's parameters go only to the schemes
// that have them, so one sweep can set a parameter of one scheme (culling=off) beside others.
Params declaredParams(const SchemeInfo& scheme, const Params& given) {
  Params own;
  for (const ParamSpec& spec : scheme.params)
    if (const auto it = given.find(spec.name); it != given.end()) own.insert(*it);
  return own;
}

int sweep(const SweepOptions& o) {
  std::vector<std::string> schemeNames = splitList(o.schemes);
  if (o.schemes == "all") {
    schemeNames.clear();
    for (const SchemeInfo& s : schemes()) schemeNames.push_back(s.name);
  }
  // Checked before the first build: a misspelt name or a bad value is an error, not a sweep of
  // default cells or of failed ones.
  const Params params = parseParams(o.params);
  std::set<std::string> declared;
  for (const std::string& name : schemeNames) {
    const SchemeInfo& scheme = findScheme(name);
    scheme.resolve(declaredParams(scheme, params));  // throws on a bad value
    for (const ParamSpec& spec : scheme.params) declared.insert(spec.name);
  }
  for (const auto& [name, value] : params)
    if (!declared.count(name))
      throw std::invalid_argument(
          fmt::format("no swept scheme has a parameter '{}' (see 'shadowbench schemes')", name));
  CellOptions options;
  options.benchLookups = !o.noBench;
  options.verifyOptions.sampledQueries = o.sampledQueries;
  size_t done = 0, skipped = 0, failed = 0;
  for (const std::string& spec : splitList(o.scenes)) {
    const Scene scene = openScene(spec);
    for (const std::string& mode : splitList(o.modes))
      for (const std::string& name : schemeNames) {
        const Params own = declaredParams(findScheme(name), params);
        for (const std::string& res : splitList(o.resolutions)) {
          const CellSpec cell{spec, 0, depthModeFromString(mode), name, own, parseResolution(res),
                              0};
          const fs::path path = fs::path(o.out) / (cellKey(cellIdentity(cell, scene)) + ".json");
          if (readRecord(path)) {
            ++skipped;
            continue;
          }
          try {
            const nlohmann::json record = runCell(cell, scene, options);
            writeJsonAtomically(path, record);
            printCellSummary(record);
            failed += hasMismatches(record);
            ++done;
          } catch (const std::exception& error) {
            // One cell that cannot be built (e.g. too large for memory) does not stop the sweep.
            fmt::print(stderr, "cell {} skipped: {}\n", path.filename().string(), error.what());
            ++failed;
          }
        }
      }
  }
  fmt::print("sweep: {} cells built, {} already done, {} failed or mismatched\n", done, skipped,
             failed);
  const auto tables = makeTables(readRecords(o.out).records);
  writeTables(tables, fs::path(o.out) / "tables");
  fmt::print("{}", toMarkdown(tables));
  return failed ? 1 : 0;
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
  sub->add_option("--out", o->out, "records folder (finished cells there are skipped)")
      ->capture_default_str();
  sub->add_flag("--no-bench", o->noBench, "skip lookup timings");
  addSampledQueries(sub, o->sampledQueries);
  sub->callback([o] { setExitStatus(sweep(*o)); });
}

}  // namespace sb::cli
