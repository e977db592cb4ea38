// Tests of the scenes library: generator invariants (closed meshes really are closed), golden
// hashes, the specification grammar, scene and model files, loader errors and memory bounds.
// The generators' style knobs and presets are in scene_style_test.cpp.

#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <unordered_map>

#include <catch2/catch.hpp>

#include "scenes/scene.h"
#include "scenes/scene_test_support.h"
#include "scenes/watertight.h"

namespace fs = std::filesystem;
using sb::Mesh;
using sb::Scene;
using sb::SceneError;
using namespace sb::testing;

namespace {

const char* kExampleScene = R"({ "name": "two-boxes",
  "meshes": [
    {"name": "a", "closed": true, "file": "box.obj", "transform": {"translate": [0,0,1], "scale": [1,1,1], "rotate": {"axis": [0,0,1], "degrees": 30}}},
    {"name": "b", "closed": false, "vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,2]]},
    {"name": "c", "closed": true, "generator": "city", "size": 2, "seed": 3}
  ],
  "lights": [{"type": "directional", "direction": [0.3, 0.2, -1]},
             {"type": "spot", "position": [0,0,10], "direction": [0,0,-1], "fov": 60, "depth": "log"}]})";

bool near(glm::vec3 a, glm::vec3 b) {
  return glm::all(glm::lessThan(glm::abs(a - b), glm::vec3(1e-5f)));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Generators

TEST_CASE("every generator at its default size gives a valid scene", "[scenes][generators]") {
  REQUIRE(sb::sceneGenerators().size() == 4);
  for (const auto& g : sb::sceneGenerators()) {
    INFO("generator " << g.name);
    const Scene scene = sb::openScene(g.name);
    checkSceneInvariants(scene);
    CHECK(scene.name == g.name + ":size=" + std::to_string(g.defaultSize) + ",seed=1");
    CHECK(scene.triangleCount() >= 2000);
    CHECK(scene.triangleCount() <= 60000);
    CHECK(scene.lights.size() == 1);
    for (const Mesh& mesh : scene.meshes) CHECK(mesh.closed == (g.name != "forest"));
  }
}

TEST_CASE("generated scenes are deterministic and match their golden hashes",
          "[scenes][generators]") {
  // Pinned on x86-64 (GCC 12); generators use only exact integer arithmetic, IEEE +-×÷√ and no
  // libm transcendentals, so any other machine must produce the same bytes.
  const std::map<std::string, std::string> golden = {
      {"city", "10bcb9ea90494930"},
      {"terrain", "182aa158c5940210"},
      {"forest", "73d5d3016faaa748"},
      {"tangle", "b0b89565c6a01bdc"},
  };
  // Style knobs and presets: the fractal hills and turns by portableSinCos, pinned too.
  CHECK(sb::openScene("city:size=2,relief=60,turn=90").hash() == "d9e4773ab01c06b1");
  CHECK(sb::openScene("city:cityscape").hash() == "a0d9a26bd01b5811");
  CHECK(sb::openScene("tangle:hairball").hash() == "7ba3a03b005d5741");
  for (const auto& g : sb::sceneGenerators()) {
    INFO("generator " << g.name);
    const std::string first = g.generate({g.defaultSize, 1}).hash();
    CHECK(first == g.generate({g.defaultSize, 1}).hash());
    CHECK(first == sb::openScene(g.name).hash());
    CHECK(first == golden.at(g.name));
  }
}

TEST_CASE("different seeds give different scenes", "[scenes][generators]") {
  for (const auto& g : sb::sceneGenerators()) {
    INFO("generator " << g.name);
    CHECK(g.generate({g.defaultSize, 1}).hash() != g.generate({g.defaultSize, 2}).hash());
  }
}

TEST_CASE("the size knob scales the triangle count", "[scenes][generators]") {
  for (const auto& g : sb::sceneGenerators()) {
    INFO("generator " << g.name);
    const uint64_t half = g.generate({g.defaultSize / 2, 1}).triangleCount();
    const uint64_t normal = g.generate({g.defaultSize, 1}).triangleCount();
    CHECK(half * 3 < normal * 2);  // roughly quadratic in size for 2D layouts, linear for tubes
    CHECK(half > 0);
  }
  CHECK(generator("tangle").generate({6, 1}).triangleCount() * 2 ==
        generator("tangle").generate({12, 1}).triangleCount());
}

TEST_CASE("full-size scenes have the papers' scale", "[.full][scenes][generators]") {
  const std::map<std::string, std::pair<uint64_t, uint64_t>> expected = {
      {"city", {500'000, 750'000}},
      {"terrain", {1'800'000, 2'400'000}},
      {"forest", {800'000, 1'300'000}},
      {"tangle", {1'800'000, 2'400'000}},
  };
  for (const auto& g : sb::sceneGenerators()) {
    INFO("generator " << g.name);
    const Scene scene = sb::openScene(g.name + ":full");
    WARN(g.name << ":full has " << scene.triangleCount() << " triangles in " << scene.meshes.size()
                << " meshes");
    CHECK(scene.triangleCount() >= expected.at(g.name).first);
    CHECK(scene.triangleCount() <= expected.at(g.name).second);
    checkSceneInvariants(scene);
  }
}

// ---------------------------------------------------------------------------------------------
// Specifications

TEST_CASE("openScene reads generator knobs", "[scenes][spec]") {
  const Scene scene = sb::openScene("city:size=3,seed=7");
  CHECK(scene.name == "city:size=3,seed=7");
  CHECK(scene.hash() == generator("city").generate({3, 7}).hash());
  CHECK(sb::openScene("tangle:seed=7,size=3").hash() ==
        generator("tangle").generate({3, 7}).hash());
  CHECK(sb::openScene("tangle:full,seed=5").name ==
        "tangle:size=" + std::to_string(generator("tangle").fullSize) + ",seed=5");
  CHECK(sb::openScene(scene.name).hash() == scene.hash());  // a generated scene's name reopens it
}

TEST_CASE("openScene rejects unknown generators and bad knobs", "[scenes][spec]") {
  const std::string unknown = sceneErrorOf([] { sb::openScene("castle"); });
  CHECK_THAT(unknown,
             Catch::Contains("castle") && Catch::Contains("city, terrain, forest, tangle"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene("castle:size=3"); }),
             Catch::Contains("city, terrain, forest, tangle"));
  for (const char* spec : {"city:size=abc", "city:size=", "city:colour=3", "city:size=3,size=4",
                           "city:full,size=3", "city:size=-1", "city:size=3,", "city:seed=1e3",
                           "city:size=0", "city:size=100000", "tangle:size=99999999999"}) {
    INFO(spec);
    const std::string message = sceneErrorOf([&] { sb::openScene(spec); });
    CHECK_THAT(message, Catch::Contains(spec));
    CHECK(message.find('\n') == std::string::npos);
  }
  CHECK_THAT(sceneErrorOf([] { sb::openScene("city:colour=3"); }),
             Catch::Contains("size=N, seed=N, full"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene("city:size=0"); }), Catch::Contains("out of range"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene(""); }), Catch::Contains("empty"));
}

