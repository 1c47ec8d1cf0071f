// The footprint of a round wire in a perspective image (pipeline.h, wireWidthFactor and
// wireDepthScale; docs/abuffer.md, "The wire's footprint"), against rays cast at the exact
// cylinder: the outline's distance from the axis's image, found by bisection on whether a ray
// meets the cylinder, and the depth where a ray first meets it, from the quadratic.
#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"
#include "render/rasterize.h"
#include "render/renderer.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace wf {
namespace {

// A wide perspective camera (90 degrees across its height), so that wires far off its axis are
// in it; at the origin looking down -z, so that eye space is world space.
Camera wideCamera() {
  Camera c;
  c.eye = glm::dvec3(0.0);
  c.target = glm::dvec3(0.0, 0.0, -1.0);
  c.up = glm::dvec3(0.0, 1.0, 0.0);
  c.fovYDegrees = 90.0;
  c.nearPlane = 0.01;
  c.farPlane = 100.0;
  return c;
}
ViewTransform wideView() { return ViewTransform::make(wideCamera(), 800, 600); }

// An 800x600 scene under wideCamera holding one free wire of radius r from e0 to e1.
Scene oneWireScene(const glm::dvec3& e0, const glm::dvec3& e1, double r, bool roundEnds = false) {
  Scene s = test::baseScene(800, 600);
  s.camera = wideCamera();
  SceneWire wire;
  wire.thickness = 2.0 * r;
  wire.restsOnSurface = false;
  wire.roundEnds = roundEnds;
  wire.lines.add({e0, e1});
  s.wires.push_back(wire);
  return s;
}

// The eye-space ray through screen point (x, y), unit length.
glm::dvec3 rayThrough(const ViewTransform& v, double x, double y) { return glm::normalize(v.eyePoint(x, y, 1.0)); }

// Where the ray from the eye along unit `dir` first meets the infinite cylinder of radius r about
// the line through a with unit direction u: the distance along the ray, or -1 if it misses.
double hitCylinder(const glm::dvec3& dir, const glm::dvec3& a, const glm::dvec3& u, double r) {
  // |(t dir - a) - ((t dir - a) . u) u|^2 = r^2
  const glm::dvec3 dp = dir - glm::dot(dir, u) * u, ap = -a - glm::dot(-a, u) * u;
  const double A = glm::dot(dp, dp), B = 2 * glm::dot(dp, ap), C = glm::dot(ap, ap) - r * r;
  const double disc = B * B - 4 * A * C;
  if (!(A > 0) || disc < 0) return -1.0;
  return (-B - std::sqrt(disc)) / (2 * A);
}

struct RandomWire {
  glm::dvec3 e0, e1;
  double r;
};
RandomWire randomWire(std::mt19937_64& rng, const ViewTransform& v) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (;;) {
    // An end anywhere in the image at depth 2 ... 6, the other 0.5 away in a random direction.
    const double d = 2.0 + 4.0 * U(rng);
    const glm::dvec3 e0 = v.eyePoint(40 + 720 * U(rng), 40 + 520 * U(rng), d);
    const double z = 2 * U(rng) - 1, phi = 6.283185307179586 * U(rng), s = std::sqrt(1 - z * z);
    const glm::dvec3 e1 = e0 + 0.5 * glm::dvec3(s * std::cos(phi), s * std::sin(phi), z);
    const glm::dvec2 p0 = v.project(e0), p1 = v.project(e1);
    if (glm::length(p1 - p0) < 20.0) continue;  // well away from end-on
    return {e0, e1, 1e-5 * d};                  // thin: the first order holds to about 1e-5
  }
}

// segmentPolygonConvex (set-up's mitre check, which skips building the polygon for a mitred
// quadrilateral) answers as isConvex(segmentPolygon(s)) does: random mitres, many of them folded
// (offsets longer than the segment, crossed, reversed), caps at either end, end-on segments,
// zero offsets and corners that coincide (which removeDuplicates merges). Both answers must occur.
TEST(WireFootprint, MitreConvexityCheckMatchesThePolygon) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int convex = 0, folded = 0;
  for (int i = 0; i < 20000; ++i) {
    SegmentPrim s{};
    s.p0 = {100 + 20 * U(rng), 80 + 20 * U(rng)};
    s.p1 = i % 17 == 0 ? s.p0 : glm::dvec2(100 + 20 * U(rng), 80 + 20 * U(rng));
    const double scale = i % 3 == 0 ? 30.0 : 2.0;
    s.o0 = glm::vec2(float(scale * U(rng)), float(scale * U(rng)));
    s.o1 = i % 11 == 0 ? s.o0 : glm::vec2(float(scale * U(rng)), float(scale * U(rng)));
    if (i % 13 == 0) s.o1 = glm::vec2(0.0f);
    if (i % 19 == 0) s.o0 = -s.o1;  // p0 - o0 may land on p1 + o1 where the ends coincide
    s.w0 = float(std::abs(2 * U(rng)) + 0.1), s.w1 = float(std::abs(2 * U(rng)) + 0.1);
    const int kind = i % 7;
    s.flags = kind == 1 ? kSegmentCap0 : kind == 2 ? kSegmentCap1 : kind == 3 ? kSegmentEndOn : 0;
    if (s.flags & (kSegmentCap0 | kSegmentCap1) && s.p0 == s.p1) s.flags = 0;  // caps need a direction
    ScreenPolygon poly;
    segmentPolygon(s, poly);
    const bool want = isConvex(poly);
    ASSERT_EQ(segmentPolygonConvex(s), want) << "case " << i;
    (want ? convex : folded)++;
  }
  EXPECT_GT(convex, 1000);
  EXPECT_GT(folded, 1000);
  // By hand: exact collinear turns (all four corners on the axis's line, or three of them), the
  // first and last corners one (o0 = 0), the middle two one (o1 = 0), both.
  auto check = [](glm::dvec2 p0, glm::dvec2 p1, glm::vec2 o0, glm::vec2 o1) {
    SegmentPrim s{};
    s.p0 = p0, s.p1 = p1, s.o0 = o0, s.o1 = o1, s.w0 = 1.0f, s.w1 = 1.0f;
    ScreenPolygon poly;
    segmentPolygon(s, poly);
    return segmentPolygonConvex(s) == isConvex(poly);
  };
  EXPECT_TRUE(check({0, 0}, {8, 0}, {2, 0}, {2, 0}));
  EXPECT_TRUE(check({0, 0}, {8, 0}, {2, 0}, {-2, 0}));
  EXPECT_TRUE(check({0, 0}, {8, 0}, {0, 2}, {4, 0}));
  EXPECT_TRUE(check({0, 0}, {8, 0}, {0, 0}, {0, 2}));
  EXPECT_TRUE(check({0, 0}, {8, 0}, {0, 2}, {0, 0}));
  EXPECT_TRUE(check({0, 0}, {8, 0}, {0, 0}, {0, 0}));
  EXPECT_TRUE(check({0, 0}, {8, 4}, {-2, 4}, {6, -4}));
}

