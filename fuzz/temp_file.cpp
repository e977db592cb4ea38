#include "fuzz/temp_file.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace sb::fuzz {

std::filesystem::path writeTempFile(const uint8_t* data, size_t size, std::string_view extension) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("shadowbench-fuzz-" + std::to_string(getpid()) + std::string(extension));
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out.flush()) {
    std::fprintf(stderr, "cannot write the fuzz input to %s\n", path.c_str());
    std::abort();
  }
  return path;
}

}  // namespace sb::fuzz
