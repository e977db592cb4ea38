// The pictures read back through the libraries' own readers: the PNG's pixels are the mask's
// colours, the EXR's channel is the visibility, and an unwritable path is an error naming it.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <png.h>

#include "harness/views/frame_images.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> readPng(const fs::path& path, uint32_t& width, uint32_t& height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&image, path.c_str()));
  image.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> rgb(PNG_IMAGE_SIZE(image));
  REQUIRE(png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr));
  width = image.width, height = image.height;
  return rgb;
}

}  // namespace

TEST_CASE("masks and error maps as PNG and EXR", "[views][images]") {
  const fs::path dir = fs::temp_directory_path() / ("sb_frame_images_" + std::to_string(getpid()));
  fs::create_directories(dir);
  // 3 × 2: lit, shadowed, sky / false lit, false shadow, correct shadow.
  const std::vector<uint8_t> covered = {1, 1, 0, 1, 1, 1}, truth = {1, 0, 0, 0, 1, 0};
  const std::vector<float> visibility = {1, 0, 0, 1, 0, 0.25f};

  writePng(dir / "mask.png", shadowMaskImage(3, 2, covered, visibility));
  uint32_t w = 0, h = 0;
  const std::vector<uint8_t> mask = readPng(dir / "mask.png", w, h);
  CHECK((w == 3 && h == 2));
  const auto pixel = [](const std::vector<uint8_t>& rgb, int p) {
    return std::array<int, 3>{rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]};
  };
  CHECK(pixel(mask, 0) != pixel(mask, 1));  // lit against shadowed
  CHECK(pixel(mask, 1) == pixel(mask, 4));  // both shadowed
  CHECK(pixel(mask, 2) != pixel(mask, 0));  // sky
  CHECK(pixel(mask, 2) != pixel(mask, 1));

  writePng(dir / "error.png", errorImage(3, 2, covered, truth, visibility));
  const std::vector<uint8_t> error = readPng(dir / "error.png", w, h);
  CHECK(pixel(error, 3)[0] > 200);  // false lit: red
  CHECK(pixel(error, 4)[2] > 200);  // false shadow: blue
  CHECK(pixel(error, 5)[0] < 100);  // right: dimmed

  writeVisibilityExr(dir / "mask.exr", 3, 2, covered, visibility);
  Imf::InputFile file((dir / "mask.exr").c_str());
  std::vector<float> v(6);
  Imf::FrameBuffer frame;
  frame.insert("V", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float),
                               3 * sizeof(float)));
  file.setFrameBuffer(frame);
  file.readPixels(0, 1);
  CHECK(v == std::vector<float>{1, 0, -1, 1, 0, 0.25f});

  CHECK_THROWS_WITH(writePng(dir / "missing" / "x.png", shadowMaskImage(3, 2, covered, visibility)),
                    Catch::Contains("missing/x.png"));
  CHECK_THROWS_AS(shadowMaskImage(4, 2, covered, visibility), std::invalid_argument);
  fs::remove_all(dir);
}