// The screen half width at an end, from rays: the largest offset across the axis's image at
// which a ray still meets the cylinder, against r f / d times wireWidthFactor. Without the
// factor the outline is up to 1 / cos(45 degrees) = 1.41 times wider at this view's corners.
TEST(WireFootprint, WidthFactorIsTheOutlineOfTheCylinder) {
  const ViewTransform v = wideView();
  std::mt19937_64 rng(11);
  double worstWithout = 0;
  for (int k = 0; k < 200; ++k) {
    const RandomWire w = randomWire(rng, v);
    const glm::dvec2 p0 = v.project(w.e0), p1 = v.project(w.e1);
    const glm::dvec2 across = glm::normalize(glm::dvec2(p0.y - p1.y, p1.x - p0.x));
    const glm::dvec3 u = glm::normalize(w.e1 - w.e0);
    double lo = 0.0, hi = 1.0;
    for (double side : {1.0, -1.0}) {
      double in = 0.0, out = 1e3 * w.r * v.pixelsPerWorld(-w.e0.z);
      for (int it = 0; it < 80; ++it) {
        const double m = 0.5 * (in + out);
        const glm::dvec2 p = p0 + side * m * across;
        (hitCylinder(rayThrough(v, p.x, p.y), w.e0, u, w.r) > 0 ? in : out) = m;
      }
      (side > 0 ? lo : hi) = in;
    }
    const double measured = 0.5 * (lo + hi);
    const double plain = w.r * v.pixelsPerWorld(-w.e0.z);
    const double predicted = plain * wireWidthFactor(v, w.e0, w.e1);
    EXPECT_NEAR(predicted / measured, 1.0, 1e-4) << k;
    worstWithout = std::max(worstWithout, std::abs(plain / measured - 1.0));
  }
  EXPECT_GT(worstWithout, 0.05);  // the test can tell: the plain width misses by more than 5%
}

// The depth where the ray through a point q half widths from the axis's image first meets the
// cylinder, against the axis's depth there less r sqrt(1 - q^2) times wireDepthScale.
TEST(WireFootprint, DepthScaleIsWhereTheRayEntersTheCylinder) {
  const ViewTransform v = wideView();
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double worstWithout = 0;
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const RandomWire w = randomWire(rng, v);
    const glm::dvec3 u = glm::normalize(w.e1 - w.e0);
    // Below the kMaxWireDepthScale bound the formula is the exact first order; beyond it the
    // bound holds instead (the caps are what shows there).
    const double scale = wireDepthScale(v, w.e0, w.e1 - w.e0);
    if (scale >= 0.99 * kMaxWireDepthScale) continue;
    const glm::dvec2 p0 = v.project(w.e0), p1 = v.project(w.e1);
    const glm::dvec2 across = glm::normalize(glm::dvec2(p0.y - p1.y, p1.x - p0.x));
    const double halfWidth = w.r * v.pixelsPerWorld(-w.e0.z) * wireWidthFactor(v, w.e0, w.e1);
    const double q = k % 2 ? 0.0 : 0.9 * U(rng);  // odd k: the axis's image, where no tilt enters
    const glm::dvec2 p = p0 + q * halfWidth * across;
    const glm::dvec3 dir = rayThrough(v, p.x, p.y);
    const double s = hitCylinder(dir, w.e0, u, w.r);
    ASSERT_GT(s, 0) << k;
    const double depth = -(s * dir).z;
    // The axis's depth at the same screen parameter: 1/d is linear along the axis's image.
    const glm::dvec2 d = p1 - p0;
    const double t = glm::dot(p - p0, d) / glm::dot(d, d);
    const double axisDepth = 1.0 / ((1 - t) / -w.e0.z + t / -w.e1.z);
    const double cut = axisDepth - depth;  // how far the surface stands in front of the axis
    const double predicted = w.r * std::sqrt(1 - q * q) * scale;
    // On the axis's image the model is the first order; across it the surface is also tilted,
    // up to r q sin(theta) / sin(beta) (the ray's angle to the view axis: the circle is seen
    // from aside): this test checks the scale alone; SegmentTilt adds the tilt (the next test but
    // three checks the whole model, TiltedDepthIsWhereTheRayEntersTheCylinder).
    const glm::dvec3 e = v.viewVector(w.e0);
    const double sinBeta = glm::length(glm::cross(e, u)), sinTheta = std::sqrt(std::max(0.0, 1 - e.z * e.z));
    if (q == 0.0) EXPECT_NEAR(predicted / cut, 1.0, 2e-3) << k << " scale " << scale;
    else EXPECT_LE(std::abs(predicted - cut), 1.001 * w.r * q * sinTheta / sinBeta + 1e-3 * w.r) << k;
    worstWithout = std::max(worstWithout, std::abs(w.r * std::sqrt(1 - q * q) / cut - 1.0));
    ++checked;
  }
  EXPECT_GT(checked, 150);
  EXPECT_GT(worstWithout, 0.5);  // one radius is far off where the wire slants
}

// The set-up stores both: a wire of world thickness gets the outline's width and depth radii;
// a wire of a thickness in pixels keeps its width as given.
TEST(WireFootprint, SetUpStoresTheOutlineAndTheDepthRadius) {
  const int W = 800, H = 600;
  Scene s = test::baseScene(W, H);
  s.camera = wideCamera();
  const ViewTransform v = wideView();
  // Near the image's upper right corner, across the radial direction, slanting away.
  const glm::dvec3 e0 = v.eyePoint(700, 80, 3.0), e1 = v.eyePoint(760, 140, 3.6);
  SceneWire wire;
  wire.thickness = 0.02;
  wire.restsOnSurface = false;
  wire.lines.add({e0, e1});  // the camera sits at the origin looking down -z: eye = world
  s.wires.push_back(wire);
  SceneWire pixels = wire;
  pixels.thicknessInPixels = true;
  pixels.thickness = 3.0;
  s.wires.push_back(pixels);
  RenderStats st;
  const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
  ASSERT_EQ(ps.segments.size(), 2u);
  const SegmentPrim& a = ps.segments[0];
  EXPECT_NEAR(a.w0, 0.01 * v.pixelsPerWorld(3.0) * wireWidthFactor(v, e0, e1), 1e-4);
  EXPECT_GT(wireWidthFactor(v, e0, e1), 1.05);
  EXPECT_NEAR(a.r0, 0.01 * wireDepthScale(v, e0, e1 - e0), 1e-7);
  EXPECT_NEAR(a.r1, 0.01 * wireDepthScale(v, e1, e1 - e0), 1e-7);
  EXPECT_GT(wireDepthScale(v, e1, e1 - e0), 1.05);  // 1.10 here: r0 and r1 differ
  EXPECT_NEAR(ps.segments[1].w0, 1.5, 1e-6);
}

// A segment turning towards the eye: its depth radius goes from r times wireDepthScale (long on
// the screen) to one r (end-on, its end's sphere) without a jump, ramped while its screen length
// falls from two half widths to one. Without the ramp r0 jumped from 5 r to r at the turn.
TEST(WireFootprint, DepthRadiusHasNoJumpAsTheSegmentTurnsEndOn) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  const double r = 0.01, L = 0.2;
  double last0 = -1.0, last1 = -1.0;
  int endOn = 0, full = 0;
  for (int i = 0; i <= 600; ++i) {
    const double a = 0.6 * i / 600.0;  // the axis's angle to the view axis
    const glm::dvec3 e1(0.0, 0.0, -3.0), e0 = e1 + L * glm::dvec3(std::sin(a), 0.0, std::cos(a));
    const Scene s = oneWireScene(e0, e1, r);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    ASSERT_EQ(ps.segments.size(), 1u) << a;
    const SegmentPrim& p = ps.segments[0];
    const double ratio = glm::length(p.p1 - p.p0) / std::max(p.w0, p.w1);
    if (p.flags & kSegmentEndOn) {
      ++endOn;
      EXPECT_NEAR(p.r0, r, 1e-7) << a;
    } else if (ratio >= 2.0) {
      ++full;
      EXPECT_NEAR(p.r0, r * wireDepthScale(v, e0, e1 - e0), 1e-6) << a;
    }
    if (last0 >= 0.0) {  // about 0.08 r per step at most here (20 sin(a) length / width, scale 5)
      EXPECT_LT(std::abs(p.r0 - last0), 0.1 * r) << "angle " << a << ", screen length / width " << ratio;
      EXPECT_LT(std::abs(p.r1 - last1), 0.1 * r) << "angle " << a << ", screen length / width " << ratio;
    }
    last0 = p.r0, last1 = p.r1;
  }
  EXPECT_GT(endOn, 10);  // the sweep covers both sides of the turn
  EXPECT_GT(full, 10);
}

