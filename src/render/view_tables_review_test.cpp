// Review tests of ViewGrid at the extremes the CLI allows (--view-grid 1 ... 16, images from
// 1 x 1 to 16384 wide). No bug found here: these document what was checked.
#include "render/view_tables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace wf {
namespace {

// One node (the view axis) is the same grid at any image size, so the tables of a full-size frame
// serve its reduced frames (vtkWireFurRenderPass's image reduction) and back; a grid of several
// nodes over the image is not.
TEST(ViewTablesReview, OneNodeIsTheSameGridAtAnySize) {
  Camera c;
  c.fovYDegrees = 30;
  EXPECT_TRUE(ViewGrid(ViewTransform::make(c, 800, 600), 1).sameAs(ViewGrid(ViewTransform::make(c, 400, 300), 1)));
  EXPECT_FALSE(ViewGrid(ViewTransform::make(c, 800, 600), 3).sameAs(ViewGrid(ViewTransform::make(c, 400, 300), 3)));
  EXPECT_TRUE(ViewGrid(ViewTransform::make(c, 800, 600), 3).sameAs(ViewGrid(ViewTransform::make(c, 800, 600), 3)));
}

TEST(ViewTablesReview, CornersValidForEveryGridAndTinyOrHugeImages) {
  for (int n = 1; n <= 16; ++n)
    for (auto [w, h] : {std::pair{1, 1}, std::pair{1, 7}, std::pair{3000, 3000}, std::pair{16384, 1}}) {
      Camera c;
      c.fovYDegrees = 60;
      const ViewTransform v = ViewTransform::make(c, w, h);
      const ViewGrid g(v, n);
      ASSERT_EQ(g.size(), n);
      for (int k = 0; k < g.nodes(); ++k) {
        const glm::dmat3 R = g.frameFromEye(k);
        const glm::dmat3 I = glm::transpose(R) * R;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) ASSERT_NEAR(I[a][b], a == b ? 1.0 : 0.0, 1e-12) << n << " " << w << "x" << h;
      }
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (double x : {-1e9, 0.0, 0.5 * w, double(w), 1e9, nan})
        for (double y : {-1e9, 0.0, 0.5 * h, double(h), 1e9, nan}) {
          int node[4];
          double wt[4];
          g.corners(x, y, node, wt);
          double sum = 0;
          for (int q = 0; q < 4; ++q) {
            ASSERT_GE(wt[q], 0.0);
            if (wt[q] > 0) {
              ASSERT_GE(node[q], 0);
              ASSERT_LT(node[q], g.nodes());
            }
            sum += wt[q];
          }
          ASSERT_NEAR(sum, 1.0, 1e-12);
        }
    }
}

TEST(ViewTablesReview, CentreNodeOfOddGridIsTheViewAxis) {
  Camera c;
  const ViewTransform v = ViewTransform::make(c, 33, 33);
  const ViewGrid g(v, 3);
  const glm::dmat3 R = g.frameFromEye(4);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(R[a][b], a == b ? 1.0 : 0.0, 1e-12);
  // A corner node's frame takes its own view vector to +z.
  const glm::dvec3 p = v.eyePoint(33 * 0.5 / 3, 33 * 0.5 / 3, 1.0);
  const glm::dvec3 z = g.frameFromEye(0) * v.viewVector(p);
  EXPECT_NEAR(z.z, 1.0, 1e-12);
}

TEST(ViewTablesReview, OrthographicAlwaysOneNode) {
  Camera c;
  c.projection = Camera::Projection::Orthographic;
  const ViewGrid g(ViewTransform::make(c, 10, 10), 16);
  EXPECT_EQ(g.nodes(), 1);
}

}  // namespace
}  // namespace wf
