// Textures of paper §4.1: filtered lookups against brute-force averages, analytic gradients
// against central differences, finiteness on hostile input.
#include "texture/textures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

namespace wf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

UvFootprint boxFootprint(double halfU, double halfV) {
  UvFootprint f;
  f.dx = {halfU, 0.0};
  f.dy = {0.0, halfV};
  return f;  // halfBox() = (halfU / 2, halfV / 2): callers pass full widths
}

bool finite(const glm::vec3& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

/// Mean of n x n midpoint samples of a point lookup over the box [uv - half, uv + half].
template <class F>
glm::dvec3 bruteForceMean(F&& pointSample, glm::dvec2 uv, glm::dvec2 half, int n) {
  glm::dvec3 sum(0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 p = uv - half + 2.0 * half * glm::dvec2((i + 0.5) / n, (j + 0.5) / n);
      sum += glm::dvec3(pointSample(p));
    }
  return sum / double(n * n);
}

// ---------------------------------------------------------------------------------------------
TEST(ChequerTexture, PointSamplesPickTheSquare) {
  const ChequerTexture chequer(4, 2, glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));
  const UvFootprint zero;
  EXPECT_EQ(chequer.sample({0.1, 0.1}, zero), glm::vec3(1, 0, 0));   // square (0, 0)
  EXPECT_EQ(chequer.sample({0.3, 0.1}, zero), glm::vec3(0, 0, 1));   // square (1, 0)
  EXPECT_EQ(chequer.sample({0.3, 0.6}, zero), glm::vec3(1, 0, 0));   // square (1, 1)
  EXPECT_EQ(chequer.sample({-0.1, 0.1}, zero), glm::vec3(0, 0, 1));  // square (-1, 0)
}

TEST(ChequerTexture, BoxFilterEqualsBruteForceAverage) {
  // Footprints from a tenth of a square to several squares, at unaligned centres, against an
  // n x n midpoint rule. The rule's own error is up to 1/(2n) in coverage per square edge
  // crossed (a sample cell holding an edge misassigns up to half of itself): with n = 200 that
  // is 2.5e-3 per edge, larger than the tolerance (measured: 1.7e-3 for a box with one edge),
  // so n = 2000 (<= 2.5e-4 per edge, random signs). tol 1e-3; the worst is recorded.
  const ChequerTexture chequer(8, 5, glm::vec3(1.0f), glm::vec3(0.0f));
  const UvFootprint zero;
  auto point = [&](glm::dvec2 p) { return chequer.sample(p, zero); };
  const glm::dvec2 centres[] = {{0.37, 0.41}, {0.125, 0.2}, {0.9, 0.03}, {-0.31, 1.7}};
  const glm::dvec2 halves[] = {{0.004, 0.01}, {0.03, 0.02}, {0.1, 0.07}, {0.31, 0.45}};
  double worst = 0.0;
  for (const glm::dvec2& c : centres)
    for (const glm::dvec2& h : halves) {
      const double filtered = chequer.sample(c, boxFootprint(2 * h.x, 2 * h.y)).x;
      const double brute = bruteForceMean(point, c, h, 2000).x;
      worst = std::max(worst, std::fabs(filtered - brute));
      EXPECT_NEAR(filtered, brute, 1e-3) << "centre " << c.x << "," << c.y << " half " << h.x;
    }
  RecordProperty("worst_abs_error", testing::PrintToString(worst));
}

TEST(ChequerTexture, SubPixelChequerAveragesToTheMean) {
  // 1000 x 1000 squares, footprint of 37.3 x 41.7 squares: the mean 0.5 within
  // 1 / (squares in footprint) = 1 / (37.3 * 41.7).
  const ChequerTexture chequer(1000, 1000, glm::vec3(1.0f), glm::vec3(0.0f));
  const glm::dvec2 half(0.5 * 0.0373, 0.5 * 0.0417);
  const double bound = 1.0 / (37.3 * 41.7);
  for (double u : {0.1234, 0.5, 0.77777})
    EXPECT_NEAR(chequer.sample({u, 0.3}, boxFootprint(2 * half.x, 2 * half.y)).x, 0.5, bound);
  // Along one axis only (a thin sliver 0.01 square wide crossing 50 squares): within 1/50 of
  // the mean along u times the local square in v.
  EXPECT_NEAR(ChequerTexture::meanSquareWave(3.3, 25.0), 0.0, 1.0 / 50.0);
}