// Degenerate axes give the plain footprint (1), never NaN: an axis through the eye, one of no
// length, one with a NaN or infinite end; an orthographic view's width is exact as it is.
TEST(WireFootprint, DegenerateAxesGiveThePlainFootprint) {
  const ViewTransform v = wideView();
  const double nan = std::nan(""), inf = INFINITY;
  const glm::dvec3 e(0.3, -0.2, -2.0);
  EXPECT_EQ(wireWidthFactor(v, e, 2.0 * e), 1.0);  // through the eye
  EXPECT_EQ(wireWidthFactor(v, e, e), 1.0);
  EXPECT_EQ(wireWidthFactor(v, glm::dvec3(nan, 0, -1), e), 1.0);
  EXPECT_EQ(wireWidthFactor(v, glm::dvec3(inf, 0, -1), e), 1.0);
  EXPECT_EQ(wireDepthScale(v, e, glm::dvec3(0.0)), 1.0);
  EXPECT_EQ(wireDepthScale(v, e, glm::dvec3(nan, 0, 0)), 1.0);
  EXPECT_EQ(wireDepthScale(v, e, glm::dvec3(inf, 0, 0)), 1.0);
  // Along the ray: bounded, the end's sphere being what shows.
  EXPECT_LE(wireDepthScale(v, e, e), kMaxWireDepthScale);
  ViewTransform o = v;
  o.perspective = false;
  EXPECT_EQ(wireWidthFactor(o, e, glm::dvec3(2.0, 1.0, -3.0)), 1.0);
  EXPECT_NEAR(wireDepthScale(o, e, glm::dvec3(1.0, 0.0, 1.0)), std::sqrt(2.0), 1e-12);  // 1 / sin(45 deg)
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

// The whole round-wire depth (segmentDepthAt: the axis depth, the tilt across the wire and the
// slide along it, SegmentTilt, and the cut r sqrt(1 - q^2) scaled) against the depth where the ray first meets the exact cylinder, for
// wires anywhere in a 90-degree view at offsets across the whole width (q in [-0.95, 0.95]).
TEST(WireFootprint, TiltedDepthIsWhereTheRayEntersTheCylinder) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double worst = 0, worstFlat = 0;
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const RandomWire w = randomWire(rng, v);
    if (wireDepthScale(v, w.e0, w.e1 - w.e0) >= 0.99 * kMaxWireDepthScale ||
        wireDepthScale(v, w.e1, w.e1 - w.e0) >= 0.99 * kMaxWireDepthScale)
      continue;
    const Scene s = oneWireScene(w.e0, w.e1, w.r);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    ASSERT_EQ(ps.segments.size(), 1u) << k;
    const SegmentPrim& p = ps.segments[0];
    const SegmentFrame fr(p);
    const glm::dvec3 u = glm::normalize(w.e1 - w.e0);
    const glm::dvec2 across(fr.nx, fr.ny);
    for (int j = 0; j < 5; ++j) {
      const double t = 0.2 + 0.6 * U(rng), q = 1.9 * U(rng) - 0.95;
      const double wt = p.w0 + (p.w1 - p.w0) * t;
      const glm::dvec2 at = p.p0 + t * (p.p1 - p.p0) + q * wt * across;
      const glm::dvec3 dir = rayThrough(v, at.x, at.y);
      const double hit = hitCylinder(dir, w.e0, u, w.r);
      ASSERT_GT(hit, 0) << k;
      const double exact = -(hit * dir).z;
      const double model = segmentDepthAt(v, p, fr, at.x, at.y, WireDepth::Round);
      worst = std::max(worst, std::abs(model - exact) / w.r);
      // Without the tilt: the axis depth less the cut alone.
      const SegmentEndKeys keys(v, p);
      const double tc = std::clamp(fr.t(at.x, at.y), 0.0, 1.0);
      const double r = p.r0 + (p.r1 - p.r0) * tc;
      const double flat = v.depthFromKey(keys.axis(tc)) - r * std::sqrt(1.0 - std::min(1.0, fr.distance2(at.x, at.y) / (wt * wt)));
      worstFlat = std::max(worstFlat, std::abs(flat - exact) / w.r);
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(worstFlat, 0.3);
}

// WireCapsule (a hair's exact solid: a sphere at each end and the cylinder between, for equal radii) against a brute
// force that knows only the solid's definition, the points within r of the axis segment: along a
// ray the distance to a segment is convex, so its minimum is found by golden-section search and
// the first point within r by bisection before it. Random wires in a wide view, slanting at any
// angle (towards the eye too, where the ends' spheres are what is seen), rays through the
// polygon and a little beyond it (misses: where the ray passes the solid nearest, the minimum of
// the distance), in perspective and orthographic views. The world
// radius comes back from the half widths.
TEST(WireFootprint, CapsuleDepthIsWhereTheRayFirstMeetsTheSolid) {
  Camera ortho = wideCamera();
  ortho.projection = Camera::Projection::Orthographic;
  ortho.orthoHeight = 16.0;  // holds the wide view's wires
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int hits = 0, misses = 0, endHits = 0;
  double worst = 0;
  for (int k = 0; k < 80; ++k) {
    const bool isOrtho = k % 4 == 3;  // parallel rays from the image plane
    const ViewTransform v = isOrtho ? ViewTransform::make(ortho, 800, 600) : wideView();
    RandomWire w = randomWire(rng, wideView());
    w.r = 0.004 * -w.e0.z;
    Scene s = oneWireScene(w.e0, w.e1, w.r);
    if (isOrtho) s.camera = ortho;
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(800, 600), st);
    ASSERT_EQ(ps.segments.size(), 1u);
    const SegmentPrim& p = ps.segments[0];
    WireCapsule c(v, p);
    ASSERT_TRUE(c.valid);
    // The half widths stand for the world radius (to set-up's first order and its floats).
    EXPECT_NEAR(c.r0, w.r, 2e-3 * w.r) << k;
    EXPECT_NEAR(c.r1, w.r, 2e-3 * w.r) << k;
    c.r1 = c.r0;  // one radius, so that the solid is exactly the points within it of the axis
    const glm::dvec3 a = c.e0, b = c.e0 + c.u * c.length;
    auto dist = [&](const glm::dvec3& q) {
      const double t = std::clamp(glm::dot(q - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
      return glm::length(q - (a + t * (b - a)));
    };
    const SegmentFrame fr(p);
    for (int j = 0; j < 60; ++j) {
      const double t = -0.3 + 1.6 * U(rng), q = 2.4 * U(rng) - 1.2;
      const double wt = p.w0 + (p.w1 - p.w0) * std::clamp(t, 0.0, 1.0);
      const glm::dvec2 at = p.p0 + t * (p.p1 - p.p0) + q * wt * glm::dvec2(fr.nx, fr.ny);
      // z = -1: the parameter is the view depth (from the eye, or from the image plane)
      const glm::dvec3 org = isOrtho ? v.eyePoint(at.x, at.y, 0.0) : glm::dvec3(0.0);
      const glm::dvec3 dir = isOrtho ? glm::dvec3(0.0, 0.0, -1.0) : v.eyePoint(at.x, at.y, 1.0);
      auto f = [&](double sigma) { return dist(org + sigma * dir) - c.r0; };
      double lo = std::min(-a.z, -b.z) - 10 * c.r0, hi = std::max(-a.z, -b.z) + 10 * c.r0;
      for (int i = 0; i < 200; ++i) {  // golden section for the minimum of the convex distance
        const double m1 = hi - 0.618033988749895 * (hi - lo), m2 = lo + 0.618033988749895 * (hi - lo);
        (f(m1) < f(m2) ? hi : lo) = f(m1) < f(m2) ? m2 : m1;
      }
      const double sMin = 0.5 * (lo + hi);
      bool hit = false;
      const double got = c.depthAt(v, at.x, at.y, &hit);
      if (f(sMin) > 1e-9 * c.r0) {  // the ray misses the solid
        if (f(sMin) > 1e-6 * c.r0) {
          EXPECT_FALSE(hit) << k << " " << j << " " << got;
          // where it passes the solid nearest: the distance's minimum (whose place is found to
          // about the square root of the rounding only: compared by the distance there)
          EXPECT_LE(f(got), f(sMin) + 1e-7 * c.r0) << k << " " << j;
        }
        ++misses;
        continue;
      }
      double out = std::min(-a.z, -b.z) - 10 * c.r0, in = sMin;
      for (int i = 0; i < 200; ++i) {
        const double m = 0.5 * (out + in);
        (f(m) > 0 ? out : in) = m;
      }
      if (f(sMin) < -1e-4 * c.r0) {  // clearly inside somewhere: a hit, not a graze
        ASSERT_TRUE(hit) << k << " " << j;
        worst = std::max(worst, std::abs(got - in) / c.r0);
        EXPECT_NEAR(got, in, 1e-7 * c.r0 + 1e-12 * in) << k << " " << j;
        ++hits;
        if (t < 0.1 || t > 0.9) ++endHits;
      }
    }
  }
  std::printf("[ measured ] capsule depth against the brute force: %d hits (%d near the ends), %d misses, worst %.3g r\n",
              hits, endHits, misses, worst);
  EXPECT_GT(hits, 2000);
  EXPECT_GT(endHits, 500);
  EXPECT_GT(misses, 200);
}

// A wire whose width is given in pixels is a cone in a perspective world: its radius
// w / pixelsPerWorld(d) grows with depth, by up to the wire's angular half width w / f per unit
// of length (the most when it points away from the eye). Against a brute force that knows only
// the solid's definition, the union of the balls of radius r(t) = r0 + (r1 - r0) t about the axis
// points a + t (b - a) (the ends' spheres and the cone tangent to them): the distance to it, min
// over t of |q - c(t)| - r(t), is convex along a ray, so the entry is found as above, with a
// golden-section search over t inside. Half widths of 2 ... 12 pixels in a 90-degree view; two
// thirds of the wires with ends anywhere, 1.2 ... 3.5 times as deep as each other (either end the
// nearer), a third nearly end-on (0.3 ... 3 half widths on screen, their rays nearly along the
// cone's side). Hits: the entry, in double and in the resolve's floats. Misses (the outline lies
// a little outside the solid's, and the polygon's corners): no hit, and a depth continuous with
// the hits at the outline, where the ray passes the solid nearest. (Taking the body's radius where
// the ray passes the axis nearest, as WireCapsule did before, is right to first order in the
// slope only: for a steep wire that point lies far along the axis from where the ray enters, and
// such a ray was taken to miss, its depth up to 3.7 radii too far; and its misses took the axis's
// nearest point, which jumps off the grazing point by radii.)
TEST(WireFootprint, TaperedCapsuleDepthIsWhereTheRayMeetsTheCone) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int hits = 0, floats = 0, misses = 0, nearMisses = 0, nearMissesEndOn = 0, endOnHits = 0, shrinking = 0, floatMisses = 0;
  double worst = 0, worstFloat = 0, largestTaper = 0, worstGraze = 0, worstGrazeEndOn = 0, worstMissFloat = 0;
  auto goldenMin = [](auto&& fn, double lo, double hi, int steps) {  // the minimum of a convex fn
    double m1 = hi - 0.618033988749895 * (hi - lo), m2 = lo + 0.618033988749895 * (hi - lo);
    double f1 = fn(m1), f2 = fn(m2);
    for (int i = 0; i < steps; ++i) {
      if (f1 < f2) hi = m2, m2 = m1, f2 = f1, m1 = hi - 0.618033988749895 * (hi - lo), f1 = fn(m1);
      else lo = m1, m1 = m2, f1 = f2, m2 = lo + 0.618033988749895 * (hi - lo), f2 = fn(m2);
    }
    return 0.5 * (lo + hi);
  };
  for (int k = 0; k < 90; ++k) {
    const bool endOn = k % 3 == 2;
    const double d0 = 1.0 + 2.0 * U(rng), halfWidth = 2.0 + 10.0 * U(rng);
    const glm::dvec3 e0 = v.eyePoint(200 + 400 * U(rng), 150 + 300 * U(rng), d0);
    glm::dvec3 e1;
    if (endOn) {  // along the ray through e0, then moved across it by 0.3 ... 3 half widths on screen
      const double d1 = d0 * (k % 2 ? 1.5 + U(rng) : 1.0 / (1.5 + U(rng)));
      const double phi = 6.283185307179586 * U(rng), off = (0.3 + 2.7 * U(rng)) * halfWidth;
      const glm::dvec2 p0 = v.project(e0);
      e1 = v.eyePoint(p0.x + off * std::cos(phi), p0.y + off * std::sin(phi), d1);
    } else {
      const double ratio = 1.2 + 2.3 * U(rng);
      e1 = v.eyePoint(200 + 400 * U(rng), 150 + 300 * U(rng), k % 2 ? d0 * ratio : d0 / ratio);
    }
    Scene s = oneWireScene(e0, e1, 0.0);
    s.wires[0].thickness = 2.0 * halfWidth;  // pixels
    s.wires[0].thicknessInPixels = true;
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    ASSERT_EQ(ps.segments.size(), 1u);
    const SegmentPrim& p = ps.segments[0];
    const WireCapsule c(v, p, true);
    ASSERT_TRUE(c.valid);
    ASSERT_GT(c.length, 0.0);
    const std::uint32_t prim = ps.primitiveCount() - 1;
    ASSERT_TRUE(segmentUsesCapsule(ps, prim));
    const PreparedFragmentSource source(ps);
    largestTaper = std::max(largestTaper, std::max(c.r1 / c.r0, c.r0 / c.r1));
    shrinking += c.r1 < c.r0;
    const double slope = std::abs(c.r1 - c.r0) / c.length;
    EXPECT_LE(slope, halfWidth / v.focal * (1.0 + 1e-3)) << k;  // at most the angular half width
    const glm::dvec3 a = c.e0, b = c.e0 + c.u * c.length;
    const double rmax = std::max(c.r0, c.r1);
    auto solid = [&](const glm::dvec3& q) {  // min over t of |q - c(t)| - r(t): convex in t
      auto g = [&](double t) { return glm::length(q - (a + t * (b - a))) - (c.r0 + (c.r1 - c.r0) * t); };
      return std::min({g(0.0), g(1.0), g(goldenMin(g, 0.0, 1.0, 60))});
    };
    const SegmentFrame fr(p);
    for (int j = 0; j < 40; ++j) {
      const double t = -0.2 + 1.4 * U(rng), q = 2.2 * U(rng) - 1.1;
      const double wt = p.w0 + (p.w1 - p.w0) * std::clamp(t, 0.0, 1.0);
      glm::dvec2 at = p.p0 + t * (p.p1 - p.p0) + q * wt * glm::dvec2(fr.nx, fr.ny);
      if (endOn) at = p.p0 + t * (p.p1 - p.p0) + q * wt * glm::dvec2(std::cos(7.0 * j), std::sin(7.0 * j));
      const glm::dvec3 dir = v.eyePoint(at.x, at.y, 1.0);  // z = -1: the parameter is the view depth
      auto f = [&](double sigma) { return solid(sigma * dir); };
      const double sMin = goldenMin(f, std::min(-a.z, -b.z) - 10 * rmax, std::max(-a.z, -b.z) + 10 * rmax, 100);
      bool hit = false;
      const double got = c.depthAt(v, at.x, at.y, &hit);
      if (f(sMin) > 1e-6 * rmax) {  // a miss: where it passes the solid nearest, near the outline
        EXPECT_FALSE(hit) << k << " " << j;
        ++misses;
        if (f(sMin) < 0.02 * rmax) {
          // (along a nearly end-on wire the ray runs nearly parallel to the cone's side: the
          // distance is flat over many radii, and where it is least is ill-conditioned)
          double& w = endOn ? worstGrazeEndOn : worstGraze;
          w = std::max(w, (f(got) - f(sMin)) / rmax);
          ++(endOn ? nearMissesEndOn : nearMisses);
        }
        // The resolve's float solid takes the same point for a miss.
        const int col = int(std::floor(at.x)), row = int(std::floor(at.y));
        SurfaceDepth sd;
        if (!endOn && col >= 0 && row >= 0 && col < W && row < H && source.surfaceDepth(prim, col, row, sd) && sd.capsule) {
          const double zf = sd.at(float(at.x - col), float(at.y - row));
          worstMissFloat = std::max(worstMissFloat, std::abs(zf - got) / rmax);
          ++floatMisses;
        }
        continue;
      }
      if (!(f(sMin) < -0.05 * rmax)) continue;  // a clear hit (a graze decides by rounding)
      double out = std::min(-a.z, -b.z) - 10 * rmax, in = sMin;
      for (int i = 0; i < 100; ++i) {
        const double m = 0.5 * (out + in);
        (f(m) > 0 ? out : in) = m;
      }
      ASSERT_TRUE(hit) << k << " " << j;
      const double rHere = c.r0 + (c.r1 - c.r0) * std::clamp(glm::dot(in * dir - a, c.u) / c.length, 0.0, 1.0);
      worst = std::max(worst, std::abs(got - in) / rHere);
      // The resolve's float solid (SurfaceDepth::atSamples) where it takes the solid: the same
      // to float rounding of terms of the segment's world length.
      const int col = int(std::floor(at.x)), row = int(std::floor(at.y));
      SurfaceDepth sd;
      if (col >= 0 && row >= 0 && col < W && row < H && source.surfaceDepth(prim, col, row, sd) && sd.capsule) {
        const double zf = sd.at(float(at.x - col), float(at.y - row));
        worstFloat = std::max(worstFloat, std::abs(zf - in) / rHere);
        ++floats;
      }
      ++hits;
      endOnHits += endOn;
    }
  }
  std::printf("[ measured ] tapered capsule against the union of balls: %d hits (%d of nearly end-on wires), taper up "
              "to %.2f (%d of 90 wires narrowing away from p0), worst %.3g r; the resolve's float solid at %d hits, "
              "worst %.3g r; %d misses, %d (%d on nearly end-on wires) within 0.02 r of the solid, at a depth no more "
              "than %.3g r (%.3g r) farther from it than its nearest point; the float solid's miss depth at %d of them "
              "within %.3g r of the double's\n",
              hits, endOnHits, largestTaper, shrinking, worst, floats, worstFloat, misses, nearMisses, nearMissesEndOn,
              worstGraze, worstGrazeEndOn, floatMisses, worstMissFloat);
  EXPECT_GT(hits, 1500);
  EXPECT_GT(endOnHits, 300);
  EXPECT_GT(largestTaper, 2.5);
  EXPECT_GT(shrinking, 30);
  EXPECT_LT(worst, 1e-7);
  EXPECT_GT(floats, 500);
  EXPECT_LT(worstFloat, 2e-3);
  EXPECT_GT(nearMisses, 30);
  EXPECT_GT(nearMissesEndOn, 5);
  EXPECT_LT(worstGraze, 1e-4);
  EXPECT_LT(worstGrazeEndOn, 0.5);
  EXPECT_GT(floatMisses, 100);
  EXPECT_LT(worstMissFloat, 1e-3);
}

// The hairs whose model is not the solid's body: steep (within a few degrees of the ray, where
// set-up caps the depth radius's scale), short (one to two half widths on screen, where it ramps
// the scale to 1), end-on (the hull of its end discs, either end nearer the eye), a width in
// pixels, under a perspective and an orthographic camera. Every depth the resolve's subpixels
// and the reference take where the polygon covers a pixel lies within the pixel's range [zmin,
// zmax], behind the nearest depth the rasteriser culls the pixel, its row and its band by, and
// behind binning's nearest depth of the whole segment and of its item in the pixel's tile (what
// culling trusts). Then the same for long hairs, tapered (a width in pixels) and foreshortened,
// some at the image's edges and some orthographic, whose far side the solid may bound itself
// (SegmentDepth::capsuleFarthest).
TEST(WireFootprint, SolidStaysWithinTheCullingBoundsOfEveryHair) {
  const int W = 800, H = 600;
  Camera ortho = wideCamera();
  ortho.projection = Camera::Projection::Orthographic;
  ortho.orthoHeight = 1.5;
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int checked = 0, everywhere = 0, missed = 0;
  int longChecked[2] = {0, 0};     // samples on the long hairs without, with the solid everywhere
  int farFromSolid = 0;            // pixels whose far bound is the solid's own (capsuleFarthest)
  for (int k = 0; k < 540; ++k) {
    // The last 300: long hairs, 0.3 ... 3 times as long as their near end's distance from the
    // eye (the far end 1.3 ... 4 times as deep), either end first, mostly in perspective away
    // from the image's edges (a seventh of them at the edges, a seventh seen orthographically:
    // capsuleReach's other branch): steep, short on screen (two fifths: their far side is where
    // the solid may lie behind the round model's) and end-on ones a pixel or a few wide (in
    // perspective a width in pixels is a cone in the world; off the view axis the solid is
    // their depth everywhere; orthographically a cylinder), and foreshortened ones of one world
    // radius at 17 ... 34 degrees to the ray (the solid mostly near their ends only: there the
    // round model bounds the body).
    const bool tapered = k >= 240;
    const bool isOrtho = tapered ? k % 7 == 6 : k % 2 == 1;
    const Camera cam = isOrtho ? ortho : wideCamera();
    const ViewTransform v = ViewTransform::make(cam, W, H);
    const double d = tapered ? 0.5 + 1.5 * U(rng) : 2.0 + 3.0 * U(rng);
    // a third of the first 240 at the image's edges, where the projection stretches the solid most
    const bool edge = tapered ? k % 7 == 5 : k % 3 == 2;
    const double ex = edge ? (U(rng) < 0.5 ? 8 + 20 * U(rng) : 772 + 20 * U(rng)) : 100 + 600 * U(rng);
    const double ey = edge ? 8 + 584 * U(rng) : 100 + 400 * U(rng);
    const glm::dvec3 e0 = v.eyePoint(ex, ey, d);
    const glm::dvec3 ray = isOrtho ? glm::dvec3(0, 0, -1) : glm::normalize(e0);  // away from the eye
    glm::dvec3 side = glm::normalize(glm::cross(ray, glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5)));
    // (orthographic: thinner short hairs; long ones as wide on screen as in perspective, 1.4 ... 7 px)
    const double r = 0.006 * d * (isOrtho ? (tapered ? 1.0 / d : 0.3) : 1.0) * (tapered ? 0.3 + 1.2 * U(rng) : 1.0);
    const double L = tapered ? d * (0.3 + 2.7 * U(rng)) : 0.3;
    const int kind = tapered ? (k % 5 == 4 ? 5 : k % 5 == 3 ? 2 : k % 5 == 2 ? 1 : k % 5) : (k / 2) % 5;
    // the angle to the ray: steep, short on screen (about 1.5 half widths; the long ones in
    // perspective 0.4 ... 1.2), end-on, any; foreshortened
    double angle = kind == 0 ? 0.02 + 0.08 * U(rng) : kind == 1 ? 0.0 : kind == 2 ? 0.0 : kind == 5 ? 0.3 + 0.3 * U(rng) : 0.3 + 1.2 * U(rng);
    const double pxPerWorld = v.pixelsPerWorld(d);
    if (kind == 1) angle = std::asin(std::min(1.0, 1.5 * r / L));
    // p0 the nearer end, or the farther (tapered: the same hair with its points swapped)
    const double sign = tapered || k % 4 < 2 ? 1.0 : -1.0;
    const bool swapEnds = tapered && (k / 5) % 2 == 1;
    glm::dvec3 e1 = e0 + sign * L * (std::cos(angle) * ray + std::sin(angle) * side);
    if (kind == 2 && !isOrtho) e1 = e0 * (1.0 + sign * L / glm::length(e0));  // exactly along the ray
    if (e1.z > -0.05) continue;
    Scene s = test::baseScene(W, H);
    s.camera = cam;
    SceneWire wire;
    wire.restsOnSurface = false;
    wire.roundEnds = true;
    wire.thicknessInPixels = kind == 4 || (tapered && kind != 5);
    wire.thickness = wire.thicknessInPixels ? 2.0 * r * pxPerWorld : 2.0 * r;
    if (swapEnds) {
      wire.lines.add({e1, e0});
    } else {
      wire.lines.add({e0, e1});
    }
    s.wires.push_back(wire);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    if (ps.segments.size() != 1) continue;
    const std::uint32_t prim = ps.primitiveCount() - 1;
    ASSERT_TRUE(segmentUsesCapsule(ps, prim));
    const SegmentPrim& p = ps.segments[0];
    const SegmentDepth depth(v, p, WireDepth::Round, true, segmentWidthInPixels(ps, prim));
    ASSERT_TRUE(depth.capsule.valid) << k;
    if (!tapered) everywhere += depth.capsule.everywhere;
    const double zlo = segmentZlo(v, p, true);
    // Binning's nearest depth of the segment in each tile it covers (what culls it there whole).
    constexpr int kTile = 32;
    const TileBins bins = binPrimitives(ps, kTile, st, size_t(1) << 30);
    auto tileZlo = [&](int col, int row) -> double {
      const int tile = (row / kTile) * bins.tilesX + col / kTile;
      for (std::uint32_t b = bins.begin(tile); b < bins.end(tile); ++b)
        if (bins.items[b].index == prim) return double(bins.items[b].zlo);
      return INFINITY;  // not binned there: a covered pixel would be lost
    };
    const PreparedFragmentSource source(ps);
    ScreenPolygon poly, cell;
    segmentPolygon(p, poly);
    double bx0 = 1e300, by0 = 1e300, bx1 = -1e300, by1 = -1e300;
    for (int i = 0; i < poly.count; ++i)
      bx0 = std::min(bx0, poly.x[i]), bx1 = std::max(bx1, poly.x[i]), by0 = std::min(by0, poly.y[i]), by1 = std::max(by1, poly.y[i]);
    for (int row = std::max(0, int(by0)); row <= std::min(H - 1, int(by1)); ++row)
      for (int col = std::max(0, int(bx0)); col <= std::min(W - 1, int(bx1)); ++col) {
        clipRect(poly, cell, col, row, col + 1.0, row + 1.0);
        if (cell.count < 3 || !(cell.area() > 1e-9)) continue;
        const auto pn = depth.pixelNearest(col, row);
        float zmin, zmax, zkey;
        depth.range(col, row, col + 0.5, row + 0.5, pn, zmin, zmax, zkey);
        farFromSolid += pn.solid < INFINITY && depth.endMargin == INFINITY &&
                        float(depth.capsuleFarthest(col, row, col + 1.0, row + 1.0)) == zmax;
        const double itemZlo = tileZlo(col, row);
        const double rowNear = depth.nearest(std::max(0, col - 3), row, col + 4.0, row + 1.0);
        const double bandNear = depth.nearest(std::max(0, col - 5), row & ~3, col + 6.0, (row & ~3) + 4.0);
        SurfaceDepth sd;
        ASSERT_TRUE(source.surfaceDepth(prim, col, row, sd));
        float sx[16], sy[16], out[16];
        for (int i = 0; i < 16; ++i) sx[i] = (i % 4 + 0.5f) / 4, sy[i] = (i / 4 + 0.5f) / 4;
        sd.atSamples(sx, sy, 16, out);  // (unheld: the resolve holds them to [zmin, zmax] as well)
        const bool solidHere = WireCapsule::nearEnd(SegmentFrame(p).t(col + 0.5, row + 0.5), SegmentFrame(p).length,
                                                    depth.endMargin, WireCapsule::kPixelSpread);
        for (int i = 0; i < 16; ++i) {
          // A ray that misses the solid takes where it passes it nearest, which the resolve holds
          // to [zmin, zmax] (and the rasteriser its centroid's): the bounds are for the solid.
          bool hit = true;
          depth.capsule.depthAt(v, col + double(sx[i]), row + double(sy[i]), &hit);
          if (!hit) {
            ++missed;
            continue;
          }
          const double ref = primitiveDepthAt(ps, prim, col + double(sx[i]), row + double(sy[i]));
          // The resolve's depth (the solid's near the ends, else the model's), and the solid's in
          // double where the resolve takes it (along the body the model is what culling holds:
          // there the solid may differ from it by more than the slack in views this wide).
          const double zs[2] = {double(out[i]), ref};
          for (int m = 0; m < (solidHere ? 2 : 1); ++m) {
            const double z = zs[m];
            const double tol = 2e-5 * z;
            ASSERT_GE(z, double(zmin) - tol) << k << " kind " << kind << " " << col << "," << row << " sample " << i;
            ASSERT_LE(z, double(zmax) + tol) << k << " kind " << kind << " " << col << "," << row << " sample " << i;
            ASSERT_GE(z, pn.z - tol) << k << " kind " << kind;
            ASSERT_GE(z, rowNear - tol) << k << " kind " << kind;
            ASSERT_GE(z, bandNear - tol) << k << " kind " << kind;
            ASSERT_GE(z, double(zlo) - tol) << k << " kind " << kind;
            ASSERT_GE(z, itemZlo - tol) << k << " kind " << kind << " " << col << "," << row;
          }
          ++checked;
          if (tapered) ++longChecked[depth.capsule.everywhere ? 1 : 0];
        }
        ASSERT_GE(double(zkey), double(zmin));
        ASSERT_LE(double(zkey), double(zmax));
      }
  }
  std::printf("[ measured ] %d sample depths checked (on the long hairs %d with the solid everywhere, %d without; %d rays missing "
              "the solid left out), %d of the first 240 segments with the solid everywhere; %d pixels bounded far by the solid itself\n",
              checked, longChecked[1], longChecked[0], missed, everywhere, farFromSolid);
  EXPECT_GT(checked, 20000);
  EXPECT_GT(longChecked[0], 5000);
  EXPECT_GT(longChecked[1], 5000);
  EXPECT_GT(farFromSolid, 100);
  EXPECT_GT(everywhere, 30);
}

