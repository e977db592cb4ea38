// Sweeps on tiny cells (64², verified, no lookup timings): records reused only for the same cell
// content, everything checked before the first build, and two sweeps sharing one folder.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/cell_key.h"
#include "harness/cell_lock.h"
#include "harness/record.h"
#include "harness/sweep.h"
#include "tests/support/scratch_dir.h"

namespace fs = std::filesystem;

namespace {

using sb::testing::ScratchDir;

sb::SweepSpec tinySweep(const fs::path& out) {
  sb::SweepSpec spec;
  spec.scenes = {"city:size=2"};
  spec.modes = {"open"};
  spec.schemes = {"sm32"};
  spec.resolutions = {"64"};
  spec.out = out;
  spec.cellOptions.benchLookups = false;
  return spec;
}

// A box of height `height` standing on a 4×4 ground square.
void writeModel(const fs::path& path, float height) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path);
  out << "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
      << "v -0.5 -0.5 " << height << "\nv 0.5 -0.5 " << height << "\nv 0.5 0.5 " << height
      << "\nv -0.5 0.5 " << height << "\n"
      << "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n"
      << "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
      << "f 9 10 6\nf 9 6 5\nf 10 11 7\nf 10 7 6\nf 11 12 8\nf 11 8 7\nf 12 9 5\nf 12 5 8\n";
}

std::vector<std::string> jsonFilesIn(const fs::path& dir) {
  std::vector<std::string> names;
  if (!fs::exists(dir)) return names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".json") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Runs `sweep` and returns the problem it refused with; "" when it ran.
std::string refusal(const sb::SweepSpec& spec) {
  try {
    sb::runSweep(spec);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

}  // namespace

// Issue 11 A1: two models with one stem shared a record ("1 built, 1 already done"), and an
// edited model kept its old record.
TEST_CASE("a sweep reuses a record only for the same cell content", "[sweep]") {
  ScratchDir dir("sb-sweep-test");
  const fs::path a = dir.path() / "a" / "model.obj", b = dir.path() / "b" / "model.obj";
  writeModel(a, 1.0f);
  writeModel(b, 2.0f);
  sb::SweepSpec spec = tinySweep(dir.path() / "out");
  spec.scenes = {a.string(), b.string()};

  sb::SweepOutcome first = sb::runSweep(spec);
  CHECK(first.built == 2);
  CHECK(first.reused == 0);
  CHECK(first.failed == 0);
  CHECK(jsonFilesIn(spec.out).size() == 2);

  sb::SweepOutcome again = sb::runSweep(spec);
  CHECK(again.built == 0);
  CHECK(again.reused == 2);

  // The edited model is rebuilt; its old record is kept aside, the other model's is reused.
  writeModel(a, 1.5f);
  std::vector<std::string> warnings;
  sb::SweepEvents events;
  events.warning = [&](const std::string& w) { warnings.push_back(w); };
  sb::SweepOutcome edited = sb::runSweep(spec, events);
  CHECK(edited.built == 1);
  CHECK(edited.reused == 1);
  CHECK(edited.superseded == 1);
  const auto current = jsonFilesIn(spec.out);
  REQUIRE(current.size() == 2);
  const auto aside = jsonFilesIn(spec.out / "superseded");
  REQUIRE(aside.size() == 1);
  const sb::Record old = sb::loadRecord(spec.out / "superseded" / aside[0]);
  CHECK(old.scene.spec == a.string());
  CHECK(std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
          return w.find("scene_hash") != std::string::npos &&
                 w.find("moved to") != std::string::npos;
        }) == 1);
  std::set<std::string> hashes;
  for (const std::string& name : current) hashes.insert(sb::loadRecord(spec.out / name).scene.hash);
  CHECK(hashes.size() == 2);
  CHECK_FALSE(hashes.count(old.scene.hash));

  // The tables see the current records only; the two "model" scenes share a table cell, which
  // the table step reports.
  CHECK(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.find("records of one table cell") != std::string::npos &&
           w.find("scene specs") != std::string::npos;
  }));
}

