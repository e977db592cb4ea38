// How wrongly a technique shadows one frame, against the ray-traced ground truth (DESIGN §5b):
// pixels shadowed that are lit (false shadow) and lit that are shadowed (false lit), over every
// covered pixel and over those near a shadow boundary, where aliasing lives.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

namespace sb {

// A technique's visibility counts as lit from this value up: the point test answers 0 or 1, a
// PCF answer is a fraction and is judged by which side of one half it falls.
inline constexpr float kLitThreshold = 0.5f;

struct FrameScore {
  uint64_t covered = 0, falseLit = 0, falseShadow = 0;
  uint64_t boundary = 0, boundaryFalseLit = 0, boundaryFalseShadow = 0;

  FrameScore& operator+=(const FrameScore& other);
  double errorRate() const;          // (false lit + false shadow) / covered
  double boundaryErrorRate() const;  // the same over boundary pixels
  nlohmann::json toJson() const;
};

// Per pixel: 1 where a covered pixel lies within `radius` pixels (Chebyshev) of a covered pixel
// whose ground truth differs from its own.
std::vector<uint8_t> shadowBoundary(uint32_t width, uint32_t height,
                                    std::span<const uint8_t> covered, std::span<const uint8_t> lit,
                                    uint32_t radius);

FrameScore scoreFrame(std::span<const uint8_t> covered, std::span<const uint8_t> truthLit,
                      std::span<const uint8_t> boundary, std::span<const float> visibility);

}  // namespace sb
