// The map's shape as a user writes it: texels per side ("4K", "1M") and the tile size streamed
// to the encoder, checked before any work starts.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace sb {

// Parses "4096", "4K", "4k", "256K", "1M", "1m" into texels per side (K = 1024, M = 1024²);
// throws std::invalid_argument unless it is a power of two from 8 to 1024K.
uint32_t parseResolution(std::string_view text);
std::string resolutionLabel(uint32_t resolution);  // 4096 → "4K"

// Throws std::invalid_argument unless `tileSize` is 0 (the default) or a power of two in
// [8, resolution]: what streamDualDepth accepts, checked before the scene is opened.
void checkTileSize(uint32_t tileSize, uint32_t resolution);

}  // namespace sb
