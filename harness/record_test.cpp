// Records: the Record type, atomic writes, which files are records, cell keys and the machine
// facts a record carries.
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/cell_key.h"
#include "harness/machine.h"
#include "harness/record.h"
#include "harness/source_commit.h"
#include "tests/support/scratch_dir.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using sb::testing::ScratchDir;

json sampleRecord() {
  return json::parse(R"({
    "format": "shadowbench-record/1", "complete": true,
    "scene": {"name": "city", "spec": "city", "triangles": 12345, "hash": "0123456789abcdef"},
    "light_index": 0, "light": {"type": "directional", "direction": [0.35, 0.25, -1]},
    "mode": "closed",
    "scheme": {"name": "sm32", "kind": "depth", "params": {"chunk": "32"}, "paper": "..."},
    "resolution": 4096, "depth_resolution": 0, "tile_size": 512,
    "size_bytes": {"total": 67108864, "components": {"depths": 67108864}},
    "time_s": {"total": 3.2, "depth": 2.9, "phases": {"encode": 0.3}},
    "depth": {"texels": 16777216, "mtexels_per_s": 5.8, "closed_fallbacks": 12,
              "method": "rasterize"},
    "counters": {},
    "memory": {"peak_rss_bytes": 123, "baseline_rss_bytes": 45},
    "verification": {"method": "exhaustive", "queries": 123456, "mismatches": 0, "examples": []},
    "lookup": [{"query_set": "uniform", "filter": 1, "queries": 1000000, "ns_per_query_1t": 12.5,
                "mqueries_per_s_all": 150.0, "threads": 2},
               {"query_set": "view", "filter": 3, "queries": 1000000, "ns_per_query_1t": 40.0,
                "mqueries_per_s_all": 50.0, "threads": 2, "cache_hit_rate": 0.75}],
    "machine": {"cpu": "...", "cores": 2, "memory_bytes": 0, "os": "..."},
    "commit": "abc123", "created": "2026-11-26T10:00:00Z" })");
}

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> filesUnder(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) names.push_back(fs::relative(entry.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

bool isFileNameSafe(const std::string& name) {
  return !name.empty() && name.front() != '.' &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_.-") == std::string::npos;
}

}  // namespace

TEST_CASE("writeJsonAtomically creates folders, leaves only the record, and replaces it whole",
          "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path path = dir.path() / "a" / "b" / "cell.json";
  const json first = sampleRecord();
  sb::writeJsonAtomically(path, first);
  CHECK(filesUnder(dir.path()) == std::vector<std::string>{"a/b/cell.json"});
  REQUIRE(sb::readRecord(path).has_value());
  CHECK(*sb::readRecord(path) == first);

  json second = first;
  second["size_bytes"]["total"] = 42;
  sb::writeJsonAtomically(path, second);
  CHECK(filesUnder(dir.path()) == std::vector<std::string>{"a/b/cell.json"});
  CHECK(sb::readRecord(path)->at("size_bytes").at("total") == 42);
}

TEST_CASE("a failed atomic write throws and leaves neither a partial file nor a temporary",
          "[record]") {
  ScratchDir dir("sb-record-test");
  writeText(dir.path() / "blocker", "not a folder");
  CHECK_THROWS_AS(sb::writeJsonAtomically(dir.path() / "blocker" / "cell.json", sampleRecord()),
                  std::runtime_error);
  // A folder where the record should go: the rename fails after the temporary was written.
  fs::create_directories(dir.path() / "cell.json" / "occupied");
  CHECK_THROWS_AS(sb::writeJsonAtomically(dir.path() / "cell.json", sampleRecord()),
                  std::runtime_error);
  CHECK(filesUnder(dir.path()) == std::vector<std::string>{"blocker"});
}

TEST_CASE("concurrent atomic writes of one record leave one whole record", "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path path = dir.path() / "cell.json";
  std::vector<std::thread> writers;
  for (int t = 0; t < 4; ++t)
    writers.emplace_back([&, t] {
      json record = sampleRecord();
      record["counters"]["writer"] = t;
      for (int i = 0; i < 20; ++i) sb::writeJsonAtomically(path, record);
    });
  for (auto& w : writers) w.join();
  CHECK(filesUnder(dir.path()) == std::vector<std::string>{"cell.json"});
  CHECK(sb::readRecord(path).has_value());
}

TEST_CASE("readRecord accepts only the whole text of a complete record", "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path path = dir.path() / "cell.json";
  sb::writeJsonAtomically(path, sampleRecord());
  const std::string text = readText(path);
  // Only trailing whitespace may be missing from a text that still holds the whole record.
  const size_t wholeRecord = text.find_last_not_of(" \n") + 1;
  for (size_t length = 0; length <= text.size(); ++length) {
    writeText(path, text.substr(0, length));
    INFO("truncated to " << length << " of " << text.size() << " bytes");
    CHECK(sb::readRecord(path).has_value() == (length >= wholeRecord));
  }
}

TEST_CASE("readRecord rejects garbage, incomplete and foreign records", "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path path = dir.path() / "cell.json";
  CHECK_FALSE(sb::readRecord(dir.path() / "missing.json"));
  CHECK_FALSE(sb::readRecord(dir.path()));  // a folder

  const auto rejects = [&](const std::string& text) {
    writeText(path, text);
    return !sb::readRecord(path).has_value();
  };
  CHECK(rejects(""));
  CHECK(rejects(std::string("\0\0\xff{garbage", 12)));
  CHECK(rejects("[1, 2, 3]"));
  CHECK(rejects("\"shadowbench-record/1\""));

  const auto rejectsEdited = [&](auto edit) {
    json record = sampleRecord();
    edit(record);
    return rejects(record.dump());
  };
  CHECK_FALSE(rejectsEdited([](json&) {}));
  CHECK(rejectsEdited([](json& r) { r["complete"] = false; }));
  CHECK(rejectsEdited([](json& r) { r["complete"] = "true"; }));
  CHECK(rejectsEdited([](json& r) { r.erase("complete"); }));
  CHECK(rejectsEdited([](json& r) { r["format"] = "shadowbench-record/2"; }));
  CHECK(rejectsEdited([](json& r) { r.erase("format"); }));
  CHECK(rejectsEdited([](json& r) { r["scene"].erase("name"); }));
  CHECK(rejectsEdited([](json& r) { r.erase("mode"); }));
  CHECK(rejectsEdited([](json& r) { r["scheme"]["name"] = 3; }));
  CHECK(rejectsEdited([](json& r) { r["resolution"] = "4096"; }));
  CHECK(rejectsEdited([](json& r) { r["size_bytes"].erase("total"); }));
  // Optional parts may be absent.
  CHECK_FALSE(rejectsEdited([](json& r) {
    for (const char* key :
         {"verification", "lookup", "time_s", "depth", "memory", "machine", "light_index"})
      r.erase(key);
  }));
}

TEST_CASE("a Record reads every field of a record and writes the same JSON back", "[record]") {
  json written = sampleRecord();
  written["many_lights"] = {{"lights", 3}};  // a field this version does not know is kept
  const sb::Record record = written.get<sb::Record>();
  CHECK(record.scene.hash == "0123456789abcdef");
  CHECK(record.scheme.params == std::map<std::string, std::string>{{"chunk", "32"}});
  CHECK(record.resolution == 4096);
  CHECK(record.tileSize == 512);
  CHECK(record.sizeBytes == 67108864);
  REQUIRE(record.time.has_value());
  CHECK(record.time->phases.at("encode") == 0.3);
  REQUIRE(record.lookup.has_value());
  CHECK(record.lookup->at(0).nsPerQuerySingleThread == 12.5);
  CHECK(!record.lookup->at(0).cacheHitRate.has_value());
  CHECK(record.lookup->at(1).cacheHitRate == 0.75);
  CHECK(record.verification->queries == 123456);
  CHECK(json(record) == written);
}

TEST_CASE("a Record of a build in parts keeps its part size, shared depth pass and estimate",
          "[record][parts]") {
  json written = sampleRecord();
  written["part_size"] = 1024;
  written["time_s"]["depth_shared_with"] = {"mh", "dag-mh"};
  written["memory"]["estimated_bytes"] = 1000;
  written["memory"]["parts"] = {{"estimated_bytes", 600}, {"peak_rss_bytes", 700}};
  written["memory"]["merge"] = {{"estimated_bytes", 1000}, {"peak_rss_bytes", 900}};
  const sb::Record record = written.get<sb::Record>();
  CHECK(record.partSize == 1024);
  CHECK(record.time->depthSharedWith == std::vector<std::string>{"mh", "dag-mh"});
  CHECK(record.memory->estimatedBytes == 1000);
  CHECK(record.memory->parts->peakRssBytes == 700);
  CHECK(record.memory->merge->estimatedBytes == 1000);
  CHECK(json(record) == written);
  written["memory"]["merge"].erase("peak_rss_bytes");
  CHECK_THROWS_WITH(written.get<sb::Record>(), Catch::Contains("memory.merge.peak_rss_bytes"));
  written["memory"]["merge"]["peak_rss_bytes"] = 900;
  written["time_s"]["depth_shared_with"] = "mh";
  CHECK_THROWS_WITH(written.get<sb::Record>(), Catch::Contains("time_s.depth_shared_with"));
}

// Issue 11 A4: tables printed a negative size; impossible values must be refused, by name.
TEST_CASE("a Record refuses impossible values and says which field", "[record]") {
  const auto refusal = [](auto edit) -> std::string {
    json record = sampleRecord();
    edit(record);
    try {
      (void)record.get<sb::Record>();
    } catch (const sb::RecordError& error) {
      return error.what();
    }
    return "accepted";
  };
  const auto refused = [&](auto edit, const std::string& words) {
    const std::string why = refusal(edit);
    INFO(why);
    return why.find(words) != std::string::npos;
  };
  CHECK(refused([](json& r) { r["size_bytes"]["total"] = -5; }, "size_bytes.total is -5"));
  CHECK(refused([](json& r) { r["size_bytes"]["total"] = 1.5; }, "size_bytes.total is 1.5"));
  CHECK(refused([](json& r) { r["size_bytes"]["total"] = "12"; }, "not a number"));
  CHECK(refused([](json& r) { r["size_bytes"]["components"]["depths"] = -1; },
                "size_bytes.components.depths is -1"));
  CHECK(refused([](json& r) { r["resolution"] = 1000; }, "resolution is 1000"));
  CHECK(refused([](json& r) { r["resolution"] = 4; }, "power of two"));
  CHECK(refused([](json& r) { r["resolution"] = 0; }, "resolution is 0"));
  CHECK(refused([](json& r) { r["resolution"] = -4096; }, "resolution is -4096"));
  CHECK(refused([](json& r) { r["time_s"]["total"] = -1.0; }, "time_s.total is -1.0"));
  CHECK(refused([](json& r) { r["time_s"]["phases"]["encode"] = -0.5; }, "time_s.phases.encode"));
  CHECK(refused([](json& r) { r["lookup"][0]["ns_per_query_1t"] = -3.0; },
                "lookup[0].ns_per_query_1t"));
  CHECK(refused([](json& r) { r["lookup"][0]["filter"] = 4; }, "lookup[0].filter is 4"));
  CHECK(refused([](json& r) { r["lookup"][1]["cache_hit_rate"] = 1.5; },
                "lookup[1].cache_hit_rate is 1.5"));
  CHECK(refused([](json& r) { r["verification"]["mismatches"] = -2; },
                "verification.mismatches is -2"));
  CHECK(refused([](json& r) { r["mode"] = "closd"; }, "mode is 'closd'"));
  CHECK(refused([](json& r) { r["scene"] = "city"; }, "scene is \"city\", not an object"));
  CHECK(refused([](json& r) { r["scene"].erase("name"); }, "scene.name is missing"));
  CHECK(refused([](json& r) { r["complete"] = false; }, "complete is false"));
  CHECK(refused([](json& r) { r["format"] = "shadowbench-record/2"; }, "format is"));
  // A size written as a float without fraction is still a whole number of bytes.
  CHECK(refusal([](json& r) { r["size_bytes"]["total"] = 1024.0; }) == "accepted");
}

TEST_CASE("loadRecord names the file and why it is not a record", "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path path = dir.path() / "cell.json";
  const auto why = [&](const std::string& text) -> std::string {
    writeText(path, text);
    try {
      sb::loadRecord(path);
    } catch (const sb::RecordError& error) {
      return error.what();
    }
    return "accepted";
  };
  CHECK(why("") == "'" + path.string() + "' is empty");
  CHECK(why("  \n") == "'" + path.string() + "' is empty");
  CHECK(why(sampleRecord().dump().substr(0, 50)) ==
        "'" + path.string() + "' is not JSON (cut short while written?)");
  json negative = sampleRecord();
  negative["size_bytes"]["total"] = -1;
  CHECK(why(negative.dump()).rfind("'" + path.string() + "': size_bytes.total is -1", 0) == 0);
  CHECK(why(sampleRecord().dump()) == "accepted");
  CHECK_THROWS_AS(sb::loadRecord(dir.path() / "missing.json"), sb::RecordError);
}

TEST_CASE("readRecords finds complete records recursively, sorted, and counts the rest",
          "[record]") {
  ScratchDir dir("sb-record-test");
  const fs::path root = dir.path() / "results";
  json a = sampleRecord(), b = sampleRecord(), c = sampleRecord();
  a["resolution"] = 1024, b["resolution"] = 2048, c["resolution"] = 512;
  sb::writeJsonAtomically(root / "z.json", a);
  sb::writeJsonAtomically(root / "deep" / "er" / "b.json", b);
  sb::writeJsonAtomically(root / "a.json", c);
  writeText(root / "truncated.json", sampleRecord().dump().substr(0, 100));
  writeText(root / "deep" / "garbage.json", "not json");
  json incomplete = sampleRecord();
  incomplete["complete"] = false;
  writeText(root / "incomplete.json", incomplete.dump());
  writeText(root / "tables" / "size.csv", "scheme,4K²\r\n");
  writeText(root / ".cell.json.tmp-1-2-3", sampleRecord().dump().substr(0, 10));

  const sb::LoadedRecords loaded = sb::readRecords(root);
  REQUIRE(loaded.records.size() == 3);
  CHECK(loaded.paths ==
        std::vector<fs::path>{root / "a.json", root / "deep" / "er" / "b.json", root / "z.json"});
  CHECK(loaded.records[0].resolution == 512);
  CHECK(loaded.records[1].resolution == 2048);
  CHECK(loaded.records[2].resolution == 1024);
  REQUIRE(loaded.skipped.size() == 3);
  CHECK(loaded.skipped[0].path == root / "deep" / "garbage.json");
  CHECK(loaded.skipped[0].reason.find("not JSON") != std::string::npos);
  CHECK(loaded.skipped[1].reason.find("complete is false") != std::string::npos);
  CHECK(loaded.skipped[2].reason.find("not JSON") != std::string::npos);

  // Records a sweep moved aside are not current records.
  sb::writeJsonAtomically(root / "superseded" / "old.json", a);
  CHECK(sb::readRecords(root).records.size() == 3);

  CHECK(sb::readRecords(dir.path() / "nothing-here").records.empty());
}

TEST_CASE("readableCellKey names the cell from its request, stably", "[record]") {
  sb::Record record = sampleRecord();
  CHECK(sb::readableCellKey(record) == "city_0_closed_sm32_chunk-32_4096");

  // The identity alone (as a sweep has it before building) gives the same keys.
  sb::Record identity;
  identity.scene = {"city", "city", 12345, "0123456789abcdef"};
  identity.light = record.light;
  identity.mode = "closed";
  identity.scheme.name = "sm32";
  identity.scheme.params = {{"chunk", "32"}};
  identity.resolution = 4096;
  identity.tileSize = 512;
  CHECK(sb::readableCellKey(identity) == sb::readableCellKey(record));
  CHECK(sb::cellKey(identity) == sb::cellKey(record));

  // Parameters in name order whatever order they were given in; generator names stay readable.
  record.scene.name = "city:size=24,seed=1";
  record.lightIndex = 2;
  record.scheme.name = "mmh";
  record.scheme.params = {{"search", "1000"}, {"height", "3"}};
  CHECK(sb::readableCellKey(record) ==
        "city-size-24-seed-1_2_closed_mmh_height-3_search-1000_4096");
  const std::string key = sb::cellKey(record);
  CHECK(key.rfind(sb::readableCellKey(record) + "_", 0) == 0);
  CHECK(key.size() == sb::readableCellKey(record).size() + 9);
  CHECK(key.find_first_not_of("0123456789abcdef", key.size() - 8) == std::string::npos);

  // Every key part matters.
  std::set<std::string> keys;
  for (const char* mode : {"open", "closed", "static"})
    for (uint32_t resolution : {512u, 1024u})
      for (const char* search : {"10", "100"}) {
        record.mode = mode;
        record.resolution = resolution;
        record.scheme.params["search"] = search;
        keys.insert(sb::cellKey(record));
      }
  CHECK(keys.size() == 12);
}

// Issue 11 A1: `a/model.stl` and `b/model.obj` shared one record, and an edited scene kept the
// old one, because the key was the scene's name.
TEST_CASE("requests that read alike have different keys; content is identity, not name",
          "[record]") {
  const sb::Record base = sampleRecord();
  const auto keyWith = [&](auto edit) {
    sb::Record record = base;
    edit(record);
    CHECK(sb::readableCellKey(record) == sb::readableCellKey(base));
    return sb::cellKey(record);
  };
  // Another scene spec (a model of one stem in another folder) or tile size: another record.
  std::set<std::string> keys{sb::cellKey(base)};
  keys.insert(keyWith([](sb::Record& r) { r.scene.spec = "b/model.obj"; }));
  keys.insert(keyWith([](sb::Record& r) { r.tileSize = 256; }));
  CHECK(keys.size() == 3);

  // An edited scene is the same request: its record replaces the old one at the same name, and
  // the identity tells them apart.
  sb::Record edited = base;
  edited.scene.hash = "fedcba9876543210";
  edited.light["direction"] = {0, 0, -1};
  CHECK(sb::cellKey(edited) == sb::cellKey(base));
  CHECK(sb::recordRequest(edited) == sb::recordRequest(base));
  CHECK(sb::recordIdentity(edited) != sb::recordIdentity(base));
  sb::Record newFormat = base;
  newFormat.format = "shadowbench-record/2";
  CHECK(sb::recordIdentity(newFormat) != sb::recordIdentity(base));

  // Measurements are neither: a rebuilt record of the same content is the same cell.
  sb::Record rebuilt = base;
  rebuilt.sizeBytes = 1;
  rebuilt.created = "2030-01-01T00:00:00Z";
  rebuilt.commit = "other";
  CHECK(sb::recordIdentity(rebuilt) == sb::recordIdentity(base));
}

TEST_CASE("cellKey is filesystem-safe and distinct for odd scene names", "[record]") {
  ScratchDir dir("sb-record-test");
  const std::vector<std::string> names = {"../../etc/passwd",
                                          "a/b",
                                          "a\\b",
                                          "a?b",
                                          "a*b",
                                          "Straße",
                                          "日本",
                                          "",
                                          ".",
                                          "..",
                                          ".hidden",
                                          "with space",
                                          "with\"quote",
                                          "tab\there",
                                          std::string(300, 'x'),
                                          "CITY",
                                          "-dash-",
                                          "ends."};
  std::set<std::string> keys;
  for (const std::string& name : names) {
    sb::Record record = sampleRecord();
    record.scene.name = name;
    const std::string key = sb::cellKey(record);
    INFO("scene name '" << name << "' → key '" << key << "'");
    CHECK(isFileNameSafe(key));
    CHECK(key.size() <= 200);
    CHECK(key == sb::cellKey(record));
    keys.insert(key);
    // The key works as a file name here.
    sb::writeRecord(dir.path() / (key + ".json"), record);
    CHECK(sb::loadRecord(dir.path() / (key + ".json")).scene.name == name);
  }
  CHECK(keys.size() == names.size());
  CHECK(filesUnder(dir.path()).size() == names.size());

  // Long parameter lists are cut to a bounded key that still tells cells apart.
  sb::Record record = sampleRecord();
  for (int i = 0; i < 40; ++i)
    record.scheme.params[std::string("p").append(std::to_string(i))] = "value";
  const std::string longKey = sb::cellKey(record);
  record.scheme.params["p39"] = "other";
  CHECK(longKey.size() <= 200);
  CHECK(sb::cellKey(record).size() <= 200);
  CHECK(sb::cellKey(record) != longKey);
}

TEST_CASE("the memory a build may use is its control group's room where that is less",
          "[record][regression]") {
  // Issue 12: under Slurm a merge checked the node's free memory, not its job's limit.
  ScratchDir dir("sb-cgroup-test");
  const std::filesystem::path root = dir.path() / "cgroup";
  const auto write = [](const std::filesystem::path& file, const std::string& text) {
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
  };
  write(root / "slurm/job1/memory.max", "1000\n");
  write(root / "slurm/job1/memory.current", "400\n");
  write(root / "slurm/job1/step0/memory.max", "max\n");
  write(root / "slurm/job1/step0/memory.current", "100\n");
  const std::filesystem::path self = dir.path() / "self";
  write(self, "0::/slurm/job1/step0\n");
  CHECK(sb::cgroupMemoryLeft(root, self) == 600u);  // the job's limit, above the step
  write(root / "slurm/job1/step0/memory.max", "150\n");
  CHECK(sb::cgroupMemoryLeft(root, self) == 50u);  // the tighter of the two
  write(root / "slurm/job1/step0/memory.current", "900\n");
  CHECK(sb::cgroupMemoryLeft(root, self) == 0u);  // over its limit: no room, not a wrap-around
  // cgroup v1: the memory controller's own hierarchy.
  write(root / "memory/job/memory.limit_in_bytes", "2000\n");
  write(root / "memory/job/memory.usage_in_bytes", "500\n");
  write(self, "4:memory:/job\n0::/\n");
  CHECK(sb::cgroupMemoryLeft(root, self) == 1500u);
  write(self, "0::/unlimited\n");
  CHECK(sb::cgroupMemoryLeft(root, self) == std::nullopt);
  CHECK(sb::cgroupMemoryLeft(root, dir.path() / "absent") == std::nullopt);
}

TEST_CASE("machine facts and memory figures come from this machine", "[record]") {
  const json machine = sb::machineInfo();
  CHECK(machine.at("cpu").is_string());
  CHECK(!machine.at("cpu").get<std::string>().empty());
  CHECK(machine.at("cores").get<unsigned>() == std::thread::hardware_concurrency());
  CHECK(machine.at("memory_bytes").get<uint64_t>() > (uint64_t(64) << 20));
  CHECK(machine.at("os").get<std::string>().find("Linux") != std::string::npos);

  CHECK(sb::availableMemoryBytes() > 0);
  CHECK(sb::availableMemoryBytes() <= machine.at("memory_bytes").get<uint64_t>());
  sb::resetPeakRss();
  const uint64_t before = sb::currentRssBytes();
  CHECK(before > 0);
  {
    // Touch 64 MiB so that it is resident: the peak must see it after it is freed.
    std::vector<char> block(64u << 20);
    for (size_t i = 0; i < block.size(); i += 4096) block[i] = char(i);
    CHECK(sb::currentRssBytes() >= before + (48u << 20));
  }
  CHECK(sb::peakRssBytes() >= before + (48u << 20));
}

TEST_CASE("sourceCommit names the commit, marks a dirty tree, and never throws", "[record]") {
  ScratchDir dir("sb-record-test");
  CHECK(sb::sourceCommit(dir.path() / "missing") == "unknown");
  CHECK(sb::sourceCommit(dir.path()) == "unknown");  // not a repository
  if (std::system("git --version >/dev/null 2>&1") != 0) return;

  // A quote in the path must not break the shell command.
  const fs::path repo = dir.path() / "it's a repo";
  fs::create_directories(repo);
  std::string git = "git -C '";
  git += dir.path().string();
  git += "/it'\\''s a repo' ";
  REQUIRE(std::system((git + "init -q").c_str()) == 0);
  CHECK(sb::sourceCommit(repo) == "unknown");  // no commit yet
  writeText(repo / "file.txt", "one\n");
  REQUIRE(std::system((git + "add file.txt && " + git +
                       "-c user.name=test -c user.email=test@example.com -c commit.gpgsign=false "
                       "commit -q -m one")
                          .c_str()) == 0);
  const std::string clean = sb::sourceCommit(repo);
  CHECK(clean.size() == 12);
  CHECK(clean.find_first_not_of("0123456789abcdef") == std::string::npos);
  writeText(repo / "untracked.txt", "ignored\n");
  CHECK(sb::sourceCommit(repo) == clean);
  writeText(repo / "file.txt", "two\n");
  CHECK(sb::sourceCommit(repo) == clean + "-dirty");
}

// --- progress ---------------------------------------------------------------------------------