// The same depth three ways: the double-precision one (a hair's exact solid near its ends,
// or where the ray passes it nearest if it misses; the round model along the body), the
// resolve's SurfaceDepth (float, at() and atSamples()) agree within float rounding, and the
// rasteriser's per-pixel range [zmin, zmax] holds every depth of the solid and the model in the
// pixel, for wires as thick as several pixels anywhere in a wide view, slanting at every angle
// (the tilt and the slide along the axis are largest there).
TEST(WireFootprint, ResolveAndRasteriserBoundsFollowTheTiltedModel) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int pixels = 0, nearEnds = 0, alongBody = 0, missed = 0;
  double worstAgree = 0;
  for (int k = 0; k < 60; ++k) {
    RandomWire w = randomWire(rng, v);
    w.r = 0.004 * -w.e0.z;  // 1 to 3 pixels wide
    const Scene s = oneWireScene(w.e0, w.e1, w.r);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    ASSERT_EQ(ps.segments.size(), 1u) << k;
    const SegmentPrim& p = ps.segments[0];
    const SegmentFrame fr(p);
    ASSERT_TRUE(segmentUsesCapsule(ps, ps.primitiveCount() - 1));
    const SegmentDepth depth(v, p, WireDepth::Round, true);
    const PreparedFragmentSource source(ps);
    // Pixels along the wire and across it, out to twice the half width.
    for (int j = 0; j < 40; ++j) {
      const double t = -0.1 + 1.2 * U(rng), q = 4.0 * U(rng) - 2.0;
      const double wt = p.w0 + (p.w1 - p.w0) * std::clamp(t, 0.0, 1.0);
      const glm::dvec2 at = p.p0 + t * (p.p1 - p.p0) + q * wt * glm::dvec2(fr.nx, fr.ny);
      const int col = int(std::floor(at.x)), row = int(std::floor(at.y));
      if (col < 0 || row < 0 || col >= W || row >= H) continue;
      SurfaceDepth sd;
      ASSERT_TRUE(source.surfaceDepth(ps.primitiveCount() - 1, col, row, sd));
      const double zNear = depth.nearest(col, row, col + 1.0, row + 1.0);
      float zmin, zmax, zkey;
      depth.range(col, row, col + 0.5, row + 0.5, zNear, zmin, zmax, zkey);
      float sx[16], sy[16], out[16];
      for (int i = 0; i < 16; ++i) sx[i] = (i % 4 + 0.5f) / 4, sy[i] = (i / 4 + 0.5f) / 4;
      sd.atSamples(sx, sy, 16, out);
      for (int i = 0; i < 16; ++i) {
        // The resolve takes the solid near the ends (within its margin of the pixel's centre),
        // the model along the body, where the two differ by under kCapsuleSlack radii.
        const double x = col + double(sx[i]), y = row + double(sy[i]);
        const bool solid = WireCapsule::nearEnd(fr.t(col + 0.5, row + 0.5), fr.length, depth.endMargin, WireCapsule::kPixelSpread);
        const double exact = solid ? primitiveDepthAt(ps, ps.primitiveCount() - 1, x, y)
                                   : segmentDepthAt(v, p, fr, x, y, WireDepth::Round);
        const double tol = 2e-5 * exact;
        bool hit = true;
        if (solid) depth.capsule.depthAt(v, x, y, &hit);
        worstAgree = std::max(worstAgree, std::abs(out[i] - exact) / exact);
        EXPECT_NEAR(out[i], exact, tol) << k << " " << col << "," << row;
        EXPECT_NEAR(sd.at(sx[i], sy[i]), exact, tol) << k;
        if (!hit) {  // where it passes the solid nearest: the same in both precisions, and held
          ++missed;  // to the fragment's range by the resolve, so not bounded here
          continue;
        }
        ++(solid ? nearEnds : alongBody);
        EXPECT_GE(exact, double(zmin) - tol) << k << " " << col << "," << row;
        EXPECT_LE(exact, double(zmax) + tol) << k << " " << col << "," << row << " t " << t << " q " << q;
      }
      ++pixels;
    }
  }
  EXPECT_GT(pixels, 1000);
  EXPECT_GT(nearEnds, 1000);  // both ways are tried
  EXPECT_GT(alongBody, 1000);
  EXPECT_GT(missed, 100);
}


