// Robustness of the A-buffer renderer on extreme geometry (issue 7): coordinates scaled by 1e-6 and
// 1e6, segments thinner than 1e-3 px and longer than 1e6 px, 5,000 layers in one pixel,
// zero-length hairs, a 1x1 image. Each against an independent expectation: the same picture at
// unit scale, the exact area, the closed-form composite, the image without the dropped input,
// the brute-force reference.
#include "render/renderer.h"

#include "render_test_scenes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace wf {
namespace {

using test::V2;

double rmsDiff(const ImageRGBA& a, const ImageRGBA& b) {
  double sq = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      const double d = double(a.pixels[i][c]) - double(b.pixels[i][c]);
      sq += d * d;
    }
  return std::sqrt(sq / (4.0 * double(a.pixels.size())));
}

// A perspective scene with every kind of primitive: a shaded surface, shaded wires of world
// thickness, plain and depth-cued wires, all scaled about a point off the origin by `s` together
// with the camera (eye, target; near / far left to the bounds).
Scene scaledScene(double s) {
  Scene sc;
  sc.background = glm::vec4(0.0f);
  sc.lights = LightRig::studioRig(3);
  sc.lightsFollowCamera = true;
  const glm::dvec3 c(0.3, -0.2, 0.1);
  auto P = [&](glm::dvec3 p) { return (p + c) * s; };
  SceneSurface surf;
  const int n = 12;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = -1 + 2.0 * i / n, v = -1 + 2.0 * j / n;
      surf.mesh.positions.push_back(P({u, v, 0.3 * std::sin(2 * u) * std::cos(2 * v) - 0.4}));
    }
  test::addGridTriangles(surf.mesh, n);
  sc.surfaces.push_back(surf);
  SceneWire shaded;
  shaded.thickness = 0.03 * s;
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * std::numbers::pi * k / 16;
    shaded.lines.add({P({0.9 * std::cos(a), 0.9 * std::sin(a), 0.0}), P({0.3 * std::cos(a + 0.5), 0.3 * std::sin(a + 0.5), 0.5}),
                      P({0.0, 0.0, 0.8})});
  }
  sc.wires.push_back(shaded);
  SceneWire plain = shaded;
  plain.style = WireStyle::Plain;
  plain.thickness = 1.5;
  plain.thicknessInPixels = true;
  plain.colour = glm::vec3(0.2f, 0.9f, 0.4f);
  plain.lines = PolylineSet{};
  plain.lines.add({P({-1, -1, 0.2}), P({1, 1, 0.25})});
  sc.wires.push_back(plain);
  SceneWire cued = plain;
  cued.style = WireStyle::DepthCued;
  cued.lines = PolylineSet{};
  cued.lines.add({P({-1, 1, -0.2}), P({1, -1, 0.6})});
  sc.wires.push_back(cued);
  Camera cam;
  cam.eye = P({2.0, -3.0, 2.5});
  cam.target = P({0, 0, 0});
  cam.up = {0, 0, 1};
  cam.fovYDegrees = 35;
  sc.camera = cam;
  return sc;
}

// Scene and camera scaled together by 1e-6 and 1e6: the same picture. Expectation: RMS over all
// channels within 1e-4 of the unit-scale image (single-precision depths and areas), no NaN, on
// both shading paths; the unit-scale image is a real picture (more than 500 covered pixels).
TEST(RobustGeometry, CoordinatesScaledBy1eMinus6And1e6GiveTheSameImage) {
  for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
    RenderOptions o;
    o.width = 120;
    o.height = 90;
    o.shading = path;
    const RenderResult ref = render(scaledScene(1.0), o);
    ASSERT_GT(test::sumAlpha(ref.image), 500.0);
    for (double s : {1e-6, 1e6}) {
      const RenderResult r = render(scaledScene(s), o);
      ASSERT_TRUE(test::allFinite(r.image));
      EXPECT_LT(rmsDiff(r.image, ref.image), 1e-4) << "scale " << s;
      EXPECT_EQ(r.stats.segments, ref.stats.segments);
      EXPECT_EQ(r.stats.triangles, ref.stats.triangles);
    }
  }
}

