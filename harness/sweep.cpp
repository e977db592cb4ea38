#include "harness/sweep.h"

#include <algorithm>
#include <deque>
#include <set>
#include <stdexcept>
#include <system_error>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "harness/cell_key.h"
#include "harness/cell_lock.h"
#include "harness/machine.h"
#include "harness/record.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

struct PlannedCell {
  CellSpec spec;
  const Scene* scene = nullptr;
  Record identity;  // cellIdentity: a reusable record has its recordIdentity
  std::string key;
  fs::path path;        // out/<key>.json
  fs::path legacyPath;  // out/<readableCellKey>.json, where records were before the hash
};

struct SweepPlan {
  std::deque<Scene> scenes;  // a deque: cells point into it
  std::vector<PlannedCell> cells;
};

// The parameters of `given` that `scheme` declares.
Params declaredParams(const SchemeInfo& scheme, const Params& given) {
  Params own;
  for (const ParamSpec& spec : scheme.params)
    if (const auto it = given.find(spec.name); it != given.end()) own.insert(*it);
  return own;
}

std::vector<const SchemeInfo*> sweptSchemes(const SweepSpec& spec) {
  std::vector<const SchemeInfo*> swept;
  for (const std::string& name : spec.schemes) {
    if (name == "all")
      for (const SchemeInfo& s : schemes()) swept.push_back(&s);
    else
      swept.push_back(&findScheme(name));  // throws naming the schemes there are
  }
  return swept;
}

void checkParams(const std::vector<const SchemeInfo*>& swept, const Params& params) {
  std::set<std::string> declared;
  for (const SchemeInfo* scheme : swept) {
    scheme->resolve(declaredParams(*scheme, params));  // throws on a bad value
    for (const ParamSpec& p : scheme->params) declared.insert(p.name);
  }
  for (const auto& [name, value] : params)
    if (!declared.count(name))
      throw std::invalid_argument(
          fmt::format("no swept scheme has a parameter '{}' (see 'shadowbench schemes')", name));
}

// The record at `path` when it answers `identity`; nullopt when absent, unreadable or another.
std::optional<Record> answering(const fs::path& path, const Record& identity) {
  std::error_code error;
  if (!fs::exists(path, error)) return std::nullopt;
  try {
    Record record = loadRecord(path);
    if (recordIdentity(record) == recordIdentity(identity)) return record;
  } catch (const RecordError&) {
  }
  return std::nullopt;
}

SweepPlan plan(const SweepSpec& spec) {
  const std::vector<const SchemeInfo*> swept = sweptSchemes(spec);
  checkParams(swept, spec.params);
  std::vector<DepthMode> modes;
  for (const std::string& mode : spec.modes) modes.push_back(depthModeFromString(mode));
  std::vector<uint32_t> resolutions;
  for (const std::string& resolution : spec.resolutions)
    resolutions.push_back(parseResolution(resolution));
  SweepPlan plan;
  for (const std::string& sceneSpec : spec.scenes) plan.scenes.push_back(openScene(sceneSpec));
  checkWritableFolder(spec.out);

  for (size_t s = 0; s < spec.scenes.size(); ++s)
    for (DepthMode mode : modes)
      for (const SchemeInfo* scheme : swept)
        for (uint32_t resolution : resolutions) {
          PlannedCell cell;
          cell.spec = {spec.scenes[s], 0, mode, scheme->name, declaredParams(*scheme, spec.params),
                       resolution, 0,
                       // Schemes that build only whole are built whole (and refused below
                       // where that does not fit).
                       scheme->buildsInParts() && spec.partSize && spec.partSize < resolution
                           ? spec.partSize
                           : 0};
          cell.scene = &plan.scenes[s];
          cell.identity = cellIdentity(cell.spec, *cell.scene);
          cell.key = cellKey(cell.identity);
          cell.path = spec.out / (cell.key + ".json");
          cell.legacyPath = spec.out / (readableCellKey(cell.identity) + ".json");
          if (!answering(cell.path, cell.identity) && !answering(cell.legacyPath, cell.identity)) {
            try {
              const BuildShape shape = cell.spec.shape();
              const MapInfo map = mapFor(*scheme, mode, resolution);
              if (shape.partSize) checkPartShape(*scheme, map, shape);
              checkBuildFits(*scheme, map, scheme->resolve(cell.spec.params), shape);
            } catch (const std::exception& error) {
              throw std::runtime_error(fmt::format("cell {}: {}", cell.key, error.what()));
            }
          }
          plan.cells.push_back(std::move(cell));
        }
  return plan;
}

