#include "harness/views/camera_path.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "scenes/det_math.h"
#include "scenes/memory.h"

namespace sb {

namespace {

using nlohmann::json;

constexpr std::string_view kFormat = "shadowbench-camera-path";
constexpr int kVersion = 1;
constexpr double kMaxFovYDegrees = 179;

[[noreturn]] void fail(std::string_view source, std::string_view field, std::string_view problem) {
  throw PathError(fmt::format("{}: {}: {}", source, field, problem));
}

// A short rendering of a rejected value for the message.
std::string shown(const json& value) {
  std::string text = value.dump();
  constexpr size_t kMaxShown = 40;
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "…";
  return fmt::format("{} {}", value.type_name(), text);
}

// Rejects fields other than `known`: a misspelt optional field would otherwise pass unnoticed.
void checkKnownFields(const json& object, std::initializer_list<std::string_view> known,
                      std::string_view source, std::string_view prefix) {
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail(source, fmt::format("{}{}", prefix, key), "unknown field");
}

const json& member(const json& object, std::string_view key, std::string_view source,
                   const std::string& field) {
  const auto it = object.find(key);
  if (it == object.end()) fail(source, field, "missing");
  return *it;
}

// JSON has no NaN or infinity, but writers emit them as strings ("NaN") or null; a json built in
// memory can hold them as numbers.
double finiteNumber(const json& value, std::string_view source, const std::string& field) {
  if (!value.is_number()) fail(source, field, "expected a finite number, got " + shown(value));
  const double number = value.get<double>();
  if (!std::isfinite(number)) fail(source, field, fmt::format("not finite ({})", number));
  return number;
}

glm::dvec3 vector3(const json& value, std::string_view source, const std::string& field) {
  if (!value.is_array() || value.size() != 3)
    fail(source, field, "expected an array of 3 numbers, got " + shown(value));
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i)
    v[i] = finiteNumber(value[i], source, fmt::format("{}[{}]", field, i));
  return v;
}

std::string textField(const json& value, std::string_view source, const std::string& field) {
  if (!value.is_string()) fail(source, field, "expected a string, got " + shown(value));
  return value.get<std::string>();
}

uint32_t frameSide(const json& value, std::string_view source, const std::string& field) {
  if (!value.is_number_integer()) fail(source, field, "expected an integer, got " + shown(value));
  const int64_t side = value.is_number_unsigned() && value.get<uint64_t>() > kMaxFrameSide
                           ? int64_t{kMaxFrameSide} + 1
                           : value.get<int64_t>();
  if (side < 1 || side > kMaxFrameSide)
    fail(source, field, fmt::format("must lie in [1, {}], got {}", kMaxFrameSide, value.dump()));
  return uint32_t(side);
}

Camera cameraFromJson(const json& value, std::string_view source, const std::string& field) {
  if (!value.is_object()) fail(source, field, "expected an object, got " + shown(value));
  checkKnownFields(value, {"eye", "target", "up", "fov_y"}, source, field + ".");
  Camera camera;
  camera.eye = vector3(member(value, "eye", source, field + ".eye"), source, field + ".eye");
  camera.target =
      vector3(member(value, "target", source, field + ".target"), source, field + ".target");
  camera.up = vector3(member(value, "up", source, field + ".up"), source, field + ".up");
  camera.fovYDegrees =
      finiteNumber(member(value, "fov_y", source, field + ".fov_y"), source, field + ".fov_y");
  // Distinct points far apart enough not to underflow, near enough not to overflow.
  const double viewLength = glm::length(camera.target - camera.eye);
  if (!(viewLength > 0 && std::isfinite(viewLength)))
    fail(source, field + ".target",
         fmt::format("gives no view direction from eye ({}, {}, {}): |target - eye| = {}",
                     camera.eye.x, camera.eye.y, camera.eye.z, viewLength));
  // Below this sine of the angle between up and the view direction the camera's roll is
  // decided by rounding. (Written so that a NaN from an infinite up fails too.)
  constexpr double kMinSine = 1e-6;
  const glm::dvec3 forward = (camera.target - camera.eye) / viewLength;
  const double upLength = glm::length(camera.up);
  if (!(upLength > 0 && glm::length(glm::cross(forward, camera.up / upLength)) >= kMinSine))
    fail(source, field + ".up", "zero or parallel to the view direction (target - eye)");
  if (!(camera.fovYDegrees > 0 && camera.fovYDegrees < kMaxFovYDegrees))
    fail(source, field + ".fov_y",
         fmt::format("must lie in (0, {}) degrees, got {}", kMaxFovYDegrees, camera.fovYDegrees));
  return camera;
}

json vectorJson(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

// The closed mesh enclosing `point`, if any: the nearest hit of a ray leaving a closed mesh's
// inside is a back face of it (its outward normal along the ray). Of the six axis rays the
// majority must agree, so that one ray slipping through a crack or grazing an edge decides
// nothing.
std::optional<uint32_t> enclosingMesh(const Scene& scene, const SceneRays& rays,
                                      const glm::dvec3& point) {
  std::map<uint32_t, int> votes;
  int backFaces = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      glm::dvec3 direction(0);
      direction[axis] = sign;
      const SceneRays::Hit hit = rays.intersect(point, direction);
      if (!hit.valid() || !scene.meshes[hit.mesh].closed) continue;
      if (glm::dot(hit.normal, direction) <= 0) continue;
      ++votes[hit.mesh];
      ++backFaces;
    }
  if (backFaces < 4) return std::nullopt;
  // The mesh most rays left through (the lowest index among equals: map order).
  const auto most = std::max_element(
      votes.begin(), votes.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return most->first;
}

// The height of the ground under (x, y): the lowest upward-facing surface a ray dropped from
// `top`, above the scene, meets (canopies, roofs and leaves lie above it). Computed from the hit
// triangle's plane in double rather than from Embree's float t, whose last bits depend on the
// instruction set Embree picked: the path must be the same bytes on every machine.
std::optional<double> groundHeight(const Scene& scene, const SceneRays& rays, double top, double x,
                                   double y) {
  const glm::dvec3 down(0, 0, -1);
  std::optional<double> ground;
  double tnear = 0;
  for (SceneRays::Hit hit; (hit = rays.intersect({x, y, top}, down, tnear)).valid();) {
    // Past the surface just hit, by more than float's rounding of t.
    tnear = hit.t * (1 + 1e-6) + 1e-3;
    if (hit.normal.z <= 0) continue;
    const Mesh& mesh = scene.meshes[hit.mesh];
    const glm::uvec3 triangle = mesh.triangles[hit.triangle];
    const glm::dvec3 a(mesh.vertices[triangle.x]), b(mesh.vertices[triangle.y]),
        c(mesh.vertices[triangle.z]);
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    ground = a.z - (normal.x * (x - a.x) + normal.y * (y - a.y)) / normal.z;
  }
  return ground;
}

// Coordinates in the files are rounded to 0.1 mm, which keeps them short; adding +0 turns a
// rounded -0 into 0.
double rounded(double v) {
  return std::nearbyint(v * 1e4) / 1e4 + 0.0;
}

glm::dvec3 rounded(const glm::dvec3& v) {
  return {rounded(v.x), rounded(v.y), rounded(v.z)};
}

// The gaze swings left and right of the direction of travel over the path, so that the frames
// see the sides of a street as well as down it.
glm::dvec3 swungGaze(uint32_t frame, uint32_t frames, double swingDegrees) {
  const double phase = 2 * detail::kPi * frame / frames;
  const double yaw = swingDegrees * detail::kPi / 180 * detail::portableSinCos(phase).x;
  const glm::dvec2 sc = detail::portableSinCos(yaw);
  return {sc.y, sc.x, 0};
}

// Positions spread evenly over [x0, x0 + length] (the middle when there is one frame).
double along(double x0, double length, uint32_t frame, uint32_t frames) {
  return frames == 1 ? x0 + length / 2 : x0 + length * frame / (frames - 1);
}

constexpr double kEyeHeight = 1.7;    // metres: a standing person's eyes
constexpr double kShoulder = 0.3;     // metres each side of a walker that must be clear
constexpr double kFlightHeight = 30;  // metres above the highest ground near the flight line

// A walk at eye height along the line y = const closest to the scene's centre on which every
// eye stands on the ground outside all geometry and the way from each eye to the next, and a
// shoulder's width to either side, is clear: a street, or an aisle between rows of trees.
std::vector<Camera> walk(const Scene& scene, const SceneRays& rays, uint32_t frames,
                         std::string_view sceneSpec) {
  const Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double length = std::min(0.5 * (double(bounds.max.x) - bounds.min.x), 300.0);
  const double x0 = centre.x - length / 2;
  const double halfWidth = 0.5 * (double(bounds.max.y) - bounds.min.y);
  const double top = double(bounds.max.z) + 1;
  constexpr double kStep = 0.5;  // metres between the lines tried
  const auto clearLine = [&](double y) -> std::optional<std::vector<Camera>> {
    std::vector<Camera> cameras;
    for (uint32_t f = 0; f < frames; ++f) {
      const double x = along(x0, length, f, frames);
      const std::optional<double> ground = groundHeight(scene, rays, top, x, y);
      if (!ground) return std::nullopt;
      Camera camera;
      camera.eye = rounded(glm::dvec3(x, y, *ground + kEyeHeight));
      // Looking 20 m ahead and a little down, at the street and the shadows on it.
      camera.target = rounded(camera.eye + 20.0 * swungGaze(f, frames, 30) + glm::dvec3(0, 0, -2));
      if (enclosingMesh(scene, rays, camera.eye)) return std::nullopt;
      if (!cameras.empty())
        for (const double side : {-kShoulder, 0.0, kShoulder}) {
          const glm::dvec3 from = cameras.back().eye + glm::dvec3(0, side, 0);
          const glm::dvec3 to = camera.eye + glm::dvec3(0, side, 0);
          if (rays.occluded(from, to - from, 0, 1)) return std::nullopt;
        }
      cameras.push_back(camera);
    }
    return cameras;
  };
  for (int k = 0; k * kStep < halfWidth; ++k)
    for (const double sign : {1.0, -1.0}) {
      if (k == 0 && sign < 0) continue;
      if (auto cameras = clearLine(centre.y + sign * k * kStep)) return *cameras;
    }
  throw PathError(fmt::format("{}: no clear line for a walk along x near the centre", sceneSpec));
}

// A flight along the line y = centre, kFlightHeight above the highest ground within a frame's
// spacing either side, so that the straight way between two frames clears the ground between
// them; looking ahead and down.
std::vector<Camera> lowFlight(const Scene& scene, const SceneRays& rays, uint32_t frames,
                              std::string_view sceneSpec) {
  const Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double length = 0.5 * (double(bounds.max.x) - bounds.min.x);
  const double x0 = centre.x - length / 2;
  const double spacing = frames == 1 ? 0 : length / (frames - 1);
  const double top = double(bounds.max.z) + 1;
  constexpr double kSampleStep = 1;  // metres between the ground samples
  std::vector<Camera> cameras;
  for (uint32_t f = 0; f < frames; ++f) {
    const double x = along(x0, length, f, frames);
    std::optional<double> highest;
    // Samples on a grid through x itself, so that the eye clears the ground right below it.
    const int reach = int(std::ceil(spacing / kSampleStep));
    for (int k = -reach; k <= reach; ++k)
      if (const auto ground = groundHeight(scene, rays, top, x + k * kSampleStep, centre.y))
        highest = std::max(highest.value_or(*ground), *ground);
    if (!highest)
      throw PathError(fmt::format("{}: no ground under the flight line at x = {}", sceneSpec, x));
    Camera camera;
    camera.eye = rounded(glm::dvec3(x, centre.y, *highest + kFlightHeight));
    camera.target =
        rounded(camera.eye + 100.0 * swungGaze(f, frames, 20) + glm::dvec3(0, 0, -kFlightHeight));
    cameras.push_back(camera);
  }
  return cameras;
}

// A circle around the scene at 80% of its bounding radius, 60% of it above the centre, looking
// at the centre (the view samples' camera, query_sets.h).
std::vector<Camera> orbit(const Scene& scene, uint32_t frames) {
  const Bounds bounds = scene.bounds();
  const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
  const double radius = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) * 0.5;
  std::vector<Camera> cameras;
  for (uint32_t f = 0; f < frames; ++f) {
    const glm::dvec2 sc = detail::portableSinCos(2 * detail::kPi * (f + 0.125) / frames);
    Camera camera;
    camera.eye =
        rounded(centre + glm::dvec3(sc.y * radius * 0.8, sc.x * radius * 0.8, radius * 0.6));
    camera.target = rounded(centre);
    cameras.push_back(camera);
  }
  return cameras;
}

}  // namespace