// Segments thinner than 1e-3 px (down to 1e-7 px), at odd angles, with square ends: the total
// alpha is the exact area width x length (each fragment carries its exact area; the masks only
// decide hiding). Tolerance 1e-6 relative (float alpha summed over ~60 pixels). Nothing else in
// the image is touched, and no pixel is NaN.
TEST(RobustGeometry, SegmentsThinnerThan1e3PixelCoverTheirExactArea) {
  const int W = 64, H = 48;
  for (double width : {1e-3, 3.7e-4, 1e-5, 1e-7})
    for (const auto& [a, b] : {std::pair<V2, V2>{{3.3, 5.1}, {58.7, 41.9}}, {{10.25, 40.5}, {50.5, 7.75}}, {{5.5, 20.2}, {60.1, 20.9}}}) {
      Scene s = test::baseScene(W, H);
      s.wires.push_back(test::plainWire({{a, b}}, width, 5.0, W, H));
      const RenderResult r = render(s, test::smallOptions(W, H));
      ASSERT_TRUE(test::allFinite(r.image));
      const double want = width * glm::length(b - a);
      EXPECT_NEAR(test::sumAlpha(r.image) / want, 1.0, 1e-6) << "width " << width;
      // The exact per-pixel areas (the quad clipped to every pixel, test support) bound each
      // pixel: alpha within 1e-6 relative of its own exact area.
      const V2 d = glm::normalize(b - a), nrm(-d.y * width / 2, d.x * width / 2);
      const std::vector<double> areas = test::pixelAreas({{a + nrm, b + nrm, b - nrm, a - nrm}}, W, H);
      for (size_t i = 0; i < areas.size(); ++i)
        ASSERT_NEAR(r.image.pixels[i].w, areas[i], 1e-6 * areas[i] + 1e-12) << "pixel " << i << " width " << width;
    }
}

// Segments longer than 1e6 px (ends 1e7 px outside the image) crossing the image: the covered
// band inside the image has the exact area width x visible length (width / cos(theta) per
// column), checked in total within 1e-6 relative and per pixel against the exact clipped areas
// within 1e-6 absolute (double-precision screen coordinates of size 1e7: ~1e-9 rounding).
TEST(RobustGeometry, SegmentsLongerThan1e6PixelCoverTheExactVisibleBand) {
  const int W = 80, H = 60;
  for (double width : {2.0, 0.01})
    for (double slope : {0.0, 1e-6, 2.3e-6}) {
      const double L = 1e7;
      const V2 a(-L, 30.3 - slope * (L + 40)), b(L, 30.3 + slope * (L - 40));
      Scene s = test::baseScene(W, H);
      s.wires.push_back(test::plainWire({{a, b}}, width, 5.0, W, H));
      RenderOptions o = test::smallOptions(W, H);
      const RenderResult r = render(s, o);
      ASSERT_TRUE(test::allFinite(r.image));
      const double theta = std::atan(slope);
      const double want = W * width / std::cos(theta);
      EXPECT_NEAR(test::sumAlpha(r.image) / want, 1.0, 1e-6) << "width " << width << " slope " << slope;
      const V2 d = glm::normalize(b - a), nrm(-d.y * width / 2, d.x * width / 2);
      const std::vector<double> areas = test::pixelAreas({{a + nrm, b + nrm, b - nrm, a - nrm}}, W, H);
      int where = -1;
      EXPECT_LT(test::maxAlphaError(r.image, areas, &where), 1e-6) << "pixel " << where;
    }
}

