// The sRGB transfer function (IEC 61966-2-1), one value at a time: the core's images are linear
// light; 8-bit files and VTK's colour arrays are sRGB-encoded. One definition for the PNG writer,
// the viewer, the VTK filters' colour arrays and the render pass, in the precision of the
// argument (float for images, double where a filter computes in double).
#pragma once

#include <cmath>
#include <concepts>

namespace wf {

/// Linear value to sRGB-encoded, clamped to [0, 1]; NaN -> 0.
template <std::floating_point T>
inline T linearToSrgb(T v) {
  if (!(v > T(0))) return T(0);
  if (v >= T(1)) return T(1);
  return v <= T(0.0031308) ? T(12.92) * v : T(1.055) * std::pow(v, T(1) / T(2.4)) - T(0.055);
}

/// sRGB-encoded value to linear, clamped to [0, 1]; NaN -> 0.
template <std::floating_point T>
inline T srgbToLinear(T e) {
  if (!(e > T(0))) return T(0);
  if (e >= T(1)) return T(1);
  return e <= T(0.04045) ? e / T(12.92) : std::pow((e + T(0.055)) / T(1.055), T(2.4));
}

/// Linear value to an 8-bit sRGB code.
template <std::floating_point T>
inline unsigned char srgb8(T v) {
  return static_cast<unsigned char>(std::lround(T(255) * linearToSrgb(v)));
}

}  // namespace wf
