// Part files (DESIGN §5, issue 12): one part of a build in parts as one scheme encoded it, with
// everything that says which build it belongs to — scene hash, fitted light, mode, resolution,
// tile and part size, scheme and parameters, part index — and what encoding it cost, so that a
// merge can record the whole build's times from the parts alone. A build resumes from the part
// files it finds; one that belongs to another build is refused, never overwritten.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "schemes/interface/serial.h"

namespace sb {

inline constexpr FileFraming kPartFraming{{'S', 'H', 'D', 'W', 'P', 'A', 'R', 'T'}, 1, "part file"};

// Which build a part belongs to, and which part it is.
struct PartIdentity {
  StructureHeader structure;  // scheme, resolved parameters, map, scene hash
  nlohmann::json light;       // Light::describe() of the fitted light
  uint32_t tileSize = 0, partSize = 0;
  uint64_t part = 0;
};

// What encoding one part cost. The depth pass of a part may be shared by several schemes
// (`depthSharedWith` names the others); its time is the same figure in each of their part files.
// So may its part encoder, when their schemes write the same part payload
// (SchemeInfo::partPayload; `encoderSharedWith` names them): its phases are the same in each.
struct PartCosts {
  double depthSeconds = 0;  // tracing, thread-seconds divided by the threads available
  double wallSeconds = 0;   // the part's depth pass and encoding, wall time
  std::vector<std::pair<std::string, double>> phases;
  std::map<std::string, uint64_t> counters;
  uint64_t peakRssBytes = 0;
  // The declared memory of the part's depth pass: every part encoder it ran (0: not recorded;
  // the key is optional, so part files written before it existed still read).
  uint64_t estimatedBytes = 0;
  uint64_t closedFallbacks = 0;
  std::vector<std::string> depthSharedWith;
  std::vector<std::string> encoderSharedWith;
};

// A part's scheme payload is written compressed (zstd): the MH's part payloads take 13 bytes a
// node, 12 GB for the open city at 32K² and 4× more a doubling, and compress to about half.
// Files written before, with the payload as it is, still read.
struct PartFile {
  PartIdentity identity;
  PartCosts costs;
  // The whole file, its payload after its tag; or the payload decompressed, where the file holds
  // it compressed.
  std::vector<uint8_t> bytes;
  std::span<const uint8_t> payload;  // the scheme's payload, in `bytes`
};

// The file of part `part` in a build's part folder.
std::filesystem::path partFilePath(const std::filesystem::path& folder, uint64_t part);

// `compress`: the payload compressed, as savePartFile writes it; false: as it is, as part files
// were written before.
std::vector<uint8_t> encodePartFile(const PartIdentity& identity, const PartCosts& costs,
                                    std::span<const uint8_t> payload, bool compress = true);
// Throws FormatError for a damaged or foreign file.
PartFile decodePartFile(std::vector<uint8_t> bytes);

// Written atomically: a build killed while writing leaves no part file, never half of one.
void savePartFile(const std::filesystem::path& path, const PartIdentity& identity,
                  const PartCosts& costs, std::span<const uint8_t> payload);

// A part file that exists but belongs to another build (scene, light, mode, resolution, tile or
// part size, scheme or parameters, part index): the message names the field and both values.
class PartMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The bytes of the payload of part file `path` as a merge holds it (decompressed), from its
// header alone; a file written before compression, its size. Throws FormatError.
uint64_t partPayloadBytes(const std::filesystem::path& path);

// Loads `path` and checks it is the part `expected` describes: throws FormatError (prefixed with
// the path) for a damaged file and PartMismatch for another build's.
PartFile loadPartFile(const std::filesystem::path& path, const PartIdentity& expected);

}  // namespace sb
