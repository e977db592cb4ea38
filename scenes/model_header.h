// The element counts a model file's header declares (PLY, OFF, binary STL), read and checked
// against the file's size before Assimp allocates for them: a header of a few bytes may claim
// 4·10⁹ vertices, and Assimp sizes its arrays from the header, not from the data.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "scenes/scene.h"

namespace sb::detail {

// What the header of `path` (a file of `fileSize` bytes) declares, as a lower bound of the
// memory Assimp and we take for it; nullopt for formats without counts in a header (OBJ, glTF…)
// and for headers this reader does not understand, which Assimp then judges. Throws a
// SceneError "<prefix>: the header declares <count> <element>s, which need at least <n> bytes,
// but the file is only <size> bytes long" when the file cannot hold what its header declares.
std::optional<SceneFootprint> declaredFootprint(const std::filesystem::path& path,
                                                uint64_t fileSize, const std::string& prefix);

}  // namespace sb::detail