// One wire off the view's axis (so that the slide along it, SegmentTilt, is large) swept from
// slanting to end-on: the slide's share of the depth at points 0.7 half widths either side of
// the axis's middle (the model with the slide less the model without it) changes by a small part
// of the radius per step and is zero once the segment is end-on. Here the share reaches 0.43 r
// and changes by at most 0.016 r per step; before the slide faded with the depth radius's ramp
// it jumped by 0.86 r in one step at the turn (the shift then reached across much of the short
// segment, whose depth range is many radii when it points nearly at the eye).
TEST(WireFootprint, SlideFadesAsTheSegmentTurnsEndOn) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  const double r = 0.01, L = 0.2;
  double last = 0.0, largest = 0.0, worstStep = 0.0;
  int endOn = 0, full = 0;
  bool first = true;
  for (int i = 0; i <= 600; ++i) {
    const double a = 0.6 * i / 600.0;  // the axis's angle to the ray through e1
    // e1 a third of the way to the image's corner; e0 behind it, turning from the ray through e1
    // sideways, so that the axis's image runs obliquely to the line from the image centre (both
    // L and A of SegmentTilt nonzero).
    const glm::dvec3 e1(1.0, 0.7, -3.0), toward = glm::normalize(e1), side = glm::normalize(glm::cross(toward, glm::dvec3(0, 1, 0)));
    const glm::dvec3 e0 = e1 + L * (std::cos(a) * toward + std::sin(a) * side);
    const Scene s = oneWireScene(e0, e1, r);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    ASSERT_EQ(ps.segments.size(), 1u) << a;
    const SegmentPrim& p = ps.segments[0];
    const SegmentFrame fr(p);
    const SegmentEndKeys keys(v, p);
    const SegmentTilt tilt(v, p, fr);
    SegmentTilt still = tilt;
    still.shift0 = still.shiftT = 0.0;
    const glm::dvec2 mid = 0.5 * (p.p0 + p.p1);
    const glm::dvec2 n(fr.nx, fr.ny);
    const double w = 0.5 * (p.w0 + p.w1);
    double share = 0.0;
    for (double side : {-0.7, 0.7}) {
      const glm::dvec2 at = mid + side * w * n;
      share = std::max(share, std::abs(segmentDepthAt(v, p, fr, keys, tilt, at.x, at.y, WireDepth::Round) -
                                       segmentDepthAt(v, p, fr, keys, still, at.x, at.y, WireDepth::Round)));
    }
    if (p.flags & kSegmentEndOn) {
      ++endOn;
      EXPECT_EQ(tilt.shift0, 0.0) << a;
      EXPECT_EQ(tilt.shiftT, 0.0) << a;
    } else if (glm::length(p.p1 - p.p0) >= 2.0 * std::max(p.w0, p.w1)) {
      ++full;
    }
    largest = std::max(largest, share);
    if (!first) worstStep = std::max(worstStep, std::abs(share - last));
    last = share, first = false;
  }
  EXPECT_GT(endOn, 10);
  EXPECT_GT(full, 10);
  EXPECT_GT(largest, 0.3 * r);  // the slide matters here
  EXPECT_LT(worstStep, 0.1 * r) << "largest share " << largest / r << " r";
}

