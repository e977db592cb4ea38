// Scenes: triangle meshes (each marked closed or open) and the lights that shine on them.
// Everything downstream sees a scene only through this header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace sb {

// A triangle mesh. `closed` promises a watertight surface, consistently wound counter-clockwise
// seen from outside (outward normal = cross(v1 - v0, v2 - v0)), never viewed from inside:
// the precondition of the closed-object optimisation (Sintorn §6.1, Kämpe §3.3).
struct Mesh {
  std::string name;
  bool closed = false;
  std::vector<glm::vec3> vertices;
  std::vector<glm::uvec3> triangles;
};

enum class LightKind { Directional, Spot };

// How a spot light spreads depth over [0, 1]: linear in view z, or logarithmic (Kämpe eq. 1),
// which keeps the ratio of a voxel's height to its depth constant.
enum class DepthDistribution { Linear, Logarithmic };

// The widest spot light. Its map is planar: a texel at angle θ off the axis spans cos²θ of the
// angle a central texel spans, so towards 180° nearly every texel lies at the rim, and
// tan(fov/2), which scales the frustum, grows without bound. 179° (tan 89.5° ≈ 115) is the
// widest the harness fits.
inline constexpr float kMaxSpotFovDegrees = 179.0f;
// A spot light's fov is accepted when 0 < fov < kMaxSpotFovDegrees (in float, as it is stored).
constexpr bool isValidSpotFov(float degrees) {
  return degrees > 0.0f && degrees < kMaxSpotFovDegrees;
}

struct LightSpec {
  LightKind kind = LightKind::Directional;
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // world-space direction in which the light travels
  glm::vec3 position{0.0f};                // spot lights only
  float fovDegrees = 60.0f;                // spot lights only: full opening angle
  DepthDistribution depth = DepthDistribution::Linear;  // spot lights only
};

struct Bounds {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<LightSpec> lights;  // at least one; the first is the default light

  uint64_t triangleCount() const;
  Bounds bounds() const;  // over all vertices referenced by triangles
  // 16 lower-case hex digits: XXH3-64 over mesh names, closedness, vertices and triangles, so
  // that records name exactly which geometry they measured.
  std::string hash() const;
};

// Every problem with a scene (missing, empty or corrupt file, bad JSON, non-triangle
// primitives, an index out of range, an unknown generator) is one SceneError whose message
// names the file or generator and the problem.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a scene will hold and occupy, known before it is built: from a generator's knobs, or
// from the counts a model file's header declares.
struct SceneFootprint {
  uint64_t vertices = 0, triangles = 0;  // at most
  uint64_t bytes = 0;                    // memory at the peak of building it
};

// A knob of a generator beyond size and seed ("relief=40"): an integer in [0, max], 0 by
// default, where 0 leaves the scene as the generator builds it without the knob.
struct StyleKnob {
  std::string name;
  std::string description;
  uint32_t max;
};

// The knobs of a procedural generator. `size` is the generator's own scale; `style` holds the
// generator's style knobs in the order of GeneratorInfo::styleKnobs (missing ones are 0).
struct GeneratorKnobs {
  uint32_t size = 0;
  uint64_t seed = 1;
  std::vector<uint32_t> style{};
  uint32_t styleKnob(size_t index) const { return index < style.size() ? style[index] : 0; }
};

// A named setting of all a generator's knobs ("city:cityscape"). A calibrated stand-in names the
// published curve its knobs were fitted to (README, "Calibrated stand-ins"); the seed is part of
// the fit.
struct GeneratorPreset {
  std::string name;
  uint32_t size;
  uint64_t seed;
  std::vector<uint32_t> style;
  std::string fittedTo;
};

// A deterministic procedural scene generator: the same knobs give the same bytes on every
// machine (own PRNG, no std distributions).
struct GeneratorInfo {
  std::string name;
  std::string description;
  uint32_t defaultSize;  // small enough for CI
  uint32_t fullSize;     // the papers' scale
  std::vector<StyleKnob> styleKnobs{};
  std::vector<GeneratorPreset> presets{};
  // Both throw a SceneError naming the generator for a size or style knob out of range.
  std::function<Scene(const GeneratorKnobs&)> generate{};
  // An upper bound for every seed, so that a size too large for the memory is refused before
  // anything is allocated.
  std::function<SceneFootprint(const GeneratorKnobs&)> footprint{};
};

const std::vector<GeneratorInfo>& sceneGenerators();

// Opens a scene by specification:
//   "city"                     generator at its default size and seed 1
//   "city:full"                generator at its full size
//   "city:size=40,seed=7"      explicit knobs, and the generator's style knobs ("relief=40")
//   "city:cityscape"           a preset of all the generator's knobs
//   "path/scene.json"          a scene file (meshes, transforms, closedness, lights)
//   "path/model.obj|glb|ply…"  any model Assimp reads; one mesh per model mesh and a default
//                              directional light; the meshes are open, or with
//   "path/model.off:closed"    closed, each checked to be watertight and wound outward
//                              (":open" says the default explicitly; the last ':' part is read
//                              as closedness only when it is one of these two words)
// A scene whose estimated memory (SceneFootprint, or a model header's counts) exceeds
// `memoryLimitBytes` is refused before it is built; the first form takes the memory the
// system has available now.
Scene openScene(std::string_view spec);
Scene openScene(std::string_view spec, uint64_t memoryLimitBytes);

Scene loadSceneFile(const std::filesystem::path& path);
Scene loadSceneFile(const std::filesystem::path& path, uint64_t memoryLimitBytes);

// The files a specification reads: none for a generator; the model file (without a ":closed"
// suffix); or the scene file and the model files its meshes name, as loadSceneFile resolves
// them. What an output must never overwrite. Never throws; an unreadable file lists itself.
std::vector<std::filesystem::path> sceneSourceFiles(std::string_view spec);

// The default light for a scene without one: the sun from above and a little aside.
LightSpec defaultLight();

}  // namespace sb