// ---------------------------------------------------------------------------------------------
// Scene queries

TEST_CASE("triangle count, bounds and hash of a small scene", "[scenes]") {
  Scene scene;
  Mesh mesh;
  mesh.name = "m";
  mesh.vertices = {{0, 0, 0}, {2, 0, 1}, {0, 3, -1}, {100, 100, 100}};  // the last is unused
  mesh.triangles = {{0, 1, 2}};
  scene.meshes.push_back(mesh);
  CHECK(scene.triangleCount() == 1);
  CHECK(scene.bounds().min == glm::vec3(0, 0, -1));
  CHECK(scene.bounds().max == glm::vec3(2, 3, 1));

  const std::string hash = scene.hash();
  CHECK(hash.size() == 16);
  CHECK(hash.find_first_not_of("0123456789abcdef") == std::string::npos);
  Scene renamed = scene;
  renamed.meshes[0].name = "n";
  Scene closed = scene;
  closed.meshes[0].closed = true;
  Scene moved = scene;
  moved.meshes[0].vertices[0].x = 1e-30f;
  Scene rewound = scene;
  rewound.meshes[0].triangles[0] = {0, 2, 1};
  for (const Scene* other : {&renamed, &closed, &moved, &rewound}) CHECK(other->hash() != hash);
  Scene lit = scene;
  lit.lights = {sb::defaultLight()};
  CHECK(lit.hash() == hash);  // geometry only
}

