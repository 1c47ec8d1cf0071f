// Tests of the isotropic Phong model (paper §2.1) and of PhongMaterial::sanitized.
// Expected values are worked out by hand from the formula in phong.h:
//   I = kd (ambient + sum L max(0, N.l)) + ks sum L [N.l > 0] max(0, R.V)^n,  R = 2 (N.l) N - l.
#include "shading/phong.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace wf {
namespace {

using namespace wf::test;


TEST(PhongLobe, KnownValues) {
  // 0^0 := [x > 0]: exponent 0 is the indicator of a positive argument.
  EXPECT_EQ(phongLobe(0.5, 0.0), 1.0);
  EXPECT_EQ(phongLobe(0.0, 0.0), 0.0);
  EXPECT_EQ(phongLobe(-0.5, 0.0), 0.0);
  // max(0, x)^n: exact small powers (binary powering is exact to a few ulp).
  EXPECT_NEAR(phongLobe(0.5, 3.0), 0.125, 1e-16);
  EXPECT_NEAR(phongLobe(0.9, 1.0), 0.9, 1e-16);
  EXPECT_EQ(phongLobe(-0.9, 3.0), 0.0);
  EXPECT_EQ(phongLobe(std::nan(""), 2.0), 0.0);
  // Integer exponents up to 1024 go through binary powering, others through pow: both must agree
  // with pow to a few ulp (relative 1e-13 allows ~10 roundings per multiply chain of 10 steps).
  for (double x : {0.1, 0.5, 0.9, 0.999, 0.999999})
    for (double n : {2.0, 7.0, 20.0, 128.0, 1000.0, 1024.0, 1025.0, 20.5, 1e5, 1e6})
      EXPECT_NEAR(phongLobe(x, n), std::pow(x, n), 1e-13 * std::pow(x, n)) << x << "^" << n;
  // Argument above 1 (rounding of R.V) is clamped to 1.
  EXPECT_EQ(phongLobe(1.0 + 1e-15, 1e6), 1.0);
}

TEST(PhongRadiance, HandComputedSingleLight) {
  // N = V = z, light at 45 deg in the x-z plane: N.l = 1/sqrt2, R = (-1/sqrt2, 0, 1/sqrt2),
  // R.V = 1/sqrt2. I = kd (amb + L/sqrt2) + ks L (1/sqrt2)^n.
  PhongMaterial m;
  m.diffuse = glm::dvec3(0.6, 0.5, 0.4);
  m.specular = glm::dvec3(0.3, 0.2, 0.1);
  m.exponent = 8.0;
  LightRig rig;
  rig.ambient = glm::dvec3(0.1);
  rig.lights.push_back({glm::normalize(glm::dvec3(1, 0, 1)), glm::dvec3(2.0)});
  const double c = 1.0 / std::sqrt(2.0);
  const glm::dvec3 want = m.diffuse * (0.1 + 2.0 * c) + m.specular * (2.0 * std::pow(c, 8.0));
  const glm::dvec3 got = phongRadiance({0, 0, 1}, {0, 0, 1}, m, rig);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-14);
  // N and V need not be unit: scaled copies give the same value.
  const glm::dvec3 got2 = phongRadiance({0, 0, 7}, {0, 0, 0.25}, m, rig);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got2[i], want[i], 1e-14);
}

TEST(PhongRadiance, MirrorDirectionGivesFullHighlight) {
  // V the mirror of l about N: R = V, R.V = 1, the lobe is 1 for every exponent.
  PhongMaterial m;
  m.diffuse = glm::dvec3(0.0);
  m.specular = glm::dvec3(1.0);
  const glm::dvec3 N = glm::normalize(glm::dvec3(0.2, 0.3, 1.0));
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.5, -0.4, 0.8));
  const glm::dvec3 V = 2.0 * glm::dot(N, l) * N - l;
  LightRig rig;
  rig.lights.push_back({l, glm::dvec3(1.0)});
  for (double n : {0.0, 1.0, 100.0, 1e6}) {
    m.exponent = n;
    EXPECT_NEAR(phongRadiance(N, V, m, rig).x, 1.0, 1e-9 * std::max(1.0, n)) << n;
  }
}

TEST(PhongRadiance, LightBehindNormalContributesNothing) {
  // N.l <= 0: neither diffuse nor specular; only kd * ambient.
  PhongMaterial m;
  LightRig rig;
  rig.ambient = glm::dvec3(0.2);
  rig.lights.push_back({glm::normalize(glm::dvec3(0.3, 0.1, -1.0)), glm::dvec3(1.0)});
  rig.lights.push_back({glm::dvec3(1, 0, 0), glm::dvec3(1.0)});  // N.l = 0 exactly
  const glm::dvec3 got = phongRadiance({0, 0, 1}, {0, 0, 1}, m, rig);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], m.diffuse[i] * 0.2, 1e-16);
}

