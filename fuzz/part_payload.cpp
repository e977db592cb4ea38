// libFuzzer target: one scheme's part payload parser (PartMerger::add, issue 12). The input is
// the payload of part 0 of a 32² map in parts of 16² (closed mode, the scheme's defaults); parts
// 1–3 get the valid payloads the scheme's own part encoder writes for a seeded random map, so a
// payload that is accepted is merged into a whole structure, which must then answer every lookup
// within bounds. The scheme is named by SHADOWBENCH_FUZZ_SCHEME. With SHADOWBENCH_FUZZ_WRITE_SEED
// set to a path, the binary writes the valid payload of part 0 there and exits: the seed of
// fuzz/corpus/part-<scheme>/.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <span>
#include <vector>

#include "fuzz/exercise_decoder.h"
#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

namespace {

constexpr uint32_t kResolution = 32, kPartSize = 16;
const sb::SchemeInfo* scheme = nullptr;
sb::ParamValues params;
sb::MapInfo map;
std::vector<std::vector<uint8_t>> validPayloads;  // of parts 0 … 3

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* name = std::getenv("SHADOWBENCH_FUZZ_SCHEME");
  try {
    scheme = &sb::findScheme(name ? name : "");
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "SHADOWBENCH_FUZZ_SCHEME: %s\n", error.what());
    std::exit(2);
  }
  if (!scheme->buildsInParts()) {
    std::fprintf(stderr, "SHADOWBENCH_FUZZ_SCHEME: %s does not build in parts\n", name);
    std::exit(2);
  }
  params = scheme->resolve({});
  const auto depths = sb::testing::SyntheticMap::random(kResolution, sb::DepthMode::Closed, 0x5eed);
  map = depths.info(scheme->kind);
  validPayloads = depths.partPayloads(*scheme, {}, kPartSize, kPartSize);
  if (const char* seed = std::getenv("SHADOWBENCH_FUZZ_WRITE_SEED")) {
    std::ofstream(seed, std::ios::binary)
        .write(reinterpret_cast<const char*>(validPayloads[0].data()),
               std::streamsize(validPayloads[0].size()));
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sb::testing::NullBuildContext context;
  auto merger = scheme->makePartMerger(map, params, {kPartSize, kPartSize});
  try {
    sb::fuzz::exerciseDecoder(*sb::testing::mergePayloads(
        *merger, validPayloads.size(), kPartSize,
        [&](uint64_t index) {
          return index == 0 ? std::span(data, size)
                            : std::span<const uint8_t>(validPayloads[index]);
        },
        context));
  } catch (const sb::FormatError&) {
  }
  return 0;
}
