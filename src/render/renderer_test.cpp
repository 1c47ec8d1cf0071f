// Tests of the A-buffer renderer (renderer.h) on small scenes. Most use an orthographic camera
// at one pixel per world unit looking down -z (eye (0, 0, 10), so world (x, y, z) lands on
// screen (W/2 + x, H/2 - y) at view depth 10 - z), Plain wires of colour 1 and a transparent
// background, so that alpha is coverage and its exact value is the area of the screen polygon
// in each pixel, worked out here with clipRect (itself tested against shoelace sums in
// coverage_mask_test.cpp). Surfaces are lit by ambient 1 alone with diffuse 1 and no specular,
// so their radiance is their vertex colour.
#include "render/renderer.h"

#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"

#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

namespace wf {
namespace {

using namespace wf::test;








double shoelace(const Poly& v) {
  double s = 0;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) s += v[j].x * v[i].y - v[i].x * v[j].y;
  return 0.5 * s;
}





// A rectangle of half-width w around the segment p0-p1 (the paper's wire polygon, no caps).
Poly segmentRect(const V2& p0, const V2& p1, double w) {
  const V2 d = glm::normalize(p1 - p0), n(-d.y, d.x);
  return {p0 + n * w, p1 + n * w, p1 - n * w, p0 - n * w};
}

// Intersection of the lines a + t u and b + s v.
V2 intersect(const V2& a, const V2& u, const V2& b, const V2& v) {
  const double den = u.x * v.y - u.y * v.x;
  const double t = ((b.x - a.x) * v.y - (b.y - a.y) * v.x) / den;
  return a + t * u;
}

// ---- coverage ------------------------------------------------------------------------------

TEST(Render, RandomTriangleCoverageIsItsExactArea) {
  // Alpha in every pixel is the exact area of triangle ∩ pixel (fragments carry the exact
  // clipped area; a lone fragment adds its area): 1e-5 per pixel allows float areas; the sum
  // equals the shoelace area within 1e-4 relative.
  const int W = 64, H = 64;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(3.0, 61.0);
  for (int k = 0; k < 8; ++k) {
    Poly t{{U(rng), U(rng)}, {U(rng), U(rng)}, {U(rng), U(rng)}};
    const double area = std::abs(shoelace(t));
    if (area < 1.0) continue;
    Scene scene = baseScene(W, H);
    scene.surfaces.push_back(screenSurface({t}, 10.0, W, H));
    const RenderResult r = render(scene, smallOptions(W, H));
    EXPECT_NEAR(sumAlpha(r.image), area, 1e-4 * area) << "triangle " << k;
    int at = -1;
    EXPECT_LE(maxAlphaError(r.image, pixelAreas({t}, W, H), &at), 1e-5) << "triangle " << k << " pixel " << at;
    EXPECT_EQ(r.stats.triangles, 1u);
    EXPECT_EQ(r.stats.abuffer.merged, 0u);  // one primitive: nothing to merge
  }
}

TEST(Render, TrianglesSharingAnEdgeHaveNoCrackAndNoOverlap) {
  // One mesh, two triangles sharing the edge PQ (shared vertices), opposite vertices on either
  // side (union convex or not): each pixel's alpha is the union's exact area (the two pieces
  // of a seam pixel merge and add their areas), never above 1, and pixels on the seam that
  // the union covers wholly are exactly 1 (no crack), within float rounding (1e-6).
  const int W = 64, H = 64;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int seamFull = 0;
  for (int k = 0; k < 10; ++k) {
    const V2 P{12 + 40 * U(rng), 12 + 40 * U(rng)};
    const double ang = 2 * std::numbers::pi * U(rng), len = 10 + 20 * U(rng);
    V2 Q = P + len * V2(std::cos(ang), std::sin(ang));
    Q = glm::clamp(Q, V2(4), V2(60));
    const V2 d = glm::normalize(Q - P), n(-d.y, d.x);
    auto side = [&](double s) {
      const V2 r = P + (0.2 + 0.6 * U(rng)) * (Q - P) + s * (3 + 12 * U(rng)) * n;
      return glm::clamp(r, V2(2), V2(62));
    };
    const Poly A{P, Q, side(+1)}, B{Q, P, side(-1)};
    if (std::abs(shoelace(A)) < 1 || std::abs(shoelace(B)) < 1 || shoelace(A) * shoelace(B) <= 0) continue;
    Scene scene = baseScene(W, H);
    SceneSurface s;
    for (const V2& p : {P, Q, A[2], B[2]}) s.mesh.positions.push_back(world(p, 10.0, W, H));
    s.mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
    scene.surfaces.push_back(s);
    const RenderResult r = render(scene, smallOptions(W, H));
    const std::vector<double> want = pixelAreas({A, B}, W, H);
    int at = -1;
    EXPECT_LE(maxAlphaError(r.image, want, &at), 1e-5) << "case " << k << " pixel " << at;
    for (const glm::vec4& p : r.image.pixels) EXPECT_LE(p.w, 1.0f);
    // Pixels the seam crosses and the union covers wholly.
    for (int step = 0; step <= 200; ++step) {
      const V2 m = P + (step / 200.0) * (Q - P);
      const int px = int(m.x), py = int(m.y);
      if (want[size_t(py) * W + px] < 1 - 1e-12) continue;
      ++seamFull;
      EXPECT_NEAR(r.image.at(px, py).w, 1.0, 1e-6) << "crack at (" << px << "," << py << ")";
    }
    EXPECT_GT(r.stats.abuffer.merged, 0u);  // the seam pixels merged
  }
  EXPECT_GT(seamFull, 20);
}

TEST(Render, LinesOfAnyWidthCoverWidthTimesLength) {
  // Plain lines 0.05 ... 20 px wide at several angles: the wire polygon is the rectangle
  // width x length (no caps, as in the paper), so alpha sums to width * length (1e-3
  // relative) and each pixel holds the rectangle's exact area in it (1e-5).
  const int W = 128, H = 128;
  const double L = 60;
  for (double width : {0.05, 0.3, 1.0, 2.5, 7.0, 20.0})
    for (double deg : {0.0, 13.0, 45.0, 90.0, 121.0, 200.5}) {
      const double a = deg * std::numbers::pi / 180;
      const V2 c(64.3, 63.8), d(std::cos(a), std::sin(a));
      const V2 p0 = c - 0.5 * L * d, p1 = c + 0.5 * L * d;
      Scene scene = baseScene(W, H);
      scene.wires.push_back(plainWire({{p0, p1}}, width, 10.0, W, H));
      const RenderResult r = render(scene, smallOptions(W, H));
      const double want = width * L;
      EXPECT_NEAR(sumAlpha(r.image), want, 1e-3 * want) << "width " << width << " angle " << deg;
      int at = -1;
      EXPECT_LE(maxAlphaError(r.image, pixelAreas({segmentRect(p0, p1, width / 2)}, W, H), &at), 1e-5)
          << "width " << width << " angle " << deg << " pixel " << at;
      EXPECT_EQ(r.stats.endOnDiscs, 0u);
      if (width < 0.1) {
        // A 0.05 px line fades: no pixel holds more than the strip's width times the pixel's
        // diagonal, and it lights a pixel at least every unit of length (no gaps/aliasing).
        int lit = 0;
        for (const glm::vec4& p : r.image.pixels) {
          EXPECT_LE(p.w, width * std::sqrt(2.0) + 1e-6);
          lit += p.w > 0;
        }
        EXPECT_GE(lit, int(L) - 1);
      }
    }
}

// The largest tiles (TileBins::kMaxTileSize, whose bin items keep their rectangles in bytes): a
// wire across three of them, through their last and first columns and rows, still holds the
// exact area in every pixel (1e-5), as with the default tiles.
TEST(Render, WireAcrossTheLargestTilesHasItsExactAreaAtTheirEdges) {
  const int W = 600, H = 400;
  for (const V2& p0 : {V2(2.3, 380.6), V2(597.4, 3.2)}) {
    const V2 p1(W - p0.x, H - p0.y);
    Scene scene = baseScene(W, H);
    scene.wires.push_back(plainWire({{p0, p1}}, 2.5, 10.0, W, H));
    RenderOptions o = smallOptions(W, H);
    o.tileSize = TileBins::kMaxTileSize;
    const RenderResult r = render(scene, o);
    int at = -1;
    EXPECT_LE(maxAlphaError(r.image, pixelAreas({segmentRect(p0, p1, 1.25)}, W, H), &at), 1e-5) << "pixel " << at;
    EXPECT_NEAR(sumAlpha(r.image), 2.5 * glm::length(p1 - p0), 1e-3 * 2.5 * glm::length(p1 - p0));
  }
}

// A wire that keeps colours (plain) but whose polylines form no segment (one point each): the
// scene has no room for colours, and must still render, with nothing of that wire; with a shaded
// wire beside it, whose segment then gets the colours' room, that wire draws its exact area.
TEST(Render, WireOfNoSegmentThatKeepsColoursDrawsNothing) {
  const int W = 32, H = 32;
  Scene scene = baseScene(W, H);
  scene.wires.push_back(plainWire({{V2(10.5, 10.5)}, {V2(20.0, 5.0)}}, 2.0, 10.0, W, H));
  RenderResult r;
  ASSERT_NO_THROW(r = render(scene, smallOptions(W, H)));
  EXPECT_EQ(r.stats.segments, 0u);
  EXPECT_EQ(sumAlpha(r.image), 0.0);
  SceneWire shaded = plainWire({{V2(4.0, 16.0), V2(28.0, 16.0)}}, 2.0, 10.0, W, H);
  shaded.style = WireStyle::Shaded;
  scene.wires.push_back(shaded);
  ASSERT_NO_THROW(r = render(scene, smallOptions(W, H)));
  EXPECT_EQ(r.stats.segments, 1u);
  EXPECT_NEAR(sumAlpha(r.image), 2.0 * 24.0, 1e-3 * 48.0);
}

TEST(Render, PolylineJointIsAMitreWithoutOverlap) {
  // A polyline bending by 60 degrees (and, the other reading of "a 60-degree bend", by 120
  // degrees, an interior angle of 60): the outline is two quads meeting on the mitre line,
  // whose vertices are where the offset lines meet. Its area is exactly thickness * (L1 + L2)
  // (the mitre adds on the outside what it takes on the inside); alpha matches it in total
  // (1e-3 relative) and per pixel (1e-5), and no joint pixel exceeds 1.
  const int W = 128, H = 128;
  const double thickness = 6, w = thickness / 2, L1 = 40, L2 = 35;
  for (double turnDeg : {60.0, 120.0, -60.0}) {
    const double a1 = 0.3, a2 = a1 + turnDeg * std::numbers::pi / 180;
    const V2 d1(std::cos(a1), std::sin(a1)), d2(std::cos(a2), std::sin(a2));
    const V2 B(64.2, 63.7), A = B - L1 * d1, C = B + L2 * d2;
    const V2 n1(-d1.y, d1.x), n2(-d2.y, d2.x);
    const V2 mPlus = intersect(A + w * n1, d1, C + w * n2, d2), mMinus = intersect(A - w * n1, d1, C - w * n2, d2);
    const Poly q1{A + w * n1, mPlus, mMinus, A - w * n1}, q2{mPlus, C + w * n2, C - w * n2, mMinus};
    const double outline = std::abs(shoelace(q1)) + std::abs(shoelace(q2));
    ASSERT_NEAR(outline, thickness * (L1 + L2), 1e-9) << "the test's own geometry";
    Scene scene = baseScene(W, H);
    scene.wires.push_back(plainWire({{A, B, C}}, thickness, 10.0, W, H));
    const RenderResult r = render(scene, smallOptions(W, H));
    EXPECT_NEAR(sumAlpha(r.image), outline, 1e-3 * outline) << "turn " << turnDeg;
    int at = -1;
    EXPECT_LE(maxAlphaError(r.image, pixelAreas({q1, q2}, W, H), &at), 1e-5) << "turn " << turnDeg << " pixel " << at;
    for (int y = int(B.y) - 8; y <= int(B.y) + 8; ++y)
      for (int x = int(B.x) - 8; x <= int(B.x) + 8; ++x) EXPECT_LE(r.image.at(x, y).w, 1.0f + 1e-6f);
    EXPECT_EQ(r.stats.segments, 2u);
    EXPECT_GT(r.stats.abuffer.merged, 0u);  // the two pieces of the joint pixels merged
  }
}

// ---- visibility ----------------------------------------------------------------------------

TEST(Render, NearerOpaqueSurfaceHidesTheFartherOne) {
  // Red square [10, 40.5] x [10, 40] at depth 9, green [25, 55]^2 at depth 10. Overlap: red,
  // exactly (1, 0, 0, 1); green alone: green; the column x = 40 where red covers the left half
  // of pixels over green: 0.5 red + 0.5 green (the mask hides exactly the half behind red).
  // Both scene orders give the same image.
  const int W = 64, H = 64;
  for (int order = 0; order < 2; ++order) {
    Scene scene = baseScene(W, H);
    const SceneSurface red = screenRect(10, 10, 40.5, 40, 9.0, W, H, {1, 0, 0});
    const SceneSurface green = screenRect(25, 25, 55, 55, 10.0, W, H, {0, 1, 0});
    scene.surfaces = order ? std::vector<SceneSurface>{green, red} : std::vector<SceneSurface>{red, green};
    const RenderResult r = render(scene, smallOptions(W, H));
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        glm::vec4 want(0);
        const bool inRed = x >= 10 && x < 40 && y >= 10 && y < 40, inGreen = x >= 25 && x < 55 && y >= 25 && y < 55;
        if (inRed) want = {1, 0, 0, 1};
        else if (x == 40 && y >= 25 && y < 40) want = {0.5f, 0.5f, 0, 1};
        else if (x == 40 && y >= 10 && y < 25) want = {0.5f, 0, 0, 0.5f};
        else if (inGreen) want = {0, 1, 0, 1};
        const glm::vec4 got = r.image.at(x, y);
        for (int i = 0; i < 4; ++i) ASSERT_NEAR(got[i], want[i], 1e-5) << "(" << x << "," << y << ") channel " << i << " order " << order;
      }
  }
}

