// The one atomic writer: whole contents or old contents, never a temporary left behind, and
// never a device node, FIFO or folder replaced by a plain file (issue 11 A2: `build -o` onto a
// device node replaced the node and exited 0).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "schemes/interface/atomic_file.h"
#include "tests/support/scratch_dir.h"

namespace fs = std::filesystem;
using sb::testing::ScratchDir;

namespace {

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t entriesIn(const fs::path& dir) {
  size_t count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++count;
  return count;
}

}  // namespace

TEST_CASE("writeFileAtomically replaces a regular file whole", "[atomic_file]") {
  ScratchDir dir("sb-atomic-test");
  const fs::path path = dir.path() / "x" / "out.bin";
  sb::writeFileAtomically(path, "first");
  sb::writeFileAtomically(path, "second, longer");
  CHECK(readText(path) == "second, longer");
  CHECK(entriesIn(path.parent_path()) == 1);
}

TEST_CASE("writeFileAtomically refuses targets that are not regular files, before writing",
          "[atomic_file][regression]") {
  ScratchDir dir("sb-atomic-test");
  const fs::path fifo = dir.path() / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH(sb::writeFileAtomically(fifo, "data"),
                    Catch::Contains("pipe") && Catch::Contains("not a regular file"));
  CHECK(fs::is_fifo(fifo));

  const fs::path folder = dir.path() / "folder";
  fs::create_directories(folder);
  CHECK_THROWS_WITH(sb::writeFileAtomically(folder, "data"), Catch::Contains("not a regular file"));
  CHECK(fs::is_directory(folder));
  CHECK(entriesIn(dir.path()) == 2);  // no temporary left beside them
  CHECK_NOTHROW(sb::checkReplaceable(dir.path() / "absent"));
}

TEST_CASE("a link may be replaced when it points to a regular file, never to a FIFO",
          "[atomic_file]") {
  ScratchDir dir("sb-atomic-test");
  sb::writeFileAtomically(dir.path() / "target", "old");
  fs::create_symlink(dir.path() / "target", dir.path() / "link");
  CHECK_NOTHROW(sb::checkReplaceable(dir.path() / "link"));
  const fs::path fifo = dir.path() / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  fs::create_symlink(fifo, dir.path() / "pipe-link");
  CHECK_THROWS(sb::checkReplaceable(dir.path() / "pipe-link"));
}
