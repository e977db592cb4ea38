#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/table.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct TableOptions {
  std::string records = "results/sweep", out;
};

void writeTablesOf(const TableOptions& o) {
  const FolderTables found = tablesOfFolder(o.records);
  for (const std::string& problem : found.problems) fmt::print(stderr, "table: {}\n", problem);
  if (found.records == 0)
    throw std::runtime_error(fmt::format("no complete records under '{}'", o.records));
  writeTables(found.tables, o.out.empty() ? fs::path(o.records) / "tables" : fs::path(o.out));
  fmt::print("{}", toMarkdown(found.tables));
}

}  // namespace

void addTableCommand(CLI::App& app) {
  auto o = std::make_shared<TableOptions>();
  CLI::App* sub = app.add_subcommand("table", "regenerate Markdown and CSV tables from records");
  sub->add_option("records", o->records, "records folder")->capture_default_str();
  sub->add_option("--out", o->out, "folder for tables.md and CSVs (default RECORDS/tables)");
  sub->callback([o] { writeTablesOf(*o); });
}

}  // namespace sb::cli