TEST(Render, TranslucentSurfacesCompositeInDepthOrder) {
  // Blue at depth 8 and red at depth 9, both of material opacity 0.5, over opaque green at
  // depth 10: 0.5 blue + 0.5 * 0.5 red + 0.25 green = (0.25, 0.25, 0.5), alpha 1. Where only
  // red lies over the transparent background: (0.5, 0, 0, 0.5).
  const int W = 64, H = 64;
  Scene scene = baseScene(W, H);
  Material half = scene.materials[0];
  half.opacity = 0.5f;
  scene.materials.push_back(half);
  scene.surfaces.push_back(screenRect(20, 20, 60, 60, 10.0, W, H, {0, 1, 0}, 0));
  scene.surfaces.push_back(screenRect(4, 4, 44, 44, 9.0, W, H, {1, 0, 0}, 1));
  scene.surfaces.push_back(screenRect(16, 16, 40, 40, 8.0, W, H, {0, 0, 1}, 1));
  const RenderResult r = render(scene, smallOptions(W, H));
  for (int y = 22; y < 38; ++y)
    for (int x = 22; x < 38; ++x) {
      const glm::vec4 got = r.image.at(x, y);
      const glm::vec4 want(0.25f, 0.25f, 0.5f, 1.0f);
      for (int i = 0; i < 4; ++i) ASSERT_NEAR(got[i], want[i], 1e-5) << "(" << x << "," << y << ") channel " << i;
    }
  for (int y = 5; y < 15; ++y)
    for (int x = 5; x < 15; ++x) {
      const glm::vec4 got = r.image.at(x, y);
      const glm::vec4 want(0.5f, 0, 0, 0.5f);
      for (int i = 0; i < 4; ++i) ASSERT_NEAR(got[i], want[i], 1e-5) << "(" << x << "," << y << ") channel " << i;
    }
  // Red over green without blue (x in [41, 44)): 0.5 red + 0.5 green, alpha 1.
  const glm::vec4 got = r.image.at(42, 30);
  EXPECT_NEAR(got.x, 0.5, 1e-5);
  EXPECT_NEAR(got.y, 0.5, 1e-5);
  EXPECT_NEAR(got.w, 1.0, 1e-5);
}

