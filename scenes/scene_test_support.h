// What the scenes tests share: a scratch folder for scene and model files, a small closed model,
// a generator by name, and the message of an expected SceneError.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <catch2/catch.hpp>

#include "scenes/scene.h"
#include "scenes/watertight.h"

namespace sb::testing {

namespace fs = std::filesystem;

// A fresh folder under the system's temp folder, removed with everything in it at scope exit.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("sb_scenes_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, const std::string& content) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << content;
    return file;
  }

 private:
  fs::path path_;
};

// A unit cube [0, 1]^3, faces counter-clockwise from outside (OBJ indices are 1-based).
inline const char* kCubeObj = R"(o cube
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
v 0 0 1
v 1 0 1
v 0 1 1
v 1 1 1
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
)";

// The generator named `name`; fails the test if there is none.
inline const sb::GeneratorInfo& generator(const std::string& name) {
  for (const auto& g : sb::sceneGenerators())
    if (g.name == name) return g;
  FAIL("no generator " << name);
  throw;
}

// The message of the SceneError that `open` throws; fails the test if it throws anything else.
template <typename F>
std::string sceneErrorOf(F&& open) {
  try {
    open();
  } catch (const sb::SceneError& e) {
    return e.what();
  }
  FAIL("expected a SceneError");
  return "";
}

inline bool validName(const std::string& name) {
  return !name.empty() && name.find_first_not_of(
                              "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") ==
                              std::string::npos;
}

// Every closed mesh closed and outward, names unique and valid, something to render.
inline void checkSceneInvariants(const sb::Scene& scene) {
  INFO("scene " << scene.name);
  CHECK(scene.triangleCount() > 0);
  CHECK(!scene.lights.empty());
  std::set<std::string> names;
  for (const sb::Mesh& mesh : scene.meshes) {
    INFO("mesh " << mesh.name);
    CHECK(validName(mesh.name));
    CHECK(names.insert(mesh.name).second);
    if (mesh.closed) {
      const sb::Watertightness surface = sb::checkWatertight(mesh);
      INFO(surface.describe());
      CHECK(surface.watertight());
      CHECK(surface.degenerateTriangles == 0);
      CHECK(sb::enclosedVolume(mesh) > 0.0);
    }
  }
}

}  // namespace sb::testing
