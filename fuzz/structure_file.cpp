// libFuzzer target: a whole structure file (container and payload), as `query`, `verify` and
// `bench` read it. The only acceptable failure is a FormatError.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz/exercise_decoder.h"
#include "schemes/interface/serial.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const auto decoder = sb::decodeStructureFile(std::span(data, size), nullptr);
    sb::fuzz::exerciseDecoder(*decoder);
  } catch (const sb::FormatError&) {
  }
  return 0;
}
