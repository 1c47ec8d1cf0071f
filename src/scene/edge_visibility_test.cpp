// wf::splitByVisibility (scene/edge_visibility.h) against closed forms: a segment behind a
// square, in perspective and orthographic views, is hidden exactly where its projection
// through the eye falls on the square; an edge lying on the square's own triangles is seen.
#include "scene/edge_visibility.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

// A square [-0.5, 0.5]^2 at z = 0 facing +z, two triangles.
Scene squareScene(bool perspective) {
  Scene s;
  SceneSurface q;
  q.mesh.positions = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
  q.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.surfaces.push_back(q);
  Camera c;
  c.eye = {0, 0, 5};
  c.target = {0, 0, 0};
  c.projection = perspective ? Camera::Projection::Perspective : Camera::Projection::Orthographic;
  c.orthoHeight = 4;
  c.nearPlane = 0.1, c.farPlane = 100;
  s.camera = c;
  return s;
}

PolylineSet segment(glm::dvec3 a, glm::dvec3 b) {
  PolylineSet l;
  l.add({a, b});
  return l;
}

}  // namespace

// Perspective, eye at z = 5: the point (x, 0.1, -1) is seen through z = 0 at x * 5/6, so it is
// hidden for |x| <= 0.6; the split points lie there to 1e-4 (the bisection's 1e-3 px at
// about 200 px per unit). Orthographic: hidden for |x| <= 0.5. Three pieces: seen, hidden, seen.
TEST(EdgeVisibility, SegmentBehindASquare) {
  for (bool perspective : {true, false}) {
    const Scene s = squareScene(perspective);
    const OcclusionGrid grid(s, *s.camera, 640, 480);
    VisibilityStats st;
    const VisibleLines v = splitByVisibility(segment({-2, 0.1, -1}, {2, 0.1, -1}), grid, {}, st);
    ASSERT_EQ(v.lines.polylineCount(), 3u) << perspective;
    const double edge = perspective ? 0.6 : 0.5;
    EXPECT_EQ(v.visible, (std::vector<std::uint8_t>{1, 0, 1}));
    const glm::dvec3 cut1 = v.lines.points[v.lines.starts[1]], cut2 = v.lines.points[v.lines.starts[2] - 1];
    EXPECT_NEAR(cut1.x, -edge, 1e-4);
    EXPECT_NEAR(cut2.x, edge, 1e-4);
    EXPECT_NEAR(st.hiddenLength, 2 * edge, 2e-4);
    EXPECT_NEAR(st.visibleLength, 4 - 2 * edge, 2e-4);
    for (std::uint32_t src : v.source) EXPECT_EQ(src, 0u);
  }
}

// An edge on the square (its border and its diagonal, which runs over both triangles' common
// edge) is seen whole: a point is not hidden by the triangle it lies on. A segment in front is
// seen; one through the square is split where it crosses z = 0 (x = 0 here).
TEST(EdgeVisibility, EdgesOnTheSurfaceAreSeen) {
  const Scene s = squareScene(true);
  const OcclusionGrid grid(s, *s.camera, 640, 480);
  VisibilityStats st;
  for (const PolylineSet& l : {segment({-0.5, -0.5, 0}, {0.5, -0.5, 0}), segment({-0.5, -0.5, 0}, {0.5, 0.5, 0}),
                               segment({-0.4, 0, 1}, {0.4, 0, 1})}) {
    const VisibleLines v = splitByVisibility(l, grid, {}, st);
    ASSERT_EQ(v.lines.polylineCount(), 1u);
    EXPECT_EQ(v.visible[0], 1);
  }
  const VisibleLines v = splitByVisibility(segment({-0.2, 0, 1}, {0.2, 0, -1}), grid, {}, st);
  ASSERT_EQ(v.lines.polylineCount(), 2u);
  EXPECT_EQ(v.visible, (std::vector<std::uint8_t>{1, 0}));
  EXPECT_NEAR(v.lines.points[1].x, 0.0, 1e-4);
}

// Bad input: a non-finite point ends a piece and is left out; the part behind the eye is not
// seen; no NaN reaches the output.
TEST(EdgeVisibility, NonFinitePointsAndPointsBehindTheEye) {
  const Scene s = squareScene(true);
  const OcclusionGrid grid(s, *s.camera, 640, 480);
  VisibilityStats st;
  PolylineSet l;
  l.add({{-1, 0, 1}, {1, 0, 1}, {NAN, 0, 0}, {1, 1, 1}, {1, 1, 2}, {0, 0, 10}});
  const VisibleLines v = splitByVisibility(l, grid, {}, st);
  ASSERT_EQ(v.lines.polylineCount(), 3u);
  for (const glm::dvec3& p : v.lines.points) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
  EXPECT_EQ(v.visible, (std::vector<std::uint8_t>{1, 1, 0}));
}

