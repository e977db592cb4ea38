// Build records on disk: one JSON file per built cell, written atomically, read back by resumed
// sweeps, tables and plots (DESIGN §6). The record itself is harness/record_type.h.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/record_type.h"
#include "schemes/interface/atomic_file.h"

namespace sb {

// JSON as indented text through writeFileAtomically.
void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json);
void writeRecord(const std::filesystem::path& path, const Record& record);

// The record at `path`; throws RecordError naming the file and why it is not a record this
// version can read: unreadable, empty, not JSON (a half-written file), or what from_json refuses.
Record loadRecord(const std::filesystem::path& path);

// The JSON of the record at `path` (unknown fields included); nullopt where loadRecord throws.
std::optional<nlohmann::json> readRecord(const std::filesystem::path& path);

struct SkippedRecord {
  std::filesystem::path path;
  std::string reason;
};

// Records moved aside by a sweep (an older answer to a cell) live here, under the records
// folder; readers of current records do not look into it.
inline constexpr std::string_view kSupersededFolder = "superseded";

struct LoadedRecords {
  std::vector<Record> records;               // sorted by path
  std::vector<std::filesystem::path> paths;  // paths[i] holds records[i]
  std::vector<SkippedRecord> skipped;        // *.json files that are not records, and why
};

// Every record in *.json files under `dir` (recursively, but not in superseded folders); a
// missing folder gives none.
LoadedRecords readRecords(const std::filesystem::path& dir);

}  // namespace sb
