// The closed form of the cylinder-averaged Phong model (shading/cylinder_lobe.h) against the
// quadrature over the cylinder's normals (cylinderSpecularQuadrature, cylinderRadianceExact),
// against closed forms of its one-variable factor, and on the stiff cases.
#include "shading/cylinder_lobe.h"
#include "shading/cylinder_shading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace wf {
namespace {

glm::dvec3 randomUnit(std::mt19937_64& g) {
  std::normal_distribution<double> N(0.0, 1.0);
  for (;;) {
    const glm::dvec3 v(N(g), N(g), N(g));
    if (glm::length(v) > 1e-3) return glm::normalize(v);
  }
}

double maxAbs(const glm::dvec3& d) { return std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}); }

// The specular factor of one light: closed form (exact G) against the quadrature over theta, at
// random T, V, l and exponents from 0 to 1e5, including T within 1e-6 of V, l within 1e-6 of T,
// and grazing views (V nearly across T). Tolerance 1e-9 absolute (the factor is at most 1).
TEST(CylinderLobe, SpecularMatchesTheQuadratureOverTheNormals) {
  std::mt19937_64 g(7);
  double worst = 0.0;
  for (double n : {0.0, 1.0, 3.7, 20.0, 128.0, 1000.0, 1e4, 1e5}) {
    for (int it = 0; it < 400; ++it) {
      glm::dvec3 T = randomUnit(g), V = randomUnit(g), l = randomUnit(g);
      if (it % 8 == 1) V = glm::normalize(T + 1e-6 * randomUnit(g));        // nearly end-on
      if (it % 8 == 2) l = glm::normalize(T + 1e-6 * randomUnit(g));        // light along the axis
      if (it % 8 == 3) V = glm::normalize(glm::cross(T, randomUnit(g)));    // V across T
      if (it % 8 == 4) l = glm::normalize(-glm::reflect(V, T) + 1e-3 * randomUnit(g));  // on the highlight
      const CylinderFrame fr = cylinderFrame(T, V);
      if (fr.endOn) continue;
      const double a = glm::dot(fr.e1, l), b = glm::dot(fr.e2, l), q = glm::dot(l, V);
      const double ref = cylinderSpecularQuadrature(a, b, q, fr.v, n, 1e-12);
      const double got = cylinderSpecularClosedForm(a, b, glm::dot(T, l), glm::dot(T, V), fr.v, n, nullptr);
      worst = std::max(worst, std::abs(got - ref));
      ASSERT_NEAR(got, ref, 1e-9) << "n " << n << " it " << it;
    }
  }
  RecordProperty("worst", std::to_string(worst));
}

