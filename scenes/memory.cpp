#include "scenes/memory.h"

#include <charconv>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "scenes/scene.h"

namespace sb::detail {

uint64_t availableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  constexpr std::string_view kKey = "MemAvailable:";
  for (std::string line; std::getline(meminfo, line);) {
    if (line.compare(0, kKey.size(), kKey) != 0) continue;
    const size_t digits = line.find_first_not_of(' ', kKey.size());
    uint64_t kilobytes = 0;
    if (digits == std::string::npos) return 0;
    const auto [end, error] =
        std::from_chars(line.data() + digits, line.data() + line.size(), kilobytes);
    return error == std::errc{} && end != line.data() + digits ? kilobytes * 1024 : 0;
  }
  return 0;
}

void checkFitsInMemory(std::string_view origin, std::string_view what, uint64_t neededBytes,
                       uint64_t limitBytes, std::string_view advice) {
  if (neededBytes <= limitBytes) return;
  constexpr double kGiB = 1ull << 30;
  throw SceneError(
      fmt::format("{}: {} needs at least {:.2f} GiB ({} bytes) but only {:.2f} GiB of memory is "
                  "available; {}",
                  origin, what, neededBytes / kGiB, neededBytes, limitBytes / kGiB, advice));
}

}  // namespace sb::detail
