// atan2 without the C library's call: a polynomial on a reduced range, for the shading hot
// paths (the closed-form cylinder diffuse, grain turns) where std::atan2 was 5-7% of a frame.
//
// Reduction: z = min(|x|, |y|) / max(|x|, |y|) in [0, 1]; above tan(pi/8), atan z = pi/4 +
// atan((z - 1) / (z + 1)), so the polynomial only sees |z| <= tan(pi/8). There atan z = z + z^3
// p(z^2), p of degree 9, fitted (Chebyshev least squares against atan in 80-bit precision) to a
// relative error of 3e-16; with the reduction's roundings the result is within 1e-15 absolute of
// std::atan2 (src/core/fast_atan2_test.cpp checks it over 10^6 random and the special inputs;
// an independent check against atan2l over 4e7 inputs found 5.2e-16 at worst). Both zero,
// either infinite, NaN, or |x| + |y| beyond double range go to std::atan2, so the signs and
// special values are the C library's; one zero with the other finite goes through the
// polynomial and gives the same result (signed zeros included).
#pragma once

#include <cmath>

namespace wf {

inline double fastAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  // Both zero, either infinite, NaN (the test fails for it too), or |x| + |y| overflowing: the library.
  if (!(ax + ay > 0.0) || !(ax + ay < INFINITY)) return std::atan2(y, x);
  const bool swap = ay > ax;
  double z = swap ? ax / ay : ay / ax;  // [0, 1]
  constexpr double kTanPi8 = 0.41421356237309503;
  constexpr double kPi = 3.141592653589793, kHalfPi = 1.5707963267948966, kQuarterPi = 0.7853981633974483;
  double base = 0.0;
  if (z > kTanPi8) {
    z = (z - 1.0) / (z + 1.0);
    base = kQuarterPi;
  }
  const double t = z * z;
  double p = 0.0227789949225549;
  p = p * t - 0.04485042989205994;
  p = p * t + 0.05736703528561229;
  p = p * t - 0.06649641946945592;
  p = p * t + 0.07691053532204095;
  p = p * t - 0.09090852111711159;
  p = p * t + 0.1111110960481776;
  p = p * t - 0.14285714265089022;
  p = p * t + 0.19999999999885013;
  p = p * t - 0.33333333333333154;
  double r = base + (z + z * t * p);  // atan(min / max), [0, pi/4]
  if (swap) r = kHalfPi - r;
  if (x < 0.0) r = kPi - r;
  return std::signbit(y) ? -r : r;
}

}  // namespace wf
