// Builds in parts driven step by step for the CPVS tests: the payload of every part kept, as the
// harness writes them to part files, and merged with a context that records the counters.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

namespace sb::testing {

class CountingContext final : public BuildContext {
 public:
  void phase(std::string_view) override {}
  void count(std::string_view name, uint64_t value) override { counts[std::string(name)] += value; }
  void reserve(uint64_t, std::string_view) override {}
  std::map<std::string, uint64_t> counts;
};

inline std::unique_ptr<Decoder> buildWhole(const SyntheticMap& map, const SchemeInfo& scheme,
                                           const Params& params, uint32_t tileSize,
                                           BuildContext& context) {
  auto encoder =
      scheme.makeEncoder(map.info(scheme.kind), scheme.resolve(params), BuildShape{tileSize});
  map.stream(tileSize, [&](const DualDepthTile& tile) { encoder->consume(tile, context); });
  return encoder->finish(context);
}

// Adds parts [0, end) to `merger`, each payload read to its end.
inline void addParts(PartMerger& merger, const std::vector<std::vector<uint8_t>>& payloads,
                     uint32_t partSize, BuildContext& context, size_t first = 0,
                     size_t end = ~size_t(0)) {
  for (size_t index = first; index < std::min(end, payloads.size()); ++index) {
    ByteReader in(payloads[index]);
    merger.add(MapPart::of(index, partSize), in, context);
    in.expectEnd();
  }
}

inline std::unique_ptr<Decoder> mergeParts(const SyntheticMap& map, const SchemeInfo& scheme,
                                           const Params& params, uint32_t tileSize,
                                           uint32_t partSize,
                                           const std::vector<std::vector<uint8_t>>& payloads,
                                           BuildContext& context) {
  auto merger =
      scheme.makePartMerger(map.info(scheme.kind), scheme.resolve(params), {tileSize, partSize});
  return mergePayloads(
      *merger, payloads.size(), partSize,
      [&](uint64_t index) -> std::span<const uint8_t> { return payloads[index]; }, context);
}

}  // namespace sb::testing
