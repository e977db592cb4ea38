// Builds in parts (DESIGN §5, issue 12): the harness's side of parts.h. Each part's depth is
// traced once and handed to every scheme that still needs that part, each part encoding is saved
// as a part file at once, and a build killed at any moment resumes from the part files it finds
// (checksums and identity checked), losing at most the part in flight. The merge reads a scheme's
// part files in order and records the whole build's costs from them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>

#include "harness/build.h"
#include "harness/part_file.h"

namespace sb {

// One scheme's share of a build in parts: which build its part files belong to and where they go.
struct PartsTarget {
  SchemeBuild build;
  PartIdentity identity;         // of part 0; every part file of the build matches it but the index
  std::filesystem::path folder;  // the scheme's part files, partFilePath(folder, index)
};

// Throws std::invalid_argument unless `partSize` is a power of two with tileSize ≤ partSize < R,
// and the scheme builds in parts.
void checkPartShape(const SchemeInfo& scheme, const MapInfo& map, const BuildShape& shape);

// The declared memory of one part's depth pass over `builds`: one part encoder per distinct part
// payload (SchemeInfo::partPayload), as encodeParts runs them.
uint64_t partPassBytes(std::span<const SchemeBuild> builds, DepthMode mode, uint32_t resolution,
                       const BuildShape& shape);

struct PartsEncoded {
  uint64_t encoded = 0;  // parts encoded now, for at least one target
  uint64_t kept = 0;     // parts every target already had
};

// Encodes every part (or only part `only`) that some target lacks, one depth pass per part for all
// the targets lacking it, and saves each target's part file as soon as it is encoded. A damaged
// part file (checksum, format) is encoded again; one of another build is refused (PartMismatch)
// and nothing is overwritten. `progress` is told parts done out of the parts to do.
PartsEncoded encodeParts(const DepthSource& source, std::span<const PartsTarget> targets,
                         const BuildShape& shape, std::optional<uint64_t> only = std::nullopt,
                         const std::function<void(uint64_t done, uint64_t total)>& progress = {});

// The target's structure from its part files, in part order; throws naming a missing part (and
// how many are missing), and refuses a merge whose declared memory, from the part files' bytes
// (BuildShape::partFiles), does not fit. Times, counters and peak memory are the parts' (summed;
// the peak is the largest) with the merge's phases and peak added. `progress` hears of every
// part merged, per pass over the parts (PartMerger::anotherPass), counted from 0.
BuildOutcome mergeParts(
    const PartsTarget& target, DepthMode mode, uint32_t resolution, const BuildShape& shape,
    const std::function<void(uint64_t pass, uint64_t done, uint64_t total)>& progress = {});

}  // namespace sb