// F_n's closed forms: n = 0 (y), n = 1 (y - y^3/3), n = 2 (y - 2y^3/3 + y^5/5); F_n(1) =
// sqrt(pi) Gamma(n+1) / (2 Gamma(n+3/2)) for integer and non-integer n up to 1e6.
TEST(CylinderLobe, FactorMatchesClosedForms) {
  for (double y : {1e-9, 1e-3, 0.1, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(lobeFactorExact(0.0, y), 1.0, 1e-15);
    EXPECT_NEAR(lobeFactorExact(1.0, y), 1.0 - y * y / 3.0, 1e-14);
    EXPECT_NEAR(lobeFactorExact(2.0, y), 1.0 - 2.0 * y * y / 3.0 + std::pow(y, 4) / 5.0, 1e-14);
    // The adaptive quadrature agrees with the recurrence (integer exponents up to 32).
    EXPECT_NEAR(lobeIntegral(2.0, 0.0, y) / y, lobeFactorExact(2.0, y), 1e-13);
  }
  // Above 32, the exact factor's fixed Gauss-Legendre rules against the adaptive quadrature.
  for (double n : {32.5, 33.0, 40.5, 100.0, 257.0, 1000.0, 7777.7, 1e5, 1e6})
    for (int i = 0; i <= 200; ++i) {
      const double y = std::pow(10.0, -5.0 + 5.0 * i / 200.0);
      const double ref = lobeIntegral(n, 0.0, y) / y;
      EXPECT_NEAR(lobeFactorExact(n, y) / ref, 1.0, 1e-13) << n << " " << y;
    }
  for (double n : {0.5, 3.7, 20.0, 255.0, 256.0, 257.0, 1000.0, 1e5, 1e6}) {
    const double f1 = std::sqrt(std::acos(-1.0)) / 2.0 * std::exp(std::lgamma(n + 1.0) - std::lgamma(n + 1.5));
    // lgamma's own rounding: 1e-16 of its value, which exp() turns into a relative error.
    const double tol = 1e-12 + 4e-16 * std::lgamma(n + 1.5);
    EXPECT_NEAR(lobeFactorExact(n, 1.0) / f1, 1.0, tol) << n;
    EXPECT_NEAR(lobeFactorExact(n, 4.0) / (f1 / 4.0), 1.0, tol) << n;  // beyond 1: F_n(1) / y
  }
  // Undefined and extreme arguments: defined values.
  EXPECT_EQ(lobeFactorExact(20.0, 0.0), 1.0);
  EXPECT_EQ(lobeFactorExact(20.0, -1.0), 1.0);
  EXPECT_EQ(lobeFactorExact(20.0, NAN), 1.0);
  EXPECT_EQ(lobeFactorExact(20.0, INFINITY), 0.0);
  EXPECT_TRUE(std::isfinite(lobeFactorExact(NAN, 0.5)));
  EXPECT_TRUE(std::isfinite(lobeFactorExact(1e300, 0.5)));
}

// The table against the exact factor on a fine grid of y (not only where it measured itself),
// densest just below y = 1 where non-integer exponents below 4 have a weak singularity, for
// exponents 0 ... 1e6 on both node layouts: within 4e-9, and its measured error bounds it.
TEST(CylinderLobe, TableMatchesTheExactFactorEverywhere) {
  for (double n : {0.0, 1e-300, 0.01, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.7, 3.999, 4.0, 4.5, 20.0, 128.0, 1000.0, 1e5, 1e6}) {
    const CylinderLobeTable t(n);
    EXPECT_LT(t.measuredError(), 4e-9) << n;
    double worst = 0.0;
    for (int i = 0; i <= 4000; ++i) {
      const double y = std::pow(10.0, -6.0 + 6.5 * i / 4000.0);  // 1e-6 ... 3.2
      worst = std::max(worst, std::abs(t.factor(y) - lobeFactorExact(n, y)));
      const double below = 1.0 - std::pow(10.0, -9.0 + 8.0 * i / 4000.0);  // 1 - 1e-9 ... 0.9
      worst = std::max(worst, std::abs(t.factor(below) - lobeFactorExact(n, below)));
    }
    EXPECT_LT(worst, 4e-9) << n;
    EXPECT_LE(worst, t.measuredError() + 1e-15) << n;
    EXPECT_EQ(t.factor(0.0), 1.0);
    EXPECT_EQ(t.factor(NAN), 1.0);
    EXPECT_EQ(t.factor(INFINITY), 0.0);
  }
}

// The whole model, table path, against the quadrature reference for 7 lights and coloured
// materials: within the table's measured error times the lights' specular sum.
TEST(CylinderLobe, RadianceMatchesTheReferenceWithinTheTableBound) {
  std::mt19937_64 g(11);
  const LightRig rig = LightRig::studioRig(7).canonical();
  double lightSum = 0.0;
  for (const DirectionalLight& l : rig.lights) lightSum += std::max({l.intensity.x, l.intensity.y, l.intensity.z});
  for (double n : {1.0, 20.0, 77.5, 1000.0, 1e5}) {
    PhongMaterial m;
    m.diffuse = glm::dvec3(0.5, 0.3, 0.1);
    m.specular = glm::dvec3(0.9, 0.8, 0.6);
    m.exponent = n;
    const CylinderLobeTable t(n);
    const double bound = t.measuredError() * lightSum * 0.9 + 1e-12;
    for (int it = 0; it < 200; ++it) {
      const glm::dvec3 T = randomUnit(g), V = randomUnit(g);
      const glm::dvec3 ref = cylinderRadianceExact(T, V, m, rig, 1e-12);
      EXPECT_LE(maxAbs(cylinderRadianceClosed(T, V, m, rig, &t) - ref), bound) << n;
      EXPECT_LE(maxAbs(cylinderRadianceClosed(T, V, m, rig, nullptr) - ref), 1e-11) << n;
    }
  }
}

// Stiff and undefined input: end-on, zero, NaN and Inf vectors give what the reference gives;
// the scale of T and V does not matter (1e-6 ... 1e6); a table of another exponent is not used.
TEST(CylinderLobe, StiffAndUndefinedInputAsTheReference) {
  const LightRig rig = LightRig::studioRig(3).canonical();
  PhongMaterial m;
  m.exponent = 1e5;
  const CylinderLobeTable t(m.exponent);
  const glm::dvec3 T(0.3, -0.5, 0.8);
  for (const glm::dvec3& V : {glm::dvec3(0, 0, 1), T, -T, glm::dvec3(0.0), glm::dvec3(NAN, 0, 1), glm::dvec3(INFINITY, 0, 0),
                              glm::normalize(T) + glm::dvec3(1e-12, 0, 0)}) {
    const glm::dvec3 ref = cylinderRadianceExact(T, V, m, rig);
    const glm::dvec3 got = cylinderRadianceClosed(T, V, m, rig, &t);
    EXPECT_TRUE(std::isfinite(got.x + got.y + got.z));
    EXPECT_LE(maxAbs(got - ref), 1e-9);
  }
  const glm::dvec3 V(0.1, 0.2, 1.0);
  const glm::dvec3 one = cylinderRadianceClosed(T, V, m, rig, &t);
  for (double s : {1e-6, 1e6})
    EXPECT_LE(maxAbs(cylinderRadianceClosed(s * T, s * V, m, rig, &t) - one), 1e-12) << s;
  const CylinderLobeTable other(20.0);
  EXPECT_EQ(cylinderRadianceClosed(T, V, m, rig, &other), cylinderRadianceClosed(T, V, m, rig, nullptr));
}

}  // namespace
}  // namespace wf
