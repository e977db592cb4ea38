// Transcendental functions whose results do not depend on the C library.
//
// libm's sin and cos may differ in the last bit between versions and platforms; a generator
// that used them could produce different scene bytes (and hashes) on another machine. These use
// only +, ×, ÷ and rounding, which IEEE 754 defines exactly.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace sb::detail {

inline constexpr double kPi = 3.14159265358979323846;

// {sin x, cos x} by Taylor series after reduction to [-π, π]; accurate to a few ulps of double,
// far below float precision.
inline glm::dvec2 portableSinCos(double x) {
  x -= 2.0 * kPi * std::nearbyint(x / (2.0 * kPi));
  const double x2 = x * x;
  double sinTerm = x, cosTerm = 1.0, sinSum = x, cosSum = 1.0;
  for (int k = 1; k <= 24; ++k) {
    sinTerm *= -x2 / ((2.0 * k) * (2.0 * k + 1.0));
    cosTerm *= -x2 / ((2.0 * k - 1.0) * (2.0 * k));
    sinSum += sinTerm;
    cosSum += cosTerm;
  }
  return {sinSum, cosSum};
}

// The point k/n of a turn around the unit circle, exact at the quarter turns.
inline glm::vec2 circlePoint(int k, int n) {
  k %= n;
  if (4 * k == 0) return {1.0f, 0.0f};
  if (4 * k == n) return {0.0f, 1.0f};
  if (4 * k == 2 * n) return {-1.0f, 0.0f};
  if (4 * k == 3 * n) return {0.0f, -1.0f};
  const glm::dvec2 sc = portableSinCos(2.0 * kPi * k / n);
  return {static_cast<float>(sc.y), static_cast<float>(sc.x)};
}

}  // namespace sb::detail