TEST_CASE("the default light is the sun from above and aside", "[scenes]") {
  const sb::LightSpec light = sb::defaultLight();
  CHECK(light.kind == sb::LightKind::Directional);
  CHECK(near(light.direction, glm::normalize(glm::vec3(0.35f, 0.25f, -1.0f))));
  CHECK(std::abs(glm::length(light.direction) - 1.0f) < 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Scene files

TEST_CASE("a scene file with a model, inline geometry, a generator and two lights",
          "[scenes][file]") {
  TempDir dir;
  dir.write("box.obj", kCubeObj);
  const fs::path file = dir.write("example.json", kExampleScene);
  const Scene scene = sb::loadSceneFile(file);
  CHECK(scene.name == "two-boxes");
  REQUIRE(scene.meshes.size() == 3);
  checkSceneInvariants(scene);

  const Mesh& a = scene.meshes[0];
  CHECK(a.name == "a");
  CHECK(a.closed);
  CHECK(a.triangles.size() == 12);
  // (1, 0, 0) turned 30° about z, then lifted by 1.
  const glm::vec3 expected{std::sqrt(3.0f) / 2, 0.5f, 1.0f};
  CHECK(std::any_of(a.vertices.begin(), a.vertices.end(),
                    [&](glm::vec3 v) { return near(v, expected); }));
  CHECK(std::abs(sb::enclosedVolume(a) - 1.0) < 1e-5);

  const Mesh& b = scene.meshes[1];
  CHECK(b.name == "b");
  CHECK(!b.closed);
  CHECK(b.vertices == std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});
  CHECK(b.triangles == std::vector<glm::uvec3>{{0, 1, 2}});

  const Mesh& c = scene.meshes[2];
  CHECK(c.closed);
  CHECK(c.triangles.size() == sb::openScene("city:size=2,seed=3").triangleCount());

  REQUIRE(scene.lights.size() == 2);
  CHECK(scene.lights[0].kind == sb::LightKind::Directional);
  CHECK(near(scene.lights[0].direction, glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f))));
  CHECK(scene.lights[1].kind == sb::LightKind::Spot);
  CHECK(scene.lights[1].position == glm::vec3(0, 0, 10));
  CHECK(scene.lights[1].direction == glm::vec3(0, 0, -1));
  CHECK(scene.lights[1].fovDegrees == 60.0f);
  CHECK(scene.lights[1].depth == sb::DepthDistribution::Logarithmic);

  CHECK(sb::openScene(file.string()).hash() == scene.hash());
}

TEST_CASE("relative model paths resolve against the scene file's folder", "[scenes][file]") {
  TempDir dir;
  dir.write("models/cube.obj", kCubeObj);
  const fs::path file =
      dir.write("scenes/s.json", R"({"meshes": [{"name": "cube", "file": "../models/cube.obj"}]})");
  const Scene scene = sb::loadSceneFile(file);  // the test's working directory is elsewhere
  REQUIRE(scene.meshes.size() == 1);
  CHECK(!scene.meshes[0].closed);  // closedness is the scene file's promise, not the model's
  CHECK(scene.name == "s");        // no name: the file's stem
  CHECK(scene.lights.size() == 1);
  CHECK(near(scene.lights[0].direction, sb::defaultLight().direction));
}

TEST_CASE("inline boxes, matrices and mirroring transforms", "[scenes][file]") {
  TempDir dir;
  const fs::path file = dir.write("boxes.json", R"({"meshes": [
    {"name": "plain", "box": {"min": [-1, -2, -3], "max": [1, 2, 3]}},
    {"name": "shifted", "box": {"min": [0, 0, 0], "max": [1, 1, 1]},
     "transform": {"matrix": [1,0,0,5, 0,1,0,0, 0,0,2,0, 0,0,0,1]}},
    {"name": "mirrored", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "transform": {"scale": [-1, 1, 1]}}]})");
  const Scene scene = sb::loadSceneFile(file);
  REQUIRE(scene.meshes.size() == 3);
  checkSceneInvariants(scene);
  for (const Mesh& mesh : scene.meshes) {
    CHECK(mesh.closed);
    CHECK(mesh.triangles.size() == 12);
  }
  CHECK(sb::enclosedVolume(scene.meshes[0]) == Approx(48.0));
  CHECK(sb::enclosedVolume(scene.meshes[1]) == Approx(2.0));
  CHECK(sb::enclosedVolume(scene.meshes[2]) == Approx(1.0));  // winding flipped with the mirror
  CHECK(std::count(scene.meshes[1].vertices.begin(), scene.meshes[1].vertices.end(),
                   glm::vec3(6, 1, 2)) == 1);
  CHECK(scene.bounds().min == glm::vec3(-1, -2, -3));
  CHECK(scene.bounds().max == glm::vec3(6, 2, 3));
}

