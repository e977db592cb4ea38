// libFuzzer target: parseQueryLine on one line (the input up to its first newline, as getline
// gives it). Refusals are std::invalid_argument; an accepted line must be a valid query.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "harness/query_line.h"
#include "schemes/interface/lightspace.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view line(reinterpret_cast<const char*>(data), size);
  line = line.substr(0, line.find('\n'));
  try {
    const auto parsed = sb::parseQueryLine(line, 1);
    if (parsed && !(std::isfinite(parsed->query.x) && std::isfinite(parsed->query.y) &&
                    std::isfinite(parsed->query.z) && sb::validFilterSize(parsed->filter)))
      std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