TEST_CASE("a record named before the request hash is reused and renamed, not rebuilt", "[sweep]") {
  ScratchDir dir("sb-sweep-test");
  const sb::SweepSpec spec = tinySweep(dir.path() / "out");
  REQUIRE(sb::runSweep(spec).built == 1);
  const std::string name = jsonFilesIn(spec.out).at(0);
  const sb::Record record = sb::loadRecord(spec.out / name);
  const fs::path legacy = spec.out / (sb::readableCellKey(record) + ".json");
  fs::rename(spec.out / name, legacy);

  const sb::SweepOutcome resumed = sb::runSweep(spec);
  CHECK(resumed.built == 0);
  CHECK(resumed.reused == 1);
  CHECK(jsonFilesIn(spec.out) == std::vector<std::string>{name});
  CHECK(nlohmann::json(sb::loadRecord(spec.out / name)) == nlohmann::json(record));
}

// Issue 11 A9: a bad entry late in a list, a cell that cannot fit, or an unwritable folder were
// found after earlier cells were built.
TEST_CASE(
    "a sweep checks every scene, mode, resolution, scheme, parameter, memory and the "
    "folder before building",
    "[sweep]") {
  ScratchDir dir("sb-sweep-test");
  const fs::path out = dir.path() / "out";
  const auto refusedWith = [&](auto edit, const std::string& words) {
    sb::SweepSpec spec = tinySweep(out);
    edit(spec);
    const std::string why = refusal(spec);
    INFO(why);
    CHECK(why.find(words) != std::string::npos);
    CHECK(jsonFilesIn(out).empty());
  };
  refusedWith(
      [](sb::SweepSpec& s) {
        s.scenes = {"city:size=2", "no-such-scene.obj"};
      },
      "no-such-scene.obj");
  refusedWith([](sb::SweepSpec& s) { s.modes = {"open", "shut"}; }, "shut");
  refusedWith([](sb::SweepSpec& s) { s.resolutions = {"64", "100"}; }, "resolution '100'");
  refusedWith([](sb::SweepSpec& s) { s.schemes = {"sm32", "no-such-scheme"}; }, "no-such-scheme");
  refusedWith([](sb::SweepSpec& s) { s.params.emplace("no-such-param", "1"); }, "no-such-param");
  refusedWith(
      [](sb::SweepSpec& s) {
        s.schemes = {"sm32", "mmh"};
        s.params.emplace("search-distance", "-7");
      },
      "search-distance");
  // sm32 at 1024K² needs 4 TiB: refused with the figure before the 64² cell is built.
  refusedWith([](sb::SweepSpec& s) { s.resolutions = {"64", "1024K"}; }, "_1048576_");
  std::ofstream(dir.path() / "file") << "not a folder";
  sb::SweepSpec unwritable = tinySweep(dir.path() / "file" / "out");
  CHECK(refusal(unwritable).find("cannot create the folder") != std::string::npos);
}

// Issue 11 A10: two sweeps into one folder each built every cell.
TEST_CASE("a cell locked by another sweep is built once and reused after its lock", "[sweep]") {
  ScratchDir dir("sb-sweep-test");
  sb::SweepSpec spec = tinySweep(dir.path() / "out");
  spec.resolutions = {"64", "128"};
  const sb::Scene scene = sb::openScene(spec.scenes[0]);
  const sb::CellSpec held{spec.scenes[0], 0, sb::DepthMode::Open, "sm32", {}, 64, 0};
  const std::string heldKey = sb::cellKey(sb::cellIdentity(held, scene));

  // This test plays the other sweep: it holds the 64² cell while the sweep runs, then writes
  // that cell's record and lets go.
  auto lock = sb::CellLock::acquire(spec.out, heldKey, false);
  REQUIRE(lock);
  std::mutex mutex;
  std::condition_variable waiting;
  bool sweepWaits = false;
  sb::SweepEvents events;
  events.warning = [&](const std::string& w) {
    if (w.find("being built by another sweep") == std::string::npos) return;
    std::lock_guard guard(mutex);
    sweepWaits = true;
    waiting.notify_all();
  };
  sb::SweepOutcome outcome;
  std::thread sweep([&] { outcome = sb::runSweep(spec, events); });
  {
    std::unique_lock guard(mutex);
    REQUIRE(waiting.wait_for(guard, std::chrono::minutes(5), [&] { return sweepWaits; }));
  }
  sb::CellOptions options = spec.cellOptions;
  sb::writeRecord(spec.out / (heldKey + ".json"), sb::runCell(held, scene, options));
  lock.reset();
  sweep.join();
  CHECK(outcome.built == 1);  // 128² only
  CHECK(outcome.reused == 1);
  CHECK(jsonFilesIn(spec.out).size() == 2);

  // Two sweeps at once into a fresh folder build each cell once between them.
  spec.out = dir.path() / "shared";
  spec.resolutions = {"32", "64", "128"};
  sb::SweepOutcome one, two;
  std::thread first([&] { one = sb::runSweep(spec); });
  std::thread second([&] { two = sb::runSweep(spec); });
  first.join();
  second.join();
  CHECK(one.built + two.built == 3);
  CHECK(one.reused + two.reused == 3);
  CHECK(one.failed + two.failed == 0);
  CHECK(jsonFilesIn(spec.out).size() == 3);
}

