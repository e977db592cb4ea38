// Tables regenerated from synthetic records: ordering, analytic rows, duplicates, missing cells,
// records left out and why, the number formats, and the Markdown / CSV output.
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/cell_key.h"
#include "harness/record.h"
#include "harness/table.h"
#include "harness/table_number.h"
#include "tests/support/scratch_dir.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kMiB = 1 << 20;

// A minimal complete record of one cell; tests add the optional parts they look at.
json record(const std::string& scheme, uint64_t resolution, double bytes,
            json params = json::object(), const std::string& created = "2026-11-26T10:00:00Z") {
  return {{"format", "shadowbench-record/1"},
          {"complete", true},
          {"scene", {{"name", "city:size=24,seed=1"}, {"spec", "city"}}},
          {"light_index", 0},
          {"mode", "closed"},
          {"scheme", {{"name", scheme}, {"params", params}}},
          {"resolution", resolution},
          {"size_bytes", {{"total", bytes}}},
          {"created", created}};
}

// The records the tables read, from their JSON form.
std::vector<sb::Table> tablesOf(const std::vector<json>& records) {
  std::vector<sb::Record> typed;
  for (const json& r : records) typed.push_back(r.get<sb::Record>());
  return sb::makeTables(typed);
}

const sb::Table& tableTitled(const std::vector<sb::Table>& tables, const std::string& prefix) {
  const auto it = std::find_if(tables.begin(), tables.end(),
                               [&](const sb::Table& t) { return t.title.rfind(prefix, 0) == 0; });
  if (it == tables.end()) FAIL("no table titled '" << prefix << "…'");
  return *it;
}

bool hasTableTitled(const std::vector<sb::Table>& tables, const std::string& prefix) {
  return std::any_of(tables.begin(), tables.end(),
                     [&](const sb::Table& t) { return t.title.rfind(prefix, 0) == 0; });
}

const std::vector<std::string>& rowLabelled(const sb::Table& table, const std::string& label) {
  const auto it = std::find_if(table.rows.begin(), table.rows.end(),
                               [&](const auto& row) { return !row.empty() && row[0] == label; });
  if (it == table.rows.end()) FAIL("no row '" << label << "' in '" << table.title << "'");
  return *it;
}

std::vector<std::string> rowLabels(const sb::Table& table) {
  std::vector<std::string> labels;
  for (const auto& row : table.rows) labels.push_back(row.at(0));
  return labels;
}

std::string cell(const sb::Table& table, const std::string& row, const std::string& column) {
  const auto at = std::find(table.header.begin(), table.header.end(), column);
  if (at == table.header.end()) FAIL("no column '" << column << "' in '" << table.title << "'");
  return rowLabelled(table, row).at(size_t(at - table.header.begin()));
}

void checkRectangular(const std::vector<sb::Table>& tables) {
  for (const sb::Table& t : tables)
    for (const auto& row : t.rows) {
      INFO(t.title);
      CHECK(row.size() == t.header.size());
    }
}

}  // namespace

TEST_CASE("the analytic shadow-map rows are R²·2 and R²·4 bytes in MiB, exactly", "[table]") {
  std::vector<json> records;
  for (uint64_t r : {256u, 512u, 4096u, 65536u, 262144u})
    records.push_back(record("sm32", r, double(r * r * 4)));
  const auto tables = tablesOf(records);
  checkRectangular(tables);
  const sb::Table& size = tableTitled(tables, "Size — ");
  const sb::Table& percent = tableTitled(tables, "Size relative");
  for (uint64_t r : {256u, 512u, 4096u, 65536u, 262144u}) {
    const std::string column = sb::resolutionHeading(r);
    INFO(column);
    CHECK(std::stod(cell(size, "16-bit shadow map (analytic)", column)) ==
          double(r * r * 2) / kMiB);
    CHECK(std::stod(cell(size, "32-bit shadow map (analytic)", column)) ==
          double(r * r * 4) / kMiB);
    CHECK(cell(size, "sm32", column) == cell(size, "32-bit shadow map (analytic)", column));
    CHECK(cell(percent, "16-bit shadow map (analytic)", column) == "100");
    CHECK(cell(percent, "32-bit shadow map (analytic)", column) == "200");
  }
  CHECK(cell(size, "16-bit shadow map (analytic)", "256K²") == "131072");
  CHECK(cell(size, "16-bit shadow map (analytic)", "4K²") == "32.0");
  CHECK(cell(size, "16-bit shadow map (analytic)", "256²") == "0.125");
}