TEST(ChequerTexture, NarrowFootprintAcrossAnEdgeIsExact) {
  // Interval [1 - 0.5e-12, 1 + 1.5e-12]: 1/4 on square 0 (s = +1), 3/4 on square 1 (s = -1),
  // mean -0.5. Tolerance 1e-3: the interval's ends carry rounding of 2.2e-16 / 2e-12 = 1e-4; the
  // triangle-wave formula would lose everything here (differences of O(1) values over 2e-12).
  const double m = ChequerTexture::meanSquareWave(1.0 + 0.5e-12, 1e-12);
  EXPECT_NEAR(m, -0.5, 1e-3);
}

TEST(ChequerTexture, FiniteForHostileInput) {
  const ChequerTexture chequer(3, 3, glm::vec3(1, 0.5, 0), glm::vec3(0, 0.5, 1));
  const glm::vec3 mean(0.5f);
  EXPECT_EQ(chequer.sample({kNaN, 0.3}, {}), mean);
  EXPECT_TRUE(finite(chequer.sample({1e300, -1e300}, boxFootprint(1e-3, 1e-3))));
  EXPECT_TRUE(finite(chequer.sample({0.2, 0.2}, boxFootprint(kInf, kNaN))));
  EXPECT_NEAR(chequer.sample({0.2, 0.2}, boxFootprint(kInf, kNaN)).x, 0.5, 1e-6);
}

// ---------------------------------------------------------------------------------------------
ImageRGBA testImage(int w, int h) {
  ImageRGBA img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(x, y) = glm::vec4(float((x * 7 + y * 3) % 11) / 10.0f, float(x) / w, float(y) / h, 1);
  return img;
}

TEST(ImageTexture, BilinearIsExactAtTexelCentres) {
  const ImageRGBA img = testImage(13, 7);
  const ImageTexture tex(img, false, false);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 13; ++x) {
      // Texel (x, y) (row y from the top) is centred at u = (x + 1/2) / W, v = 1 - (y + 1/2) / H.
      const glm::dvec2 uv((x + 0.5) / 13.0, 1.0 - (y + 0.5) / 7.0);
      const glm::vec3 s = tex.sample(uv, {});
      EXPECT_NEAR(s.x, img.at(x, y).x, 1e-6);
      EXPECT_NEAR(s.y, img.at(x, y).y, 1e-6);
      EXPECT_NEAR(s.z, img.at(x, y).z, 1e-6);
    }
}

TEST(ImageTexture, SummedAreaBoxEqualsMeanOfCoveredTexels) {
  const ImageRGBA img = testImage(32, 24);
  const ImageTexture tex(img, false, false);
  // Texels x 5..14, y (from the top) 3..10: a box aligned with texel edges.
  glm::dvec3 sum(0.0);
  for (int y = 3; y <= 10; ++y)
    for (int x = 5; x <= 14; ++x) sum += glm::dvec3(glm::vec3(img.at(x, y)));
  const glm::dvec3 expected = sum / 80.0;
  const glm::dvec2 uv(10.0 / 32.0, 1.0 - 7.0 / 24.0);  // the box centre
  const glm::vec3 s = tex.sample(uv, boxFootprint(10.0 / 32.0, 8.0 / 24.0));
  EXPECT_NEAR(s.x, expected.x, 1e-6);
  EXPECT_NEAR(s.y, expected.y, 1e-6);
  EXPECT_NEAR(s.z, expected.z, 1e-6);
}