// "2026-11-26T10:00:00Z" → "20261126T100000Z": the letters and digits of a record's time, for a
// file name; "undated" when there are none.
std::string compactTime(const std::string& created) {
  std::string compact;
  for (char c : created)
    if ((c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) compact += c;
  return compact.empty() ? std::string("undated") : compact;
}

class Sweeper {
 public:
  Sweeper(const SweepSpec& spec, const SweepEvents& events) : spec_(spec), events_(events) {}

  // Whether a record answers the cell (moving a record from its name before the request hash
  // to the cell's path); the caller holds the cell's lock.
  bool reuse(const PlannedCell& cell) {
    if (answering(cell.path, cell.identity)) {
      ++outcome.reused;
      return true;
    }
    if (answering(cell.legacyPath, cell.identity)) {
      fs::rename(cell.legacyPath, cell.path);
      ++outcome.reused;
      return true;
    }
    return false;
  }

  // Builds cells of one depth pass from that pass, in batches that fit in memory together; the
  // caller holds their locks. Each record is written as soon as its cell is complete.
  void buildTogether(const std::vector<const PlannedCell*>& cells) {
    for (const std::vector<const PlannedCell*>& batch : batchesThatFit(cells)) {
      std::vector<CellSpec> specs;
      for (const PlannedCell* cell : batch) specs.push_back(cell->spec);
      std::vector<bool> finished(batch.size(), false);
      try {
        runCells(specs, *batch.front()->scene, spec_.cellOptions,
                 [&](size_t c, const Record& record) {
                   moveAsideOlderRecords(*batch[c]);
                   writeRecord(batch[c]->path, record);
                   finished[c] = true;
                   ++outcome.built;
                   if (record.verification && record.verification->mismatches > 0) ++outcome.failed;
                   if (events_.built) events_.built(record);
                 });
      } catch (const std::exception& error) {
        // Cells that cannot be built (e.g. memory taken since the check) do not stop the sweep;
        // those of the batch already recorded stay.
        for (size_t c = 0; c < batch.size(); ++c)
          if (!finished[c]) {
            warn(fmt::format("cell {} skipped: {}", batch[c]->key, error.what()));
            ++outcome.failed;
          }
      }
    }
  }

  void warn(const std::string& message) const {
    if (events_.warning) events_.warning(message);
  }

  SweepOutcome outcome;

 private:
  // What the new record replaces, kept and never reused: the file at the cell's path (another
  // identity — an edited scene — or not a record at all) and a record of the same request under
  // the name used before the request hash.
  void moveAsideOlderRecords(const PlannedCell& cell) {
    std::error_code error;
    if (fs::exists(cell.path, error)) moveAside(cell.path, cell);
    try {
      if (fs::exists(cell.legacyPath, error) &&
          recordRequest(loadRecord(cell.legacyPath)) == recordRequest(cell.identity))
        moveAside(cell.legacyPath, cell);
    } catch (const RecordError&) {
      // Not a record: not this cell's to move.
    }
  }

  // Moves `path` to <out>/superseded/<name>.<created>.json, saying why it no longer answers
  // `cell`.
  void moveAside(const fs::path& path, const PlannedCell& cell) {
    std::string created, why;
    try {
      const Record old = loadRecord(path);
      created = old.created;
      const nlohmann::json was = recordIdentity(old), now = recordIdentity(cell.identity);
      std::vector<std::string> changed;
      for (const auto& [field, value] : now.items())
        if (was.value(field, nlohmann::json()) != value) changed.push_back(field);
      why = fmt::format("its {} differ", fmt::join(changed, ", "));
    } catch (const RecordError& error) {
      why = error.what();
    }
    const fs::path folder = spec_.out / kSupersededFolder;
    fs::create_directories(folder);
    const std::string base = fmt::format("{}.{}", path.stem().string(), compactTime(created));
    fs::path target = folder / (base + ".json");
    for (int n = 2; fs::exists(target); ++n) target = folder / fmt::format("{}-{}.json", base, n);
    fs::rename(path, target);
    ++outcome.superseded;
    warn(fmt::format("'{}' does not answer cell {} ({}): moved to '{}'", path.string(), cell.key,
                     why, target.string()));
  }

  // Consecutive runs of `cells` whose declared build memory fits in what is free together.
  static std::vector<std::vector<const PlannedCell*>> batchesThatFit(
      const std::vector<const PlannedCell*>& cells) {
    const uint64_t available = availableMemoryBytes();
    std::vector<std::vector<const PlannedCell*>> batches;
    uint64_t held = 0;
    for (const PlannedCell* cell : cells) {
      const SchemeInfo& scheme = findScheme(cell->spec.scheme);
      const uint64_t bytes =
          scheme.buildBytes
              ? scheme.buildBytes(mapFor(scheme, cell->spec.mode, cell->spec.resolution),
                                  scheme.resolve(cell->spec.params), cell->spec.shape())
              : 0;
      if (batches.empty() || held + bytes > available) batches.emplace_back(), held = 0;
      batches.back().push_back(cell);
      held += bytes;
    }
    return batches;
  }

  const SweepSpec& spec_;
  const SweepEvents& events_;
};

}  // namespace