// 5,000 layers in one pixel. Every layer a full-pixel translucent quad of opacity a = 2^-12
// (exact in float, as is 1 - a), one colour: alpha is the closed form 1 - (1 - a)^5000 and the
// colour c x alpha, whatever the budget K (K kept exactly, the rest blended into the tail,
// whose transmittance is the exact product). Tolerance 2e-4: 5000 float products, each
// rounding by at most 2^-24 relative (5000 x 6e-8 = 3e-4 relative of T = 0.29). Memory: the
// A-buffer's peak bytes are bounded by the budget, not the 5,000 layers: at most 1.15 x those
// with 500 layers, and below 64 KiB per pixel x 16 pixels x threads.
Scene layers(int count, float opacity, bool distinctColours) {
  Scene s;
  s.background = glm::vec4(0.0f);
  s.lights.ambient = glm::dvec3(1.0);
  Material m;
  m.phong.diffuse = glm::dvec3(1.0);
  m.phong.specular = glm::dvec3(0.0);
  m.opacity = opacity;
  s.materials = {m};
  SceneSurface surf;
  for (int k = 0; k < count; ++k) {
    const double z = -1e-3 * ((k * 7919) % count);  // depths in a scrambled order
    const std::uint32_t b = std::uint32_t(surf.mesh.positions.size());
    surf.mesh.positions.insert(surf.mesh.positions.end(), {{-2, -2, z}, {2, -2, z}, {2, 2, z}, {-2, 2, z}});
    const glm::vec3 c = distinctColours ? (z == 0.0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)) : glm::vec3(0.25f, 0.5f, 1.0f);
    for (int i = 0; i < 4; ++i) surf.mesh.colours.push_back(c);
    surf.mesh.triangles.push_back({b, b + 1, b + 2});
    surf.mesh.triangles.push_back({b, b + 2, b + 3});
  }
  s.surfaces.push_back(surf);
  Camera cam;
  cam.projection = Camera::Projection::Orthographic;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  cam.orthoHeight = 2;
  cam.nearPlane = 1;
  cam.farPlane = 20;
  s.camera = cam;
  return s;
}

TEST(RobustGeometry, FiveThousandTranslucentLayersInOnePixelMatchTheClosedForm) {
  const float a = 0x1p-12f;
  const double alpha = 1.0 - std::pow(1.0 - double(a), 5000);
  RenderOptions o;
  o.width = 4;
  o.height = 4;
  for (int budget : {1, 64, 4096}) {
    o.budget = budget;
    const RenderResult r = render(layers(5000, a, false), o);
    for (const glm::vec4& p : r.image.pixels) {
      ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w));
      EXPECT_NEAR(p.w, alpha, 2e-4) << "budget " << budget;
      EXPECT_NEAR(p.x, 0.25 * alpha, 2e-4);
      EXPECT_NEAR(p.z, 1.0 * alpha, 2e-4);
    }
    EXPECT_GE(r.stats.abuffer.maxFragmentsPerPixel, 5000u);
    EXPECT_LE(r.stats.abuffer.maxListLength, unsigned(budget));
    if (budget < 5000) {
      EXPECT_GT(r.stats.abuffer.tail, 0u);
    }
  }
  o.budget = 64;
  o.threads = 1;
  const RenderResult deep = render(layers(5000, a, false), o);
  const RenderResult shallow = render(layers(500, a, false), o);
  EXPECT_LE(double(deep.stats.abuffer.peakBytes), 1.15 * double(shallow.stats.abuffer.peakBytes));
  EXPECT_LT(deep.stats.abuffer.peakBytes, size_t(16) * 64 * 1024);
}

// 5,000 opaque layers in one pixel, submitted in scrambled depth order: the nearest wins, and
// the pixel is exactly its colour (red) with alpha 1, for any budget.
TEST(RobustGeometry, FiveThousandOpaqueLayersInOnePixelShowTheNearest) {
  RenderOptions o;
  o.width = 4;
  o.height = 4;
  for (int budget : {1, 64}) {
    o.budget = budget;
    const RenderResult r = render(layers(5000, 1.0f, true), o);
    for (const glm::vec4& p : r.image.pixels) {
      EXPECT_NEAR(p.w, 1.0, 1e-6);
      EXPECT_NEAR(p.x, 1.0, 1e-6);
      EXPECT_NEAR(p.y, 0.0, 1e-6);
    }
  }
}

