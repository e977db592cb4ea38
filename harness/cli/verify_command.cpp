#include <memory>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/progress.h"
#include "harness/verify.h"

namespace sb::cli {

namespace {

struct VerifyCommandOptions {
  MapOptions map;
  std::string structure;
  uint64_t sampledQueries = 10'000'000;
};

int verifyStructure(const VerifyCommandOptions& o) {
  const LoadedStructure loaded(o.structure, o.map);
  VerifyOptions options;
  options.sampledQueries = o.sampledQueries;
  Progress progress("verify", 0, "queries");
  const VerifyReport report =
      verify(*loaded.decoder, findScheme(loaded.header.scheme).kind, loaded.header.map,
             *loaded.source, options, [&](uint64_t done) { progress.set(done); });
  progress.finish();
  printVerification(report.toJson());
  return report.mismatches ? 1 : 0;
}

}  // namespace

void addVerifyCommand(CLI::App& app) {
  auto o = std::make_shared<VerifyCommandOptions>();
  CLI::App* sub = app.add_subcommand("verify", "check a saved structure against the reference");
  o->map.addTo(sub, false);
  sub->add_option("structure", o->structure, "structure file")->required();
  addSampledQueries(sub, o->sampledQueries);
  sub->callback([o] { setExitStatus(verifyStructure(*o)); });
}

}  // namespace sb::cli