// ---- determinism ---------------------------------------------------------------------------

Scene randomScene(int W, int H, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Scene scene = baseScene(W, H);
  scene.lights = LightRig::studioRig(3);
  Camera c;
  c.eye = {0.3, -0.2, 6};
  c.fovYDegrees = 40;
  c.nearPlane = 1;
  c.farPlane = 20;
  scene.camera = c;
  Material glass;
  glass.opacity = 0.4f;
  scene.materials.push_back(glass);
  for (int s = 0; s < 3; ++s) {
    SceneSurface surf;
    surf.material = s == 2 ? 1 : 0;
    for (int t = 0; t < 60; ++t) {
      const std::uint32_t b = std::uint32_t(surf.mesh.positions.size());
      const glm::dvec3 o(4 * U(rng) - 2, 4 * U(rng) - 2, 2 * U(rng) - 1);
      for (int k = 0; k < 3; ++k) surf.mesh.positions.push_back(o + glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5));
      surf.mesh.triangles.push_back({b, b + 1, b + 2});
    }
    scene.surfaces.push_back(surf);
  }
  for (WireStyle style : {WireStyle::Plain, WireStyle::DepthCued, WireStyle::Shaded}) {
    SceneWire w;
    w.style = style;
    w.thickness = style == WireStyle::Plain ? 1.5 : 0.02;
    w.thicknessInPixels = style == WireStyle::Plain;
    w.opacity = style == WireStyle::DepthCued ? 0.7f : 1.0f;
    for (int l = 0; l < 20; ++l) {
      std::vector<glm::dvec3> pts;
      glm::dvec3 p(4 * U(rng) - 2, 4 * U(rng) - 2, 2 * U(rng) - 1);
      for (int k = 0; k < 6; ++k) {
        pts.push_back(p);
        p += glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5) * 0.6;
      }
      w.lines.add(pts);
    }
    scene.wires.push_back(w);
  }
  return scene;
}

TEST(Render, ImagesAreBitIdenticalWhateverTheThreadCount) {
  // Tiles are independent and each sorts its primitives deterministically, and set-up
  // concatenates its chunks in a fixed order: 1, 2 and 16 threads must give the same bits.
  const int W = 96, H = 80;
  const Scene scene = randomScene(W, H, 31);
  RenderOptions o = smallOptions(W, H);
  o.budget = 6;  // exercise the tails too
  std::vector<RenderResult> rs;
  for (int threads : {1, 2, 16}) {
    o.threads = threads;
    rs.push_back(render(scene, o));
  }
  ASSERT_GT(sumAlpha(rs[0].image), 100.0);  // the scene is not empty
  EXPECT_GT(rs[0].stats.abuffer.tail, 0u);
  for (size_t i = 1; i < rs.size(); ++i) {
    ASSERT_EQ(rs[i].image.pixels.size(), rs[0].image.pixels.size());
    EXPECT_EQ(0, std::memcmp(rs[i].image.pixels.data(), rs[0].image.pixels.data(),
                             rs[0].image.pixels.size() * sizeof(glm::vec4)))
        << "threads differ: run " << i;
    EXPECT_EQ(rs[i].stats.abuffer.fragments, rs[0].stats.abuffer.fragments);
    EXPECT_EQ(rs[i].stats.abuffer.merged, rs[0].stats.abuffer.merged);
    EXPECT_EQ(rs[i].stats.abuffer.culled, rs[0].stats.abuffer.culled);
    EXPECT_EQ(rs[i].stats.abuffer.tail, rs[0].stats.abuffer.tail);
    EXPECT_EQ(rs[i].stats.primitives, rs[0].stats.primitives);
  }
}