CameraBasis basisOf(const Camera& camera) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  return {forward, right, glm::cross(right, forward)};
}

CameraRay pixelRay(const Camera& camera, uint32_t width, uint32_t height, uint32_t x, uint32_t y) {
  const CameraBasis basis = basisOf(camera);
  const double tanHalf = std::tan(glm::radians(camera.fovYDegrees) / 2);
  const double u = (2 * (x + 0.5) / width - 1) * tanHalf * width / height;
  const double v = (1 - 2 * (y + 0.5) / height) * tanHalf;
  return {camera.eye, glm::normalize(basis.forward + u * basis.right + v * basis.up)};
}

double viewDepth(const Camera& camera, const glm::dvec3& point) {
  return glm::dot(point - camera.eye, basisOf(camera).forward);
}

CameraPath cameraPathFromJson(const json& value, std::string_view source) {
  if (!value.is_object()) fail(source, "(document)", "expected a JSON object, got " + shown(value));
  checkKnownFields(value, {"format", "version", "name", "scene", "width", "height", "frames"},
                   source, "");
  const std::string format = textField(member(value, "format", source, "format"), source, "format");
  if (format != kFormat)
    fail(source, "format", fmt::format("expected \"{}\", got \"{}\"", kFormat, format));
  const json& version = member(value, "version", source, "version");
  if (!version.is_number_integer() || version.get<int64_t>() != kVersion)
    fail(source, "version", fmt::format("expected {}, got {}", kVersion, shown(version)));
  CameraPath path;
  path.name = textField(member(value, "name", source, "name"), source, "name");
  path.scene = textField(member(value, "scene", source, "scene"), source, "scene");
  path.width = frameSide(member(value, "width", source, "width"), source, "width");
  path.height = frameSide(member(value, "height", source, "height"), source, "height");
  const json& frames = member(value, "frames", source, "frames");
  if (!frames.is_array()) fail(source, "frames", "expected an array, got " + shown(frames));
  if (frames.empty()) fail(source, "frames", "empty");
  for (size_t f = 0; f < frames.size(); ++f)
    path.frames.push_back(cameraFromJson(frames[f], source, fmt::format("frames[{}]", f)));
  return path;
}

