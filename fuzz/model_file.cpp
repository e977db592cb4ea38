// libFuzzer target: a model file opened by its path, as `--scene model.obj` opens it (Assimp,
// then the scenes library's checks). Inputs that start like a PLY header are read as PLY, the
// others as OBJ. Every problem with a model must be one SceneError.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz/temp_file.h"
#include "scenes/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool ply = size >= 3 && std::memcmp(data, "ply", 3) == 0;
  const auto path = sb::fuzz::writeTempFile(data, size, ply ? ".ply" : ".obj");
  try {
    sb::openScene(path.string());
  } catch (const sb::SceneError&) {
  }
  return 0;
}
