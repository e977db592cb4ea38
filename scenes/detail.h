// Internals shared by the scenes library's source files; not part of the API.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/scene.h"

namespace sb::detail {

Scene generateCity(const GeneratorKnobs& knobs);
Scene generateTerrain(uint32_t size, uint64_t seed);
Scene generateForest(uint32_t size, uint64_t seed);
Scene generateTangle(const GeneratorKnobs& knobs);

// GeneratorInfo::footprint of each generator; like the generator, each throws a SceneError
// for a size outside the generator's range.
SceneFootprint cityFootprint(const GeneratorKnobs& knobs);
std::vector<StyleKnob> cityStyleKnobs();
std::vector<GeneratorPreset> cityPresets();
SceneFootprint terrainFootprint(uint32_t size);
SceneFootprint forestFootprint(uint32_t size);
SceneFootprint tangleFootprint(const GeneratorKnobs& knobs);
std::vector<StyleKnob> tangleStyleKnobs();
std::vector<GeneratorPreset> tanglePresets();

// The bytes of `vertices` and `triangles` in meshes grown by push_back, whose capacity may be
// twice their size.
constexpr uint64_t grownMeshBytes(uint64_t vertices, uint64_t triangles) {
  return 2 * (vertices * sizeof(glm::vec3) + triangles * sizeof(glm::uvec3));
}

// Throws a SceneError naming the generator when `size` lies outside [min, max].
void checkSize(std::string_view generator, uint32_t size, uint32_t min, uint32_t max);

// Throws a SceneError naming the generator when `knobs` sets more style knobs than it has, or
// one above its maximum.
void checkStyleKnobs(std::string_view generator, const GeneratorKnobs& knobs,
                     std::span<const StyleKnob> styleKnobs);

// "city:size=6,seed=1" (",relief=40" for each style knob that is not 0): the name of a generated
// scene, which openScene reads back.
std::string generatedSceneName(std::string_view generator, const GeneratorKnobs& knobs,
                               std::span<const StyleKnob> styleKnobs = {});

// A model file read by Assimp: one mesh per model mesh, the default light. Closed meshes must
// be watertight and wound outward; a model whose header declares more than the file can hold,
// or more than `memoryLimitBytes`, is refused before Assimp allocates.
Scene loadModelScene(const std::filesystem::path& path, bool closed, uint64_t memoryLimitBytes);

// A mesh declared closed must keep the promise of Mesh::closed: watertight and wound outward
// (positive enclosed volume). Throws a SceneError "<where>: mesh '<name>' is declared closed
// but …" naming the number of open edges.
void checkClosedMesh(const Mesh& mesh, std::string_view where);

// Mesh names are [A-Za-z0-9_-]+ so that they can appear in file names and records unquoted.
bool isValidMeshName(std::string_view name);

// The invariants every scene satisfies whatever its source: at least one triangle and one
// light, unique valid mesh names, indices in range, finite coordinates. Throws a SceneError
// "scene '<origin>': <problem>".
void validateScene(const Scene& scene, std::string_view origin);

}  // namespace sb::detail
