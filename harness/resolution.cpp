#include "harness/resolution.h"

#include <stdexcept>

#include <fmt/format.h>

#include "schemes/interface/lightspace.h"

namespace sb {

uint32_t parseResolution(std::string_view text) {
  std::string_view digits = text;
  uint64_t multiplier = 1;
  if (!digits.empty()) {
    const char unit = digits.back();
    if (unit == 'K' || unit == 'k') multiplier = 1024;
    if (unit == 'M' || unit == 'm') multiplier = 1024 * 1024;
    if (multiplier != 1) digits.remove_suffix(1);
  }
  uint64_t value = 0;
  bool ok = !digits.empty() && digits.size() < 10;
  for (char c : digits) ok = ok && c >= '0' && c <= '9', value = value * 10 + uint64_t(c - '0');
  value *= multiplier;
  if (!ok || !validResolution(value))
    throw std::invalid_argument(fmt::format(
        "resolution '{}' must be a power of two from 8 to 1024K (e.g. 512, 4K, 64K)", text));
  return uint32_t(value);
}

std::string resolutionLabel(uint32_t resolution) {
  return resolution >= 1024 ? fmt::format("{}K", resolution / 1024) : fmt::format("{}", resolution);
}

void checkTileSize(uint32_t tileSize, uint32_t resolution) {
  if (tileSize != 0 && (tileSize < 8 || tileSize > resolution || (tileSize & (tileSize - 1)) != 0))
    throw std::invalid_argument(
        fmt::format("tile size {} must be a power of two in [8, {}]", tileSize, resolution));
}

}  // namespace sb