TEST_CASE("resolutions are columns in numeric order, sm32 is the first row", "[table]") {
  std::vector<json> records;
  for (uint64_t r : {4096u, 512u, 262144u, 1024u, 2048u})
    for (const char* scheme : {"mmh", "cpvs", "sm32", "dag"})
      records.push_back(record(scheme, r, 1000));
  records.push_back(record("mmh", 1024, 500, {{"search", "1000"}}));
  records.push_back(record("mmh", 1024, 500, {{"search", "200"}}));
  for (json& r : records) r["time_s"] = {{"total", 1.0}};
  const auto tables = tablesOf(records);
  checkRectangular(tables);
  const sb::Table& size = tableTitled(tables, "Size — ");
  CHECK(size.header == std::vector<std::string>{"scheme", "512²", "1K²", "2K²", "4K²", "256K²"});
  CHECK(rowLabels(size) == std::vector<std::string>{"sm32", "cpvs", "dag", "mmh",
                                                    "mmh (search=200)", "mmh (search=1000)",
                                                    "16-bit shadow map (analytic)",
                                                    "32-bit shadow map (analytic)"});
  CHECK(tableTitled(tables, "Build time").rows.at(0).at(0) == "sm32");
}

TEST_CASE("the newest record of a cell wins, whatever the input order", "[table]") {
  const json older = record("sm32", 1024, 100 * kMiB, json::object(), "2026-01-01T00:00:00Z");
  const json newer = record("sm32", 1024, 50 * kMiB, json::object(), "2026-02-01T00:00:00Z");
  for (const auto& records : {std::vector<json>{older, newer}, std::vector<json>{newer, older}}) {
    const auto tables = tablesOf(records);
    const sb::Table& size = tableTitled(tables, "Size — ");
    CHECK(cell(size, "sm32", "1K²") == "50.0");
    CHECK(std::count(size.rows.begin(), size.rows.end(), rowLabelled(size, "sm32")) == 1);
  }
}

TEST_CASE("cells without a record, or without the measurement, show –", "[table]") {
  json a = record("aaa", 512, kMiB);
  a["time_s"] = {{"total", 3.2}};
  a["depth"] = {{"mtexels_per_s", 5.8}};
  a["verification"] = {{"method", "exhaustive"}, {"queries", 12'345'678}, {"mismatches", 0}};
  json b = record("bbb", 1024, 2 * kMiB);
  b["verification"] = {{"method", "sampled"}, {"queries", 10'000'000}, {"mismatches", 5}};
  const auto tables = tablesOf({a, b});
  checkRectangular(tables);

  const sb::Table& size = tableTitled(tables, "Size — ");
  CHECK(cell(size, "aaa", "512²") == "1.00");
  CHECK(cell(size, "aaa", "1K²") == "–");
  CHECK(cell(size, "bbb", "512²") == "–");
  CHECK(cell(size, "bbb", "1K²") == "2.00");
  CHECK(cell(tableTitled(tables, "Size relative"), "bbb", "1K²") == "100");

  const sb::Table& time = tableTitled(tables, "Build time");
  CHECK(cell(time, "aaa", "512²") == "3.20 (5.80)");
  CHECK(cell(time, "bbb", "1K²") == "–");

  const sb::Table& verification = tableTitled(tables, "Verification");
  CHECK(cell(verification, "aaa", "512²") == "12.3M / 0");
  CHECK(cell(verification, "bbb", "1K²") == "10.0M / 5 (sampled) FAIL");
  CHECK(cell(verification, "bbb", "512²") == "–");

  CHECK_FALSE(hasTableTitled(tables, "Lookup"));
  CHECK_FALSE(hasTableTitled(tablesOf({record("aaa", 512, 1)}), "Verification"));
}

