// A sweep: every cell of a matrix — scenes × modes × schemes × resolutions — built once into a
// records folder, resuming finished cells, sharing the folder with other sweeps, then tabulated
// (DESIGN §6; issue 11 A1, A9, A10).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "harness/cell.h"
#include "harness/record_type.h"
#include "harness/table.h"

namespace sb {

struct SweepSpec {
  std::vector<std::string> scenes{"city"};
  std::vector<std::string> modes{"closed"};
  std::vector<std::string> schemes{"all"};  // "all": every registered scheme
  std::vector<std::string> resolutions{"1K", "2K", "4K", "8K"};
  // Given to the swept schemes that declare each parameter, so that one sweep can set a
  // parameter of one scheme beside others; a parameter no swept scheme has is an error.
  Params params;
  std::filesystem::path out = "results/sweep";
  // Cells above this resolution are built in parts of this side (0: every cell whole); their part
  // files go to cellOptions.partsRoot.
  uint32_t partSize = 0;
  CellOptions cellOptions;
};

struct SweepEvents {
  std::function<void(const Record&)> built;         // a cell built and its record written
  std::function<void(const std::string&)> warning;  // a cell that failed, waits, records moved
};

struct SweepOutcome {
  size_t built = 0, reused = 0, failed = 0;  // failed: not built, or built with mismatches
  size_t superseded = 0;                     // older records moved to <out>/superseded
  std::vector<Table> tables;                 // of every record in the folder
};

// Checks the whole matrix before building anything — every scene spec opens, every mode,
// resolution, scheme and parameter is valid, every cell still to build fits in memory, the
// folder is writable — and throws naming the first problem. Then builds each cell unless a record
// in `out` answers it (recordIdentity equal), under a CellLock: a cell another sweep holds is
// revisited at the end, after waiting for its lock. Cells of one map (scene, mode, resolution)
// are built together from one depth pass, as many at once as fit in memory (issue 12). A rebuilt
// cell's older records (same request, other identity) move to <out>/superseded/. A cell that fails
// does not stop the sweep. Finally writes the tables of the folder to <out>/tables.
SweepOutcome runSweep(const SweepSpec& spec, const SweepEvents& events = {});

}  // namespace sb