TEST(PhongRadiance, MatchesIndependentFormulaOnRandomInput) {
  // Random unit N, V and the studio rig against the formula written out here.
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  PhongMaterial m;
  m.diffuse = glm::dvec3(0.7, 0.5, 0.3);
  m.specular = glm::dvec3(0.2, 0.4, 0.6);
  m.exponent = 37.0;
  const LightRig rig = LightRig::studioRig(7).canonical();
  for (int k = 0; k < 1000; ++k) {
    const glm::dvec3 N = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const glm::dvec3 V = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    glm::dvec3 want = m.diffuse * rig.ambient;
    for (const DirectionalLight& l : rig.lights) {
      const double nl = glm::dot(N, l.direction);
      if (nl <= 0) continue;
      const double rv = glm::dot(2.0 * nl * N - l.direction, V);
      want += l.intensity * (m.diffuse * nl + m.specular * (rv > 0 ? std::pow(rv, 37.0) : 0.0));
    }
    const glm::dvec3 got = phongRadiance(N, V, m, rig);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-13);
  }
}

TEST(PhongMaterialSanitized, ClampsEveryField) {
  PhongMaterial m;
  m.diffuse = glm::dvec3(std::nan(""), -1.0, 0.5);
  m.specular = glm::dvec3(INFINITY, 0.25, -INFINITY);
  auto withN = [&](double n) {
    PhongMaterial c = m;
    c.exponent = n;
    return c.sanitized();
  };
  const PhongMaterial s = withN(20.0);
  // Non-finite or negative colour components -> 0, others unchanged.
  EXPECT_EQ(s.diffuse, glm::dvec3(0.0, 0.0, 0.5));
  EXPECT_EQ(s.specular, glm::dvec3(0.0, 0.25, 0.0));
  // Exponent: NaN -> 1, negative -> 0, > 1e6 -> 1e6, in range unchanged (phong.h).
  EXPECT_EQ(withN(std::nan("")).exponent, 1.0);
  EXPECT_EQ(withN(-3.0).exponent, 0.0);
  EXPECT_EQ(withN(-INFINITY).exponent, 0.0);
  EXPECT_EQ(withN(1e9).exponent, kMaxPhongExponent);
  EXPECT_EQ(withN(INFINITY).exponent, kMaxPhongExponent);
  EXPECT_EQ(withN(0.0).exponent, 0.0);
  EXPECT_EQ(withN(1e5).exponent, 1e5);
  EXPECT_EQ(withN(20.0).exponent, 20.0);
  // Idempotent.
  EXPECT_EQ(s.sanitized(), s);
}

TEST(PhongExtremes, FiniteNonNegativeOnDegenerateInput) {
  // Contract: canonical rig; any N, V. Zero or non-finite N or V gives the ambient term alone.
  const double nan = std::nan(""), inf = INFINITY;
  LightRig raw = LightRig::studioRig(7);
  raw.lights.push_back({{nan, 0, 1}, glm::dvec3(1)});   // dropped by canonical
  raw.lights.push_back({{0, 0, 0}, glm::dvec3(1)});     // dropped by canonical
  raw.lights.push_back({{0, 0, -1}, glm::dvec3(0.5)});  // behind the viewer
  const LightRig rig = raw.canonical();
  const glm::dvec3 normals[] = {{0, 0, 1},  {0, 0, -1}, {1e-12, 0, 1}, {1, 1, 1e-12}, {0, 0, 0},
                                {nan, 0, 1}, {inf, 0, 0}, {1e-310, 0, 0}, {1e300, 1e300, 0}};
  const glm::dvec3 views[] = {{0, 0, 1}, {0.3, -0.2, 0.9}, {0, 0, 0}, {0, nan, 1}, {0, 0, -inf}};
  for (double n : {0.0, 1.0, 1e5, nan, -3.0, 1e9}) {
    PhongMaterial pm;
    pm.exponent = n;
    const PhongMaterial m = pm.sanitized();
    for (const glm::dvec3& N : normals)
      for (const glm::dvec3& V : views) {
        const glm::dvec3 c = phongRadiance(N, V, m, rig);
        EXPECT_TRUE(finite3(c) && c.x >= 0 && c.y >= 0 && c.z >= 0) << "n=" << n;
        const double ln = glm::length(N), lv = glm::length(V);
        const bool degenerate = !(ln > 0) || !std::isfinite(ln) || !(lv > 0) || !std::isfinite(lv);
        if (degenerate) {
          // Ambient alone, exactly.
          EXPECT_EQ(c, m.diffuse * rig.ambient);
        }
      }
  }
}

}  // namespace
}  // namespace wf
