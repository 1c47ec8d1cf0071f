// Writing the core's linear float images as 8-bit sRGB PNG (VTK's PNG writer), and reading PNG
// textures (libpng's simplified API, which turns every corrupt file into a message).
#pragma once

#include "core/image.h"

#include <string>

namespace wfapp {

/// sRGB transfer function of one linear value, clamped to [0, 1]; NaN -> 0.
float linearToSrgb(float linear);

/// Writes RGB over black (alpha premultiplied coverage). Writes to a temporary name in the same
/// directory and renames, so a failed write leaves nothing half-written. Throws on failure.
/// `compression`: zlib's level, 0 ... 9 (1: about three times faster than the default 5, files a
/// fifth larger; the gallery writes many).
void writePng(const wf::ImageRGBA& image, const std::string& path, int compression = 5);

/// Reads any PNG libpng reads (grey, palette, RGB, with or without alpha, 1 to 16 bits) as a
/// linear-light RGB image (alpha composited over black; alpha of the result 1), row 0 at the
/// top. At most `maxPixels` pixels (default 4096 x 4096). Throws UsageError naming the file and
/// the problem (missing, a folder, not a PNG, corrupt or truncated, too large).
wf::ImageRGBA readPng(const std::string& path, size_t maxPixels = size_t(1) << 24);

}  // namespace wfapp
