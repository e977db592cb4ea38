#include "harness/views/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/views/views_test_support.h"

namespace {

using sb::testing::kBoxMax;
using sb::testing::kBoxMin;
using sb::testing::kGroundHalf;

// A convex polygon in the plane z = 0, counter-clockwise.
using Polygon = std::vector<glm::dvec2>;

double cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Andrew's monotone chain.
Polygon convexHull(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(),
            [](const auto& a, const auto& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  Polygon hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// The signed distance of p from the polygon's boundary: positive inside.
double insideDistance(const Polygon& polygon, const glm::dvec2& p) {
  double distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    distance = std::min(distance, cross(a, b, p) / glm::length(b - a));
  }
  return distance;
}

std::vector<glm::dvec3> boxCorners() {
  std::vector<glm::dvec3> corners;
  for (int c = 0; c < 8; ++c)
    corners.push_back({c & 1 ? kBoxMax.x : kBoxMin.x, c & 2 ? kBoxMax.y : kBoxMin.y,
                       c & 4 ? kBoxMax.z : kBoxMin.z});
  return corners;
}

// The box's shadow on z = 0: the hull of its corners projected along `travel`…
Polygon shadowAlong(const glm::dvec3& travel) {
  std::vector<glm::dvec2> projected;
  for (const glm::dvec3& c : boxCorners())
    projected.push_back(glm::dvec2(c - (c.z / travel.z) * travel));
  return convexHull(projected);
}

// …or projected from a point light above it.
Polygon shadowFrom(const glm::dvec3& light) {
  std::vector<glm::dvec2> projected;
  for (const glm::dvec3& c : boxCorners())
    projected.push_back(glm::dvec2(light + (light.z / (light.z - c.z)) * (c - light)));
  return convexHull(projected);
}

// The first surface a ray meets in the closed form: the box by the slab method, or the ground.
struct AnalyticHit {
  double t;
  glm::dvec3 normal;      // outward
  double distanceToEdge;  // from the hit to the nearest edge of the face it lies on
};

std::optional<AnalyticHit> analyticHit(const glm::dvec3& origin, const glm::dvec3& direction) {
  double tEnter = -std::numeric_limits<double>::infinity();
  double tExit = std::numeric_limits<double>::infinity();
  int enterAxis = 0;
  for (int a = 0; a < 3; ++a) {
    const double t0 = (kBoxMin[a] - origin[a]) / direction[a];
    const double t1 = (kBoxMax[a] - origin[a]) / direction[a];
    if (std::min(t0, t1) > tEnter) tEnter = std::min(t0, t1), enterAxis = a;
    tExit = std::min(tExit, std::max(t0, t1));
  }
  if (tEnter <= tExit && tEnter > 0) {
    const glm::dvec3 p = origin + tEnter * direction;
    glm::dvec3 normal(0);
    normal[enterAxis] = direction[enterAxis] < 0 ? 1 : -1;
    double edge = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
      if (a != enterAxis) edge = std::min({edge, p[a] - kBoxMin[a], kBoxMax[a] - p[a]});
    return AnalyticHit{tEnter, normal, edge};
  }
  if (direction.z >= 0) return std::nullopt;
  const double t = -origin.z / direction.z;
  const glm::dvec3 p = origin + t * direction;
  const double edge = kGroundHalf - std::max(std::abs(p.x), std::abs(p.y));
  if (edge < 0) return std::nullopt;
  return AnalyticHit{t, {0, 0, 1}, edge};
}

// What the closed form says of a point: lit or not, and how far it lies from the nearest
// boundary between light and shadow (where the offset of the occlusion ray may decide).
struct Expected {
  bool lit;
  double boundaryDistance;
};

// Compares every pixel of a frame with the closed form: coverage, position, normal and view
// depth with the analytic first hit; on the ground, `groundLight`; on the box, lit exactly on the
// faces toward the light (`towardLight` at a point).
void checkAgainstClosedForm(const sb::GroundTruth& truth, const sb::Camera& camera,
                            const std::function<glm::dvec3(const glm::dvec3&)>& towardLight,
                            const std::function<Expected(const glm::dvec3&)>& groundLight) {
  constexpr double kMargin = 1e-3;  // world units kept off edges and shadow boundaries
  // Where the occlusion ray from an offset origin on a face turned from the light re-crosses
  // that face and can pass over the box's edge: offset / sin(incidence) at most, here < 5e-3.
  constexpr double kShadowedFaceMargin = 1e-2;
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  int litGround = 0, shadowedGround = 0, litFaces = 0, shadowedFaces = 0;
  for (uint32_t y = 0; y < truth.height; ++y)
    for (uint32_t x = 0; x < truth.width; ++x) {
      INFO("pixel (" << x << ", " << y << ")");
      const size_t p = truth.pixel(x, y);
      const sb::CameraRay ray = sb::pixelRay(camera, truth.width, truth.height, x, y);
      const std::optional<AnalyticHit> hit = analyticHit(ray.origin, ray.direction);
      if (hit && hit->distanceToEdge < kMargin) continue;
      REQUIRE(bool(truth.covered[p]) == bool(hit));
      if (!hit) {
        CHECK(truth.lit[p] == 0);
        CHECK(truth.viewDepth[p] == 0);
        continue;
      }
      const glm::dvec3 point = ray.origin + hit->t * ray.direction;
      CHECK(glm::length(glm::dvec3(truth.position[p]) - point) < 1e-5 * (1 + hit->t));
      CHECK(glm::length(glm::dvec3(truth.normal[p]) - hit->normal) < 1e-6);
      CHECK(truth.viewDepth[p] == Approx(glm::dot(point - camera.eye, forward)).epsilon(1e-5));
      if (hit->normal.z == 1 && point.z < 0.5) {  // the ground
        CHECK(std::abs(truth.position[p].z) < 1e-4);
        const Expected expected = groundLight(point);
        if (expected.boundaryDistance < kMargin) continue;
        CHECK(bool(truth.lit[p]) == expected.lit);
        ++(expected.lit ? litGround : shadowedGround);
      } else if (glm::dot(hit->normal, towardLight(point)) > 0) {
        CHECK(truth.lit[p] == 1);
        ++litFaces;
      } else if (hit->distanceToEdge > kShadowedFaceMargin) {
        // A face turned from the light: its own box shadows it.
        CHECK(truth.lit[p] == 0);
        ++shadowedFaces;
      }
    }
  // The view must exercise every case.
  CHECK(litGround > 1000);
  CHECK(shadowedGround > 100);
  CHECK(litFaces > 100);
  CHECK(shadowedFaces > 100);
}

// Sees the box's lit top and -y faces, its +x face turned from the light, and the ground with
// the shadow around it.
const sb::Camera kCamera{{7, -6, 8}, {0, 0, 0.5}, {0, 0, 1}, 60};
constexpr uint32_t kWidth = 321, kHeight = 241;

}  // namespace

TEST_CASE("ground truth under a directional light matches the closed form") {
  const sb::Scene scene = sb::testing::boxOverGround();
  const sb::SceneRays rays(scene);
  sb::LightSpec light;
  light.direction = glm::normalize(glm::vec3(0.5f, 0.3f, -1.0f));
  const glm::dvec3 travel = glm::normalize(glm::dvec3(light.direction));
  const Polygon shadow = shadowAlong(travel);
  REQUIRE(shadow.size() == 6);  // the hull of a box's shadow along a general direction
  const double offset = sb::defaultNormalOffset(scene);
  CHECK(offset == Approx(1e-5 * std::sqrt(40.0 * 40 + 40 * 40 + 2 * 2)));
  const sb::GroundTruth truth = sb::traceGroundTruth(rays, light, kCamera, kWidth, kHeight, offset);
  REQUIRE(truth.width == kWidth);
  REQUIRE(truth.height == kHeight);
  CHECK(truth.normalOffset == offset);
  checkAgainstClosedForm(
      truth, kCamera, [&](const glm::dvec3&) { return -travel; },
      [&](const glm::dvec3& point) {
        const double inside = insideDistance(shadow, glm::dvec2(point));
        return Expected{inside < 0, std::abs(inside)};
      });
}

TEST_CASE("ground truth under a spot light matches the closed form, dark outside the cone") {
  const sb::Scene scene = sb::testing::boxOverGround();
  const sb::SceneRays rays(scene);
  sb::LightSpec light;
  light.kind = sb::LightKind::Spot;
  light.position = {-3, -2, 10};
  light.direction = glm::normalize(glm::vec3(3.5f, 2.3f, -10.0f));
  light.fovDegrees = 50;
  const glm::dvec3 position(light.position), axis = glm::normalize(glm::dvec3(light.direction));
  const double halfFov = glm::radians(25.0);
  const Polygon shadow = shadowFrom(position);
  const sb::GroundTruth truth =
      sb::traceGroundTruth(rays, light, kCamera, kWidth, kHeight, sb::defaultNormalOffset(scene));
  size_t outsideCone = 0;
  checkAgainstClosedForm(
      truth, kCamera, [&](const glm::dvec3& point) { return position - point; },
      [&](const glm::dvec3& point) {
        const double inside = insideDistance(shadow, glm::dvec2(point));
        const double angle = std::acos(glm::dot(glm::normalize(point - position), axis));
        outsideCone += angle > halfFov;
        // A step d along the ground turns the direction from the light by at most d / distance.
        const double coneDistance = std::abs(angle - halfFov) * glm::length(point - position);
        return Expected{inside < 0 && angle < halfFov, std::min(std::abs(inside), coneDistance)};
      });
  CHECK(outsideCone > 1000);
}