TEST(Render, ABandOfRowsIsTheWholeRendersRowsBitForBit) {
  // A sort-first split (RenderOptions::rowBegin / rowEnd): three bands, one not on a tile
  // boundary, each give the whole render's rows exactly; tiles wholly outside stay transparent.
  const int W = 96, H = 80;
  const Scene scene = randomScene(W, H, 31);
  RenderOptions o = smallOptions(W, H);
  o.budget = 6;
  const RenderResult whole = render(scene, o);
  ASSERT_GT(sumAlpha(whole.image), 100.0);
  for (auto [b, e] : {std::pair{0, 27}, std::pair{27, 64}, std::pair{64, 80}}) {
    o.rowBegin = b;
    o.rowEnd = e;
    const RenderResult part = render(scene, o);
    for (int y = b; y < e; ++y) {
      EXPECT_EQ(0, std::memcmp(&part.image.at(0, y), &whole.image.at(0, y), size_t(W) * sizeof(glm::vec4))) << "row " << y;
    }
    const int tile = o.tileSize;
    for (int y = 0; y < H; ++y) {
      if (y / tile * tile + tile <= b || y / tile * tile >= e) {
        for (int x = 0; x < W; ++x) {
          EXPECT_EQ(part.image.at(x, y), glm::vec4(0.0f)) << x << ", " << y;
        }
      }
    }
  }
  o.rowBegin = 5;
  o.rowEnd = 5;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
}

// ---- clipping and degenerate input ---------------------------------------------------------

TEST(Render, SegmentThroughTheNearPlaneDrawsOnlyItsFrontPart) {
  // A segment from behind the eye to far in front: it is clipped at the near plane; the image
  // equals that of the segment clipped by hand at depth = near (1e-6: the two clip points
  // differ by rounding only), and has no NaN.
  const int W = 64, H = 64;
  struct Case {
    bool ortho;
    glm::dvec3 a, b;  // world; eye at (0, 0, 10), depth = 10 - z
  };
  const Case cases[] = {
      {true, {-30, -10, 20}, {20, 15, -20}},     // depth -10 ... 30, near 1
      {false, {0.3, 0.2, 12}, {-1, -0.5, -5}},   // depth -2 ... 15, passes 0.15 from the eye
  };
  for (const Case& cs : cases) {
    Scene scene = baseScene(W, H);
    if (!cs.ortho) {
      Camera c;
      c.eye = {0, 0, 10};
      c.nearPlane = 1;
      c.farPlane = 100;
      scene.camera = c;
    }
    SceneWire w;
    w.style = WireStyle::Plain;
    w.thickness = 3;
    w.thicknessInPixels = true;
    w.lines.add({cs.a, cs.b});
    scene.wires = {w};
    const RenderResult r = render(scene, smallOptions(W, H));
    // By hand: depth(t) = 10 - z(t) = 1 at t = (10 - 1 - a.z) / (b.z - a.z) ... solve z = 9.
    const double t = (9.0 - cs.a.z) / (cs.b.z - cs.a.z);
    const glm::dvec3 m = cs.a + t * (cs.b - cs.a);
    SceneWire w2 = w;
    w2.lines = PolylineSet{};
    w2.lines.add({m, cs.b});
    Scene scene2 = scene;
    scene2.wires = {w2};
    const RenderResult r2 = render(scene2, smallOptions(W, H));
    EXPECT_TRUE(allFinite(r.image));
    EXPECT_GT(sumAlpha(r.image), 10.0) << (cs.ortho ? "ortho" : "persp");  // something drawn
    double worst = 0;
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
      for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(r.image.pixels[i][c] - r2.image.pixels[i][c])));
    EXPECT_LE(worst, 1e-6) << (cs.ortho ? "ortho" : "persp");
    EXPECT_EQ(r.stats.segments, 1u);
    EXPECT_EQ(r.stats.clippedAway, 0u);
  }
}

TEST(Render, TriangleThroughTheNearPlaneDrawsOnlyItsFrontPart) {
  // Perspective camera, a triangle with one vertex behind the eye: it renders like the quad
  // left in front of depth = near (clipped by hand, two triangles of one mesh), pixel by pixel
  // within 1e-5 (float areas; the seam of the hand-made quad merges).
  const int W = 64, H = 64;
  Scene scene = baseScene(W, H);
  Camera c;
  c.eye = {0, 0, 10};
  c.nearPlane = 2;
  c.farPlane = 100;
  scene.camera = c;
  const glm::dvec3 A(-1.5, -1, 0), B(1.5, -0.8, -1), C(0.2, 0.6, 11);  // C at depth -1
  SceneSurface s;
  s.mesh.positions = {A, B, C};
  s.mesh.triangles = {{0, 1, 2}};
  scene.surfaces = {s};
  const RenderResult r = render(scene, smallOptions(W, H));
  // Points on AC and BC at depth 2, i.e. z = 8.
  auto at8 = [](const glm::dvec3& p, const glm::dvec3& q) { return p + (8.0 - p.z) / (q.z - p.z) * (q - p); };
  const glm::dvec3 ac = at8(A, C), bc = at8(B, C);
  SceneSurface s2;
  s2.mesh.positions = {A, B, bc, ac};
  s2.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  Scene scene2 = scene;
  scene2.surfaces = {s2};
  const RenderResult r2 = render(scene2, smallOptions(W, H));
  EXPECT_TRUE(allFinite(r.image));
  EXPECT_GT(sumAlpha(r.image), 50.0);
  double worst = 0;
  for (size_t i = 0; i < r.image.pixels.size(); ++i) worst = std::max(worst, double(std::abs(r.image.pixels[i].w - r2.image.pixels[i].w)));
  EXPECT_LE(worst, 1e-5);
}

// A plain wire 10 px wide along the view axis (orthographic): seen end-on, its disc of r = 5 px
// centred at screen (35.3, 29.9).
Scene endOnDiscScene(int W, int H) {
  Scene scene = baseScene(W, H);
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = 10;
  w.thicknessInPixels = true;
  w.lines.add({{3.3, 2.1, 2}, {3.3, 2.1, -2}});
  scene.wires = {w};
  return scene;
}

