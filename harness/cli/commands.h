// The shadowbench subcommands, one file each: every add…Command adds its subcommand, its own
// options and its callback to the app (DESIGN §6).
#pragma once

#include <CLI/CLI.hpp>

namespace sb::cli {

void addSchemesCommand(CLI::App& app);
void addSceneCommand(CLI::App& app);
void addDepthCommand(CLI::App& app);
void addBuildCommand(CLI::App& app);
void addPartCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addEstimateCommand(CLI::App& app);
void addVerifyCommand(CLI::App& app);
void addQueryCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addSweepCommand(CLI::App& app);
void addTableCommand(CLI::App& app);
void addDistantFiltersCommand(CLI::App& app);
void addSoakCommand(CLI::App& app);
void addViewsCommand(CLI::App& app);  // also `path`

}  // namespace sb::cli
