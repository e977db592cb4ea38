#include "harness/views/camera_path.h"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

#include "harness/views/views_test_support.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// A file under the system's temp folder, removed at scope exit.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(fs::temp_directory_path() / (std::to_string(getpid()) + "_" + name)) {}
  ~TempFile() {
    std::error_code ignored;
    fs::remove(path_, ignored);
  }
  const fs::path& path() const { return path_; }
  void write(const std::string& content) const {
    std::ofstream(path_, std::ios::binary | std::ios::trunc) << content;
  }

 private:
  fs::path path_;
};

sb::CameraPath twoFramePath() {
  sb::CameraPath path;
  path.name = "test-walk";
  path.scene = "city:size=2";
  path.width = 321, path.height = 241;
  path.frames = {{{1.25, -2.5, 1.7}, {10, 3, 0.5}, {0, 0, 1}, 60},
                 {{-0.1, 1e-4, 30}, {0.3, 0.2, 0}, {0, 1, 0}, 35.5}};
  return path;
}

// The message of the PathError that `f` throws; fails the test if it throws nothing or
// anything else.
std::string pathErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const sb::PathError& e) {
    return e.what();
  }
  FAIL("expected a PathError");
  return "";
}

}  // namespace

TEST_CASE(
    "pixelRay: the centre pixel looks forward, the edges span the field of view, y = 0 is "
    "the top") {
  const sb::Camera camera{{1, 2, 3}, {4, -2, 5}, {0, 0, 1}, 50};
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  constexpr uint32_t kWidth = 101, kHeight = 51;
  const double tanHalf = std::tan(glm::radians(25.0));
  const auto direction = [&](uint32_t x, uint32_t y) {
    const sb::CameraRay ray = sb::pixelRay(camera, kWidth, kHeight, x, y);
    CHECK(ray.origin == camera.eye);
    CHECK(glm::length(ray.direction) == Approx(1).epsilon(1e-12));
    return ray.direction;
  };
  CHECK(glm::length(direction(50, 25) - forward) < 1e-12);
  // Pixel centres lie half a pixel inside the image's edges.
  const double v = (1 - 1.0 / kHeight) * tanHalf;
  const double u = (1 - 1.0 / kWidth) * tanHalf * kWidth / kHeight;
  CHECK(angleBetween(direction(50, 0), direction(50, 50)) == Approx(2 * std::atan(v)));
  CHECK(angleBetween(direction(0, 25), direction(100, 25)) == Approx(2 * std::atan(u)));
  CHECK(angleBetween(direction(0, 0), direction(100, 50)) ==
        Approx(2 * std::atan(std::sqrt(u * u + v * v))));
  // The top row looks up (world z grows upward here), the left column to the left.
  CHECK(direction(50, 0).z > forward.z);
  CHECK(direction(50, 50).z < forward.z);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  CHECK(glm::dot(direction(0, 25), right) < 0);
}

TEST_CASE("viewDepth is the distance along the forward axis") {
  const sb::Camera camera{{1, 2, 3}, {1, 12, 3}, {0, 0, 1}, 60};  // looking along +y
  CHECK(sb::viewDepth(camera, {7, 5, -4}) == Approx(3));
  CHECK(sb::viewDepth(camera, {1, 2, 9}) == Approx(0).margin(1e-12));
}

TEST_CASE("camera paths round-trip through JSON and files") {
  const sb::CameraPath path = twoFramePath();
  const auto same = [&](const sb::CameraPath& read) {
    CHECK(read.name == path.name);
    CHECK(read.scene == path.scene);
    CHECK(read.width == path.width);
    CHECK(read.height == path.height);
    REQUIRE(read.frames.size() == path.frames.size());
    for (size_t f = 0; f < path.frames.size(); ++f) {
      CHECK(read.frames[f].eye == path.frames[f].eye);
      CHECK(read.frames[f].target == path.frames[f].target);
      CHECK(read.frames[f].up == path.frames[f].up);
      CHECK(read.frames[f].fovYDegrees == path.frames[f].fovYDegrees);
    }
  };
  same(sb::cameraPathFromJson(sb::toJson(path), "memory"));
  const TempFile file("path.json");
  sb::saveCameraPath(path, file.path());
  same(sb::loadCameraPath(file.path()));
  const json stored = json::parse(std::ifstream(file.path()));
  CHECK(stored.at("format") == "shadowbench-camera-path");
  CHECK(stored.at("version") == 1);
  CHECK(stored.at("frames").at(1).at("fov_y") == 35.5);
}

