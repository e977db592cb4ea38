#include "harness/views/frame_images.h"

#include <cstdio>
#include <memory>
#include <stdexcept>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <fmt/format.h>
#include <png.h>

#include "harness/views/frame_score.h"

namespace sb {

namespace {

constexpr uint8_t kLit[3] = {235, 235, 225}, kShadow[3] = {70, 70, 80}, kSky[3] = {150, 180, 215};
constexpr uint8_t kFalseLit[3] = {230, 40, 30}, kFalseShadow[3] = {30, 90, 240};

void put(RgbImage& image, size_t p, const uint8_t (&colour)[3], double scale = 1.0) {
  for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = uint8_t(colour[c] * scale);
}

RgbImage blank(uint32_t width, uint32_t height, size_t pixels) {
  if (size_t(width) * height != pixels)
    throw std::invalid_argument("frame image: masks do not match the frame size");
  return {width, height, std::vector<uint8_t>(3 * pixels)};
}

}  // namespace

RgbImage shadowMaskImage(uint32_t width, uint32_t height, std::span<const uint8_t> covered,
                         std::span<const float> visibility) {
  RgbImage image = blank(width, height, covered.size());
  for (size_t p = 0; p < covered.size(); ++p)
    put(image, p, !covered[p] ? kSky : visibility[p] >= kLitThreshold ? kLit : kShadow);
  return image;
}

RgbImage errorImage(uint32_t width, uint32_t height, std::span<const uint8_t> covered,
                    std::span<const uint8_t> truthLit, std::span<const float> visibility) {
  RgbImage image = blank(width, height, covered.size());
  for (size_t p = 0; p < covered.size(); ++p) {
    const bool lit = visibility[p] >= kLitThreshold;
    if (!covered[p])
      put(image, p, kSky, 0.5);
    else if (lit && !truthLit[p])
      put(image, p, kFalseLit);
    else if (!lit && truthLit[p])
      put(image, p, kFalseShadow);
    else
      put(image, p, truthLit[p] ? kLit : kShadow, 0.5);
  }
  return image;
}

void writePng(const std::filesystem::path& path, const RgbImage& image) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!file) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error(fmt::format("libpng cannot start '{}'", path.string()));
  }
  // libpng reports errors by longjmp; nothing with a destructor lives between here and the end.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error(fmt::format("libpng failed writing '{}'", path.string()));
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (uint32_t y = 0; y < image.height; ++y)
    png_write_row(png, image.rgb.data() + size_t(y) * image.width * 3);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0)
    throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

void writeVisibilityExr(const std::filesystem::path& path, uint32_t width, uint32_t height,
                        std::span<const uint8_t> covered, std::span<const float> visibility) {
  if (size_t(width) * height != covered.size() || covered.size() != visibility.size())
    throw std::invalid_argument("visibility EXR: masks do not match the frame size");
  std::vector<float> v(covered.size());
  for (size_t p = 0; p < v.size(); ++p) v[p] = covered[p] ? visibility[p] : -1.0f;
  Imf::Header header{int(width), int(height)};
  header.channels().insert("V", Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer frame;
  frame.insert("V", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float),
                               sizeof(float) * width));
  try {
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(int(height));
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), e.what()));
  }
}

}  // namespace sb