TEST_CASE("lookup tables have a row per scheme and resolution, a column per query set and filter",
          "[table]") {
  json a = record("sm32", 1024, 1);
  a["lookup"] = {{{"query_set", "view"},
                  {"filter", 1},
                  {"ns_per_query_1t", 20.0},
                  {"mqueries_per_s_all", 90.0},
                  {"threads", 2}},
                 {{"query_set", "uniform"},
                  {"filter", 17},
                  {"ns_per_query_1t", 400.0},
                  {"mqueries_per_s_all", 5.0},
                  {"threads", 2}},
                 {{"query_set", "uniform"},
                  {"filter", 3},
                  {"ns_per_query_1t", 40.0},
                  {"mqueries_per_s_all", 50.0},
                  {"threads", 2}},
                 {{"query_set", "uniform"},
                  {"filter", 1},
                  {"ns_per_query_1t", 12.5},
                  {"mqueries_per_s_all", 150.0},
                  {"threads", 2}}};
  json b = record("mmh", 4096, 1);  // not timed
  const auto tables = tablesOf({a, b});
  checkRectangular(tables);
  const sb::Table& ns = tableTitled(tables, "Lookup time, one thread");
  const sb::Table& mqps = tableTitled(tables, "Lookup throughput");
  CHECK(ns.header == std::vector<std::string>{"scheme", "resolution", "uniform 1×1", "uniform 3×3",
                                              "uniform 17×17", "view 1×1"});
  CHECK(ns.rows ==
        std::vector<std::vector<std::string>>{{"sm32", "1K²", "12.5", "40.0", "400", "20.0"},
                                              {"mmh", "4K²", "–", "–", "–", "–"}});
  CHECK(mqps.rows.at(0) == std::vector<std::string>{"sm32", "1K²", "150", "50.0", "5.00", "90.0"});
  CHECK(mqps.unit_note.find("(2)") != std::string::npos);
}

TEST_CASE("each scene, light and mode gets its own tables", "[table]") {
  json open = record("sm32", 512, 1), light1 = record("sm32", 512, 1),
       terrain = record("sm32", 512, 1);
  open["mode"] = "open";
  light1["light_index"] = 1;
  terrain["scene"]["name"] = "terrain:size=8,seed=1";
  const auto tables = tablesOf({record("sm32", 512, 1), open, light1, terrain});
  std::vector<std::string> sizeTitles, slugs;
  for (const sb::Table& t : tables) {
    if (t.title.rfind("Size — ", 0) == 0) sizeTitles.push_back(t.title);
    slugs.push_back(t.slug);
  }
  CHECK(sizeTitles == std::vector<std::string>{"Size — city:size=24,seed=1, light 0, closed",
                                               "Size — city:size=24,seed=1, light 0, open",
                                               "Size — city:size=24,seed=1, light 1, closed",
                                               "Size — terrain:size=8,seed=1, light 0, closed"});
  std::sort(slugs.begin(), slugs.end());
  CHECK(std::adjacent_find(slugs.begin(), slugs.end()) == slugs.end());
  CHECK(std::find(slugs.begin(), slugs.end(), "size-mib_city-size-24-seed-1_0_closed") !=
        slugs.end());
}