TEST(Render, EndOnSegmentIsADisc) {
  // A segment along the view axis (orthographic): its screen length is 0, so it is drawn as
  // its end disc, a polygon scaled to the disc's area: coverage pi r^2, r = 5 px (1%).
  const int W = 64, H = 64;
  Scene scene = endOnDiscScene(W, H);
  const RenderResult r = render(scene, smallOptions(W, H));
  const double want = std::numbers::pi * 25;
  EXPECT_NEAR(sumAlpha(r.image), want, 0.01 * want);
  EXPECT_EQ(r.stats.endOnDiscs, 1u);
  // Round: full at the centre (screen (35.3, 29.9)), empty beyond r + 1 from it.
  EXPECT_NEAR(r.image.at(35, 29).w, 1.0f, 1e-6f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (std::hypot(x + 0.5 - 35.3, y + 0.5 - 29.9) > 5 + 1.5) {
        EXPECT_EQ(r.image.at(x, y).w, 0.0f) << x << "," << y;
      }
}

TEST(Render, PixelScaleScalesWidthsGivenInPixels) {
  // The end-on disc of EndOnSegmentIsADisc (r = 5 px) at pixel scale 0.5 has r = 2.5 px:
  // coverage pi 2.5^2 (1%); a wire whose width is in world units keeps its coverage.
  const int W = 64, H = 64;
  Scene scene = endOnDiscScene(W, H);
  RenderOptions o = smallOptions(W, H);
  o.pixelScale = 0.5;
  const double want = std::numbers::pi * 2.5 * 2.5;
  EXPECT_NEAR(sumAlpha(render(scene, o).image), want, 0.01 * want);
  scene.wires[0].thicknessInPixels = false;
  scene.wires[0].thickness = 0.2;
  const double world = sumAlpha(render(scene, smallOptions(W, H)).image);
  EXPECT_GT(world, 0.0);
  EXPECT_EQ(sumAlpha(render(scene, o).image), world);
  for (double bad : {0.0, -1.0, 1e-7, 2e6, std::nan(""), double(INFINITY)}) {
    o.pixelScale = bad;
    EXPECT_NE(o.problem().find("pixel scale"), std::string::npos) << bad;
  }
}

TEST(Render, ZeroLengthSegmentIsDroppedAndDrawsNothing) {
  const int W = 32, H = 32;
  Scene scene = baseScene(W, H);
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = 4;
  w.thicknessInPixels = true;
  w.lines.add({{1, 1, 0}, {1, 1, 0}});
  scene.wires = {w};
  const RenderResult r = render(scene, smallOptions(W, H));
  EXPECT_EQ(r.stats.droppedZeroLength, 1u);
  EXPECT_EQ(r.stats.segments, 0u);
  EXPECT_EQ(sumAlpha(r.image), 0.0);  // nothing drawn over the transparent background
  for (const glm::vec4& p : r.image.pixels) EXPECT_EQ(p, glm::vec4(0));
}

TEST(Render, NonFiniteVerticesAreSkippedWithAWarning) {
  // A mesh with one NaN triangle and one good one, a polyline with an Inf point in the middle
  // (both its segments touching it are rejected; the first is fine): 1 + 2 rejected, two
  // warnings (one per object), the good triangle and segment render with their exact areas.
  const int W = 64, H = 64;
  const double nan = std::nan(""), inf = INFINITY;
  Scene scene = baseScene(W, H);
  const Poly good{{5, 5}, {30, 8}, {12, 28}};
  SceneSurface s;
  s.name = "mesh";
  for (const V2& p : good) s.mesh.positions.push_back(world(p, 10, W, H));
  s.mesh.positions.push_back({nan, 0, 0});
  s.mesh.triangles = {{0, 3, 1}, {0, 1, 2}};
  scene.surfaces = {s};
  const V2 l0(40, 40), l1(60, 50);
  SceneWire w = plainWire({{l0, l1}}, 2.0, 10.0, W, H);
  w.name = "wire";
  w.lines = PolylineSet{};
  w.lines.add({world(l0, 10, W, H), world(l1, 10, W, H), {inf, 1, 0}, world({50, 60}, 10, W, H)});
  scene.wires = {w};
  const RenderResult r = render(scene, smallOptions(W, H));
  EXPECT_EQ(r.stats.rejectedNonFinite, 3u);
  EXPECT_EQ(r.stats.warnings.size(), 2u);
  EXPECT_EQ(r.stats.triangles, 1u);
  EXPECT_EQ(r.stats.segments, 1u);
  EXPECT_TRUE(allFinite(r.image));
  const double want = std::abs(shoelace(good)) + 2.0 * glm::length(l1 - l0);
  EXPECT_NEAR(sumAlpha(r.image), want, 1e-4 * want);
  int at = -1;
  EXPECT_LE(maxAlphaError(r.image, pixelAreas({good, segmentRect(l0, l1, 1.0)}, W, H), &at), 1e-5) << at;
}

// ---- leaving out what a scene does not need ------------------------------------------------

TEST(Render, BuildsOnlyTheMapsTheSceneNeeds) {
  const int W = 32, H = 32;
  RenderOptions o = smallOptions(W, H);
  o.shading = ShadingPath::Maps;
  auto wire = [&](WireStyle style, int material) {
    SceneWire w = plainWire({{{4, 4}, {28, 20}}}, 2.0, 10.0, W, H);
    w.style = style;
    w.material = material;
    return w;
  };
  Scene base = baseScene(W, H);
  base.materials.push_back(base.materials[0]);
  base.materials[1].phong.exponent = 7;
  {
    Scene s = base;  // Plain wires only: no maps, no spheres
    s.wires = {wire(WireStyle::Plain, 0), wire(WireStyle::Plain, 1)};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.pseudoReflectanceMaps, 0);
    EXPECT_EQ(r.stats.reflectanceSpheres, 0);
  }
  {
    Scene s = base;  // Shaded wires of two materials (three wires): one map per material
    s.wires = {wire(WireStyle::Shaded, 0), wire(WireStyle::Shaded, 1), wire(WireStyle::Shaded, 0),
               wire(WireStyle::Plain, 1)};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.pseudoReflectanceMaps, 2);
    EXPECT_EQ(r.stats.reflectanceSpheres, 0);
  }
  {
    Scene s = base;  // Shaded wires on the exact path: no tables at all
    s.wires = {wire(WireStyle::Shaded, 0)};
    RenderOptions oe = o;
    oe.shading = ShadingPath::Exact;
    EXPECT_EQ(render(s, oe).stats.pseudoReflectanceMaps, 0);
  }
  {
    Scene s = base;  // surfaces only: spheres (one per material used), no maps
    s.surfaces = {screenRect(2, 2, 10, 10, 10, W, H, glm::vec3(1), 0), screenRect(12, 12, 20, 20, 10, W, H, glm::vec3(1), 0)};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.pseudoReflectanceMaps, 0);
    EXPECT_EQ(r.stats.reflectanceSpheres, 1);
  }
  // The closed path (the default): one lobe table per exponent of a shaded wire or burnished
  // surface, nothing for plain wires or Phong surfaces, no maps or spheres at all.
  RenderOptions oc = o;
  oc.shading = ShadingPath::Closed;
  {
    Scene s = base;
    s.wires = {wire(WireStyle::Plain, 0), wire(WireStyle::Plain, 1)};
    s.surfaces = {screenRect(2, 2, 10, 10, 10, W, H, glm::vec3(1), 0)};
    const RenderResult r = render(s, oc);
    EXPECT_EQ(r.stats.lobeTables, 0);
    EXPECT_EQ(r.stats.pseudoReflectanceMaps + r.stats.reflectanceSpheres, 0);
    EXPECT_EQ(r.stats.lobeError, 0.0);
  }
  {
    Scene s = base;  // exponents 20 and 7, three shaded wires: two tables
    s.wires = {wire(WireStyle::Shaded, 0), wire(WireStyle::Shaded, 1), wire(WireStyle::Shaded, 0)};
    const RenderResult r = render(s, oc);
    EXPECT_EQ(r.stats.lobeTables, 2);
    EXPECT_EQ(r.stats.pseudoReflectanceMaps + r.stats.reflectanceSpheres, 0);
    EXPECT_EQ(r.stats.lobeError, 0.0);  // ambient light only: no specular to get wrong
    s.lights.lights = {DirectionalLight{glm::dvec3(0, 0, 1), glm::dvec3(1.0)}};
    s.materials[1].phong.specular = glm::dvec3(0.5);
    const RenderResult lit = render(s, oc);
    EXPECT_GT(lit.stats.lobeError, 0.0);
    EXPECT_LT(lit.stats.lobeError, 1e-8);
  }
  {
    Scene s = base;  // the same exponent in two materials: one table
    s.materials[1].phong.exponent = s.materials[0].phong.exponent;
    s.wires = {wire(WireStyle::Shaded, 0), wire(WireStyle::Shaded, 1)};
    EXPECT_EQ(render(s, oc).stats.lobeTables, 1);
  }
}