// Zero-length hairs (two equal points, or a hair that is one point repeated) are dropped and
// counted (stats.droppedZeroLength), and the image is bit for bit the image without them.
TEST(RobustGeometry, ZeroLengthHairsAreDroppedCountedAndChangeNothing) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Scene with, without;
  for (Scene* s : {&with, &without}) {
    s->background = glm::vec4(0.1f, 0.1f, 0.1f, 1.0f);
    s->lights = LightRig::studioRig(2);
    s->lightsFollowCamera = true;
  }
  SceneWire hw, hwo;
  hw.thickness = hwo.thickness = 0.02;
  size_t zeroSegments = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::dvec3 root(U(rng), U(rng), U(rng) * 0.3);
    const glm::dvec3 tip = root + 0.2 * glm::dvec3(U(rng), U(rng), 1.0);
    if (i % 4 == 1) {
      hw.lines.add({root, root});  // a zero-length hair
      ++zeroSegments;
    } else if (i % 4 == 3) {
      hw.lines.add({root, root, root, root});  // one point, repeated
      zeroSegments += 3;
    } else {
      hw.lines.add({root, tip});
      hwo.lines.add({root, tip});
    }
  }
  with.wires.push_back(hw);
  without.wires.push_back(hwo);
  // The same camera for both (framing from the bounds would differ: the dropped hairs' roots
  // count in the bounds).
  Camera cam;
  cam.eye = {0.3, -3.5, 2.0};
  cam.target = {0, 0, 0};
  cam.up = {0, 0, 1};
  with.camera = without.camera = cam;
  for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
    RenderOptions o;
    o.width = 96;
    o.height = 72;
    o.shading = path;
    const RenderResult a = render(with, o), b = render(without, o);
    EXPECT_EQ(a.stats.droppedZeroLength, zeroSegments);
    EXPECT_EQ(a.stats.segments, b.stats.segments);
    ASSERT_TRUE(test::allFinite(a.image));
    EXPECT_EQ(test::maxDiff(a.image, b.image), 0.0);
    EXPECT_GT(test::sumAlpha(b.image), 0.0);
  }
}

// A 1x1 image: the A-buffer against the brute-force reference (64 x 64 stratified samples, exact
// shading on both). A lone triangle edge: alpha is the exact area (closed form, 0.5 for the
// diagonal) within 1e-6, the reference within 2e-3 (its stratified sampling). Overlapping
// triangle and wire: within one subpixel of the mask (1/32) plus the reference's 2e-3, in every
// channel. Framed from the bounds (no camera) on a 1x1 image: finite.
TEST(RobustGeometry, OneByOneImageMatchesTheReference) {
  Scene s = test::baseScene(1, 1);
  s.surfaces.push_back(test::screenSurface({{{0, 0}, {1, 0}, {0, 1}}}, 5.0, 1, 1, glm::vec3(0.8f, 0.5f, 0.2f)));
  RenderOptions o = test::smallOptions(1, 1);
  o.shading = ShadingPath::Exact;
  o.referenceSamples = 64;
  {
    const RenderResult r = render(s, o), ref = renderReference(s, o);
    EXPECT_NEAR(r.image.pixels[0].w, 0.5, 1e-6);
    EXPECT_NEAR(ref.image.pixels[0].w, 0.5, 2e-3);
    EXPECT_LT(test::maxDiff(r.image, ref.image), 2e-3);
  }
  s.wires.push_back(test::plainWire({{{-0.5, 0.2}, {1.5, 0.9}}}, 0.3, 4.0, 1, 1));
  s.wires.back().colour = glm::vec3(0.1f, 0.9f, 0.3f);
  {
    const RenderResult r = render(s, o), ref = renderReference(s, o);
    ASSERT_TRUE(test::allFinite(r.image));
    EXPECT_LT(test::maxDiff(r.image, ref.image), 1.0 / 32 + 2e-3);
  }
  Scene framed = s;
  framed.camera.reset();
  framed.lights = LightRig::studioRig(2);
  const RenderResult f = render(framed, o);
  ASSERT_TRUE(test::allFinite(f.image));
  EXPECT_LE(f.image.pixels[0].w, 1.0f);
}

}  // namespace
}  // namespace wf
