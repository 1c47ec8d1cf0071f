// The sRGB transfer function (IEC 61966-2-1), one value at a time: the core's images are linear
// light; 8-bit files and VTK's colour arrays are sRGB-encoded. One definition for the PNG writer,
// the VTK filters' colour arrays and the render pass.
#pragma once

#include <cmath>

namespace wf {

/// Linear value to sRGB-encoded, clamped to [0, 1]; NaN -> 0.
inline float linearToSrgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

/// sRGB-encoded value to linear, clamped to [0, 1]; NaN -> 0.
inline float srgbToLinear(float e) {
  if (!(e > 0.0f)) return 0.0f;
  if (e >= 1.0f) return 1.0f;
  return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
}

/// Linear value to an 8-bit sRGB code.
inline unsigned char srgb8(float v) { return static_cast<unsigned char>(std::lround(255.0f * linearToSrgb(v))); }

}  // namespace wf
