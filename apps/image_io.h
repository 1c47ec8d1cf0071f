// Writing the core's linear float images as 8-bit sRGB PNG, and reading PNG textures: libpng's
// simplified API both ways, which turns every corrupt file and every failed write into a message
// and prints nothing of its own.
#pragma once

#include "core/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace wfapp {

/// sRGB transfer function of one linear value, clamped to [0, 1]; NaN -> 0.
float linearToSrgb(float linear);

/// Writes RGB over black (alpha premultiplied coverage) to `path`: refused when the path is a
/// device, FIFO or folder (UsageError); written under a unique temporary name beside it and
/// renamed (apps/safe_files.h), so a failed or stopped write leaves nothing, and renders writing
/// one path at once leave one whole image. A failed write throws OutputError. `compression`:
/// 0 ... 3 is libpng's fast mode (about three times faster, files a fifth larger; the gallery
/// writes many), above it the default.
void writePng(const wf::ImageRGBA& image, const std::string& path, int compression = 5);
/// The same written straight to `file` (a temporary the caller renames); `name` in messages.
void writePngFile(const wf::ImageRGBA& image, const std::string& file, const std::string& name, int compression = 5);

/// An image as the PNG holds it: 8-bit sRGB, RGB over black, rows top to bottom (a fifth of the
/// float image's bytes: what a caller keeps of many renders before writing them, the gallery).
struct SrgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};
SrgbImage toSrgb(const wf::ImageRGBA& image);
void writePng(const SrgbImage& image, const std::string& path, int compression = 5);

/// Reads any PNG libpng reads (grey, palette, RGB, with or without alpha, 1 to 16 bits) as a
/// linear-light RGB image (alpha composited over black; alpha of the result 1), row 0 at the
/// top. At most `maxPixels` pixels (default 4096 x 4096). Throws UsageError naming the file and
/// the problem (missing, a folder, not a PNG, corrupt or truncated, too large).
wf::ImageRGBA readPng(const std::string& path, size_t maxPixels = size_t(1) << 24);

}  // namespace wfapp