SweepOutcome runSweep(const SweepSpec& spec, const SweepEvents& events) {
  const SweepPlan planned = plan(spec);
  Sweeper sweeper(spec, events);
  // Cells of one depth pass are adjacent once sorted by it: scene, mode, resolution, tile and
  // part size. A scheme that builds only whole does not share the pass of those built in parts
  // of the same map (one traces the map once, the other once per part).
  std::vector<const PlannedCell*> order;
  for (const PlannedCell& cell : planned.cells) order.push_back(&cell);
  const auto depthPassOf = [](const PlannedCell* cell) {
    return std::tuple(cell->scene, cell->spec.mode, cell->spec.resolution, cell->spec.tileSize,
                      cell->spec.partSize);
  };
  std::stable_sort(order.begin(), order.end(), [&](const PlannedCell* a, const PlannedCell* b) {
    return depthPassOf(a) < depthPassOf(b);
  });
  std::vector<const PlannedCell*> heldElsewhere;
  for (size_t begin = 0; begin < order.size();) {
    size_t end = begin;
    while (end < order.size() && depthPassOf(order[end]) == depthPassOf(order[begin])) ++end;
    std::vector<CellLock> locks;
    std::vector<const PlannedCell*> toBuild;
    for (size_t c = begin; c < end; ++c) {
      auto lock = CellLock::acquire(spec.out, order[c]->key, /*wait=*/false);
      if (!lock)
        heldElsewhere.push_back(order[c]);
      else if (!sweeper.reuse(*order[c]))
        toBuild.push_back(order[c]), locks.push_back(std::move(*lock));
    }
    sweeper.buildTogether(toBuild);
    begin = end;
  }
  for (const PlannedCell* cell : heldElsewhere) {
    sweeper.warn(fmt::format("cell {} is being built by another sweep: waiting for it", cell->key));
    const auto lock = CellLock::acquire(spec.out, cell->key, /*wait=*/true);
    if (!sweeper.reuse(*cell)) sweeper.buildTogether({cell});
  }

  FolderTables found = tablesOfFolder(spec.out);
  for (const std::string& problem : found.problems) sweeper.warn("table: " + problem);
  writeTables(found.tables, spec.out / "tables");
  SweepOutcome outcome = std::move(sweeper.outcome);
  outcome.tables = std::move(found.tables);
  return outcome;
}

}  // namespace sb