// A wire through the near plane, one end cut there and its image far off screen: the slide's
// bound counts only the part of the axis the image can show (|A| <= the image's farthest corner
// from its centre, grown by the polygon's reach and 2 px), so it stays within w (R + reach + 2) / (2 f) pixels
// rather than w |a0| / (2 f) (hundreds of pixels), and the rasteriser's ranges still hold the
// model's depth at every pixel the segment can cover.
TEST(WireFootprint, SlideBoundIgnoresTheAxisBeyondTheImage) {
  const int W = 800, H = 600;
  const ViewTransform v = wideView();
  const double R = std::hypot(400.0, 300.0);
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int pixels = 0, cut = 0;
  for (int k = 0; k < 40; ++k) {
    // From near the eye (beside it: partly behind the near plane) out to a point in the image.
    const glm::dvec3 e1 = v.eyePoint(100 + 600 * U(rng), 100 + 400 * U(rng), 1.0 + 2.0 * U(rng));
    const glm::dvec3 e0(0.3 * (U(rng) - 0.5), 0.3 * (U(rng) - 0.5), 0.02 - 0.03 * U(rng));
    const Scene s = oneWireScene(e0, e1, 0.003);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(W, H), st);
    if (ps.segments.size() != 1u) continue;
    const SegmentPrim& p = ps.segments[0];
    if (p.flags & kSegmentEndOn) continue;
    const SegmentFrame fr(p);
    const SegmentTilt tilt(v, p, fr);
    const double w = std::max(p.w0, p.w1), reach = segmentReach(p);
    const double far = std::max(glm::length(p.p0 - glm::dvec2(v.cx, v.cy)), glm::length(p.p1 - glm::dvec2(v.cx, v.cy)));
    if (far > 4.0 * R) ++cut;
    EXPECT_LE(tilt.shiftBound(v, p, fr) * fr.length, w * (R + reach + 2.0) / (2.0 * v.focal) * (1.0 + 1e-5)) << k << " end " << far << " px out";
    const SegmentDepth depth(v, p, WireDepth::Round);
    for (int j = 0; j < 400; ++j) {
      // Points within the reach of the axis (beyond the ends too), inside the image.
      const double t = 1.4 * U(rng) - 0.2, q = 2.0 * U(rng) - 1.0;
      const glm::dvec2 at = p.p0 + t * (p.p1 - p.p0) + q * reach * glm::dvec2(fr.nx, fr.ny);
      const int col = int(std::floor(at.x)), row = int(std::floor(at.y));
      if (col < 0 || row < 0 || col >= W || row >= H) continue;
      const double zNear = depth.nearest(col, row, col + 1.0, row + 1.0);
      float zmin, zmax, zkey;
      depth.range(col, row, col + 0.5, row + 0.5, zNear, zmin, zmax, zkey);
      for (int i = 0; i < 16; ++i) {
        const double x = col + (i % 4 + 0.5) / 4, y = row + (i / 4 + 0.5) / 4;
        if (fr.distance2(x, y) > reach * reach) continue;
        const double exact = segmentDepthAt(v, p, fr, x, y, WireDepth::Round);
        const double tol = 2e-6 * exact;
        EXPECT_GE(exact, double(zmin) - tol) << k << " " << col << "," << row;
        EXPECT_LE(exact, double(zmax) + tol) << k << " " << col << "," << row;
      }
      ++pixels;
    }
  }
  EXPECT_GT(cut, 10);  // most wires had an end far off screen
  EXPECT_GT(pixels, 2000);
}

