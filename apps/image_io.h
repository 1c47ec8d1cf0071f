// Writing the core's linear float images as 8-bit sRGB PNG, through VTK's PNG writer.
#pragma once

#include "core/image.h"

#include <string>

namespace wfapp {

/// sRGB transfer function of one linear value, clamped to [0, 1]; NaN -> 0.
float linearToSrgb(float linear);

/// Writes RGB over black (alpha premultiplied coverage). Writes to a temporary name in the same
/// directory and renames, so a failed write leaves nothing half-written. Throws on failure.
void writePng(const wf::ImageRGBA& image, const std::string& path);

}  // namespace wfapp
