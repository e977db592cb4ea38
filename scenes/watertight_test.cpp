// Watertightness: what a closed mesh promises (Mesh::closed), checked for model files declared
// closed and for scene files' closed meshes.
#include <catch2/catch.hpp>

#include "scenes/scene.h"
#include "scenes/scene_test_support.h"
#include "scenes/watertight.h"

namespace fs = std::filesystem;
using sb::Mesh;
using sb::Scene;
using sb::SceneError;
using namespace sb::testing;

// Watertightness (issue 11: closedness of model files, `scene info`)

namespace {

// The unit cube as 12 triangles, outward, with the corners of each face repeated per face (as
// model files often store them): edges join by position, not by index.
Mesh cubeWithVerticesPerFace() {
  const Scene scene = [] {
    TempDir dir;
    return sb::openScene(dir.write("cube.obj", kCubeObj).string());
  }();
  Mesh cube;
  cube.name = "cube";
  for (const glm::uvec3& t : scene.meshes[0].triangles) {
    const auto first = static_cast<uint32_t>(cube.vertices.size());
    for (int k = 0; k < 3; ++k) cube.vertices.push_back(scene.meshes[0].vertices[t[k]]);
    cube.triangles.push_back({first, first + 1, first + 2});
  }
  return cube;
}

}  // namespace

TEST_CASE("watertightness counts open edges by kind", "[scenes][watertight]") {
  const Mesh cube = cubeWithVerticesPerFace();
  REQUIRE(cube.triangles.size() == 12);
  const sb::Watertightness whole = sb::checkWatertight(cube);
  CHECK(whole.watertight());
  CHECK(whole.edges == 18);  // 12 cube edges and 6 face diagonals
  CHECK(whole.describe() == "watertight");
  CHECK(sb::enclosedVolume(cube) == Approx(1.0));

  Mesh holed = cube;  // one face (two triangles) removed: its four sides are a hole's rim
  holed.triangles.resize(10);
  const sb::Watertightness hole = sb::checkWatertight(holed);
  CHECK(hole.boundaryEdges == 4);
  CHECK(hole.openEdges() == 4);
  CHECK_FALSE(hole.watertight());
  CHECK_THAT(hole.describe(), Catch::StartsWith("not watertight: 4 open edges (4 on holes)"));

  Mesh flipped = cube;  // one triangle wound the wrong way: its three edges run with neighbours
  std::swap(flipped.triangles[0].y, flipped.triangles[0].z);
  const sb::Watertightness flip = sb::checkWatertight(flipped);
  CHECK(flip.misorientedEdges == 3);
  CHECK(flip.boundaryEdges == 0);
  CHECK(flip.openEdges() == 3);

  Mesh fin = cube;  // a third triangle on a cube edge
  fin.vertices.push_back({0.5f, -1.0f, 0.0f});
  fin.triangles.push_back(
      {fin.triangles[0].x, fin.triangles[0].y, static_cast<uint32_t>(fin.vertices.size() - 1)});
  const sb::Watertightness finned = sb::checkWatertight(fin);
  CHECK(finned.nonManifoldEdges == 1);
  CHECK(finned.boundaryEdges == 2);

  Mesh sliver = cube;  // a triangle without area changes nothing but is counted
  sliver.triangles.push_back({0, 0, 1});
  CHECK(sb::checkWatertight(sliver).watertight());
  CHECK(sb::checkWatertight(sliver).degenerateTriangles == 1);

  Mesh inverted = cube;
  for (glm::uvec3& t : inverted.triangles) std::swap(t.y, t.z);
  CHECK(sb::checkWatertight(inverted).watertight());
  CHECK(sb::enclosedVolume(inverted) == Approx(-1.0));
}

