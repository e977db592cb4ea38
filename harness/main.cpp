// shadowbench — one CLI for building, verifying, querying, sweeping, benchmarking and tabulating
// compressed shadow-map schemes (DESIGN §6). Each subcommand lives in its own file in cli/.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/many_lights.h"

namespace {

// A closed standard stream's descriptor would be handed to the next file opened (a scene, the
// temporary of an atomic write), and output meant for the terminal would land in that file.
// /dev/null opened the other way round holds the descriptor, and every write to it fails with
// EBADF, reported like any other lost output.
void holdClosedStandardStreams() {
  for (const int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO})
    if (::fcntl(fd, F_GETFD) == -1 && errno == EBADF)
      ::open("/dev/null", fd == STDIN_FILENO ? O_WRONLY : O_RDONLY);  // lowest free: fd
}

// std::fprintf, unlike fmt::print, does not throw when stderr itself cannot be written.
int fail(const std::string& message) {
  std::fprintf(stderr, "shadowbench: %s\n", message.c_str());
  return 2;
}

// fmt::print throws std::system_error when a write to standard output fails: the lost output is
// then the error, whatever the message of the exception.
std::string describe(const std::exception& error) {
  const auto* system = dynamic_cast<const std::system_error*>(&error);
  if (system && std::ferror(stdout))
    return fmt::format("cannot write standard output: {}", system->code().message());
  return error.what();
}

}  // namespace

int main(int argc, char** argv) {
  holdClosedStandardStreams();
  CLI::App app{"shadowbench: build, verify and measure compressed precomputed shadow maps"};
  app.require_subcommand(1);
  sb::cli::addSchemesCommand(app);
  sb::cli::addSceneCommand(app);
  sb::cli::addDepthCommand(app);
  sb::cli::addBuildCommand(app);
  sb::cli::addPartCommand(app);
  sb::cli::addMergeCommand(app);
  sb::cli::addEstimateCommand(app);
  sb::cli::addVerifyCommand(app);
  sb::cli::addQueryCommand(app);
  sb::cli::addBenchCommand(app);
  sb::cli::addSweepCommand(app);
  sb::cli::addTableCommand(app);
  sb::addManyLightsCommand(app);
  sb::cli::addDistantFiltersCommand(app);
  sb::cli::addSoakCommand(app);
  sb::cli::addViewsCommand(app);

  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
      if (error.get_exit_code() != 0)
        return fail(fmt::format("{} (run with --help for usage)", error.what()));
      app.exit(error);  // --help: an "error" of status 0 whose text CLI11 prints
    }
    sb::cli::flushStandardOutput();
  } catch (const std::exception& error) {
    return fail(describe(error));
  }
  return sb::cli::exitStatus();
}