json toJson(const CameraPath& path) {
  json frames = json::array();
  for (const Camera& camera : path.frames)
    frames.push_back({{"eye", vectorJson(camera.eye)},
                      {"target", vectorJson(camera.target)},
                      {"up", vectorJson(camera.up)},
                      {"fov_y", camera.fovYDegrees}});
  return {{"format", kFormat},   {"version", kVersion}, {"name", path.name},
          {"scene", path.scene}, {"width", path.width}, {"height", path.height},
          {"frames", frames}};
}

CameraPath loadCameraPath(const std::filesystem::path& file) {
  const std::string source = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw PathError(fmt::format("{}: cannot open the camera path", source));
  const std::string content{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  json value;
  try {
    value = json::parse(content);
  } catch (const json::exception& e) {
    throw PathError(fmt::format("{}: not valid JSON ({})", source, e.what()));
  }
  return cameraPathFromJson(value, source);
}

void saveCameraPath(const CameraPath& path, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  out << toJson(path).dump(2) << '\n';
  if (!out) throw PathError(fmt::format("{}: cannot write the camera path", file.string()));
}

CameraPath makeFlythrough(const Scene& scene, std::string_view sceneSpec, const SceneRays& rays,
                          uint32_t frames) {
  if (frames == 0)
    throw PathError(fmt::format("{}: frames: a fly-through needs at least one", sceneSpec));
  const std::string_view generator = sceneSpec.substr(0, sceneSpec.find(':'));
  CameraPath path;
  path.scene = std::string(sceneSpec);
  if (generator == "city" || generator == "forest") {
    path.name = fmt::format("{}-walk", generator);
    path.frames = walk(scene, rays, frames, sceneSpec);
  } else if (generator == "terrain") {
    path.name = "terrain-flight";
    path.frames = lowFlight(scene, rays, frames, sceneSpec);
  } else {
    path.name = fmt::format("{}-orbit", scene.name);
    path.frames = orbit(scene, frames);
  }
  return path;
}

void checkCamerasOutside(const CameraPath& path, const Scene& scene, const SceneRays& rays,
                         std::string_view source) {
  for (size_t f = 0; f < path.frames.size(); ++f) {
    const glm::dvec3& eye = path.frames[f].eye;
    if (const auto mesh = enclosingMesh(scene, rays, eye))
      throw PathError(fmt::format("{}: frames[{}].eye ({}, {}, {}) lies inside closed mesh '{}'",
                                  source, f, eye.x, eye.y, eye.z, scene.meshes[*mesh].name));
  }
}

void checkFrameFits(const CameraPath& path, uint64_t bytesPerPixel, std::string_view source,
                    uint64_t memoryLimitBytes) {
  const uint64_t pixels = uint64_t{path.width} * path.height;
  const uint64_t needed =
      pixels != 0 && bytesPerPixel > std::numeric_limits<uint64_t>::max() / pixels
          ? std::numeric_limits<uint64_t>::max()
          : pixels * bytesPerPixel;
  try {
    detail::checkFitsInMemory(source,
                              fmt::format("a frame of width × height {} × {} at {} bytes per pixel",
                                          path.width, path.height, bytesPerPixel),
                              needed, memoryLimitBytes, "lower width × height");
  } catch (const SceneError& e) {
    throw PathError(e.what());
  }
}

void checkFrameFits(const CameraPath& path, uint64_t bytesPerPixel, std::string_view source) {
  const uint64_t available = detail::availableMemoryBytes();
  checkFrameFits(path, bytesPerPixel, source,
                 available > 0 ? available : std::numeric_limits<uint64_t>::max());
}

}  // namespace sb
