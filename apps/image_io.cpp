#include "image_io.h"

#include "cli.h"
#include "safe_files.h"

#include "core/srgb.h"

#include <png.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace wfapp {

float linearToSrgb(float v) { return wf::linearToSrgb(v); }

wf::ImageRGBA readPng(const std::string& path, size_t maxPixels) {
  // libpng's simplified API: it checks every chunk, reports a bad file as a message instead of
  // longjmp-ing through our stack (VTK's PNG reader crashes on a corrupt file), and converts to
  // 16-bit linear light itself (sRGB or the file's gAMA decoded). Alpha is composited over black.
  // Read once through the checked descriptor (apps/safe_files.h), then decoded from memory.
  const std::string bytes = readInputFile(path, "the image");
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    throw UsageError(path + ": not a PNG image");
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()))
    throw UsageError(path + ": bad PNG (" + std::string(image.message) + ")");
  const size_t w = image.width, h = image.height;
  if (w == 0 || h == 0 || w * h > maxPixels) {
    png_image_free(&image);
    throw UsageError(path + ": the PNG is " + std::to_string(w) + "x" + std::to_string(h) + ", more than the " +
                     std::to_string(maxPixels) + " pixels a texture may have");
  }
  image.format = PNG_FORMAT_LINEAR_RGB;
  std::vector<png_uint_16> buffer(PNG_IMAGE_SIZE(image) / sizeof(png_uint_16));
  if (!png_image_finish_read(&image, nullptr, buffer.data(), 0, nullptr))
    throw UsageError(path + ": bad PNG (" + std::string(image.message) + ")");  // finish_read frees on failure
  wf::ImageRGBA img{int(w), int(h)};
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x) {
      const png_uint_16* p = &buffer[3 * (y * w + x)];
      img.at(int(x), int(y)) = glm::vec4(p[0] / 65535.0f, p[1] / 65535.0f, p[2] / 65535.0f, 1.0f);
    }
  return img;
}

SrgbImage toSrgb(const wf::ImageRGBA& image) {
  SrgbImage s;
  s.width = std::max(image.width, 0);
  s.height = std::max(image.height, 0);
  s.rgb.resize(size_t(s.width) * size_t(s.height) * 3);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const glm::vec4& p = image.at(x, y);
      png_byte* o = &s.rgb[3 * (size_t(y) * size_t(s.width) + size_t(x))];
      for (int c = 0; c < 3; ++c) o[c] = png_byte(std::lround(255.0f * linearToSrgb(p[c])));
    }
  return s;
}

namespace {

void writeSrgbFile(const SrgbImage& image, const std::string& file, const std::string& name, int compression) {
  if (image.width <= 0 || image.height <= 0) throw std::runtime_error(name + ": empty image");
  // libpng's simplified API: no message of its own on stderr (a full disk is one line here), and
  // the file is flushed and closed before it counts as written.
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  if (compression <= 3) png.flags |= PNG_IMAGE_FLAG_FAST;
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw OutputError(name + ": cannot write (" + std::strerror(errno) + ")");
  const bool encoded = png_image_write_to_stdio(&png, f, 0, image.rgb.data(), 0, nullptr) != 0;
  const std::string why = encoded ? std::string() : std::string(png.message);
  const bool flushed = encoded && std::fflush(f) == 0 && !std::ferror(f);
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  png_image_free(&png);
  if (!encoded) throw OutputError(name + ": cannot write the PNG (" + why + ")");
  if (!flushed || !closed) throw OutputError(name + ": cannot write (" + std::strerror(flushed ? errno : err) + ")");
}

}  // namespace

void writePngFile(const wf::ImageRGBA& image, const std::string& file, const std::string& name, int compression) {
  writeSrgbFile(toSrgb(image), file, name, compression);  // (an empty image: refused there)
}

void writePng(const SrgbImage& image, const std::string& path, int compression) {
  requireOutputPath(path);
  OutputFile out(path);
  writeSrgbFile(image, out.temporaryPath(), path, compression);
  out.commit();
}

void writePng(const wf::ImageRGBA& image, const std::string& path, int compression) {
  writePng(toSrgb(image), path, compression);
}

}  // namespace wfapp