TEST_CASE("model files open directly, one open mesh per model mesh", "[scenes][file]") {
  TempDir dir;
  const fs::path obj = dir.write("two parts.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 0 5
v 1 0 5
v 1 1 5
o my:part
f 1 2 3
o my/part
f 4 5 6
)");
  const Scene scene = sb::openScene(obj.string());
  CHECK(scene.name == "two parts");
  REQUIRE(scene.meshes.size() == 2);
  CHECK(scene.meshes[0].name == "my_part");
  CHECK(scene.meshes[1].name == "my_part_2");
  for (const Mesh& mesh : scene.meshes) CHECK(!mesh.closed);
  CHECK(scene.triangleCount() == 2);
  CHECK(scene.bounds().max == glm::vec3(1, 1, 5));
  CHECK(scene.lights.size() == 1);

  const fs::path ply = dir.write("tri.ply", R"(ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
4 0 1 2 3
)");
  CHECK(sb::openScene(ply.string()).triangleCount() == 2);  // the quad is triangulated
}

// ---------------------------------------------------------------------------------------------
// Loader errors: always one SceneError line that names the file

TEST_CASE("loader errors name the file and the problem", "[scenes][errors]") {
  TempDir dir;
  const fs::path emptyJson = dir.write("empty.json", "");
  const fs::path emptyObj = dir.write("empty.obj", "");
  const fs::path garbageJson = dir.write("garbage.json", std::string("\x7f\x00\xff{[\"", 6));
  const fs::path garbageGlb =
      dir.write("garbage.glb", std::string("glTF\x02\x00\x00\x00\xff\xff\xff\xff garbage", 21));
  const fs::path garbageObj = dir.write("garbage.obj", "f 1 2 3\nthis is not an obj\n\x01\x02\x03");
  const fs::path lines = dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n");
  const fs::path objOutOfRange = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n");
  const fs::path nanObj = dir.write("nan.obj", "v nan 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  const fs::path misspelt = dir.write(
      "misspelt.json",
      R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}, "tranform": {}}]})");
  const fs::path badType = dir.write(
      "badtype.json",
      R"({"meshes": [{"name": "a", "closed": "yes", "box": {"min": [0,0,0], "max": [1,1,1]}}]})");
  const fs::path badIndex = dir.write(
      "badindex.json",
      R"({"meshes": [{"name": "a", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,3]]}]})");
  const fs::path negative = dir.write(
      "negative.json",
      R"({"meshes": [{"name": "a", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,-1]]}]})");
  const fs::path noTriangles = dir.write(
      "none.json", R"({"meshes": [{"name": "a", "vertices": [[0,0,0]], "triangles": []}]})");
  const fs::path badName = dir.write(
      "badname.json", R"({"meshes": [{"name": "a b", "box": {"min": [0,0,0], "max": [1,1,1]}}]})");
  const fs::path twice = dir.write(
      "twice.json",
      R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}}, {"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}}]})");
  const fs::path badGenerator =
      dir.write("badgen.json", R"({"meshes": [{"name": "a", "generator": "castle"}]})");
  const fs::path openGenerator =
      dir.write("opengen.json",
                R"({"meshes": [{"name": "a", "generator": "forest", "size": 1, "closed": true}]})");
  const fs::path styleOutOfRange = dir.write(
      "styleout.json",
      R"({"meshes": [{"name": "a", "generator": "city", "size": 1, "style": {"turn": 91}}]})");
  const fs::path styleUnknown = dir.write(
      "styleunknown.json",
      R"({"meshes": [{"name": "a", "generator": "terrain", "size": 2, "style": {"relief": 4}}]})");
  const fs::path styleWithoutGenerator = dir.write(
      "stylebox.json",
      R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}, "style": {}}]})");
  const fs::path missingModel =
      dir.write("missingmodel.json", R"({"meshes": [{"name": "a", "file": "nowhere.obj"}]})");
  const fs::path badLight = dir.write(
      "badlight.json",
      R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}}], "lights": [{"type": "spot", "direction": [0,0,0], "position": [0,0,1]}]})");
  const fs::path singular = dir.write(
      "singular.json",
      R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}, "transform": {"scale": 0}}]})");

  const std::vector<std::tuple<fs::path, std::string>> cases = {
      {dir.path() / "missing.json", "no such file"},
      {dir.path() / "missing.obj", "no such file"},
      {dir.path(), "not a regular file"},
      {emptyJson, "empty file"},
      {emptyObj, "empty file"},
      {garbageJson, "invalid JSON"},
      {garbageGlb, ""},
      {garbageObj, ""},
      {lines, "no triangles (the file holds only lines or points)"},
      {objOutOfRange, ""},
      {nanObj, "non-finite"},
      {misspelt, "unknown key 'tranform'"},
      {badType, "meshes[0].closed: expected true or false"},
      {badIndex, "meshes[0].triangles[0]: vertex index 3 out of range"},
      {negative, "meshes[0].triangles[0][2]: expected a non-negative integer"},
      {noTriangles, "no triangles"},
      {badName, "not [A-Za-z0-9_-]+"},
      {twice, "two meshes are named 'a'"},
      {badGenerator, "unknown generator 'castle' (valid: city, terrain, forest, tangle)"},
      {openGenerator, "open"},
      {styleOutOfRange, "meshes[0].style.turn: 91 out of range [0, 90]"},
      {styleUnknown, "meshes[0].style: generator 'terrain' has no style knobs"},
      {styleWithoutGenerator, "'size', 'seed' and 'style' belong to a 'generator' mesh"},
      {missingModel, "nowhere.obj': no such file"},
      {badLight, "lights[0].direction: direction must not be zero"},
      {singular, "singular"},
  };
  for (const auto& [file, problem] : cases) {
    const fs::path path = file;  // Clang 14 cannot capture a structured binding in a lambda
    const std::string message = sceneErrorOf([&] { sb::openScene(path.string()); });
    INFO(message);
    CHECK_THAT(message, Catch::StartsWith("scene '" + path.string() + "': "));
    CHECK_THAT(message, Catch::Contains(problem));
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("a generator mesh in a scene file takes the generator's style knobs",
          "[scenes][file][style]") {
  TempDir dir;
  const fs::path file = dir.write(
      "styled.json",
      R"({"meshes": [{"name": "c", "generator": "city", "size": 2, "style": {"relief": 60, "turn": 90}}]})");
  const Scene fromFile = sb::openScene(file.string());
  const Scene fromSpec = sb::openScene("city:size=2,relief=60,turn=90");
  REQUIRE(fromFile.meshes.size() == 1);
  CHECK(fromFile.triangleCount() == fromSpec.triangleCount());
  CHECK(fromFile.bounds().min == fromSpec.bounds().min);
  CHECK(fromFile.bounds().max == fromSpec.bounds().max);
}

TEST_CASE("truncated or corrupted scene files give a Scene or a SceneError, nothing else",
          "[scenes][errors]") {
  TempDir dir;
  dir.write("cube.obj", kCubeObj);
  const std::string valid = R"({"name": "small", "meshes": [
 {"name": "cube", "closed": true, "file": "cube.obj", "transform": {"rotate": {"axis": [1,2,3], "degrees": 45}, "scale": 2}},
 {"name": "tri", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,2]], "transform": {"matrix": [1,0,0,1, 0,1,0,2, 0,0,1,3, 0,0,0,1]}},
 {"name": "box", "box": {"min": [-1,-1,-1], "max": [0.5,0.5,0.5]}}],
 "lights": [{"type": "spot", "position": [0,0,10], "direction": [0,0,-1], "fov": 45, "depth": "linear"}]})";
  REQUIRE(sb::loadSceneFile(dir.write("valid.json", valid)).meshes.size() == 3);

  int scenes = 0, errors = 0;
  auto attempt = [&](const std::string& text) {
    const fs::path file = dir.write("variant.json", text);
    try {
      const Scene scene = sb::loadSceneFile(file);
      CHECK(scene.triangleCount() > 0);
      ++scenes;
    } catch (const SceneError& e) {
      CHECK(std::string(e.what()).find('\n') == std::string::npos);
      ++errors;
    } catch (const std::exception& e) {
      FAIL("not a SceneError: " << e.what() << "\nfor: " << text);
    }
  };
  for (size_t length = 0; length < valid.size(); ++length) attempt(valid.substr(0, length));
  CHECK(errors == static_cast<int>(valid.size()));  // no proper prefix of the file is a scene

  // Byte flips at every position: low bits turn digits into other digits or punctuation,
  // high bits make invalid UTF-8.
  for (const uint8_t mask : {0x01, 0x02, 0x10, 0x80})
    for (size_t at = 0; at < valid.size(); ++at) {
      std::string corrupt = valid;
      corrupt[at] = static_cast<char>(corrupt[at] ^ mask);
      attempt(corrupt);
    }
  CHECK(scenes > 0);
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("generator footprints bound what the generators build", "[scenes][memory]") {
  std::vector<std::pair<const sb::GeneratorInfo*, sb::GeneratorKnobs>> cases;
  for (const auto& g : sb::sceneGenerators())
    for (const uint32_t size : {g.defaultSize / 2, g.defaultSize}) cases.push_back({&g, {size, 1}});
  for (const sb::GeneratorPreset& preset : generator("city").presets)
    cases.push_back({&generator("city"), {preset.size, preset.seed, preset.style}});
  cases.push_back({&generator("city"), {3, 1, {20, 90}}});
  for (const auto& [generatorInfo, knobs] : cases) {
    const sb::GeneratorInfo& g = *generatorInfo;
    const uint32_t size = knobs.size;
    {
      INFO("generator " << g.name << " size " << size << " style knobs " << knobs.style.size());
      const Scene scene = g.generate(knobs);
      const sb::SceneFootprint footprint = g.footprint(knobs);
      uint64_t vertices = 0, bytes = 0;
      for (const Mesh& mesh : scene.meshes) {
        vertices += mesh.vertices.size();
        bytes += mesh.vertices.capacity() * sizeof(glm::vec3) +
                 mesh.triangles.capacity() * sizeof(glm::uvec3);
      }
      CHECK(vertices <= footprint.vertices);
      CHECK(scene.triangleCount() <= footprint.triangles);
      CHECK(bytes <= footprint.bytes);
      // A bound, yet not so loose that it refuses scenes that fit: within 4× of the real count.
      CHECK(footprint.triangles <= 4 * scene.triangleCount());
      if (g.name == "tangle" || g.name == "terrain") {
        CHECK(footprint.triangles == scene.triangleCount());
        CHECK(footprint.vertices == vertices);
      }
    }
  }
}

