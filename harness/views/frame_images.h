// The pictures of a scored frame: a shadow mask (lit, shadowed, nothing hit) and an error map
// (false lit, false shadow over the dimmed truth), as 8-bit PNG (libpng) and as EXR (OpenEXR:
// the visibility itself, a float channel, for tools that want the numbers).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace sb {

struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgb;  // row-major, top row first
};

RgbImage shadowMaskImage(uint32_t width, uint32_t height, std::span<const uint8_t> covered,
                         std::span<const float> visibility);
RgbImage errorImage(uint32_t width, uint32_t height, std::span<const uint8_t> covered,
                    std::span<const uint8_t> truthLit, std::span<const float> visibility);

// Both throw std::runtime_error naming the file.
void writePng(const std::filesystem::path& path, const RgbImage& image);
// Channel "V": visibility where covered, −1 where nothing was hit.
void writeVisibilityExr(const std::filesystem::path& path, uint32_t width, uint32_t height,
                        std::span<const uint8_t> covered, std::span<const float> visibility);

}  // namespace sb