// clampedRange against brute force: every clamp(l, -w, w) over the boxes lies in [a, b], and a
// and b are taken (the bound is the range itself, not a loose one).
TEST(WireFootprint, ClampedRangeIsTheRangeOfTheClampedOffset) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> U(-3.0, 3.0), P(0.0, 2.0);
  for (int k = 0; k < 2000; ++k) {
    double llo = U(rng), lhi = U(rng), wlo = P(rng), whi = P(rng);
    if (llo > lhi) std::swap(llo, lhi);
    if (wlo > whi) std::swap(wlo, whi);
    double a, b;
    clampedRange(llo, lhi, wlo, whi, a, b);
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) {
        const double l = i == 40 ? lhi : llo + (lhi - llo) * i / 40.0, w = j == 40 ? whi : wlo + (whi - wlo) * j / 40.0;
        const double c = std::clamp(l, -w, w);
        lo = std::min(lo, c), hi = std::max(hi, c);
      }
    EXPECT_LE(a, lo) << llo << " " << lhi << " " << wlo << " " << whi;
    EXPECT_GE(b, hi) << llo << " " << lhi << " " << wlo << " " << whi;
    EXPECT_NEAR(a, lo, 1e-12);
    EXPECT_NEAR(b, hi, 1e-12);
  }
}