TEST(Render, EmptySceneTouchesNoTile) {
  // Nothing to draw: every tile is empty, no pixel needs a list, the image is the background.
  Scene s;
  s.background = glm::vec4(0.1f, 0.2f, 0.3f, 1.0f);
  RenderOptions o = smallOptions(40, 24);
  const RenderResult r = render(s, o);
  EXPECT_EQ(r.stats.tiles, 3u * 2u);  // ceil(40 / 16) x ceil(24 / 16)
  EXPECT_EQ(r.stats.tilesEmpty, r.stats.tiles);
  EXPECT_EQ(r.stats.abuffer.pixelsWithList, 0u);
  EXPECT_EQ(r.stats.abuffer.fragments, 0u);
  for (const glm::vec4& p : r.image.pixels) EXPECT_EQ(p, s.background);
}

TEST(Render, OpaqueQuadNeedsListsOnlyAtItsEdges) {
  const int W = 64, H = 64;
  RenderOptions o = smallOptions(W, H);
  {
    // Covering the image edge to edge (and beyond): every pixel is solid, even on the
    // diagonal where the two triangles' pieces merge into a whole pixel: no list anywhere.
    Scene s = baseScene(W, H);
    s.surfaces = {screenRect(-7.3, -5.1, 70.2, 71.9, 10, W, H, glm::vec3(1))};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.abuffer.pixelsWithList, 0u);
    EXPECT_EQ(r.stats.abuffer.pixelsSolidOnly, size_t(W) * H);
    EXPECT_EQ(r.stats.tilesEmpty, 0u);
    for (const glm::vec4& p : r.image.pixels) EXPECT_NEAR(p.w, 1.0f, 1e-6f);
  }
  {
    // Pixel-aligned edges [8, 56]^2: again every covered pixel is whole.
    Scene s = baseScene(W, H);
    s.surfaces = {screenRect(8, 8, 56, 56, 10, W, H, glm::vec3(1))};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.abuffer.pixelsWithList, 0u);
    EXPECT_EQ(r.stats.abuffer.pixelsSolidOnly, 48u * 48u);
  }
  {
    // Edges through pixel middles [8.5, 55.5]^2: the ring of 48 x 48 - 46 x 46 = 188 edge pixels
    // needs lists, the 46 x 46 inside are solid.
    Scene s = baseScene(W, H);
    s.surfaces = {screenRect(8.5, 8.5, 55.5, 55.5, 10, W, H, glm::vec3(1))};
    const RenderResult r = render(s, o);
    EXPECT_EQ(r.stats.abuffer.pixelsWithList, 188u);
    EXPECT_EQ(r.stats.abuffer.pixelsSolidOnly, 46u * 46u);
    EXPECT_EQ(r.stats.abuffer.coveredPixels, 48u * 48u);
  }
}

// ---- against the brute-force reference -----------------------------------------------------

TEST(Render, AgreesWithTheBruteForceReference) {
  // A few overlapping opaque triangles at different depths (one tilted) and two lines: the
  // A-buffer differs from 16 x 16 point samples per pixel only by mask quantisation where
  // edges overlap (about 1/32 in those pixels) and sampling noise: RMS alpha < 1/64.
  const int W = 64, H = 64;
  Scene scene = baseScene(W, H);
  SceneSurface s;
  auto addTri = [&](V2 a, V2 b, V2 c, double da, double db, double dc) {
    const std::uint32_t k = std::uint32_t(s.mesh.positions.size());
    s.mesh.positions.push_back(world(a, da, W, H));
    s.mesh.positions.push_back(world(b, db, W, H));
    s.mesh.positions.push_back(world(c, dc, W, H));
    s.mesh.triangles.push_back({k, k + 1, k + 2});
  };
  addTri({5, 7}, {50, 12}, {20, 45}, 10, 10, 10);
  addTri({30, 4}, {60, 40}, {12, 58}, 12, 8, 9);  // tilted, cuts through the first
  addTri({40, 30}, {62, 62}, {25, 60}, 7, 7, 7);
  scene.surfaces = {s};
  scene.wires = {plainWire({{{3, 60}, {60, 3}}, {{2, 20}, {40, 35}, {61, 22}}}, 1.7, 8.5, W, H)};
  RenderOptions o = smallOptions(W, H);
  o.referenceSamples = 16;
  const RenderResult a = render(scene, o), ref = renderReference(scene, o);
  double sq = 0;
  for (size_t i = 0; i < a.image.pixels.size(); ++i) {
    const double d = a.image.pixels[i].w - ref.image.pixels[i].w;
    sq += d * d;
  }
  const double rms = std::sqrt(sq / double(a.image.pixels.size()));
  EXPECT_LT(rms, 1.0 / 64) << "rms " << rms;
  EXPECT_GT(sumAlpha(ref.image), 1000.0);
  EXPECT_NEAR(sumAlpha(a.image), sumAlpha(ref.image), 0.01 * sumAlpha(ref.image));  // total coverage agrees
}

