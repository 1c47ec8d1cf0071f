#include "core/fast_atan2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

// Against the C library over random directions at every scale, and the axes, the diagonals and
// the reduction's break at tan(pi/8) where the two branches meet.
TEST(FastAtan2, WithinOneEMinus15OfTheLibrary) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-300.0, 300.0);
  double worst = 0.0;
  for (int i = 0; i < 1000000; ++i) {
    const double s = std::pow(10.0, e(rng) * (i % 2 ? 1.0 : 0.01));
    const double y = u(rng) * s, x = u(rng) * s;
    worst = std::max(worst, std::abs(wf::fastAtan2(y, x) - std::atan2(y, x)));
  }
  const double t8 = std::tan(M_PI / 8);
  // Extreme ratios (z underflows to 0 or is subnormal) and |x| + |y| overflowing (the library's path).
  for (double y : {1e300, -1e300, 1e-300, 4.9e-324, 1e308, -1.7e308})
    for (double x : {1e-300, -1e-300, 1e300, 1e308, -1.7e308, 4.9e-324})
      worst = std::max(worst, std::abs(wf::fastAtan2(y, x) - std::atan2(y, x)));
  for (double z : {0.0, 1e-300, 1e-8, t8 * (1 - 1e-15), t8, t8 * (1 + 1e-15), 0.5, 1.0 - 1e-16, 1.0})
    for (double sx : {1.0, -1.0})
      for (double sy : {1.0, -1.0}) {
        worst = std::max(worst, std::abs(wf::fastAtan2(sy * z, sx * 1.0) - std::atan2(sy * z, sx * 1.0)));
        worst = std::max(worst, std::abs(wf::fastAtan2(sy * 1.0, sx * z) - std::atan2(sy * 1.0, sx * z)));
      }
  EXPECT_LE(worst, 1e-15);
}

TEST(FastAtan2, SpecialValuesAreTheLibrarys) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  for (double y : {0.0, -0.0, 1.0, -1.0, inf, -inf})
    for (double x : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
      const double a = wf::fastAtan2(y, x), b = std::atan2(y, x);
      EXPECT_EQ(a, b) << y << " " << x;
      EXPECT_EQ(std::signbit(a), std::signbit(b)) << y << " " << x;
    }
  EXPECT_TRUE(std::isnan(wf::fastAtan2(nan, 1.0)));
  EXPECT_TRUE(std::isnan(wf::fastAtan2(1.0, nan)));
  // Signed zeros with a finite other side: +-0 or +-pi as the library gives.
  EXPECT_EQ(wf::fastAtan2(-0.0, 2.0), std::atan2(-0.0, 2.0));
  EXPECT_TRUE(std::signbit(wf::fastAtan2(-0.0, 2.0)));
  EXPECT_EQ(wf::fastAtan2(-0.0, -2.0), std::atan2(-0.0, -2.0));
}

}  // namespace
