#include "harness/views/frame_score.h"

#include <algorithm>
#include <stdexcept>

namespace sb {

FrameScore& FrameScore::operator+=(const FrameScore& o) {
  covered += o.covered, falseLit += o.falseLit, falseShadow += o.falseShadow;
  boundary += o.boundary, boundaryFalseLit += o.boundaryFalseLit;
  boundaryFalseShadow += o.boundaryFalseShadow;
  return *this;
}

double FrameScore::errorRate() const {
  return covered ? double(falseLit + falseShadow) / double(covered) : 0.0;
}

double FrameScore::boundaryErrorRate() const {
  return boundary ? double(boundaryFalseLit + boundaryFalseShadow) / double(boundary) : 0.0;
}

nlohmann::json FrameScore::toJson() const {
  return {{"covered", covered},
          {"false_lit", falseLit},
          {"false_shadow", falseShadow},
          {"boundary", boundary},
          {"boundary_false_lit", boundaryFalseLit},
          {"boundary_false_shadow", boundaryFalseShadow},
          {"error_rate", errorRate()},
          {"boundary_error_rate", boundaryErrorRate()}};
}

std::vector<uint8_t> shadowBoundary(uint32_t width, uint32_t height,
                                    std::span<const uint8_t> covered, std::span<const uint8_t> lit,
                                    uint32_t radius) {
  const size_t pixels = size_t(width) * height;
  if (covered.size() != pixels || lit.size() != pixels)
    throw std::invalid_argument("shadowBoundary: masks do not match the frame size");
  // A pixel is an edge pixel when a 4-neighbour (both covered) differs; the boundary is every
  // covered pixel within `radius` of an edge pixel.
  std::vector<uint8_t> edge(pixels, 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t p = size_t(y) * width + x;
      if (!covered[p]) continue;
      const auto differs = [&](size_t q) { return covered[q] && lit[q] != lit[p]; };
      if (x + 1 < width && differs(p + 1)) edge[p] = edge[p + 1] = 1;
      if (y + 1 < height && differs(p + width)) edge[p] = edge[p + width] = 1;
    }
  std::vector<uint8_t> boundary(pixels, 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      if (!edge[size_t(y) * width + x]) continue;
      for (uint32_t v = y > radius ? y - radius : 0; v <= std::min(height - 1, y + radius); ++v)
        for (uint32_t u = x > radius ? x - radius : 0; u <= std::min(width - 1, x + radius); ++u)
          boundary[size_t(v) * width + u] = covered[size_t(v) * width + u];
    }
  return boundary;
}

FrameScore scoreFrame(std::span<const uint8_t> covered, std::span<const uint8_t> truthLit,
                      std::span<const uint8_t> boundary, std::span<const float> visibility) {
  if (truthLit.size() != covered.size() || boundary.size() != covered.size() ||
      visibility.size() != covered.size())
    throw std::invalid_argument("scoreFrame: masks do not match the frame size");
  FrameScore s;
  for (size_t p = 0; p < covered.size(); ++p) {
    if (!covered[p]) continue;
    const bool lit = visibility[p] >= kLitThreshold;
    const bool falseLit = lit && !truthLit[p], falseShadow = !lit && truthLit[p];
    ++s.covered, s.falseLit += falseLit, s.falseShadow += falseShadow;
    if (boundary[p])
      ++s.boundary, s.boundaryFalseLit += falseLit, s.boundaryFalseShadow += falseShadow;
  }
  return s;
}

}  // namespace sb
