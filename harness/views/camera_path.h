// Camera paths: the frames a view-dependent technique is rendered and scored on (DESIGN §5b),
// stored as JSON so that every technique sees the same views on every machine.
//
// File format (scenes/paths/README.md):
//   {"format": "shadowbench-camera-path", "version": 1, "name": "city-walk",
//    "scene": "city:full", "width": 1280, "height": 720,
//    "frames": [{"eye": [x, y, z], "target": [x, y, z], "up": [0, 0, 1], "fov_y": 60}, …]}
// fov_y is the full vertical opening angle in degrees; the horizontal one follows from the
// aspect ratio width / height.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "harness/views/scene_rays.h"
#include "scenes/scene.h"

namespace sb {

struct Camera {
  glm::dvec3 eye{0}, target{0, 1, 0}, up{0, 0, 1};
  double fovYDegrees = 60;
};

struct CameraPath {
  std::string name;   // e.g. "city-walk"
  std::string scene;  // the scene spec it was made for, e.g. "city:full" (informative)
  uint32_t width = 1280, height = 720;  // Alecu 2014 §4.2's 1280×720
  std::vector<Camera> frames;
};

// Every problem with a camera path; the message names the file and the field.
class PathError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The largest frame side a path may ask for.
inline constexpr uint32_t kMaxFrameSide = 16384;

// The camera's right-handed frame: forward toward the target, up as close to `Camera::up` as is
// perpendicular to forward.
struct CameraBasis {
  glm::dvec3 forward, right, up;
};
CameraBasis basisOf(const Camera& camera);

// Primary ray through the centre of pixel (x, y); y = 0 is the top row. direction is unit.
struct CameraRay {
  glm::dvec3 origin, direction;
};
CameraRay pixelRay(const Camera& camera, uint32_t width, uint32_t height, uint32_t x, uint32_t y);

// Distance of a world point along the camera's forward axis (w of clip space), for IASM's
// importance.
double viewDepth(const Camera& camera, const glm::dvec3& point);

// Parse and validate; a PathError names the file and the field.
CameraPath loadCameraPath(const std::filesystem::path& file);
void saveCameraPath(const CameraPath& path, const std::filesystem::path& file);
nlohmann::json toJson(const CameraPath& path);
// `source` names the file in errors.
CameraPath cameraPathFromJson(const nlohmann::json& json, std::string_view source);

// A deterministic fly-through of `frames` frames for a generator scene, chosen by the
// generator's name in `sceneSpec`: city → a walk at eye height along a street; forest → a walk
// at eye height between the trees; terrain → a low flight; tangle or any other → an orbit.
// Walks and flights probe the scene with `rays` to stand on the ground and stay clear of the
// geometry; the same bytes on every machine.
CameraPath makeFlythrough(const Scene& scene, std::string_view sceneSpec, const SceneRays& rays,
                          uint32_t frames);

// Throws a PathError naming the frame and the mesh when a camera's eye lies inside a closed
// mesh of `scene`, where nothing can be seen.
void checkCamerasOutside(const CameraPath& path, const Scene& scene, const SceneRays& rays,
                         std::string_view source);

// Throws a PathError naming "width × height" when a frame of `bytesPerPixel` per pixel does not
// fit in the memory available now (or in `memoryLimitBytes`).
void checkFrameFits(const CameraPath& path, uint64_t bytesPerPixel, std::string_view source);
void checkFrameFits(const CameraPath& path, uint64_t bytesPerPixel, std::string_view source,
                    uint64_t memoryLimitBytes);

}  // namespace sb
