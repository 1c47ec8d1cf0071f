// Cameras: the view transform's round trips and the automatic framing, against geometry.
#include "render/camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

// project(eyePoint(x, y, d)) = (x, y) and depthFromKey(depthKey(d)) = d, for both projections.
TEST(Camera, ScreenAndEyeSpaceRoundTrip) {
  for (auto projection : {Camera::Projection::Perspective, Camera::Projection::Orthographic}) {
    Camera c;
    c.projection = projection;
    c.eye = {1, -4, 2};
    c.target = {0.2, 0.1, -0.3};
    c.up = {0, 0, 1};
    c.nearPlane = 0.1;
    c.farPlane = 100;
    const ViewTransform v = ViewTransform::make(c, 320, 200);
    for (double x : {0.0, 17.3, 160.0, 319.9})
      for (double y : {0.0, 99.5, 199.0})
        for (double d : {0.5, 3.0, 70.0}) {
          const glm::dvec3 p = v.eyePoint(x, y, d);
          const glm::dvec2 s = v.project(p);
          EXPECT_NEAR(s.x, x, 1e-9);
          EXPECT_NEAR(s.y, y, 1e-9);
          EXPECT_NEAR(-p.z, d, 1e-12);
          EXPECT_NEAR(v.depthFromKey(v.depthKey(d)), d, 1e-12 * d);
          // The wire set-up's projection: the same point, and pixelsPerWorld at its depth.
          double scale = 0;
          const glm::dvec2 q = v.projectScaled(p, scale);
          EXPECT_NEAR(q.x, x, 1e-9);
          EXPECT_NEAR(q.y, y, 1e-9);
          EXPECT_EQ(scale, v.pixelsPerWorld(-p.z));  // the same division
        }
    // The target projects to the image centre; the eye-from-world rotation is orthonormal.
    const glm::dvec2 t = v.project(v.toEye(c.target));
    EXPECT_NEAR(t.x, 160.0, 1e-9);
    EXPECT_NEAR(t.y, 100.0, 1e-9);
    const glm::dmat3 R = v.eyeFromWorld;
    const glm::dmat3 I = R * glm::transpose(R);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(I[i][j], i == j ? 1.0 : 0.0, 1e-12);
  }
}

// frameSphere: the whole sphere is inside the image and fills the smaller side (within the
// 8% margin), at any scale.
TEST(Camera, FrameSphereFitsTheSphereAtAnyScale) {
  for (double scale : {1e-6, 1.0, 1e6})
    for (auto projection : {Camera::Projection::Perspective, Camera::Projection::Orthographic}) {
      const glm::dvec3 centre = glm::dvec3(3, -2, 5) * scale;
      const double r = 2.0 * scale;
      const Camera c = frameSphere(centre, r, 640.0 / 480.0, projection);
      EXPECT_TRUE(c.problem().empty()) << c.problem();
      const ViewTransform v = ViewTransform::make(c, 640, 480);
      // The sphere's silhouette: sample its points and project.
      double ymin = 1e300, ymax = -1e300, xmin = 1e300, xmax = -1e300;
      for (int i = 0; i < 64; ++i)
        for (int j = 0; j <= 32; ++j) {
          const double a = 2 * M_PI * i / 64, b = M_PI * j / 32;
          const glm::dvec3 p = centre + r * glm::dvec3(std::sin(b) * std::cos(a), std::sin(b) * std::sin(a), std::cos(b));
          const glm::dvec3 e = v.toEye(p);
          ASSERT_GT(-e.z, c.nearPlane);
          ASSERT_LT(-e.z, c.farPlane);
          const glm::dvec2 s = v.project(e);
          xmin = std::min(xmin, s.x), xmax = std::max(xmax, s.x), ymin = std::min(ymin, s.y), ymax = std::max(ymax, s.y);
        }
      EXPECT_GE(xmin, 0.0);
      EXPECT_LE(xmax, 640.0);
      EXPECT_GE(ymin, 0.0);
      EXPECT_LE(ymax, 480.0);
      EXPECT_GT(ymax - ymin, 0.85 * 480) << "fills the height (scale " << scale << ")";
    }
}

TEST(Camera, ProblemsAreReported) {
  Camera c;
  EXPECT_TRUE(c.problem().empty());
  c.target = c.eye;
  EXPECT_FALSE(c.problem().empty());
  c = Camera{};
  c.up = glm::normalize(c.eye - c.target);
  EXPECT_FALSE(c.problem().empty());
  c = Camera{};
  c.fovYDegrees = 180;
  EXPECT_FALSE(c.problem().empty());
  c = Camera{};
  c.nearPlane = 2, c.farPlane = 1;
  EXPECT_FALSE(c.problem().empty());
  c = Camera{};
  c.eye.x = NAN;
  EXPECT_FALSE(c.problem().empty());
}

}  // namespace
}  // namespace wf