TEST(ImageTexture, FractionalBoxEqualsBruteForceNearestTexelMean) {
  // Unaligned boxes, wrap and clamp, some straddling the image's edges: the exact integral of
  // the piecewise-constant image against a 400x400 midpoint rule of nearest-texel samples
  // (error <= 2 * 2 edges-per-row... < 2e-3 for these sizes).
  const ImageRGBA img = testImage(16, 12);
  for (bool wrap : {false, true}) {
    const ImageTexture tex(img, wrap, wrap);
    auto nearest = [&](glm::dvec2 p) {
      const double x = p.x * 16.0, y = (1.0 - p.y) * 12.0;
      int i = int(std::floor(x)), j = int(std::floor(y));
      if (wrap) {
        i = ((i % 16) + 16) % 16;
        j = ((j % 12) + 12) % 12;
      } else {
        i = std::clamp(i, 0, 15);
        j = std::clamp(j, 0, 11);
      }
      return glm::vec3(img.at(i, j));
    };
    const glm::dvec2 centres[] = {{0.41, 0.33}, {0.02, 0.97}, {0.99, 0.5}, {1.3, -0.2}};
    for (const glm::dvec2& c : centres) {
      const glm::dvec2 half(0.137, 0.093);
      const glm::dvec3 brute = bruteForceMean(nearest, c, half, 400);
      const glm::vec3 s = tex.sample(c, boxFootprint(2 * half.x, 2 * half.y));
      EXPECT_NEAR(s.x, brute.x, 2e-3) << "wrap " << wrap << " centre " << c.x << "," << c.y;
      EXPECT_NEAR(s.y, brute.y, 2e-3);
      EXPECT_NEAR(s.z, brute.z, 2e-3);
    }
  }
}

TEST(ImageTexture, HalfTexelBoxIsBilinear) {
  // The reconstruction: a one-texel box over the nearest-texel image is bilinear interpolation,
  // so a footprint just above half a texel continues the point samples.
  const ImageRGBA img = testImage(9, 9);
  const ImageTexture tex(img, true, false);
  for (glm::dvec2 uv : {glm::dvec2(0.31, 0.47), glm::dvec2(0.02, 0.6), glm::dvec2(0.77, 0.99)}) {
    const glm::vec3 point = tex.bilinear(uv);
    const glm::dvec3 box = tex.boxMeanTexels(uv.x * 9 - 0.5, uv.x * 9 + 0.5, (1 - uv.y) * 9 - 0.5,
                                             (1 - uv.y) * 9 + 0.5);
    EXPECT_NEAR(point.x, box.x, 1e-6);
    EXPECT_NEAR(point.y, box.y, 1e-6);
    EXPECT_NEAR(point.z, box.z, 1e-6);
  }
}

TEST(ImageTexture, WrapIsContinuousAcrossTheSeam) {
  const ImageRGBA img = testImage(10, 6);
  const ImageTexture tex(img, true, true);
  const double e = 1e-9;
  for (double v : {0.1, 0.5, 0.83}) {
    const glm::vec3 left = tex.sample({e, v}, {}), right = tex.sample({1.0 - e, v}, {});
    EXPECT_NEAR(left.x, right.x, 1e-6);
    EXPECT_NEAR(left.y, right.y, 1e-6);
    // u = 0 is half-way between the last and the first column.
    EXPECT_NEAR(left.y, 0.5 * (img.at(0, 2).y + img.at(9, 2).y), 1e-6);
    // A box across the seam equals the same box one period on.
    const glm::vec3 a = tex.sample({0.01, v}, boxFootprint(0.3, 0.1));
    const glm::vec3 b = tex.sample({1.01, v}, boxFootprint(0.3, 0.1));
    EXPECT_NEAR(a.x, b.x, 1e-9);
  }
}

TEST(ImageTexture, LargeImageKeepsPrecision) {
  // 2048 x 2048 of values near 1000: a one-texel box must still read its texel (SAT of
  // texel - mean in double).
  ImageRGBA img(2048, 2048);
  for (int y = 0; y < 2048; ++y)
    for (int x = 0; x < 2048; ++x)
      img.at(x, y) = glm::vec4(1000.0f + float((x * 31 + y * 17) % 97) * 0.01f, 0, 0, 1);
  const ImageTexture tex(img, false, false);
  const int x = 1777, y = 1901;
  const glm::dvec3 m = tex.boxMeanTexels(x, x + 1, y, y + 1);
  EXPECT_NEAR(m.x, img.at(x, y).x, 1e-6);
}

