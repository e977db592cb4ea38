// Model headers read before Assimp allocates: counts against the file size and the memory, and
// PLY files that would hang or crash Assimp refused.
#include <catch2/catch.hpp>

#include "scenes/scene.h"
#include "scenes/scene_test_support.h"
#include "scenes/watertight.h"

namespace fs = std::filesystem;
using sb::Mesh;
using sb::Scene;
using sb::SceneError;
using namespace sb::testing;

TEST_CASE("a model header that declares more than its file holds is refused before reading",
          "[scenes][memory][errors]") {
  TempDir dir;
  const std::string plyHeader =
      "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  auto ply = [&](const std::string& vertices) {
    std::string text = plyHeader;
    text.replace(text.find("{}"), 2, vertices);
    return text + "0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n";
  };
  const fs::path huge = dir.write("huge.ply", ply("4000000000"));
  const std::string message = sceneErrorOf([&] { sb::openScene(huge.string()); });
  CHECK_THAT(message, Catch::StartsWith("scene '" + huge.string() +
                                        "': the header declares "
                                        "4000000000 vertex and 1 face elements, which need at "
                                        "least 24000000002 bytes, but the file is only "));
  CHECK_THAT(message, Catch::EndsWith(std::to_string(fs::file_size(huge)) + " bytes long"));
  CHECK(sb::openScene(dir.write("ok.ply", ply("3")).string()).triangleCount() == 1);
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(dir.write("five.ply", ply("5")).string()); }),
             Catch::Contains("the file is only"));

  const std::string binaryHeader =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4000000000\n"
      "property list uchar int vertex_indices\nend_header\n";
  const fs::path binary = dir.write("faces.ply", binaryHeader + std::string(36 + 13, '\0'));
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(binary.string()); }),
             Catch::Contains("declares 3 vertex and 4000000000 face elements, which need at "
                             "least 4000000036 bytes"));

  const fs::path off = dir.write("huge.off",
                                 "OFF\n# a comment\n3 4000000000 0\n0 0 0\n1 0 0\n"
                                 "1 1 0\n3 0 1 2\n");
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(off.string()); }),
             Catch::Contains("declares 3 vertex and 4000000000 face elements"));

  std::string stl(84 + 50, '\0');  // one triangle, but the header says 4·10⁹
  const uint32_t count = 4'000'000'000u;
  for (int i = 0; i < 4; ++i) stl[80 + i] = static_cast<char>(count >> (8 * i));
  const fs::path badStl = dir.write("huge.stl", stl);
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(badStl.string()); }),
             Catch::Contains("the binary STL header declares 4000000000 triangles, which need "
                             "200000000084 bytes, but the file is 134 bytes long"));
}

TEST_CASE("a model whose declared counts exceed the memory is refused with the figure",
          "[scenes][memory]") {
  TempDir dir;
  // A binary STL of two triangles (normal, three corners, attribute): valid, and two triangles
  // need more than 100 bytes.
  std::string stl(80, '\0');
  auto put = [&](auto value) {
    stl.append(reinterpret_cast<const char*>(&value), sizeof(value));  // x86-64: little-endian
  };
  put(uint32_t{2});
  for (const float z : {0.0f, 1.0f}) {
    for (const float v : {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, z, 1.0f, 0.0f, z, 1.0f, 1.0f, z}) put(v);
    put(uint16_t{0});
  }
  REQUIRE(stl.size() == 84 + 2 * 50);
  const fs::path file = dir.write("two.stl", stl);
  CHECK_THAT(sceneErrorOf([&] { sb::openScene(file.string(), 100); }),
             Catch::Contains("reading the 6 vertices and 2 faces its header declares needs at "
                             "least"));
  CHECK_NOTHROW(sb::openScene(file.string(), 1ull << 30));
}

// ---------------------------------------------------------------------------------------------
// Spot lights (issue 11: fov 179.9999 passed the scene check and failed later)

TEST_CASE("PLY files that crash or hang Assimp are refused", "[scenes][errors][regression]") {
  // Found by fuzzing (fuzz/regressions/model_file/): Assimp 5.2 loops forever on a header with
  // no end_header and segfaults on a cut "format" line, so the header is checked before Assimp
  // reads the file; its post-processing aborts on a face with no index, so the faces are
  // checked between reading and post-processing.
  TempDir dir;
  const auto refusal = [&](const std::string& name, const std::string& contents) {
    const fs::path path = dir.write(name, contents);
    return sceneErrorOf([&] { sb::openScene(path.string()); });
  };
  CHECK_THAT(refusal("no_end.ply", "ply\nformat ascii 1.0\n"), Catch::Contains("no 'end_header'"));
  CHECK_THAT(refusal("cut.ply", std::string("ply\nformat binary_\0\0an\xff", 24)),
             Catch::Contains("not a PLY file"));
  CHECK_THAT(refusal("format.ply", "ply\nformat binary_\nelement vertex 0\nend_header\n"),
             Catch::Contains("header line 2"));
  CHECK_THAT(refusal("junk.ply", "ply\nformat ascii 1.0\nhello\nend_header\n"),
             Catch::Contains("header line 3"));
  // Read as PLY by its first bytes, whatever its name.
  CHECK_THAT(refusal("named.obj", "ply\nformat ascii 1.0\n"), Catch::Contains("no 'end_header'"));

  const std::string header =
      "ply\nformat {} 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  auto withFormat = [&](const std::string& format) {
    std::string text = header;
    return text.replace(text.find("{}"), 2, format);
  };
  CHECK_THAT(refusal("empty_face.ply", withFormat("ascii") + "0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n0\n"),
             Catch::Contains("face 1 has no vertex index"));
  std::string binary = withFormat("binary_little_endian") + std::string(36, '\0');
  binary += std::string("\x03\0\0\0\0\x01\0\0\0\x02\0\0\0", 13) + std::string(1, '\0');
  CHECK_THAT(refusal("empty_face_binary.ply", binary),
             Catch::Contains("face 1 has no vertex index"));
  // Assimp reads ASCII PLY by lines: a vertex line short of a value leaves the next line's
  // "00" as the face's length (found by fuzzing after the face lists were checked by tokens).
  CHECK_THAT(refusal("short_vertex_line.ply",
                     withFormat("ascii") + "0 0 0\n1 0 0\n0 13  \n00 1 2\n3 0 1 2\n"),
             Catch::Contains("face 0 has no vertex index"));
}
