// Build records: one JSON file per built cell, written atomically, read back by resumed sweeps,
// tables and plots (DESIGN §6). Also the machine facts and memory figures a record carries.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "schemes/interface/atomic_file.h"

namespace sb {

// The format tag every record carries; a reader rejects anything else.
inline constexpr std::string_view kRecordFormat = "shadowbench-record/1";

// {"cpu", "cores", "memory_bytes", "os"} of this machine; unknown facts are "unknown" or 0.
nlohmann::json machineInfo();

// The commit of the checkout at `sourceDir` (12 hex digits), with "-dirty" when tracked files
// differ from it; "unknown" when git or the repository is missing. Never throws.
std::string sourceCommit(const std::filesystem::path& sourceDir);

// Memory figures from /proc; 0 where the kernel does not say.
uint64_t availableMemoryBytes();  // MemAvailable: what a build can still use without swapping
uint64_t currentRssBytes();       // VmRSS
void resetPeakRss();              // so that the next peakRssBytes() measures from now on
uint64_t peakRssBytes();          // VmHWM

// The record as indented JSON through writeFileAtomically.
void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& record);

// True when `record` is a complete record this version can read: the format tag, "complete":
// true, and the fields every table needs (scene.name, mode, scheme.name, resolution,
// size_bytes.total) with their types.
bool isCompleteRecord(const nlohmann::json& record);

// The record at `path`; nullopt when it is missing, unreadable, not JSON or not complete.
std::optional<nlohmann::json> readRecord(const std::filesystem::path& path);

struct LoadedRecords {
  std::vector<nlohmann::json> records;         // sorted by path
  std::vector<std::filesystem::path> paths;    // paths[i] holds records[i]
  std::vector<std::filesystem::path> skipped;  // *.json files that are not complete records
};

// Every complete record in *.json files under `dir` (recursively); a missing folder gives none.
LoadedRecords readRecords(const std::filesystem::path& dir);

// A stable, filesystem-safe name for the record's cell:
//   <scene>_<light index>_<mode>_<scheme>[_<param>-<value>...]_<resolution>
// lower case, characters [a-z0-9_.-] only. Needs only the identifying fields (scene.name,
// light_index, mode, scheme.name, scheme.params, resolution), so a sweep can name a cell before
// building it. The record file of a cell is cellKey(record) + ".json".
std::string cellKey(const nlohmann::json& record);

// `text` reduced to [a-z0-9.-] for use inside file names: lower case, other characters become
// '-', runs of '-' collapse. Text with characters beyond ordinary punctuation gets a short hash
// of the original appended, so that different names stay different files. Never empty.
std::string fileNamePart(std::string_view text);

}  // namespace sb