TEST(ImageTexture, FiniteForHostileInput) {
  ImageRGBA img = testImage(5, 5);
  img.at(2, 2) = glm::vec4(std::nanf(""), INFINITY, 1, 1);
  for (bool wrap : {false, true}) {
    const ImageTexture tex(img, wrap, !wrap);
    EXPECT_TRUE(finite(tex.sample({kNaN, 0.5}, {})));
    EXPECT_TRUE(finite(tex.sample({1e300, -1e300}, boxFootprint(0.1, 0.1))));
    EXPECT_TRUE(finite(tex.sample({0.5, 0.5}, boxFootprint(kInf, kNaN))));
    EXPECT_TRUE(finite(tex.sample({-7.5, 3.2}, boxFootprint(1e12, 1e-30))));
  }
  const ImageTexture empty(ImageRGBA{}, true, true);
  EXPECT_EQ(empty.sample({0.5, 0.5}, {}), glm::vec3(0.0f));
}

// ---------------------------------------------------------------------------------------------
TEST(NoiseTexture, AnalyticGradientMatchesCentralDifferences) {
  NoiseParams p;
  p.octaves = 5;
  p.frequency = 6.0;
  p.seed = 42;
  for (bool periodic : {false, true}) {
    p.periodicU = p.periodicV = periodic;
    const NoiseTexture noise(p);
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {
      const glm::dvec2 uv(0.013 + 0.0049 * k * 1.37, -0.4 + 0.0071 * k);
      const glm::dvec2 g = noise.gradient(uv);
      const double h = 1e-7;
      const glm::dvec2 fd((noise.value(uv + glm::dvec2(h, 0)) - noise.value(uv - glm::dvec2(h, 0))) / (2 * h),
                          (noise.value(uv + glm::dvec2(0, h)) - noise.value(uv - glm::dvec2(0, h))) / (2 * h));
      // Relative to the gradient's scale (amplitude times the highest frequency ~ 100).
      const double scale = std::max(1.0, glm::length(g));
      const double err = glm::length(g - fd) / scale;
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-5) << "k " << k;
    }
    RecordProperty(periodic ? "worst_rel_periodic" : "worst_rel", testing::PrintToString(worst));
  }
}

TEST(NoiseTexture, PeriodicNoiseMatchesAcrossTheSeam) {
  NoiseParams p;
  p.frequency = 5.3;  // rounded to 5 cells per period in u
  p.lacunarity = 2.1;
  p.periodicU = true;
  p.periodicV = true;
  p.periodV = 2.0;
  const NoiseTexture noise(p);
  for (double v : {0.0, 0.37, 1.91}) {
    EXPECT_NEAR(noise.value({0.0, v}), noise.value({1.0, v}), 1e-12);
    EXPECT_NEAR(noise.value({0.25, v}), noise.value({-0.75, v}), 1e-12);
    const glm::dvec2 g0 = noise.gradient({0.0, v}), g1 = noise.gradient({1.0, v});
    EXPECT_NEAR(g0.x, g1.x, 1e-9);
    EXPECT_NEAR(g0.y, g1.y, 1e-9);
  }
  EXPECT_NEAR(noise.value({0.3, 0.0}), noise.value({0.3, 2.0}), 1e-12);
  // Not periodic with period 1 in v.
  double differs = 0.0;
  for (double u : {0.1, 0.3, 0.6}) differs += std::fabs(noise.value({u, 0.5}) - noise.value({u, 1.5}));
  EXPECT_GT(differs, 1e-3);
}