TEST(Render, MapShadingOfWiresIsWithinItsStatedErrorOfExactShading) {
  // Same geometry on both paths, so the same masks, areas and compositing weights w_i with
  // sum w_i = alpha <= 1: a pixel's premultiplied colour differs by sum w_i |dc_i| <= max |dc|,
  // and each fragment's |dc| is at most the map's error (stats.mapError: its max over 192 test
  // tangents; between test tangents and at texel corners the bilinear table error can be a
  // little larger, hence + 0.02) plus the change of the exact shading with the view ray, which
  // the map (built for V = +z) ignores (stats.orthographicError, 0 for an orthographic view).
  for (bool ortho : {true, false}) {
    const int W = 64, H = 64;
    Scene scene = baseScene(W, H);
    scene.lights = LightRig::studioRig(3);
    scene.materials[0] = Material{};
    if (!ortho) {
      Camera c;
      c.eye = {0, 0, 10};
      c.fovYDegrees = 45;
      c.nearPlane = 1;
      c.farPlane = 100;
      scene.camera = c;
    }
    SceneWire w;
    w.style = WireStyle::Shaded;
    w.thickness = 3;
    w.thicknessInPixels = true;
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const double s = ortho ? 25.0 : 3.5;  // world extent that fills the image
    for (int l = 0; l < 8; ++l) {
      std::vector<glm::dvec3> pts;
      glm::dvec3 p(s * 0.8 * U(rng), s * 0.8 * U(rng), 2 * U(rng));
      for (int k = 0; k < 4; ++k) {
        pts.push_back(p);
        p += glm::dvec3(U(rng), U(rng), U(rng)) * (0.3 * s);
      }
      w.lines.add(pts);
    }
    // Single straight segments too: their tangent is constant, so the map path shades them
    // with one lookup per segment (Primitive::constantColour), the joints' polylines per
    // fragment.
    for (int l = 0; l < 6; ++l) {
      const glm::dvec3 p(s * 0.8 * U(rng), s * 0.8 * U(rng), 2 * U(rng));
      w.lines.add({p, p + glm::dvec3(U(rng), U(rng), U(rng)) * (0.4 * s)});
    }
    scene.wires = {w};
    RenderOptions o;
    o.width = W;
    o.height = H;
    o.shading = ShadingPath::Maps;
    const RenderResult maps = render(scene, o);
    o.shading = ShadingPath::Exact;
    const RenderResult exact = render(scene, o);
    const double bound = maps.stats.mapError + maps.stats.orthographicError + 0.02;
    EXPECT_GT(maps.stats.mapError, 0.0);
    EXPECT_LT(maps.stats.mapError, 0.01);  // the default 128^2 map (pseudo_reflectance_map.h: < 2e-3)
    if (ortho) {
      EXPECT_EQ(maps.stats.orthographicError, 0.0);
    } else {
      EXPECT_GT(maps.stats.orthographicError, 0.0);
    }
    double worst = 0;
    for (size_t i = 0; i < maps.image.pixels.size(); ++i) {
      EXPECT_EQ(maps.image.pixels[i].w, exact.image.pixels[i].w);  // identical coverage
      for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(maps.image.pixels[i][c] - exact.image.pixels[i][c])));
    }
    EXPECT_LE(worst, bound) << (ortho ? "ortho" : "persp") << " mapError " << maps.stats.mapError << " orthoError "
                            << maps.stats.orthographicError;
    EXPECT_GT(sumAlpha(maps.image), 200.0);
  }
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