TEST_CASE("invalid camera paths throw a PathError naming the field") {
  const json valid = sb::toJson(twoFramePath());
  const auto errorOf = [&](const std::function<void(json&)>& spoil) {
    json spoilt = valid;
    spoil(spoilt);
    return pathErrorOf([&] { sb::cameraPathFromJson(spoilt, "path.json"); });
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const struct {
    const char* what;
    std::function<void(json&)> spoil;
    const char* named;
  } cases[] = {
      {"a NaN as a string", [](json& j) { j["frames"][1]["eye"][2] = "NaN"; }, "frames[1].eye[2]"},
      {"nan as a string", [](json& j) { j["frames"][0]["target"][0] = "nan"; },
       "frames[0].target[0]"},
      {"inf as a string", [](json& j) { j["frames"][0]["up"][1] = "inf"; }, "frames[0].up[1]"},
      {"null", [](json& j) { j["frames"][0]["fov_y"] = nullptr; }, "frames[0].fov_y"},
      {"a NaN number", [&](json& j) { j["frames"][0]["eye"][0] = nan; }, "frames[0].eye[0]"},
      {"an infinite number", [&](json& j) { j["frames"][1]["fov_y"] = -inf; }, "frames[1].fov_y"},
      {"no frames", [](json& j) { j["frames"] = json::array(); }, "frames: empty"},
      {"width 0", [](json& j) { j["width"] = 0; }, "width"},
      {"height above 16384", [](json& j) { j["height"] = 16385; }, "height"},
      {"a negative width", [](json& j) { j["width"] = -1280; }, "width"},
      {"a fractional width", [](json& j) { j["width"] = 1280.5; }, "width"},
      {"a huge height", [](json& j) { j["height"] = uint64_t{1} << 63; }, "height"},
      {"eye == target", [](json& j) { j["frames"][1]["target"] = j["frames"][1]["eye"]; },
       "frames[1].target"},
      {"up along the view",
       [](json& j) {
         j["frames"][0]["up"] = {8.75, 5.5, -1.2};
       },
       "frames[0].up"},
      {"up zero",
       [](json& j) {
         j["frames"][0]["up"] = {0, 0, 0};
       },
       "frames[0].up"},
      {"fov_y 0", [](json& j) { j["frames"][0]["fov_y"] = 0; }, "frames[0].fov_y"},
      {"fov_y 179", [](json& j) { j["frames"][0]["fov_y"] = 179; }, "frames[0].fov_y"},
      {"fov_y negative", [](json& j) { j["frames"][1]["fov_y"] = -30; }, "frames[1].fov_y"},
      {"missing name", [](json& j) { j.erase("name"); }, "name: missing"},
      {"missing scene", [](json& j) { j.erase("scene"); }, "scene: missing"},
      {"missing frames", [](json& j) { j.erase("frames"); }, "frames: missing"},
      {"missing up", [](json& j) { j["frames"][1].erase("up"); }, "frames[1].up: missing"},
      {"missing fov_y", [](json& j) { j["frames"][0].erase("fov_y"); }, "frames[0].fov_y: missing"},
      {"a number for the name", [](json& j) { j["name"] = 3; }, "name"},
      {"an object for the frames", [](json& j) { j["frames"] = json::object(); }, "frames"},
      {"a frame that is not an object", [](json& j) { j["frames"][1] = 5; }, "frames[1]"},
      {"two coordinates",
       [](json& j) {
         j["frames"][0]["eye"] = {1, 2};
       },
       "frames[0].eye"},
      {"a string for a vector", [](json& j) { j["frames"][0]["target"] = "x"; },
       "frames[0].target"},
      {"a string for the width", [](json& j) { j["width"] = "1280"; }, "width"},
      {"an unknown field", [](json& j) { j["frames"][0]["fov"] = 60; }, "frames[0].fov"},
      {"another format", [](json& j) { j["format"] = "shadowbench-scene"; }, "format"},
      {"a number for the format", [](json& j) { j["format"] = 1; }, "format"},
      {"version 2", [](json& j) { j["version"] = 2; }, "version"},
      {"version as a string", [](json& j) { j["version"] = "1"; }, "version"},
      {"missing version", [](json& j) { j.erase("version"); }, "version: missing"},
      {"an array for the document", [](json& j) { j = json::array({j}); }, "path.json"},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    const std::string message = errorOf(c.spoil);
    INFO(message);
    CHECK(message.rfind("path.json: ", 0) == 0);
    CHECK(message.find(c.named) != std::string::npos);
  }
}

TEST_CASE("a truncated or missing camera path file throws a PathError") {
  const std::string content = sb::toJson(twoFramePath()).dump(2);
  const TempFile file("truncated.json");
  for (size_t length = 0; length < content.size(); ++length) {
    INFO("length " << length);
    file.write(content.substr(0, length));
    CHECK(pathErrorOf([&] { sb::loadCameraPath(file.path()); }).find(file.path().string()) == 0);
  }
  file.write(content);
  CHECK(sb::loadCameraPath(file.path()).frames.size() == 2);
  const std::string missing = pathErrorOf([] { sb::loadCameraPath("/nonexistent/path.json"); });
  CHECK(missing.find("/nonexistent/path.json") == 0);
}

TEST_CASE("checkFrameFits refuses a frame larger than the memory, naming width × height") {
  sb::CameraPath path = twoFramePath();
  path.width = path.height = sb::kMaxFrameSide;
  constexpr uint64_t kGiB = uint64_t{1} << 30;
  // 16384² pixels of 16 bytes need 4 GiB.
  CHECK_NOTHROW(sb::checkFrameFits(path, 16, "path.json", 4 * kGiB));
  const std::string message =
      pathErrorOf([&] { sb::checkFrameFits(path, 16, "path.json", 4 * kGiB - 1); });
  CHECK(message.rfind("path.json: ", 0) == 0);
  CHECK(message.find("width × height 16384 × 16384") != std::string::npos);
  // More bytes than a 64-bit count holds can never fit in the memory available now.
  CHECK(pathErrorOf([&] {
          sb::checkFrameFits(path, uint64_t{1} << 40, "path.json");
        }).find("width × height") != std::string::npos);
}

TEST_CASE("a camera inside a closed mesh is refused, naming the frame and the mesh") {
  const sb::Scene scene = sb::testing::boxOverGround();
  const sb::SceneRays rays(scene);
  sb::CameraPath path = twoFramePath();
  path.frames[0].eye = {3, 3, 1.5};  // beside the box, above the open ground
  path.frames[1].eye = {0.2, -0.3, 1.5};
  const std::string message =
      pathErrorOf([&] { sb::checkCamerasOutside(path, scene, rays, "path.json"); });
  CHECK(message == "path.json: frames[1].eye (0.2, -0.3, 1.5) lies inside closed mesh 'box'");
  path.frames[1].eye = {0.2, -0.3, 2.5};  // above it
  CHECK_NOTHROW(sb::checkCamerasOutside(path, scene, rays, "path.json"));
  path.frames[1].eye = {0.2, -0.3, -0.5};  // below the open ground, which encloses nothing
  CHECK_NOTHROW(sb::checkCamerasOutside(path, scene, rays, "path.json"));
}

// Every committed default path is what makeFlythrough makes of its scene today: scenes and
// path-making stay deterministic, and a change to either shows up here. The full scenes build
// and probe in about a second each.
TEST_CASE("makeFlythrough regenerates the committed default paths") {
  const struct {
    const char* spec;
    const char* file;
    const char* name;
  } defaults[] = {{"city:full", "city-full.json", "city-walk"},
                  {"forest:full", "forest-full.json", "forest-walk"},
                  {"terrain:full", "terrain-full.json", "terrain-flight"}};
  for (const auto& d : defaults) {
    INFO(d.spec);
    const sb::Scene scene = sb::openScene(d.spec);
    const sb::SceneRays rays(scene);
    const sb::CameraPath path = sb::makeFlythrough(scene, d.spec, rays, 24);
    const fs::path file = fs::path(SHADOWBENCH_SOURCE_DIR) / "scenes" / "paths" / d.file;
    std::ifstream in(file, std::ios::binary);
    const std::string committed{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
    CHECK(sb::toJson(path).dump(2) + "\n" == committed);
    CHECK(path.name == d.name);
    CHECK(path.scene == d.spec);
    CHECK(path.frames.size() == 24);
    CHECK_NOTHROW(sb::checkCamerasOutside(path, scene, rays, d.file));
  }
}

TEST_CASE("walks keep the eyes at eye height over the flat ground, flights above the terrain") {
  // city and forest stand on flat ground at z = 0.
  for (const char* spec : {"city", "forest"}) {
    INFO(spec);
    const sb::Scene scene = sb::openScene(spec);
    const sb::SceneRays rays(scene);
    const sb::CameraPath path = sb::makeFlythrough(scene, spec, rays, 9);
    REQUIRE(path.frames.size() == 9);
    for (const sb::Camera& camera : path.frames) {
      CHECK(camera.eye.z == 1.7);
      // Nothing over the walker's head for the first metre up.
      CHECK_FALSE(rays.occluded(camera.eye, {0, 0, 1}, 0, 1));
    }
    // Each frame to the next is clear: the walk goes along a street or an aisle, through nothing.
    for (size_t f = 1; f < path.frames.size(); ++f) {
      const glm::dvec3 from = path.frames[f - 1].eye, to = path.frames[f].eye;
      CHECK_FALSE(rays.occluded(from, to - from, 0, 1));
    }
  }
  const sb::Scene terrain = sb::openScene("terrain");
  const sb::SceneRays rays(terrain);
  const sb::CameraPath flight = sb::makeFlythrough(terrain, "terrain", rays, 9);
  for (const sb::Camera& camera : flight.frames) {
    const sb::SceneRays::Hit below = rays.intersect(camera.eye, {0, 0, -1});
    REQUIRE(below.valid());
    CHECK(below.t >= 30 - 1e-3);
    CHECK(below.t < 230);  // tens of metres over a valley, never above the whole relief
  }
}

TEST_CASE("other scenes get an orbit on their bounding sphere") {
  const sb::Scene scene = sb::openScene("tangle");
  const sb::SceneRays rays(scene);
  const sb::CameraPath path = sb::makeFlythrough(scene, "tangle", rays, 8);
  CHECK(path.name == scene.name + "-orbit");
  const sb::Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double radius = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5;
  for (const sb::Camera& camera : path.frames) {
    // 0.8 across and 0.6 up: on the sphere through the bounding box's corners.
    CHECK(glm::length(camera.eye - centre) == Approx(radius).epsilon(1e-4));
    CHECK(camera.eye.z - centre.z == Approx(0.6 * radius).epsilon(1e-4));
    CHECK(glm::length(camera.target - centre) < 1e-3);
  }
}