TEST(NoiseTexture, RangeDeterminismAndHostileInput) {
  NoiseParams p;
  p.amplitude = 0.2;
  const NoiseTexture a(p), b(p);
  p.seed = 2;
  const NoiseTexture c(p);
  double maxAbs = 0.0, differs = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const glm::dvec2 uv(k * 0.00731, k * 0.00297);
    maxAbs = std::max(maxAbs, std::fabs(a.value(uv)));
    EXPECT_EQ(a.value(uv), b.value(uv));
    differs += std::fabs(a.value(uv) - c.value(uv));
  }
  EXPECT_LE(maxAbs, 0.2 + 1e-12);
  EXPECT_GT(maxAbs, 0.02);
  EXPECT_GT(differs, 1.0);
  EXPECT_EQ(a.value({kNaN, 0.0}), 0.0);
  EXPECT_EQ(a.gradient({0.0, kInf}), glm::dvec2(0.0));
  EXPECT_TRUE(std::isfinite(a.value({1e300, -1e300})));
  // Coordinates whose octaves overflow to infinity (1e308 times the frequencies): the cell index
  // was fmod(inf) = NaN converted to an integer (undefined); now cell 0, and the value finite.
  EXPECT_TRUE(std::isfinite(a.value({1.7e308, -1.7e308})));
  EXPECT_TRUE(std::isfinite(a.gradient({1.7e308, 1.7e308}).x));
  const glm::dvec2 g = a.gradient({1e18, 3e17});
  EXPECT_TRUE(std::isfinite(g.x) && std::isfinite(g.y));
}

// The batch (a footprint's samples, octave by octave, sharing each lattice cell's gradients)
// against the value-and-gradient pass point by point (its own loop, a cell per point and
// octave; value() itself is a batch of one): equal to the bit, for clustered points (most share cells),
// scattered ones, batches longer than the 64-point block, periodic and aperiodic noise, and
// hostile coordinates in between.
TEST(NoiseTexture, BatchEqualsPointByPointToTheBit) {
  for (const bool periodic : {false, true}) {
    NoiseParams p;
    p.octaves = 7;
    p.frequency = 9.0;
    p.periodicU = p.periodicV = periodic;
    p.periodU = 1.3;
    const NoiseTexture noise(p);
    std::vector<glm::dvec2> pts;
    for (int k = 0; k < 150; ++k) pts.push_back({0.31 + 1e-3 * (k % 13), -2.7 + 7e-4 * (k / 13)});  // one footprint
    for (int k = 0; k < 50; ++k) pts.push_back({std::sin(k * 12.9898) * 40.0, std::cos(k * 78.233) * 1e5});
    pts.push_back({-0.0, 0.37});
    pts.insert(pts.begin() + 70, {kNaN, 0.5});
    pts.insert(pts.begin() + 90, {0.25, kInf});
    pts.push_back({1e300, -1e300});
    std::vector<double> batch(pts.size());
    noise.values(pts.data(), int(pts.size()), batch.data());
    for (size_t k = 0; k < pts.size(); ++k) {
      glm::dvec2 g;
      const double one = noise.evaluate(pts[k], &g);
      EXPECT_EQ(std::memcmp(&batch[k], &one, sizeof one), 0) << k << " periodic " << periodic << ": " << batch[k] << " " << one;
    }
    EXPECT_EQ(batch[70], 0.0);
    // A batch in the cell (0, 0) of every octave: a cell kept from one octave to the next would
    // give the next octave's points the last one's gradients.
    const glm::dvec2 corner[3] = {{2e-4, 3e-4}, {5e-4, 1e-4}, {9e-4, 8e-4}};
    double cornerValues[3];
    noise.values(corner, 3, cornerValues);
    for (int k = 0; k < 3; ++k) {
      glm::dvec2 g;
      const double one = noise.evaluate(corner[k], &g);
      EXPECT_EQ(std::memcmp(&cornerValues[k], &one, sizeof one), 0) << k << " periodic " << periodic;
    }
  }
}