// Perspective-correct interpolation: a plane seen at a slant, (u, v) = (x, y) of the plane and a
// tangent along +x. At any pixel the interpolated (u, v) must be that of the point where the
// pixel's ray meets the plane (computed independently here), not the screen-linear blend.
TEST(Render, TriangleAttributesArePerspectiveCorrect) {
  Scene scene;
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.uvs = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  m.tangents = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.surfaces.push_back({"plane", m, 0});
  Camera cam;
  cam.eye = {0.3, -2.5, 1.2};  // a steep slant: screen-linear interpolation would be far off
  cam.target = {0, 0, 0};
  cam.up = {0, 0, 1};
  cam.fovYDegrees = 60;
  cam.nearPlane = 0.1;
  cam.farPlane = 10;
  scene.camera = cam;
  RenderOptions o;
  o.width = 200;
  o.height = 150;
  RenderStats st;
  const PreparedScene ps = prepareScene(scene, o, st);
  const glm::dmat3 worldFromEye = glm::transpose(ps.view.eyeFromWorld);
  int checked = 0;
  double worst = 0;
  for (std::uint32_t i = 0; i < ps.triangles.size(); ++i)
    for (int k = 0; k < 200; ++k) {
      const TrianglePrim& prim = ps.triangles[i];
      const double x = prim.bbox[0] + (prim.bbox[2] - prim.bbox[0]) * ((k * 37) % 100) / 100.0;
      const double y = prim.bbox[1] + (prim.bbox[3] - prim.bbox[1]) * ((k * 61) % 100) / 100.0;
      // The ray through (x, y) meets z = 0 at world point Q; (u, v) there is (Q.x, Q.y).
      const glm::dvec3 dirEye((x - ps.view.cx) / ps.view.focal, -(y - ps.view.cy) / ps.view.focal, -1.0);
      const glm::dvec3 dir = worldFromEye * dirEye;
      const double t = -cam.eye.z / dir.z;
      const glm::dvec3 Q = cam.eye + t * dir;
      const SurfaceSample s = interpolateSurface(ps, i, x, y);
      const glm::dvec3 b = s.barycentric;
      if (std::min({b.x, b.y, b.z}) <= 1e-9) continue;  // outside this triangle: clamped
      worst = std::max({worst, std::abs(s.uv.x - Q.x), std::abs(s.uv.y - Q.y)});
      // The tangent +x of the world, in eye space.
      const glm::dvec3 T = ps.view.eyeFromWorld * glm::dvec3(1, 0, 0);
      EXPECT_NEAR(glm::length(s.tangent - T), 0.0, 1e-12);
      ++checked;
    }
  EXPECT_GT(checked, 100);
  EXPECT_LT(worst, 1e-9) << "(u, v) must be the ray-plane intersection's";
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

Scene scaledScene(double scale) {
  Scene s;
  s.background = glm::vec4(0.0f);
  TriangleMesh m;
  m.positions = {{-1 * scale, -1 * scale, 0}, {1 * scale, -0.8 * scale, 0.2 * scale}, {0.1 * scale, 1 * scale, -0.3 * scale}};
  m.triangles = {{0, 1, 2}};
  s.surfaces.push_back({"tri", m, 0});
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = 0.05 * scale;  // world units: scales with the scene
  w.lines.add({{-1.2 * scale, 0.9 * scale, 0.5 * scale}, {1.1 * scale, -0.7 * scale, -0.4 * scale}, {1.3 * scale, 1.0 * scale, 0.1 * scale}});
  s.wires.push_back(w);
  return s;  // no camera: framed from the bounds, near and far fitted
}

// Coordinates from 1e-6 to 1e6: the same scene at three scales, framed automatically, gives the
// same image (the camera, clipping and rasterisation are scale-invariant up to rounding).
TEST(Render, SameImageForCoordinatesFrom1eMinus6To1e6) {
  RenderOptions o;
  o.width = 96;
  o.height = 72;
  const RenderResult ref = render(scaledScene(1.0), o);
  double covered = 0;
  for (const glm::vec4& p : ref.image.pixels) covered += p.w;
  ASSERT_GT(covered, 200.0);  // a real picture (measured 263 covered pixels), not an empty one
  for (double scale : {1e-6, 1e6}) {
    const RenderResult r = render(scaledScene(scale), o);
    double worst = 0;
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
      for (int c = 0; c < 4; ++c) {
        ASSERT_TRUE(std::isfinite(r.image.pixels[i][c]));
        worst = std::max(worst, double(std::abs(r.image.pixels[i][c] - ref.image.pixels[i][c])));
      }
    // Single-precision depths and areas: agreement to 1e-4 per channel.
    EXPECT_LT(worst, 1e-4) << "scale " << scale;
  }
}

// Thousands of layers in one pixel: 3000 translucent quads over the whole image. Finite, alpha
// in [0, 1], the budget keeps K exact and blends the rest, and the pixel is the closed form
// 1 - 0.99^3000 of alpha (every layer full-pixel, opacity 0.01) within the tail's approximation.
TEST(Render, ThousandsOfLayersPerPixelStayFiniteAndBounded) {
  Scene s;
  s.background = glm::vec4(0.0f);
  Material glass;
  glass.opacity = 0.01f;
  s.materials = {Material{}, glass};
  TriangleMesh m;
  for (int k = 0; k < 3000; ++k) {
    const double z = -k * 1e-3;
    const uint32_t b = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {{-2, -2, z}, {2, -2, z}, {2, 2, z}, {-2, 2, z}});
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b, b + 2, b + 3});
  }
  s.surfaces.push_back({"layers", m, 1});
  Camera cam;
  cam.projection = Camera::Projection::Orthographic;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  cam.up = {0, 1, 0};
  cam.orthoHeight = 2;
  cam.nearPlane = 1;
  cam.farPlane = 10;
  s.camera = cam;
  RenderOptions o;
  o.width = 16;
  o.height = 16;
  o.budget = 64;
  const RenderResult r = render(s, o);
  EXPECT_GT(r.stats.abuffer.tail, 0u);
  for (const glm::vec4& p : r.image.pixels) {
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.w));
    EXPECT_GE(p.w, 0.0f);
    EXPECT_LE(p.w, 1.0f);
    EXPECT_NEAR(p.w, 1.0 - std::pow(0.99, 3000), 1e-3);
  }
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

Scene hairBall(int hairs) {
  Scene s;
  s.background = glm::vec4(0.0f);
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = 1.2;
  w.thicknessInPixels = true;
  w.opacity = 0.3f;  // translucent: nothing settles, every fragment is kept or blended
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int i = 0; i < hairs; ++i) {
    const glm::dvec3 a(U(rng), U(rng), U(rng)), d(U(rng), U(rng), U(rng));
    w.lines.add({a * 0.8, a * 0.8 + d * 0.3});
  }
  s.wires.push_back(w);
  return s;
}

// The tile buffers' memory is bounded by the budget K, not by the depth complexity: doubling the
// hairs doubles the fragments but not the peak bytes of the A-buffer (lists hold at most K; the
// rest blend into one tail per pixel).
TEST(Render, BufferMemoryIsBoundedByTheBudgetNotTheDepthComplexity) {
  RenderOptions o;
  o.width = 96;
  o.height = 72;
  o.budget = 8;
  o.threads = 1;
  const RenderResult a = render(hairBall(4000), o);
  const RenderResult b = render(hairBall(8000), o);
  ASSERT_GT(a.stats.abuffer.maxFragmentsPerPixel, 40u);  // a deep scene
  EXPECT_GT(double(b.stats.abuffer.fragments), 1.8 * double(a.stats.abuffer.fragments));
  EXPECT_GT(b.stats.abuffer.tail, a.stats.abuffer.tail);
  EXPECT_LE(b.stats.abuffer.maxListLength, 8u);
  EXPECT_LE(double(b.stats.abuffer.peakBytes), 1.15 * double(a.stats.abuffer.peakBytes))
      << a.stats.abuffer.peakBytes << " -> " << b.stats.abuffer.peakBytes;
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

// A wire lying exactly on a surface (a CAD edge on its face, a mesh's own edge) is drawn at its
// visible front, one radius in front of its axis, so it shows whole: the same picture, within
// rounding, as with the wire lifted clearly in front of the surface. Drawn at the axis depth it
// tied with the surface pixel by pixel and came out dashed (worst difference about 1).
TEST(WireOnSurface, ShowsWholeNotDashed) {
  const int W = 64, H = 48;
  auto depthAt = [](const V2& p) { return 5.0 + 0.013 * p.x + 0.007 * p.y; };  // a tilted plane
  auto render = [&](double lift) {
    Scene s = test::baseScene(W, H);
    SceneSurface plane;
    for (const V2& p : {V2(2, 2), V2(62, 2), V2(62, 46), V2(2, 46)}) {
      plane.mesh.positions.push_back(test::world(p, depthAt(p), W, H));
      plane.mesh.colours.push_back(glm::vec3(1, 0, 0));
    }
    plane.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.surfaces.push_back(plane);
    SceneWire w = test::plainWire({}, 1.5, 0.0, W, H);
    std::vector<glm::dvec3> pts;
    for (int k = 0; k <= 20; ++k) {
      const V2 p(6 + 2.6 * k, 8 + 1.5 * k);
      pts.push_back(test::world(p, depthAt(p) - lift, W, H));
    }
    w.lines.add(pts);
    s.wires.push_back(w);
    return wf::render(s, test::smallOptions(W, H)).image;
  };
  const ImageRGBA onPlane = render(0.0), lifted = render(0.5);
  EXPECT_LT(test::maxDiff(onPlane, lifted), 1e-3);
}

}  // namespace
}  // namespace wf
