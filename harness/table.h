// The paper tables — size, build time, verification, lookup time — regenerated from build
// records alone (DESIGN §6), as Markdown and CSV.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/record_type.h"

namespace sb {

struct Table {
  std::string title;
  std::string unit_note;  // the unit of the cells and how to read them
  std::vector<std::string> header;
  std::vector<std::vector<std::string>>
      rows;          // each as long as header; "–" where nothing was measured
  std::string slug;  // file name of the CSV without ".csv"; from the title when empty
};

// For each (scene, light index, mode) of the records, in that order: size in MiB, size as % of a
// 16-bit shadow map, build time, and — where any record has them — verification and lookup
// tables. Schemes are rows (sm32, the baseline, first; then by name and parameters); resolutions
// are columns in numeric order. Of several records of one table cell the newest ("created")
// counts; of equal times the later one in `records`.
std::vector<Table> makeTables(const std::vector<Record>& records);

// The tables of the records under a folder, and one line for each file left out of them: not a
// record (and why), or another record of the same table cell that was not used (and why not).
struct FolderTables {
  std::vector<Table> tables;
  size_t records = 0;  // the records the tables were made from
  std::vector<std::string> problems;
};
FolderTables tablesOfFolder(const std::filesystem::path& recordsDir);

std::string toMarkdown(const std::vector<Table>& tables);
std::string toCsv(const Table& table);  // RFC 4180: CRLF line ends, fields quoted where needed

// Writes outDir/tables.md and one outDir/<slug>.csv per table, each file atomically.
void writeTables(const std::vector<Table>& tables, const std::filesystem::path& outDir);

// A resolution as the papers write it: 4096 → "4K²", 262144 → "256K²", 512 → "512²".
std::string resolutionHeading(uint64_t resolution);

}  // namespace sb
