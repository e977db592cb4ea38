// libFuzzer target: a JSON scene file opened by its path, as `--scene scene.json` opens it.
// Every problem with a scene must be one SceneError.
#include <cstddef>
#include <cstdint>

#include "fuzz/temp_file.h"
#include "scenes/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = sb::fuzz::writeTempFile(data, size, ".json");
  try {
    sb::openScene(path.string());
  } catch (const sb::SceneError&) {
  }
  return 0;
}