// A line through the eye plane, from z = -60 to 60 at x = 0.3 (eye at z = 5, a unit square at
// z = 0): hidden behind the square from -60 to 0 (its projection through the eye falls inside
// for all z <= 2), seen from 0 until it leaves the image, not seen beyond. The same answer when
// the line has a vertex near the eye (the review's case: 1 or 64 samples gave one seen piece).
TEST(EdgeVisibility, LineThroughTheEyePlane) {
  const Scene s = squareScene(true);
  const OcclusionGrid grid(s, *s.camera, 640, 480);
  for (bool split : {false, true}) {
    PolylineSet l;
    if (split) l.add({{0.3, 0, -60}, {0.3, 0, 5 - 1e-9}, {0.3, 0, 60}});
    else l.add({{0.3, 0, -60}, {0.3, 0, 60}});
    VisibilityStats st;
    const VisibleLines v = splitByVisibility(l, grid, {}, st);
    ASSERT_EQ(v.lines.polylineCount(), 3u) << split;
    EXPECT_EQ(v.visible, (std::vector<std::uint8_t>{0, 1, 0})) << split;
    // The seen piece starts where the line comes out from behind the square, at z = 0.
    EXPECT_NEAR(v.lines.points[v.lines.starts[1]].z, 0.0, 1e-4) << split;
    // ... and ends where it leaves the image: x = 0.3 at depth 5 - z is at the image's right
    // edge, 320 px from the centre, when 0.3 f / (5 - z) = 320 with f = 240 / tan(15 degrees).
    const double f = 240.0 / std::tan(15.0 * 3.14159265358979323846 / 180.0);
    EXPECT_NEAR(v.lines.points[v.lines.starts[2] - 1].z, 5.0 - 0.3 * f / 320.0, 1e-4) << split;
  }
}

// What the renderer clips away hides nothing: a square between the eye and the near plane
// (perspective), a square behind the camera (orthographic).
TEST(EdgeVisibility, OccludersOutsideNearAndFarHideNothing) {
  for (bool perspective : {true, false}) {
    Scene s = squareScene(perspective);
    for (glm::dvec3& p : s.surfaces[0].mesh.positions) p.z = perspective ? 4.95 : 6.0;  // near = 0.1
    const OcclusionGrid grid(s, *s.camera, 640, 480);
    EXPECT_EQ(grid.triangles(), 0u) << perspective;
    VisibilityStats st;
    const VisibleLines v = splitByVisibility(segment({-0.2, 0.1, -1}, {0.2, 0.1, -1}), grid, {}, st);
    ASSERT_EQ(v.lines.polylineCount(), 1u);
    EXPECT_EQ(v.visible[0], 1) << perspective;
  }
}

// A fan of 200,000 long thin triangles over the image (a planar CAD face's tessellation with many
// border nodes) bins into a bounded grid: at most 16 entries a triangle and a million (the box
// binning gave O(n^2) entries and overflowed 32 bits at a million), and still hides what is
// behind it.
TEST(EdgeVisibility, LongTrianglesBinBounded) {
  Scene s = squareScene(true);
  SceneSurface fan;
  const int n = 200000;
  fan.mesh.positions.push_back({0, 0, 0});
  for (int i = 0; i <= n; ++i) {
    const double a = 2 * 3.14159265358979323846 * i / n;
    fan.mesh.positions.push_back({3 * std::cos(a), 3 * std::sin(a), 0});
  }
  for (int i = 0; i < n; ++i) fan.mesh.triangles.push_back({0, std::uint32_t(i + 1), std::uint32_t(i + 2)});
  s.surfaces = {fan};
  const OcclusionGrid grid(s, *s.camera, 1920, 1080);
  EXPECT_EQ(grid.triangles(), std::size_t(n));
  EXPECT_LE(grid.entries(), 16u * std::size_t(n) + 1000000u);
  VisibilityStats st;
  const VisibleLines v = splitByVisibility(segment({-0.5, 0.2, -1}, {0.5, 0.2, -1}), grid, {}, st);
  ASSERT_EQ(v.lines.polylineCount(), 1u);
  EXPECT_EQ(v.visible[0], 0);
}

}  // namespace wf

namespace wf {
// From a review: a segment wholly outside the view is kept as not seen, not dropped; the pieces
// add up to the polyline's length (1e-12).
TEST(EdgeVisibility, SegmentsOutsideTheViewAreKeptAsNotSeen) {
  const Scene s = squareScene(true);
  const OcclusionGrid grid(s, *s.camera, 640, 480);
  PolylineSet l;
  l.add({{-0.2, 0.3, 1}, {0.2, 0.3, 1}, {0.2, 0.3, 20}, {5, 0.3, 30}});  // the last two behind the eye
  VisibilityStats st;
  const VisibleLines v = splitByVisibility(l, grid, {}, st);
  const double total = 0.4 + 19.0 + std::sqrt(4.8 * 4.8 + 100.0);
  EXPECT_NEAR(st.visibleLength + st.hiddenLength, total, 1e-12 * total);
  ASSERT_GE(v.visible.size(), 2u);
  EXPECT_EQ(v.visible.front(), 1);
  EXPECT_EQ(v.visible.back(), 0);
}
}  // namespace wf
