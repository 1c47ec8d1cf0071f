// Bump mapping (Blinn 1978) against the true normal of the explicitly displaced surface.
#include "texture/bump.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

namespace wf {
namespace {

using SurfaceFn = std::function<glm::dvec3(double, double)>;

/// Unit normal of f by central differences, oriented like fu x fv.
glm::dvec3 finiteDifferenceNormal(const SurfaceFn& f, double u, double v, double h) {
  const glm::dvec3 fu = (f(u + h, v) - f(u - h, v)) / (2 * h);
  const glm::dvec3 fv = (f(u, v + h) - f(u, v - h)) / (2 * h);
  return glm::normalize(glm::cross(fu, fv));
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

TEST(BumpNormal, PlaneMatchesTheDisplacedSurface) {
  // S = (2u, 3v + 0.5u, 0) (skewed, unequal speeds), h = sin(5u) cos(3v) / 4, scale 0.7; the
  // plane's normal is constant so Blinn's formula is exact: tolerance is the finite-difference
  // error (h = 1e-5: ~1e-9 rad).
  const double scale = 0.7;
  auto height = [](double u, double v) { return std::sin(5 * u) * std::cos(3 * v) / 4; };
  auto grad = [](double u, double v) {
    return glm::dvec2(5 * std::cos(5 * u) * std::cos(3 * v) / 4, -3 * std::sin(5 * u) * std::sin(3 * v) / 4);
  };
  const glm::dvec3 Su(2, 0.5, 0), Sv(0, 3, 0), N(0, 0, 1);
  SurfaceFn displaced = [&](double u, double v) {
    return u * Su + v * Sv + scale * height(u, v) * N;
  };
  double worst = 0.0;
  for (double u : {0.1, 0.4, 0.77})
    for (double v : {0.05, 0.5, 0.9}) {
      const glm::dvec3 expected = finiteDifferenceNormal(displaced, u, v, 1e-5);
      const glm::dvec3 bumped = bumpNormal(N, Su, Sv, grad(u, v), scale);
      worst = std::max(worst, angleBetween(expected, bumped));
      EXPECT_LT(angleBetween(expected, bumped), 1e-7);
      EXPECT_NEAR(glm::length(bumped), 1.0, 1e-12);
      // A normal given against the parametric orientation (reversed face) gets the reversed
      // displaced normal (the surface displaced along -N, oriented like -N).
      SurfaceFn reversed = [&](double uu, double vv) {
        return uu * Su + vv * Sv - scale * height(uu, vv) * N;
      };
      const glm::dvec3 flipped = bumpNormal(-N, Su, Sv, grad(u, v), scale);
      EXPECT_LT(angleBetween(-finiteDifferenceNormal(reversed, u, v, 1e-5), flipped), 1e-7);
    }
  RecordProperty("worst_angle_plane", testing::PrintToString(worst));
}

TEST(BumpNormal, SphereMatchesTheDisplacedSurfaceToFirstOrder) {
  // Unit sphere (u longitude, v latitude in (-pi/2, pi/2)), h = A sin(12 u) sin(9 v) with
  // A = 1e-3: the gradient tilts the normal by ~0.01 rad while the dropped term h dn/du is of
  // relative size h / R <= 1e-3; tolerance 3e-3 rad.
  const double A = 1e-3, scale = 1.0;
  auto S = [](double u, double v) {
    return glm::dvec3(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
  };
  auto height = [&](double u, double v) { return A * std::sin(12 * u) * std::sin(9 * v); };
  SurfaceFn displaced = [&](double u, double v) { return S(u, v) * (1.0 + scale * height(u, v)); };
  double worst = 0.0, tilt = 0.0;
  for (double u : {0.3, 1.1, 2.5, 4.0})
    for (double v : {-1.2, -0.4, 0.2, 0.9}) {
      const glm::dvec3 P = S(u, v);
      const glm::dvec3 Su(-std::cos(v) * std::sin(u), std::cos(v) * std::cos(u), 0.0);
      const glm::dvec3 Sv(-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v));
      const glm::dvec3 N = P;  // outward = Su x Sv / |Su x Sv|
      const glm::dvec2 g(12 * A * std::cos(12 * u) * std::sin(9 * v), 9 * A * std::sin(12 * u) * std::cos(9 * v));
      const glm::dvec3 expected = finiteDifferenceNormal(displaced, u, v, 1e-6);
      const glm::dvec3 bumped = bumpNormal(N, Su, Sv, g, scale);
      worst = std::max(worst, angleBetween(expected, bumped));
      tilt = std::max(tilt, angleBetween(N, bumped));
      EXPECT_LT(angleBetween(expected, bumped), 3e-3);
    }
  RecordProperty("worst_angle_sphere", testing::PrintToString(worst));
  EXPECT_GT(tilt, 5e-3);  // the bumps do tilt the normal: the test can see a sign error
}

TEST(BumpNormal, ZeroGradientAndDegenerateDerivativesKeepN) {
  const glm::dvec3 N = glm::normalize(glm::dvec3(0.2, -0.3, 1.0));
  const glm::dvec3 Su(1, 0, 0.2), Sv(0, 1, 0.3);
  EXPECT_EQ(bumpNormal(N, Su, Sv, {0.0, 0.0}, 5.0), N);
  EXPECT_LT(glm::length(bumpNormal(3.0 * N, Su, Sv, {0.0, 0.0}, 5.0) - N), 1e-15);
  // A pole: Su = 0.
  EXPECT_EQ(bumpNormal(N, glm::dvec3(0.0), Sv, {0.5, 0.5}, 1.0), N);
  // Parallel derivatives.
  EXPECT_EQ(bumpNormal(N, Su, 2.0 * Su, {0.5, 0.5}, 1.0), N);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(bumpNormal(N, Su, Sv, {nan, 0.5}, 1.0), N);
  EXPECT_EQ(bumpNormal(N, Su, glm::dvec3(nan), {0.5, 0.5}, 1.0), N);
  const glm::dvec3 fallback = bumpNormal(glm::dvec3(nan), glm::dvec3(0.0), glm::dvec3(0.0), {1, 1}, 1);
  EXPECT_EQ(fallback, glm::dvec3(0, 0, 1));
  // Huge gradients stay unit and finite.
  const glm::dvec3 steep = bumpNormal(N, Su, Sv, {1e300, -1e300}, 1e10);
  EXPECT_TRUE(std::isfinite(steep.x) && std::isfinite(steep.y) && std::isfinite(steep.z));
}

}  // namespace
}  // namespace wf
