// The build record: one built cell and what was measured (DESIGN §6), the one type the writer
// (runCell), the readers (records, tables, the CLI) and harness/record.schema.json describe.
// The JSON form is format "shadowbench-record/1"; field names never change, fields may be added.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sb {

// The format tag every record carries; a reader rejects anything else.
inline constexpr std::string_view kRecordFormat = "shadowbench-record/1";

// A JSON text that is not a complete, plausible record; the message names the field and value.
class RecordError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RecordScene {
  std::string name;
  std::string spec;  // as given on the command line
  uint64_t triangles = 0;
  std::string hash;  // of the loaded geometry and lights (Scene::hash)
};

struct RecordScheme {
  std::string name;
  std::string kind;                           // "depth" or "voxel"
  std::map<std::string, std::string> params;  // every parameter, resolved
  std::string paper;
};

struct RecordTimes {
  double total = 0;  // wall time of the whole build
  double depth = 0;  // depth generation
  std::map<std::string, double> phases;
  // The other schemes one depth pass also fed (issue 12): `depth` is the time of that shared pass.
  std::vector<std::string> depthSharedWith;
  // The other schemes its part encoder also wrote for (SchemeInfo::partPayload): the encoder's
  // phases are that one shared encoder's.
  std::vector<std::string> encoderSharedWith;
};

struct RecordDepth {
  uint64_t texels = 0;
  double mtexelsPerSecond = 0;
  uint64_t closedFallbacks = 0;
  std::string method;
};

// One step of a build in parts: what it declared before it started (0: not recorded, as by part
// files written before part files kept it), and its peak.
struct RecordMemoryStep {
  uint64_t estimatedBytes = 0, peakRssBytes = 0;
};

struct RecordMemory {
  uint64_t peakRssBytes = 0, baselineRssBytes = 0;
  uint64_t estimatedBytes = 0;  // the scheme's declared build memory, checked before the build
  // A build in parts: its parts' depth passes (each feeding every scheme of its cell set) and its
  // merge, the merge declared from the part files.
  std::optional<RecordMemoryStep> parts, merge;
};

struct RecordVerification {
  std::string method;  // "exhaustive" or "sampled"
  uint64_t queries = 0, mismatches = 0;
  nlohmann::json examples = nlohmann::json::array();  // VerifyReport::toJson's mismatches
};

struct RecordLookup {
  std::string querySet;
  int filter = 1;
  uint64_t queries = 0;
  double nsPerQuerySingleThread = 0;
  double mqueriesPerSecondAllThreads = 0;
  uint64_t threads = 0;
  std::optional<double> cacheHitRate;  // decoders with a block cache (issue 13)
};

struct Record {
  std::string format{kRecordFormat};
  bool complete = false;  // written last: false until every measurement is in
  RecordScene scene;
  uint32_t lightIndex = 0;
  nlohmann::json light;  // Light::describe() of the fitted light; null when unknown
  std::string mode;
  RecordScheme scheme;
  uint32_t resolution = 0;
  uint32_t depthResolution = 0;
  uint32_t tileSize = 0;
  uint32_t partSize = 0;  // a build in parts (DESIGN §5) of this side; 0 for a whole build
  uint64_t sizeBytes = 0;
  std::map<std::string, uint64_t> sizeComponents;
  std::optional<RecordTimes> time;
  std::optional<RecordDepth> depth;
  std::map<std::string, uint64_t> counters;
  std::optional<RecordMemory> memory;
  std::optional<RecordVerification> verification;
  std::optional<std::vector<RecordLookup>> lookup;
  nlohmann::json machine;  // machineInfo(); null when unknown
  std::string commit;
  std::string created;  // UTC, "2026-11-26T10:00:00Z"
  // Top-level fields this version does not know (e.g. "many_lights"), kept as they were.
  nlohmann::json extra = nlohmann::json::object();
};

// The JSON form; fields of absent optional parts are left out.
void to_json(nlohmann::json& json, const Record& record);

// Throws RecordError unless `json` is a complete record of this format whose required fields
// (those of harness/record.schema.json) are present and whose values are possible: sizes and
// counts non-negative integers, times non-negative, the resolution a power of two from 8 to 2^20,
// the mode one of open, closed, static, filters odd from 1 to 17.
void from_json(const nlohmann::json& json, Record& record);

}  // namespace sb
