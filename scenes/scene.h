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

// A deterministic procedural scene generator: the same (size, seed) gives the same bytes on
// every machine (own PRNG, no std distributions). `size` is the generator's own knob.
struct GeneratorInfo {
  std::string name;
  std::string description;
  uint32_t defaultSize;  // small enough for CI
  uint32_t fullSize;     // the papers' scale
  std::function<Scene(uint32_t size, uint64_t seed)> generate;
};

const std::vector<GeneratorInfo>& sceneGenerators();

// Opens a scene by specification:
//   "city"                     generator at its default size and seed 1
//   "city:full"                generator at its full size
//   "city:size=40,seed=7"      explicit knobs
//   "path/scene.json"          a scene file (meshes, transforms, closedness, lights)
//   "path/model.obj|glb|ply…"  any model Assimp reads; one open mesh per model mesh and a
//                              default directional light
Scene openScene(std::string_view spec);

Scene loadSceneFile(const std::filesystem::path& path);

// The default light for a scene without one: the sun from above and a little aside.
LightSpec defaultLight();

}  // namespace sb