TEST_CASE("a generator size too large for the memory is refused with the figure",
          "[scenes][memory]") {
  constexpr uint64_t kGiB = 1ull << 30;
  const std::string tangle = sceneErrorOf([] { sb::openScene("tangle:size=20000", kGiB); });
  CHECK_THAT(tangle, Catch::StartsWith("scene 'tangle:size=20000': generating up to 61440000 "
                                       "triangles needs at least 2.06 GiB"));
  CHECK_THAT(tangle,
             Catch::Contains("only 1.00 GiB of memory is available; choose a smaller size"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene("city:size=200", kGiB); }),
             Catch::Contains("choose a smaller size"));
  CHECK_THAT(sceneErrorOf([] { sb::openScene("city:size=201", kGiB); }),
             Catch::Contains("out of range"));
  CHECK(sb::openScene("tangle:size=2", kGiB).triangleCount() == 2 * 3072);
  TempDir dir;
  const fs::path file =
      dir.write("big.json", R"({"meshes": [{"name": "t", "generator": "tangle", "size": 20000}]})");
  CHECK_THAT(sceneErrorOf([&] { sb::loadSceneFile(file, kGiB); }),
             Catch::Contains("meshes[0]: generating up to 61440000 triangles needs at least"));
}

TEST_CASE("a spot light's fov is checked against the range the harness accepts",
          "[scenes][file][lights]") {
  TempDir dir;
  auto withFov = [&](const std::string& fov) {
    return dir.write("spot.json",
                     R"({"meshes": [{"name": "a", "box": {"min": [0,0,0], "max": [1,1,1]}}],
                         "lights": [{"type": "spot", "position": [0,0,5], "direction": [0,0,-1], "fov": )" +
                         fov + "}]}");
  };
  CHECK(sb::loadSceneFile(withFov("178.9")).lights[0].fovDegrees == 178.9f);
  for (const char* fov : {"179.9999", "179", "179.99999999", "0", "-3", "180"}) {
    INFO(fov);
    const std::string message = sceneErrorOf([&] { sb::loadSceneFile(withFov(fov)); });
    CHECK_THAT(message, Catch::Contains("lights[0].fov: "));
    CHECK_THAT(message, Catch::Contains("degrees is outside the accepted range (0, 179)"));
  }
  CHECK(sb::isValidSpotFov(178.99f));
  CHECK_FALSE(sb::isValidSpotFov(sb::kMaxSpotFovDegrees));
}
