// shadowbench — one CLI for building, verifying, querying, sweeping, benchmarking and tabulating
// compressed shadow-map schemes (DESIGN §6). Each subcommand lives in its own file in cli/.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/many_lights.h"

int main(int argc, char** argv) {
  CLI::App app{"shadowbench: build, verify and measure compressed precomputed shadow maps"};
  app.require_subcommand(1);
  sb::cli::addSchemesCommand(app);
  sb::cli::addSceneCommand(app);
  sb::cli::addDepthCommand(app);
  sb::cli::addBuildCommand(app);
  sb::cli::addVerifyCommand(app);
  sb::cli::addQueryCommand(app);
  sb::cli::addBenchCommand(app);
  sb::cli::addSweepCommand(app);
  sb::cli::addTableCommand(app);
  sb::addManyLightsCommand(app);
  sb::cli::addDistantFiltersCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const std::exception& error) {
    fmt::print(stderr, "shadowbench: {}\n", error.what());
    return 2;
  }
  return sb::cli::exitStatus();
}
