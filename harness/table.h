// The paper tables — size, build time, verification, lookup time — regenerated from build
// records alone (DESIGN §6), as Markdown and CSV.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sb {

struct Table {
  std::string title;
  std::string unit_note;  // the unit of the cells and how to read them
  std::vector<std::string> header;
  std::vector<std::vector<std::string>>
      rows;          // each as long as header; "–" where nothing was measured
  std::string slug;  // file name of the CSV without ".csv"; from the title when empty
};

// A size published in a paper, shown as its own row beside ours in the matching size table:
// the tables of (scene, mode) whose scene name, spec, or generator (the name before ':') is
// `scene`, at any light. The row sits after our rows of `scheme` and is labelled `label`.
struct PaperFigure {
  std::string label;  // e.g. "Sintorn 2014 Fig. 9 (paper)"
  std::string scene;
  std::string mode;
  std::string scheme;
  uint32_t resolution = 0;
  double bytes = 0;
};

// For each (scene, light index, mode) of the records, in that order: size in MiB, size as % of a
// 16-bit shadow map, build time, and — where any record has them — verification and lookup
// tables. Schemes are rows (sm32, the baseline, first; then by name and parameters); resolutions
// are columns in numeric order. Of several records of one cell the newest ("created") counts.
// `records` must be complete records (isCompleteRecord); optional fields may be absent.
std::vector<Table> makeTables(const std::vector<nlohmann::json>& records,
                              std::span<const PaperFigure> paperFigures = {});

std::string toMarkdown(const std::vector<Table>& tables);
std::string toCsv(const Table& table);  // RFC 4180: CRLF line ends, fields quoted where needed

// Writes outDir/tables.md and one outDir/<slug>.csv per table, each file atomically.
void writeTables(const std::vector<Table>& tables, const std::filesystem::path& outDir);

// A resolution as the papers write it: 4096 → "4K²", 262144 → "256K²", 512 → "512²".
std::string resolutionHeading(uint64_t resolution);

}  // namespace sb