TEST_CASE("CSV follows RFC 4180 and Markdown escapes pipes", "[table]") {
  const sb::Table table{
      "A, \"quoted\" | title",
      "unit",
      {"scheme", "4K²"},
      {{"mmh (search=1000, height=3)", "1.00"}, {"say \"hi\"", "line\nbreak"}, {"plain", "–"}},
      ""};
  CHECK(sb::toCsv(table) ==
        "scheme,4K²\r\n"
        "\"mmh (search=1000, height=3)\",1.00\r\n"
        "\"say \"\"hi\"\"\",\"line\nbreak\"\r\n"
        "plain,–\r\n");
  const std::string markdown = sb::toMarkdown({table});
  CHECK(markdown.find("## A, \"quoted\" | title\n") != std::string::npos);
  CHECK(markdown.find("| scheme | 4K² |\n| --- | ---: |\n") != std::string::npos);
  CHECK(markdown.find("| say \"hi\" | line break |\n") != std::string::npos);

  const sb::Table piped{"t", "", {"a|b"}, {{"c|d"}}, ""};
  CHECK(sb::toMarkdown({piped}).find("| a\\|b |") != std::string::npos);
}

TEST_CASE("writeTables writes tables.md and one CSV per table, named by slug", "[table]") {
  std::string pattern = (fs::temp_directory_path() / "sb-table-test-XXXXXX").string();
  REQUIRE(mkdtemp(pattern.data()));
  const fs::path dir = fs::path(pattern) / "tables";
  json a = record("sm32", 512, 1);
  a["time_s"] = {{"total", 1.0}};
  auto tables = tablesOf({a});
  tables.push_back({"Odd / title", "", {"x"}, {{"1"}}, ""});
  tables.push_back({"Odd / title", "", {"x"}, {{"2"}}, ""});  // the same slug twice
  sb::writeTables(tables, dir);

  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir))
    files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  // A title with characters beyond ordinary punctuation gets a hash in its file name.
  const std::string odd = sb::fileNamePart("Odd / title");
  CHECK(odd.rfind("odd-title-", 0) == 0);
  CHECK(files ==
        std::vector<std::string>{"build-time_city-size-24-seed-1_0_closed.csv", odd + "-2.csv",
                                 odd + ".csv", "size-mib_city-size-24-seed-1_0_closed.csv",
                                 "size-percent_city-size-24-seed-1_0_closed.csv", "tables.md"});
  std::ifstream in(dir / "size-mib_city-size-24-seed-1_0_closed.csv", std::ios::binary);
  std::stringstream csv;
  csv << in.rdbuf();
  CHECK(csv.str() == sb::toCsv(tables.at(0)));
  fs::remove_all(pattern);
}

