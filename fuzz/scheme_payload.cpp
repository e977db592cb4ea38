// libFuzzer target: one scheme's payload parser (SchemeInfo::load). The input becomes the
// payload of a valid container (the golden files' header: the scheme's defaults, 8², closed;
// correct checksum), so that the fuzzer spends its time past the checksum, in the scheme.
// The scheme is named by SHADOWBENCH_FUZZ_SCHEME: one binary serves every scheme.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

#include "fuzz/exercise_decoder.h"
#include "schemes/interface/serial.h"

namespace {

// Bytes handed to encodeStructureFile as if a decoder had saved them: the container is then
// written by the same code as every real structure file.
class RawPayload final : public sb::Decoder {
 public:
  explicit RawPayload(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  void lookup(std::span<const sb::Query>, int, std::span<float>) const override { std::abort(); }
  sb::SizeBreakdown size() const override { return {}; }
  void save(sb::ByteWriter& out) const override { out.append(bytes_.data(), bytes_.size()); }

 private:
  std::span<const uint8_t> bytes_;
};

sb::StructureHeader header;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* name = std::getenv("SHADOWBENCH_FUZZ_SCHEME");
  try {
    const sb::SchemeInfo& scheme = sb::findScheme(name ? name : "");
    constexpr uint32_t kResolution = 8;
    header = {scheme.name,
              scheme.resolve({}).text(),
              {kResolution, scheme.kind == sb::SchemeKind::Voxel ? kResolution : 0,
               sb::DepthMode::Closed},
              ""};
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "SHADOWBENCH_FUZZ_SCHEME: %s\n", error.what());
    std::exit(2);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> file =
      sb::encodeStructureFile(header, RawPayload(std::span(data, size)));
  try {
    const auto decoder = sb::decodeStructureFile(file, nullptr);
    sb::fuzz::exerciseDecoder(*decoder);
  } catch (const sb::FormatError&) {
  }
  return 0;
}
