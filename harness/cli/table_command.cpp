#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/record.h"
#include "harness/table.h"

namespace fs = std::filesystem;

namespace sb::cli {

namespace {

struct TableOptions {
  std::string records = "results/sweep", out;
};

void writeTablesOf(const TableOptions& o) {
  const auto loaded = readRecords(o.records);
  if (loaded.records.empty())
    throw std::runtime_error(fmt::format("no complete records under '{}'", o.records));
  const auto tables = makeTables(loaded.records);
  writeTables(tables, o.out.empty() ? fs::path(o.records) / "tables" : fs::path(o.out));
  fmt::print("{}", toMarkdown(tables));
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