// Issue 11 A4: `table` skipped half-written, empty and nonsense records without a word, let the
// last of duplicate records win silently, and printed a negative size.
TEST_CASE("tablesOfFolder names every record it leaves out and why", "[table]") {
  sb::testing::ScratchDir dir("sb-table-test");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path() / name, std::ios::binary) << text;
  };
  json good = record("sm32", 512, kMiB, json::object(), "2026-02-01T00:00:00Z");
  json older = record("sm32", 512, 2 * kMiB, json::object(), "2026-01-01T00:00:00Z");
  json negative = record("mmh", 512, -1);
  json oddResolution = record("mmh", 1000, kMiB);
  json negativeTime = record("mmh", 1024, kMiB);
  negativeTime["time_s"] = {{"total", -2.0}};
  json incomplete = record("mmh", 2048, kMiB);
  incomplete["complete"] = false;
  write("good.json", good.dump());
  write("older.json", older.dump());
  write("empty.json", "");
  write("half.json", good.dump().substr(0, 40));
  write("negative.json", negative.dump());
  write("odd-resolution.json", oddResolution.dump());
  write("negative-time.json", negativeTime.dump());
  write("incomplete.json", incomplete.dump());
  write("list.json", "[1, 2]");

  const sb::FolderTables found = sb::tablesOfFolder(dir.path());
  CHECK(found.records == 1);
  const auto said = [&](const std::string& file, const std::string& words) {
    for (const std::string& problem : found.problems)
      if (problem.find((dir.path() / file).string()) != std::string::npos &&
          problem.find(words) != std::string::npos)
        return true;
    return false;
  };
  for (const std::string& problem : found.problems) UNSCOPED_INFO(problem);
  CHECK(found.problems.size() == 8);
  CHECK(said("empty.json", "is empty"));
  CHECK(said("half.json", "is not JSON"));
  CHECK(said("negative.json", "size_bytes.total is -1"));
  CHECK(said("odd-resolution.json", "resolution is 1000"));
  CHECK(said("negative-time.json", "time_s.total is -2.0"));
  CHECK(said("incomplete.json", "complete is false"));
  CHECK(said("list.json", "not an object"));
  // The duplicate names both files, which one is used and why.
  CHECK(said("older.json", (dir.path() / "good.json").string()));
  CHECK(said("older.json",
             "the first is not used (created 2026-01-01T00:00:00Z, the used one "
             "2026-02-01T00:00:00Z)"));

  const sb::Table& size = tableTitled(found.tables, "Size — ");
  CHECK(rowLabels(size) == std::vector<std::string>{"sm32", "16-bit shadow map (analytic)",
                                                    "32-bit shadow map (analytic)"});
  CHECK(cell(size, "sm32", "512²") == "1.00");

  // Duplicates of equal time: the later file is used, and that is said.
  write("same-time.json", good.dump());
  const sb::FolderTables tie = sb::tablesOfFolder(dir.path());
  CHECK(std::any_of(tie.problems.begin(), tie.problems.end(), [&](const std::string& p) {
    return p.find((dir.path() / "good.json").string() + "' and '" +
                  (dir.path() / "same-time.json").string()) != std::string::npos &&
           p.find("both created 2026-02-01T00:00:00Z; the later file is used") != std::string::npos;
  }));
}

TEST_CASE("table numbers are formatted as tests/golden/number_format.tsv says", "[table]") {
  // The same file checks the Python formatter of scripts/, so both print the same text.
  std::ifstream in("tests/golden/number_format.tsv");
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  CHECK(line == "value\tkind\texpected");
  size_t rows = 0;
  std::set<std::string> kinds;
  while (std::getline(in, line)) {
    const size_t tab1 = line.find('\t'), tab2 = line.find('\t', tab1 + 1);
    REQUIRE(tab2 != std::string::npos);
    const std::string value = line.substr(0, tab1), kind = line.substr(tab1 + 1, tab2 - tab1 - 1);
    const auto parsedKind = sb::numberKindFromString(kind);
    REQUIRE(parsedKind);
    INFO(line);
    CHECK(sb::formatTableNumber(std::strtod(value.c_str(), nullptr), *parsedKind) ==
          line.substr(tab2 + 1));
    kinds.insert(kind);
    ++rows;
  }
  CHECK(rows >= 30);
  CHECK(kinds == std::set<std::string>{"significant", "count", "integer"});
  CHECK_FALSE(sb::numberKindFromString("percent"));
}

TEST_CASE("tables made from records read back from disk equal those from the records", "[table]") {
  sb::testing::ScratchDir dir("sb-table-test");
  std::vector<json> records;
  for (uint64_t r : {512u, 1024u})
    for (const char* scheme : {"sm32", "mmh"}) {
      json rec = record(scheme, r, double(r) * 300);
      rec["time_s"] = {{"total", 1.25}, {"depth", 0.5}, {"phases", {{"encode", 0.7}}}};
      rec["verification"] = {{"method", "exhaustive"}, {"queries", r * r * 7}, {"mismatches", 0}};
      records.push_back(rec);
      sb::writeJsonAtomically(dir.path() / (std::string(scheme) + std::to_string(r) + ".json"),
                              rec);
    }
  const sb::FolderTables found = sb::tablesOfFolder(dir.path());
  CHECK(found.problems.empty());
  CHECK(sb::toMarkdown(found.tables) == sb::toMarkdown(tablesOf(records)));
}