TEST_CASE("a model file opens closed with ':closed', checked to be watertight",
          "[scenes][watertight][spec]") {
  TempDir dir;
  const fs::path cube = dir.write("cube.obj", kCubeObj);
  const Scene open = sb::openScene(cube.string());
  const Scene closed = sb::openScene(cube.string() + ":closed");
  REQUIRE(closed.meshes.size() == 1);
  CHECK(closed.meshes[0].closed);
  CHECK_FALSE(open.meshes[0].closed);
  CHECK(closed.hash() != open.hash());
  CHECK(sb::openScene(cube.string() + ":open").hash() == open.hash());
  checkSceneInvariants(closed);

  // OFF, a format of scanned objects: the cube without its top face.
  const fs::path box = dir.write("box.off", R"(OFF
8 5 0
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
4 0 2 3 1
4 0 1 5 4
4 2 6 7 3
4 0 4 6 2
4 1 3 7 5
)");
  CHECK(sb::openScene(box.string()).triangleCount() == 10);
  const std::string holed = sceneErrorOf([&] { sb::openScene(box.string() + ":closed"); });
  CHECK_THAT(holed, Catch::StartsWith("scene '" + box.string() + ":closed': mesh '"));
  CHECK_THAT(holed, Catch::Contains("is declared closed but is not watertight: 4 open edges"));
  CHECK(holed.find('\n') == std::string::npos);

  // Inside out: watertight, but the closed-object optimisation needs outward faces.
  std::string inverted = kCubeObj;
  for (const char* face :
       {"f 1 3 4 2", "f 5 6 8 7", "f 1 2 6 5", "f 3 7 8 4", "f 1 5 7 3", "f 2 4 8 6"}) {
    const std::string forward = face;
    const std::string backward = "f " + std::string(forward.rbegin(), forward.rend() - 2);
    inverted.replace(inverted.find(forward), forward.size(), backward);
  }
  const fs::path inside = dir.write("inside.obj", inverted);
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(inside.string() + ":closed"); }),
             Catch::Contains("inside out"));

  // A file whose name holds a ':' is still found; only a last ":closed" or ":open" is read.
  const fs::path colon = dir.write("a:b.obj", kCubeObj);
  CHECK(sb::openScene(colon.string()).triangleCount() == 12);
  CHECK(sb::openScene(colon.string() + ":closed").meshes[0].closed);
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(cube.string() + ":shut"); }),
             Catch::Contains("no such file"));

  const fs::path json =
      dir.write("s.json", R"({"meshes": [{"name": "cube", "file": "cube.obj"}]})");
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(json.string() + ":closed"); }),
             Catch::Contains("a scene file says \"closed\" per mesh"));
}

TEST_CASE("a scene file's closed model or inline mesh must be watertight",
          "[scenes][watertight][file]") {
  TempDir dir;
  dir.write("cube.obj", kCubeObj);
  dir.write("open.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
f 1 2 3
)");
  CHECK(sb::loadSceneFile(
            dir.write("ok.json",
                      R"({"meshes": [{"name": "c", "closed": true, "file": "cube.obj"}]})"))
            .meshes[0]
            .closed);
  const std::string model = sceneErrorOf([&] {
    sb::loadSceneFile(dir.write(
        "m.json", R"({"meshes": [{"name": "tri", "closed": true, "file": "open.obj"}]})"));
  });
  CHECK_THAT(model, Catch::Contains("meshes[0]: mesh 'tri' is declared closed but is not "
                                    "watertight: 3 open edges (3 on holes)"));
  const std::string inlineMesh = sceneErrorOf([&] {
    sb::loadSceneFile(dir.write(
        "i.json",
        R"({"meshes": [{"name": "t", "closed": true, "vertices": [[0,0,0],[1,0,0],[1,1,0]], "triangles": [[0,1,2]]}]})"));
  });
  CHECK_THAT(inlineMesh, Catch::Contains("mesh 't' is declared closed but is not watertight"));
}

// ---------------------------------------------------------------------------------------------
// Memory refused up front (issue 11, item 8)
