// The scene and model loaders read paths, not bytes: their fuzz targets write each input to a
// file of this process's own, named with the extension that picks the loader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

namespace sb::fuzz {

// Writes the bytes to <temp dir>/shadowbench-fuzz-<pid><extension>, replacing the previous
// input, and returns that path; aborts if the file cannot be written.
std::filesystem::path writeTempFile(const uint8_t* data, size_t size, std::string_view extension);

}  // namespace sb::fuzz
