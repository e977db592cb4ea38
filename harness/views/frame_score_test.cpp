// The error counts on synthetic frames whose answers are known by hand (issue 15).
#include <catch2/catch.hpp>

#include "harness/views/frame_score.h"

using namespace sb;

TEST_CASE("error counts of a hand-made frame", "[views][score]") {
  // 4 × 2 pixels; the last one is sky.
  const std::vector<uint8_t> covered = {1, 1, 1, 1, 1, 1, 1, 0};
  const std::vector<uint8_t> truth = {1, 1, 0, 0, 1, 0, 1, 0};
  const std::vector<float> answer = {1, 0, 0, 1, 0.5f, 0.25f, 0.75f, 0};
  const std::vector<uint8_t> boundary = {0, 1, 1, 0, 0, 1, 1, 0};
  const FrameScore s = scoreFrame(covered, truth, boundary, answer);
  CHECK(s.covered == 7);
  CHECK(s.falseShadow == 1);  // pixel 1
  CHECK(s.falseLit == 1);     // pixel 3; pixel 4, at one half, counts as lit, as in truth
  CHECK(s.boundary == 4);
  CHECK(s.boundaryFalseShadow == 1);
  CHECK(s.boundaryFalseLit == 0);
  CHECK(s.errorRate() == Approx(2.0 / 7));
  CHECK(s.boundaryErrorRate() == Approx(1.0 / 4));
  FrameScore sum = s;
  sum += s;
  CHECK(sum.falseLit == 2);
  CHECK(sum.toJson()["boundary_false_shadow"] == 2);
}

TEST_CASE("the boundary band around a true shadow edge", "[views][score]") {
  // 8 × 3: columns 0–3 lit, 4–7 shadowed; column 7 of the middle row is sky.
  const uint32_t w = 8, h = 3;
  std::vector<uint8_t> covered(w * h, 1), lit(w * h, 0);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < 4; ++x) lit[y * w + x] = 1;
  covered[1 * w + 7] = 0;
  for (const uint32_t radius : {0u, 1u, 2u}) {
    const std::vector<uint8_t> band = shadowBoundary(w, h, covered, lit, radius);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        // The edge pixels are columns 3 and 4; the band reaches `radius` further.
        const bool near = int(x) >= 3 - int(radius) && x <= 4 + radius;
        CHECK(band[y * w + x] == uint8_t(near && covered[y * w + x]));
      }
  }
  // A shadow edge against the sky is not a shadow boundary.
  std::vector<uint8_t> allLit(w * h, 1);
  const std::vector<uint8_t> none = shadowBoundary(w, h, covered, allLit, 2);
  CHECK(std::count(none.begin(), none.end(), 1) == 0);
}

TEST_CASE("masks of other sizes are refused", "[views][score]") {
  const std::vector<uint8_t> a(4, 1), b(5, 1);
  const std::vector<float> v(4, 1);
  CHECK_THROWS_AS(scoreFrame(a, b, a, v), std::invalid_argument);
  CHECK_THROWS_AS(shadowBoundary(2, 2, a, b, 1), std::invalid_argument);
}
