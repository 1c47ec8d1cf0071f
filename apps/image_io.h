// Writing the core's linear float images as 8-bit sRGB PNG, and reading PNG textures, through
// VTK's PNG writer and reader.
#pragma once

#include "core/image.h"

#include <string>

namespace wfapp {

/// sRGB transfer function of one linear value, clamped to [0, 1]; NaN -> 0.
float linearToSrgb(float linear);

/// Writes RGB over black (alpha premultiplied coverage). Writes to a temporary name in the same
/// directory and renames, so a failed write leaves nothing half-written. Throws on failure.
void writePng(const wf::ImageRGBA& image, const std::string& path);

/// Reads an 8- or 16-bit PNG (grey, grey+alpha, RGB or RGBA) as a linear image (sRGB decoded;
/// alpha kept, 1 when absent), row 0 at the top. At most `maxPixels` pixels. Throws UsageError
/// naming the file and the problem (missing, not a PNG, truncated, too large).
wf::ImageRGBA readPng(const std::string& path, size_t maxPixels = size_t(1) << 26);

/// sRGB decoding of one 8-bit-scaled value in [0, 1].
float srgbToLinear(float encoded);

}  // namespace wfapp