// Beyond an end the slide takes the end's A, which may exceed the image's own radius R: wires
// pointing at the image centre from beyond its corner, their near end 1 to 11 pixels outside,
// their round cap reaching in. At every sample the polygon covers inside the image the slide is
// within shiftBound(). (It counts R plus the reach and two pixels; what a covered point can take
// beyond R is second order, |lat| |A| <= w R + w^2 / (2 R) or so, so the margin is generous, and
// a bound of R alone still passes here.)
TEST(WireFootprint, SlideBoundHoldsForACapReachingInAtTheCorner) {
  const ViewTransform v = wideView();
  int points = 0;
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double dist = 1.0 + 0.05 * k;  // pixels beyond the corner (0, 0) along the diagonal
    const glm::dvec2 dir = glm::normalize(glm::dvec2(-400.0, -300.0)), perp(-dir.y, dir.x);
    const glm::dvec2 q1 = dist * dir, q0 = q1 + 300.0 * dir;
    // q1 at depth 1, q0 at depth 1.5, a little sideways so that the axis misses the centre (L != 0)
    const glm::dvec3 e1 = v.eyePoint(q1.x + 3 * perp.x, q1.y + 3 * perp.y, 1.0);
    const glm::dvec3 e0 = v.eyePoint(q0.x - 40 * perp.x, q0.y - 40 * perp.y, 1.5);
    const Scene s = oneWireScene(e0, e1, 0.02, true);
    RenderStats st;
    const PreparedScene ps = prepareScene(s, test::smallOptions(800, 600), st);
    if (ps.segments.size() != 1u || (ps.segments[0].flags & kSegmentEndOn)) continue;
    const SegmentPrim& p = ps.segments[0];
    const SegmentFrame fr(p);
    const SegmentTilt tilt(v, p, fr);
    ScreenPolygon poly;
    segmentPolygon(p, poly);
    EdgeFunction edges[ScreenPolygon::kMaxVertices];
    const int ne = polygonEdges(poly, edges);
    for (int iy = 0; iy < 160; ++iy)
      for (int ix = 0; ix < 160; ++ix) {
        const double x = (ix + 0.5) / 8, y = (iy + 0.5) / 8;
        bool in = true;
        for (int e = 0; e < ne && in; ++e) in = edges[e](x, y) >= 0.0;
        if (!in) continue;
        ++points;
        const double t = fr.t(x, y), tc = std::clamp(t, 0.0, 1.0);
        const double w = p.w0 + (p.w1 - p.w0) * tc;
        const double lat = (x - fr.ax) * fr.nx + (y - fr.ay) * fr.ny;
        const double shift = std::clamp(lat, -w, w) * (tilt.shift0 + tilt.shiftT * tc);
        worst = std::max(worst, std::abs(shift) / tilt.shiftBound(v, p, fr));
      }
  }
  EXPECT_GT(points, 1000);
  EXPECT_LE(worst, 1.0);
}

// The rasteriser's per-pixel range against the model for a hand-built segment whose half width
// grows 30-fold along it at one depth (so that nothing in the axis's depth hides the tilt's
// range): every sample within a pixel of the outline, where mitres, stand-in subpixels and
// merged pieces are evaluated, lies in [zmin, zmax]. With the offset clamped to the widest half
// width over a pixel instead of clampedRange, 2,050 of 180,454 samples fell outside.
TEST(WireFootprint, PixelRangeHoldsTheTiltWhereTheWidthVaries) {
  const ViewTransform v = wideView();
  SegmentPrim p{};
  p.p0 = {100.0, 560.5};
  p.p1 = {300.0, 560.5};
  p.w0 = 2.0f, p.w1 = 60.0f;
  p.d0 = p.d1 = 2.0f;
  p.r0 = p.r1 = 0.0f;
  p.o0 = glm::vec2(0, p.w0), p.o1 = glm::vec2(0, p.w1);
  p.flags = 0;
  const SegmentFrame fr(p);
  ASSERT_NE(SegmentTilt(v, p, fr).lateral, 0.0);
  const SegmentDepth depth(v, p, WireDepth::Round);
  int bad = 0, n = 0;
  for (int row = 520; row < 600; ++row)
    for (int col = 100; col < 300; ++col) {
      const double zNear = depth.nearest(col, row, col + 1.0, row + 1.0);
      float zmin, zmax, zkey;
      depth.range(col, row, col + 0.5, row + 0.5, zNear, zmin, zmax, zkey);
      for (int i = 0; i < 16; ++i) {
        const double x = col + (i % 4 + 0.5) / 4, y = row + (i / 4 + 0.5) / 4;
        const double t = fr.t(x, y);
        if (t < 0 || t > 1) continue;
        const double w = p.w0 + (p.w1 - p.w0) * t, lat = (x - fr.ax) * fr.nx + (y - fr.ay) * fr.ny;
        if (std::abs(lat) > w + 1.0) continue;
        ++n;
        const double e = segmentDepthAt(v, p, fr, x, y, WireDepth::Round);
        if (e < double(zmin) * (1 - 1e-7) || e > double(zmax) * (1 + 1e-7)) ++bad;
      }
    }
  EXPECT_GT(n, 100000);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace wf