// A sweep with a part size once reused the whole build's record for the cell in parts: the part
// size was missing from the planned cell's identity.
TEST_CASE("a sweep in parts is its own cell, built once, and its schemes share one depth pass",
          "[sweep][parts][regression]") {
  ScratchDir dir("sb-sweep-test");
  sb::SweepSpec spec = tinySweep(dir.path() / "out");
  spec.schemes = {"sm32", "sm-zstd"};
  spec.resolutions = {"64", "128"};
  spec.cellOptions.partsRoot = dir.path() / "parts";
  std::vector<sb::Record> built;
  sb::SweepEvents events;
  events.built = [&](const sb::Record& record) { built.push_back(record); };
  CHECK(sb::runSweep(spec, events).built == 4);
  for (const sb::Record& record : built) {
    INFO(record.scheme.name << " " << record.resolution);
    CHECK(record.time->depthSharedWith.size() == 1);  // the other scheme of its map
  }

  spec.partSize = 64;  // sm32 at 128² in parts; sm-zstd builds only whole, and 64² is not above
  const sb::SweepOutcome inParts = sb::runSweep(spec);
  CHECK(inParts.built == 1);
  CHECK(inParts.reused == 3);
  CHECK(sb::runSweep(spec).reused == 4);
  size_t partRecords = 0;
  for (const std::string& name : jsonFilesIn(spec.out))
    partRecords += sb::loadRecord(spec.out / name).partSize == 64;
  CHECK(partRecords == 1);
}

// A sweep with a part size below its resolution put the schemes built in parts and one that
// builds only whole (sm-zstd) in one depth pass, which refused them all ("cells built from one
// depth pass must share … part size"): every such cell was skipped.
TEST_CASE("schemes built in parts and one built whole take a depth pass each",
          "[sweep][parts][regression]") {
  ScratchDir dir("sb-sweep-test");
  sb::SweepSpec spec = tinySweep(dir.path() / "out");
  spec.schemes = {"sm32", "sm-zstd", "mh"};
  spec.resolutions = {"128"};
  spec.partSize = 64;
  spec.cellOptions.partsRoot = dir.path() / "parts";
  std::vector<sb::Record> built;
  sb::SweepEvents events;
  std::vector<std::string> warnings;
  events.built = [&](const sb::Record& record) { built.push_back(record); };
  events.warning = [&](const std::string& message) { warnings.push_back(message); };
  const sb::SweepOutcome outcome = sb::runSweep(spec, events);
  CHECK(warnings.empty());
  CHECK(outcome.failed == 0);
  REQUIRE(outcome.built == 3);
  for (const sb::Record& record : built) {
    INFO(record.scheme.name);
    const bool whole = record.scheme.name == "sm-zstd";
    CHECK(record.partSize == (whole ? 0u : 64u));
    REQUIRE(record.verification);
    CHECK(record.verification->mismatches == 0);
    // sm32 and mh share the pass over the parts; sm-zstd traced the map alone.
    CHECK(record.time->depthSharedWith.size() == (whole ? 0u : 1u));
  }
}
