// Tests of LightRig: canonical form (what every shading routine assumes), nearlyEqual (which
// decides map rebuilds), transformed, and the studio rig used by the pictures and the accuracy
// study.
#include "shading/light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace wf {
namespace {

TEST(LightRigCanonical, DropsUndefinedAndDarkLightsAndNormalises) {
  const double nan = std::nan(""), inf = INFINITY;
  LightRig r;
  r.ambient = glm::dvec3(nan, -0.5, 0.25);
  r.lights = {{{0, 0, 2}, glm::dvec3(1.0)},              // kept, normalised to (0,0,1)
              {{nan, 0, 1}, glm::dvec3(1.0)},            // NaN direction: dropped
              {{0, 0, 0}, glm::dvec3(1.0)},              // zero direction: dropped
              {{inf, 0, 0}, glm::dvec3(1.0)},            // Inf direction: dropped
              {{1e-310, 0, 0}, glm::dvec3(1.0)},         // no usable length: dropped
              {{3, 4, 0}, glm::dvec3(0.0)},              // dark: dropped
              {{3, 4, 0}, glm::dvec3(-1.0, nan, -inf)},  // all components clamp to 0: dropped
              {{0, 3, 4}, glm::dvec3(inf, 0.5, -2.0)}};  // kept with intensity (0, 0.5, 0)
  const LightRig c = r.canonical();
  EXPECT_EQ(c.ambient, glm::dvec3(0.0, 0.0, 0.25));
  ASSERT_EQ(c.lights.size(), 2u);
  EXPECT_NEAR(c.lights[0].direction.z, 1.0, 1e-16);
  EXPECT_EQ(c.lights[0].intensity, glm::dvec3(1.0));
  // (0,3,4)/5 exactly up to rounding.
  EXPECT_NEAR(c.lights[1].direction.y, 0.6, 1e-16);
  EXPECT_NEAR(c.lights[1].direction.z, 0.8, 1e-16);
  EXPECT_EQ(c.lights[1].intensity, glm::dvec3(0.0, 0.5, 0.0));
  // Idempotent (to rounding of re-normalising a unit vector).
  EXPECT_TRUE(c.canonical().nearlyEqual(c, 1e-15));
}

TEST(LightRigNearlyEqual, ToleranceAndStructure) {
  const LightRig a = LightRig::studioRig(7);
  LightRig b = a;
  EXPECT_TRUE(a.nearlyEqual(b));
  b.lights[3].direction.x += 1e-15;  // below the default 1e-12
  EXPECT_TRUE(a.nearlyEqual(b));
  b.lights[3].direction.x += 1e-9;   // above it
  EXPECT_FALSE(a.nearlyEqual(b));
  EXPECT_TRUE(a.nearlyEqual(b, 1e-8));
  LightRig c = a;
  c.ambient.y += 1e-6;
  EXPECT_FALSE(a.nearlyEqual(c));
  LightRig d = a;
  d.lights.pop_back();  // different number of lights
  EXPECT_FALSE(a.nearlyEqual(d));
}

TEST(LightRigTransformed, RotatesDirectionsOnly) {
  const double t = 0.7;
  const glm::dmat3 rz(std::cos(t), std::sin(t), 0, -std::sin(t), std::cos(t), 0, 0, 0, 1);
  const LightRig a = LightRig::studioRig(3);
  const LightRig b = a.transformed(rz);
  ASSERT_EQ(b.lights.size(), 3u);
  EXPECT_EQ(b.ambient, a.ambient);
  for (size_t i = 0; i < 3; ++i) {
    const glm::dvec3 d = a.lights[i].direction;
    // Column-major glm: rz * d rotates by +t about z.
    const glm::dvec3 want(std::cos(t) * d.x - std::sin(t) * d.y, std::sin(t) * d.x + std::cos(t) * d.y, d.z);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.lights[i].direction[k], want[k], 1e-15);
    EXPECT_EQ(b.lights[i].intensity, a.lights[i].intensity);
  }
  // And back: the same eye-space rig within rounding (what map updates rely on).
  EXPECT_TRUE(b.transformed(glm::transpose(rz)).nearlyEqual(a, 1e-15));
}

TEST(LightRigStudio, PaperSevenLightSetUp) {
  for (int count = 1; count <= 7; ++count) {
    const LightRig r = LightRig::studioRig(count);
    ASSERT_EQ(int(r.lights.size()), count);
    glm::dvec3 total(0.0);
    for (const DirectionalLight& l : r.lights) {
      EXPECT_NEAR(glm::length(l.direction), 1.0, 1e-15);  // unit
      total += l.intensity;
    }
    // Header: total intensity ~1 split over the lights (0.95 times tints <= 1, >= 0.85).
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(total[k], 1.0 + 1e-12);
      EXPECT_GE(total[k], 0.8);
    }
    EXPECT_GT(r.ambient.x, 0.0);  // "plus a little ambient"
    // Already canonical.
    EXPECT_TRUE(r.canonical().nearlyEqual(r, 1e-15));
  }
  // The seven-light rig has a light behind the subject (l.V < 0 for V = +z).
  int behind = 0;
  for (const DirectionalLight& l : LightRig::studioRig(7).lights) behind += l.direction.z < 0;
  EXPECT_GE(behind, 1);
  // Out-of-range counts clamp to 1 ... 7.
  EXPECT_EQ(LightRig::studioRig(0).lights.size(), 1u);
  EXPECT_EQ(LightRig::studioRig(99).lights.size(), 7u);
}

}  // namespace
}  // namespace wf