// ---------------------------------------------------------------------------------------------
TEST(RampTexture, MapsValuesThroughStopsAndAveragesFootprints) {
  auto constant = std::make_shared<ConstantScalar>(0.0);
  const RampTexture ramp(constant, {{1.0, glm::vec3(1, 1, 1)}, {0.0, glm::vec3(0, 0, 0)}, {0.5, glm::vec3(1, 0, 0)}},
                         -1.0, 1.0);
  EXPECT_EQ(ramp.colourAt(-5.0), glm::vec3(0.0f));
  EXPECT_EQ(ramp.colourAt(5.0), glm::vec3(1.0f));
  EXPECT_NEAR(ramp.colourAt(0.0).x, 1.0, 1e-6);   // t = 0.5: the red stop
  EXPECT_NEAR(ramp.colourAt(0.5).y, 0.5, 1e-6);   // t = 0.75: half-way red -> white
  EXPECT_NEAR(ramp.colourAt(-0.5).x, 0.5, 1e-6);  // t = 0.25: half-way black -> red
  EXPECT_NEAR(ramp.sample({0.3, 0.3}, boxFootprint(0.1, 0.1)).x, 1.0, 1e-6);

  // A rock: the footprint average against a 64x64 brute-force average of the same ramp.
  NoiseParams p;
  p.frequency = 4.0;
  p.octaves = 2;
  auto rock = std::make_shared<NoiseTexture>(p);
  const RampTexture rockRamp(rock, {{0.0, glm::vec3(0.2f)}, {1.0, glm::vec3(0.9f)}}, -0.5, 0.5, 8);
  auto point = [&](glm::dvec2 q) { return rockRamp.sample(q, {}); };
  const glm::dvec2 c(0.4, 0.6), half(0.01, 0.01);
  EXPECT_NEAR(rockRamp.sample(c, boxFootprint(0.02, 0.02)).x, bruteForceMean(point, c, half, 64).x, 1e-3);
  EXPECT_TRUE(finite(rockRamp.sample({kNaN, 0.1}, boxFootprint(kNaN, 0.1))));
}

// ---------------------------------------------------------------------------------------------
TEST(ImageHeight, BilinearLuminanceAndItsExactGradient) {
  ImageRGBA img(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      const float g = float((x * 5 + y * 3) % 7) / 7.0f;
      img.at(x, y) = glm::vec4(g, g, g, 1);  // grey: luminance = g
    }
  for (bool wrap : {false, true}) {
    const ImageHeight height(img, wrap, wrap, 2.0, 0.5);
    // Texel centre value.
    EXPECT_NEAR(height.value({(3 + 0.5) / 8, 1 - (2 + 0.5) / 6}), 0.5 + 2.0 * img.at(3, 2).x, 1e-6);
    // Gradient = central differences of value() inside cells (away from texel-centre lines,
    // where the bilinear derivative jumps).
    for (glm::dvec2 uv : {glm::dvec2(0.33, 0.41), glm::dvec2(0.71, 0.13), glm::dvec2(0.52, 0.77)}) {
      const glm::dvec2 g = height.gradient(uv);
      const double h = 1e-7;
      const double gu = (height.value(uv + glm::dvec2(h, 0)) - height.value(uv - glm::dvec2(h, 0))) / (2 * h);
      const double gv = (height.value(uv + glm::dvec2(0, h)) - height.value(uv - glm::dvec2(0, h))) / (2 * h);
      EXPECT_NEAR(g.x, gu, 1e-5 * std::max(1.0, std::fabs(gu)));
      EXPECT_NEAR(g.y, gv, 1e-5 * std::max(1.0, std::fabs(gv)));
    }
    EXPECT_TRUE(std::isfinite(height.value({kNaN, 0.0})));
    const glm::dvec2 g = height.gradient({1e300, kInf});
    EXPECT_TRUE(std::isfinite(g.x) && std::isfinite(g.y));
  }
}

TEST(ConstantScalar, IsFlat) {
  const ConstantScalar c(0.25);
  EXPECT_EQ(c.value({kNaN, 1.0}), 0.25);
  EXPECT_EQ(c.gradient({0.3, 0.3}), glm::dvec2(0.0));
  EXPECT_EQ(ConstantScalar(kNaN).value({0, 0}), 0.0);
}

}  // namespace
}  // namespace wf
