// The groove texture of burnished metal (paper §2.2, image 6).
#include "texture/grooves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace wf {
namespace {

TEST(GrooveTexture, PointValuesAreOnePerGroove) {
  const GrooveTexture grooves(100.0, 0.6, 7);
  // Every point of groove k (coordinate in [k/100, (k+1)/100)) reads I_k, within (1 - depth, 1].
  for (std::int64_t k = -5; k < 50; ++k) {
    const double ik = grooves.grooveIntensity(k);
    EXPECT_GT(ik, 1.0 - 0.6);
    EXPECT_LE(ik, 1.0);
    for (double f : {0.01, 0.5, 0.99}) EXPECT_EQ(grooves.intensity((k + f) / 100.0, 0.0), ik);
  }
}

TEST(GrooveTexture, FilteredIntensityEqualsBruteForceAverage) {
  // Footprints of 0.3 to 40 grooves against a 100000-point midpoint average. The midpoint rule
  // misassigns at most 1/n of the interval at each groove boundary, weight depth: bound
  // (boundaries + 2) * depth / n.
  const GrooveTexture grooves(50.0, 0.8, 3);
  const int n = 100000;
  double worst = 0.0;
  for (double c : {0.1234, 0.5001, -0.377, 3.14159})
    for (double w : {0.006, 0.0213, 0.15, 0.8}) {
      const double a = c - 0.5 * w;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += grooves.intensity(a + w * (i + 0.5) / n, 0.0);
      const double brute = sum / n;
      const double bound = (w * 50.0 + 2.0) * 0.8 / n + 1e-12;
      const double filtered = grooves.intensity(c, w);
      worst = std::max(worst, std::fabs(filtered - brute));
      EXPECT_NEAR(filtered, brute, bound) << "c " << c << " w " << w;
    }
  RecordProperty("worst_abs_error", testing::PrintToString(worst));
}

TEST(GrooveTexture, WideFootprintsGiveTheMean) {
  // Over 64 grooves the whole ones count at their expected value: the documented mean
  // 1 - depth/2 up to the two fractional ends (weight <= 2 / grooves in the box).
  const GrooveTexture grooves(1000.0, 0.5, 11);
  EXPECT_DOUBLE_EQ(grooves.mean(), 0.75);
  for (double w : {0.5, 3.0, 1e6}) {
    const double grooveCount = w * 1000.0;
    EXPECT_NEAR(grooves.intensity(0.3, w), 0.75, 2.0 * 0.5 / grooveCount + 1e-12);
  }
  // Just below the cut (60 whole grooves) the exact sum: within 4 sigma of the mean
  // (sigma = depth / sqrt(12 * 60) = 0.019).
  EXPECT_NEAR(grooves.intensity(0.3, 0.061), 0.75, 4 * 0.5 / std::sqrt(12.0 * 60.0));
}

TEST(GrooveTexture, SeriesIsUncorrelatedWithTheDocumentedMean) {
  const GrooveTexture grooves(1.0, 1.0, 12345);
  const int n = 20000;
  std::vector<double> x(n);
  double mean = 0.0;
  for (int k = 0; k < n; ++k) mean += (x[k] = grooves.grooveIntensity(k));
  mean /= n;
  // Uniform on (0, 1]: mean 1/2, standard error 1 / sqrt(12 n) = 0.002; 4 sigma.
  EXPECT_NEAR(mean, 0.5, 4.0 / std::sqrt(12.0 * n));
  double c0 = 0.0, c1 = 0.0;
  for (int k = 0; k < n; ++k) c0 += (x[k] - mean) * (x[k] - mean);
  for (int k = 0; k + 1 < n; ++k) c1 += (x[k] - mean) * (x[k + 1] - mean);
  const double lag1 = c1 / c0;
  RecordProperty("lag1_correlation", testing::PrintToString(lag1));
  EXPECT_LT(std::fabs(lag1), 3.0 / std::sqrt(double(n)));
}

TEST(GrooveTexture, SameSeedSameSeriesOtherSeedOther) {
  const GrooveTexture a(20.0, 0.7, 5), b(20.0, 0.7, 5), c(20.0, 0.7, 6);
  int differ = 0;
  for (int k = -100; k < 100; ++k) {
    EXPECT_EQ(a.grooveIntensity(k), b.grooveIntensity(k));
    differ += a.grooveIntensity(k) != c.grooveIntensity(k);
  }
  EXPECT_GT(differ, 190);
}

TEST(GrooveTexture, FiniteForHostileInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const GrooveTexture grooves(64.0, 0.4, 1);
  EXPECT_EQ(grooves.intensity(nan, 0.01), grooves.mean());
  EXPECT_EQ(grooves.intensity(0.5, nan), grooves.mean());
  EXPECT_EQ(grooves.intensity(0.5, inf), grooves.mean());
  for (double c : {1e300, -1e300, 1e17, 4.5e15})
    for (double w : {0.0, 1e-3, 1e10}) {
      const double i = grooves.intensity(c, w);
      EXPECT_TRUE(std::isfinite(i));
      EXPECT_GE(i, 0.6);
      EXPECT_LE(i, 1.0);
    }
  const GrooveTexture odd(nan, nan, 0);
  EXPECT_TRUE(std::isfinite(odd.intensity(0.3, 0.1)));
  // The footprint overload reads the axis asked for.
  UvFootprint f;
  f.dx = {0.2, 0.0};
  EXPECT_EQ(grooves.intensity({0.3, 0.9}, f, 0), grooves.intensity(0.3, 0.2));
  EXPECT_EQ(grooves.intensity({0.3, 0.9}, f, 1), grooves.intensity(0.9, 0.0));
}

}  // namespace
}  // namespace wf
