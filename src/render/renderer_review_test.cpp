// Review tests of the A-buffer renderer: edge cases of rasterisation (huge coordinates, vertices
// on pixel boundaries, polygons wider than a tile), depth ranges of perspective primitives that
// recede towards the horizon, polyline joints, occlusion culling's error bound, view grids and
// degenerate cameras. Same conventions as renderer_test.cpp: an orthographic camera at one
// pixel per world unit looking down -z from (0, 0, 10) (world (x, y, z) -> screen
// (W/2 + x, H/2 - y), view depth 10 - z), Plain wires of colour 1, transparent background, so
// alpha is coverage.
#include "render/renderer.h"

#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"
#include "render/view_tables.h"

#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace wf {
namespace {

using namespace wf::test;

// ---- rasterisation: exact area ---------------------------------------------------------------

TEST(RenderReview, TriangleReachingFarOutsideTheImageKeepsAllItsRows) {
  // Triangle (-3e9, 2), (10, 2), (10, 12) (a far-away vertex, as after near-plane clipping of a
  // large ground polygon). Inside the 16 x 16 image it covers x in [max(0, left edge), 10] of
  // rows 2 ... 11: the left edge moves by 3e8 px per row, so rows 2 ... 10 are fully covered
  // on [0, 10] (10 px each) and row 11 mostly. Expected alpha per pixel: the clipped polygon's
  // exact area (clipRect), 1e-4 (the area integral works with 3e9-sized terms: ~1e-6 rounding).
  // Bug: renderer.cpp:99 converts floorToInt(xmin) = -3e9 to int, which wraps to +1.29e9, so
  // c0 > c1 and rows whose band reaches x < -2^31 (rows 2, 3, 4) are dropped: 30 px missing.
  const int W = 16, H = 16;
  const Poly tri{{-3.0e9, 2}, {10, 2}, {10, 12}};
  Scene scene = baseScene(W, H);
  scene.surfaces.push_back(screenSurface({tri}, 10.0, W, H));
  const RenderResult r = render(scene, smallOptions(W, H));
  const std::vector<double> want = pixelAreas({tri}, W, H);
  double wantSum = 0;
  for (double a : want) wantSum += a;
  ASSERT_GT(wantSum, 95.0);  // the test's own geometry: about 9 full rows of 10 px and most of row 11
  EXPECT_NEAR(sumAlpha(r.image), wantSum, 1e-3);
  int at = -1;
  EXPECT_LE(maxAlphaError(r.image, want, &at), 1e-4) << "pixel (" << at % W << ", " << at / W << ")";
  EXPECT_NEAR(r.image.at(5, 2).w, 1.0f, 1e-4f) << "row 2 is fully covered on [0, 10]";
}

TEST(RenderReview, TriangleReachingFarRightOfTheImageKeepsAllItsRows) {
  // The mirror image: a vertex at x = +3e9. Bug: int(ceilToInt(xmax)) - 1 wraps negative
  // (renderer.cpp:100), c1 < c0, rows dropped.
  const int W = 16, H = 16;
  const Poly tri{{3.0e9, 2}, {6, 12}, {6, 2}};
  Scene scene = baseScene(W, H);
  scene.surfaces.push_back(screenSurface({tri}, 10.0, W, H));
  const RenderResult r = render(scene, smallOptions(W, H));
  const std::vector<double> want = pixelAreas({tri}, W, H);
  int at = -1;
  EXPECT_LE(maxAlphaError(r.image, want, &at), 1e-4) << "pixel (" << at % W << ", " << at / W << ")";
  EXPECT_NEAR(r.image.at(10, 2).w, 1.0f, 1e-4f) << "row 2 is fully covered on [6, 16]";
}

TEST(RenderReview, PixelAlignedRectanglesAreExactAndSolidInside) {
  // A rectangle [3, 29] x [5, 21] (vertices on pixel corners, crossing the 16 px tile borders)
  // split into two triangles: every pixel inside has alpha exactly 1, colour exactly 1, every
  // pixel outside 0. Inside pixels become solid (the two halves merge along the diagonal),
  // so only diagonal pixels can need a list; none does here beyond the diagonal ones.
  const int W = 32, H = 32;
  Scene scene = baseScene(W, H);
  scene.surfaces.push_back(screenRect(3, 5, 29, 21, 10.0, W, H, glm::vec3(1)));
  const RenderResult r = render(scene, smallOptions(W, H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool in = x >= 3 && x < 29 && y >= 5 && y < 21;
      ASSERT_EQ(r.image.at(x, y).w, in ? 1.0f : 0.0f) << x << "," << y;
      ASSERT_NEAR(r.image.at(x, y).x, in ? 1.0f : 0.0f, 1e-6f) << x << "," << y;
    }
  EXPECT_EQ(r.stats.abuffer.pixelsWithList, 0u);  // the diagonal pieces merge into solids too
}

TEST(RenderReview, ThinSliversAndHalfPixelEdgesHaveTheirExactArea) {
  // Polygons with vertical and horizontal edges at x.5 and on integers, and slivers 0.01 px
  // thin (no sample hit): each pixel's alpha is its exact area (1e-5).
  const int W = 32, H = 32;
  const std::vector<Poly> tris{
      {{2.5, 2.0}, {20.5, 2.0}, {2.5, 9.5}},       // vertical and horizontal edges
      {{3.0, 12.0}, {28.0, 12.01}, {3.0, 12.02}},  // a sliver 0.02 px high, 25 px long
      {{25.0, 14.0}, {25.01, 30.0}, {25.02, 14.0}},  // a vertical sliver
  };
  Scene scene = baseScene(W, H);
  for (const Poly& t : tris) scene.surfaces.push_back(screenSurface({t}, 10.0, W, H));
  const RenderResult r = render(scene, smallOptions(W, H));
  int at = -1;
  EXPECT_LE(maxAlphaError(r.image, pixelAreas(tris, W, H), &at), 1e-5) << "pixel (" << at % W << ", " << at / W << ")";
}

// ---- depth of perspective primitives receding towards the horizon -------------------------------

// A perspective camera at the origin looking down -z, 40 x 40 px, fov 30 deg.
Camera perspectiveCamera() {
  Camera c;
  c.eye = {0, 0, 0};
  c.target = {0, 0, -1};
  c.up = {0, 1, 0};
  c.fovYDegrees = 30;
  c.nearPlane = 0.5;
  c.farPlane = 1000;
  return c;
}

// One plain wire `thicknessPx` pixels wide through eye-space points (perspectiveCamera's eye is
// the world's origin), on a clear background.
Scene perspectiveWire(std::vector<glm::dvec3> points, double thicknessPx) {
  Scene scene;
  scene.camera = perspectiveCamera();
  scene.background = glm::vec4(0.0f);
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = thicknessPx;
  w.thicknessInPixels = true;
  w.lines.add(std::move(points));
  scene.wires.push_back(w);
  return scene;
}

TEST(RenderReview, FarEndOfARecedingWireStaysBehindANearerSurface) {
  // A Plain wire (2 px wide, colour white) nearly along the view direction from depth 1 to
  // depth 50, its vanishing point 0.3 px above its far end; an
  // opaque red quad at depth 5 covers the screen region of the wire's far part (depth >= 9).
  // True picture: the quad hides the far part everywhere, so every pixel whose square lies
  // inside the quad is pure red (1, 0, 0, 1): the wire's depth there is >= 9 > 5.
  // Bug: depthRange (renderer.cpp:159) takes the depth at the pixel's corners from 1/d
  // extrapolated over the pixel square; at the far end the extrapolated key is <= 0 (beyond
  // the vanishing point), 1/key is negative, and clamping it to [zlo, zhi] gives zmin = zkey =
  // zlo = 1: the far tip sorts in front of the quad and shows white over red.
  const int W = 40, H = 40;
  Scene scene;
  scene.camera = perspectiveCamera();
  scene.background = glm::vec4(0.0f);
  scene.lights.ambient = glm::dvec3(1.0);
  scene.materials[0].phong.diffuse = glm::dvec3(1.0);
  scene.materials[0].phong.specular = glm::dvec3(0.0);
  const ViewTransform v = ViewTransform::make(*scene.camera, W, H);
  // The wire: eye-space points (0.02, -0.2 + dy d, -d), d from 1 to 50: its vanishing point is
  // at screen y = cy - focal dy = cy + 0.6, its far end at cy + 0.6 + focal 0.2 / 50 (0.9 below
  // cy): in pixel row cy, whose centre and top corners lie beyond the vanishing point.
  const double d0 = 1, d1 = 50, dy = -0.6 / v.focal;
  const double tipY = v.cy + v.focal * 0.2 / d1 + 0.6;
  ASSERT_EQ(int(std::floor(tipY)), int(v.cy));
  SceneWire wire;
  wire.style = WireStyle::Plain;
  wire.thickness = 2;
  wire.thicknessInPixels = true;
  wire.colour = glm::vec3(1.0f);
  wire.lines.add({{0.02, -0.2 + dy * d0, -d0}, {0.02, -0.2 + dy * d1, -d1}});
  scene.wires.push_back(wire);
  // The red quad at depth 5, covering screen y in [cy - 3, cy + 0.6 + focal * 0.2 / 9] (the
  // wire's part beyond depth 9) and x in [cx - 6, cx + 6].
  const double zq = 5, yTop = v.cy - 3, yBot = v.cy + v.focal * 0.2 / 9 + 0.6, xl = v.cx - 6, xr = v.cx + 6;
  auto eye = [&](double x, double y) { return v.eyePoint(x, y, zq); };
  SceneSurface quad;
  quad.mesh.positions = {eye(xl, yTop), eye(xr, yTop), eye(xr, yBot), eye(xl, yBot)};
  quad.mesh.colours = std::vector<glm::vec3>(4, glm::vec3(1, 0, 0));
  quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.surfaces.push_back(quad);
  RenderOptions o = smallOptions(W, H);
  const RenderResult r = render(scene, o);
  int bad = 0;
  for (int y = int(std::ceil(yTop)); y + 1 <= int(std::floor(yBot)); ++y)
    for (int x = int(std::ceil(xl)); x + 1 <= int(std::floor(xr)); ++x) {
      const glm::vec4 p = r.image.at(x, y);
      if (std::abs(p.x - 1) > 1e-5 || std::abs(p.y) > 1e-5 || std::abs(p.z) > 1e-5 || std::abs(p.w - 1) > 1e-5) {
        ++bad;
        ADD_FAILURE() << "pixel (" << x << ", " << y << ") inside the red quad is (" << p.x << ", " << p.y << ", "
                      << p.z << ", " << p.w << "), want (1, 0, 0, 1)";
      }
    }
  EXPECT_EQ(bad, 0);
  // The reference renderer resolves every sample at its own (positive) depth: pure red there.
  o.referenceSamples = 4;
  const RenderResult ref = renderReference(scene, o);
  const int tx = int(std::floor(v.cx + v.focal * 0.02 / d1)), ty = int(std::floor(tipY));
  EXPECT_NEAR(ref.image.at(tx, ty).y, 0.0f, 1e-6f) << "reference at the tip pixel";
  EXPECT_NEAR(r.image.at(tx, ty).y, 0.0f, 1e-6f) << "A-buffer at the tip pixel (" << tx << ", " << ty << ")";
}

TEST(RenderReview, FarEndOfARecedingTriangleStaysBehindANearerSurface) {
  // The same for a triangle: a nearly horizontal triangle from depth 1 to depth 100
  // (apex at the far end, 0.15 px from its plane's horizon), and the red quad at depth 5 over its far part.
  // Every pixel inside the quad must be pure red.
  const int W = 40, H = 40;
  Scene scene;
  scene.camera = perspectiveCamera();
  scene.background = glm::vec4(0.0f);
  scene.lights.ambient = glm::dvec3(1.0);
  scene.materials[0].phong.diffuse = glm::dvec3(1.0);
  scene.materials[0].phong.specular = glm::dvec3(0.0);
  const ViewTransform v = ViewTransform::make(*scene.camera, W, H);
  SceneSurface tri;
  // Plane y = -0.2 + dy d (horizon 0.6 px below cy), apex at depth 100 (0.75 px below cy):
  // the apex pixel's centre (cy + 0.5) and top corners lie beyond the horizon, and its bottom
  // sample row (cy + 0.875) is inside the triangle (a sampled mask: keyed at the pixel centre).
  const double dy = -0.6 / v.focal;
  tri.mesh.positions = {{-0.5, -0.2 + dy, -1}, {0.5, -0.2 + dy, -1}, {0.02, -0.2 + dy * 100, -100}};
  tri.mesh.colours = std::vector<glm::vec3>(3, glm::vec3(1, 1, 1));
  tri.mesh.triangles = {{0, 1, 2}};
  scene.surfaces.push_back(tri);
  const double zq = 5, yTop = v.cy - 3, yBot = v.cy + v.focal * 0.2 / 9 + 0.6, xl = v.cx - 6, xr = v.cx + 6;
  auto eye = [&](double x, double y) { return v.eyePoint(x, y, zq); };
  SceneSurface quad;
  quad.mesh.positions = {eye(xl, yTop), eye(xr, yTop), eye(xr, yBot), eye(xl, yBot)};
  quad.mesh.colours = std::vector<glm::vec3>(4, glm::vec3(1, 0, 0));
  quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.surfaces.push_back(quad);
  const RenderResult r = render(scene, smallOptions(W, H));
  int bad = 0;
  for (int y = int(std::ceil(yTop)); y + 1 <= int(std::floor(yBot)); ++y)
    for (int x = int(std::ceil(xl)); x + 1 <= int(std::floor(xr)); ++x) {
      const glm::vec4 p = r.image.at(x, y);
      if (std::abs(p.x - 1) > 1e-5 || std::abs(p.y) > 1e-5 || std::abs(p.w - 1) > 1e-5) {
        ++bad;
        ADD_FAILURE() << "pixel (" << x << ", " << y << ") inside the red quad is (" << p.x << ", " << p.y << ", "
                      << p.z << ", " << p.w << "), want (1, 0, 0, 1)";
      }
    }
  EXPECT_EQ(bad, 0);
}

// ---- polylines -------------------------------------------------------------------------------

TEST(RenderReview, DuplicatePointInAPolylineKeepsTheMitre) {
  // A polyline bending by 90 degrees, 4 px wide, with its corner point repeated: the repeat is a
  // zero-length segment, dropped and counted, and should change nothing else: the image must
  // equal that of the polyline without the repeat (mitred joint, exact area 4 * (L1 + L2)).
  // Bug: the dropped segment invalidates both joints around it (segment_setup.cpp, the joint
  // loop skips when a neighbour is !valid), so the two real segments get square ends: the
  // outer corner loses a 2 x 2 square and the inner one is covered twice.
  const int W = 48, H = 48;
  const V2 A(6.3, 30.2), B(30.3, 30.2), C(30.3, 6.2);
  Scene s1 = baseScene(W, H), s2 = baseScene(W, H);
  s1.wires.push_back(plainWire({{A, B, C}}, 4, 10.0, W, H));
  s2.wires.push_back(plainWire({{A, B, B, C}}, 4, 10.0, W, H));
  const RenderResult r1 = render(s1, smallOptions(W, H)), r2 = render(s2, smallOptions(W, H));
  EXPECT_EQ(r2.stats.droppedZeroLength, 1u);
  EXPECT_NEAR(sumAlpha(r1.image), 4 * (24 + 24), 1e-3);
  EXPECT_NEAR(sumAlpha(r2.image), 4 * (24 + 24), 1e-3);
  int at = -1;
  EXPECT_LE(maxDiff(r1.image, r2.image, &at), 1e-5) << "pixel (" << at % W << ", " << at / W << ")";
}

TEST(RenderReview, AClosedLoopIsMitredAtItsSeamAsAtItsOtherCorners) {
  // A square loop A B C D A, side L, half width h: its outline is the square ring between sides
  // L + 2h and L - 2h, exactly 8 L h, when all four corners are mitred. Bug (review 54): the
  // joint of the last segment and the first was never formed, so A had square ends: a notch of
  // h^2 at its outer corner (1.2% of the area here) and a jump in the shading tangent. Now the
  // seam's offset is one value in both segments and its tangent is averaged like the others.
  const int W = 64, H = 64;
  const double L = 40, h = 4;
  const V2 A(12.3, 12.2), B(A.x + L, A.y), C(A.x + L, A.y + L), D(A.x, A.y + L);
  Scene s = baseScene(W, H);
  s.wires.push_back(plainWire({{A, B, C, D, A}}, 2 * h, 10.0, W, H));
  const RenderResult r = render(s, smallOptions(W, H));
  EXPECT_NEAR(sumAlpha(r.image), 8 * L * h, 1e-3 * 8 * L * h);
  RenderStats st;
  const PreparedScene ps = prepareScene(s, smallOptions(W, H), st);
  ASSERT_EQ(ps.segments.size(), 4u);
  EXPECT_EQ(ps.segments[0].o0, ps.segments[3].o1);  // the seam's edge, shared to the bit
  EXPECT_GT(glm::length(glm::dvec2(ps.segments[0].o0)), 1.4 * h);  // a mitre (h sqrt 2), not h
  EXPECT_EQ(ps.segmentShading[0].t0, ps.segmentShading[3].t1);
  EXPECT_NEAR(glm::length(glm::dvec3(ps.segmentShading[0].t0) - glm::normalize(glm::dvec3(1, 1, 0))), 0.0, 1e-6)
      << "the seam's tangent: the mean of the first segment's (+x) and the last's (-y on screen, +y in the world)";
  // Out and back (A, B, A) is no loop: two free ends, both capped when round.
  Scene back = baseScene(W, H);
  back.wires.push_back(plainWire({{A, B, A}}, 2 * h, 10.0, W, H));
  back.wires[0].roundEnds = true;
  const PreparedScene pb = prepareScene(back, smallOptions(W, H), st);
  ASSERT_EQ(pb.segments.size(), 2u);
  EXPECT_TRUE(pb.segments[0].flags & kSegmentCap0);
  EXPECT_TRUE(pb.segments[1].flags & kSegmentCap1);
}

TEST(RenderReview, ASegmentCutToAPointByTheNearPlaneIsLeftOut) {
  // P0 behind the near plane, P1 exactly on it, P2 in front: the first segment's part between
  // the planes is the point P1 alone. Bug (review 54): it was kept as a segment of (nearly) zero
  // length, drawn as a disc of the full width at P1. Now it is clipped away and counted so;
  // the second segment is drawn as before.
  const int W = 32, H = 32;
  const Scene s = perspectiveWire({{0.03, 0.01, -0.2}, {0.0, 0.0, -0.5}, {-0.2, 0.1, -2.0}}, 3);  // near 0.5
  RenderStats st;
  const PreparedScene ps = prepareScene(s, smallOptions(W, H), st);
  EXPECT_EQ(ps.segments.size(), 1u);
  EXPECT_EQ(st.clippedAway, 1u);
  EXPECT_EQ(st.endOnDiscs, 0u);
}

TEST(RenderReview, AFreeEndBesideADroppedSegmentKeepsItsRoundCap) {
  // A round-ended wire A B whose polyline runs on to a non-finite point at either end (NaN, A, B,
  // NaN): the segments to it are dropped, so A and B are the wire's free ends. Its outline is
  // the body 2 h L and two half discs, pi h^2 (the caps' polygons have the half disc's exact
  // area), as for the polyline A B alone. Bug (review 54): only the polyline's first and last
  // segments took caps, so both ends here were square: pi h^2 short.
  const int W = 64, H = 32;
  const double L = 36, h = 3;
  const V2 A(14.3, 16.2), B(A.x + L, A.y), nan(std::nan(""), std::nan(""));
  for (const std::vector<V2>& line : {std::vector<V2>{A, B}, std::vector<V2>{nan, A, B, nan}}) {
    Scene s = baseScene(W, H);
    s.wires.push_back(plainWire({line}, 2 * h, 10.0, W, H));
    s.wires[0].roundEnds = true;
    const RenderResult r = render(s, smallOptions(W, H));
    EXPECT_NEAR(sumAlpha(r.image), 2 * h * L + std::numbers::pi * h * h, 1e-3 * 2 * h * L) << line.size() << " points";
  }
  // A neighbour the near plane took is no such case (review 56): Q before the plane (depth 0.5),
  // P on it (depth 1, the camera's near), R behind. Q P is cut to the point P and dropped; P R
  // starts on the plane, where the wire is cut: square there, round only at its free end R.
  Scene cut = baseScene(W, H);
  cut.wires.push_back(plainWire({{V2(10, 16), V2(14, 16), V2(50, 16)}}, 2 * h, 10.0, W, H));
  cut.wires[0].lines.points[0].z = 9.5, cut.wires[0].lines.points[1].z = 9.0;  // view depths 0.5 and 1
  cut.wires[0].roundEnds = true;
  RenderStats st;
  const PreparedScene ps = prepareScene(cut, smallOptions(W, H), st);
  ASSERT_EQ(ps.segments.size(), 1u);
  EXPECT_FALSE(ps.segments[0].flags & kSegmentCap0) << "a cap where the near plane cuts the wire";
  EXPECT_TRUE(ps.segments[0].flags & kSegmentCap1);
}

TEST(RenderReview, AWireOfNoThicknessIsNamedInTheWarnings) {
  // Zero, negative, NaN or infinite thickness draws nothing; the render says which wire, once.
  const int W = 16, H = 16;
  for (double t : {0.0, -2.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    Scene s = baseScene(W, H);
    s.wires.push_back(plainWire({{{2, 2}, {12, 9}}}, t, 10.0, W, H));
    s.wires[0].name = "rim";
    const RenderResult r = render(s, smallOptions(W, H));
    EXPECT_EQ(sumAlpha(r.image), 0.0) << t;
    int named = 0;
    for (const std::string& w : r.stats.warnings) named += w.find("wire 'rim': thickness") != std::string::npos;
    EXPECT_EQ(named, 1) << t;
  }
  Scene fine = baseScene(W, H);
  fine.wires.push_back(plainWire({{{2, 2}, {12, 9}}}, 1.0, 10.0, W, H));
  EXPECT_TRUE(render(fine, smallOptions(W, H)).stats.warnings.empty());
}

TEST(RenderReview, AFarPlaneGivenAloneBeforeTheSceneKeepsNearBeforeIt) {
  // withDepthRange fills the planes a camera leaves at 0 from the scene's bounding sphere. Bug
  // (review 55): with far given alone and the scene wholly beyond it, near came from the sphere
  // and lay beyond far. Now near < far always; a far plane before the scene shows nothing.
  const int W = 16, H = 16;
  Scene s = baseScene(W, H);  // the wire at depth 10
  s.wires.push_back(plainWire({{{2, 2}, {12, 9}}}, 2.0, 10.0, W, H));
  for (double far : {2.0, 3.0, 9.9, 10.5, 50.0}) {  // the sphere reaches from depth 3.8 to 16.2
    Camera c = *s.camera;
    c.nearPlane = 0, c.farPlane = far;
    const Camera filled = withDepthRange(c, s);
    EXPECT_GT(filled.nearPlane, 0.0) << far;
    EXPECT_LT(filled.nearPlane, filled.farPlane) << far;
    EXPECT_EQ(filled.farPlane, far);
    EXPECT_EQ(filled.problem(), "") << far;
    Scene t = s;
    t.camera = c;
    EXPECT_EQ(sumAlpha(render(t, smallOptions(W, H)).image) > 0.0, far > 10.0) << far;
  }
}

TEST(RenderReview, AnEndCutByTheNearPlaneKeepsItsOwnTangent) {
  // A joint behind the near plane: both segments are cut short of it, and what shows of each
  // ends at its cut, square (no mitre across an unseen joint). Bug (review 55): the shading
  // tangent at each cut was still averaged with the other segment's across that joint, so the
  // cut ends shaded as if they bent. Each segment now keeps its own tangent at a cut end.
  const int W = 32, H = 32;
  const Scene s = perspectiveWire({{-0.3, 0.1, -2.0}, {0.0, 0.0, -0.2}, {0.4, 0.2, -3.0}}, 2);  // near 0.5
  RenderStats st;
  const PreparedScene ps = prepareScene(s, smallOptions(W, H), st);
  ASSERT_EQ(ps.segments.size(), 2u);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(ps.segmentShading[k].t0, ps.segmentShading[k].t1) << "segment " << k;
  const glm::dvec3 own0 = glm::normalize(glm::dvec3(0.3, -0.1, 1.8)), own1 = glm::normalize(glm::dvec3(0.4, 0.2, -2.8));
  EXPECT_NEAR(glm::length(glm::dvec3(ps.segmentShading[0].t1) - own0), 0.0, 1e-6);
  EXPECT_NEAR(glm::length(glm::dvec3(ps.segmentShading[1].t0) - own1), 0.0, 1e-6);
}

TEST(RenderReview, SurfaceMaterialsPastSixteenBitsAreRefused) {
  // A triangle holds its shader slot in 16 bits: 65,536 surface slots render (the last of them
  // in its own material, red), one more is refused with a clear error. Bug (review 54): slot
  // 65,536 + k wrapped to slot k and drew in its material.
  const int W = 8, H = 8;
  auto scene = [&](int materials) {
    Scene s = baseScene(W, H);
    s.materials.assign(size_t(materials), s.materials.empty() ? Material{} : s.materials[0]);
    for (int i = 0; i < materials; ++i) {
      const double y = i + 1 == materials ? 1.0 : 100.0;  // the last one covers pixel (1, 1), the rest are off the image
      s.surfaces.push_back(screenSurface({{V2(0, y), V2(4, y), V2(0, y + 4)}}, 10.0, W, H, glm::vec3(1), i));
    }
    for (Material& m : s.materials) m.phong.diffuse = glm::dvec3(0.0), m.phong.specular = glm::dvec3(0.0);
    s.materials.back().phong.diffuse = glm::dvec3(1.0, 0.0, 0.0);
    return s;
  };
  const RenderResult r = render(scene(65536), smallOptions(W, H));
  EXPECT_GT(r.image.at(1, 1).x, 0.0f);
  EXPECT_EQ(r.image.at(1, 1).y, 0.0f);
  try {
    render(scene(65537), smallOptions(W, H));
    ADD_FAILURE() << "65,537 surface materials rendered";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("65,536 surface shader slots"), std::string::npos) << e.what();
  }
}

TEST(RenderReview, PolylineThroughTheNearPlaneHasNoNaNAndDrawsItsFrontParts) {
  // A 3-segment polyline whose middle segment passes behind the camera (perspective): the front
  // parts are drawn, nothing is NaN, no pixel exceeds alpha 1.
  const int W = 32, H = 32;
  const Scene scene = perspectiveWire({{-0.3, 0.1, -3}, {-0.1, 0.1, -1}, {0.1, -0.1, 2}, {0.3, -0.1, -3}}, 2);
  const RenderResult r = render(scene, smallOptions(W, H));
  EXPECT_TRUE(allFinite(r.image));
  EXPECT_GT(sumAlpha(r.image), 5.0);
  for (const glm::vec4& p : r.image.pixels) EXPECT_LE(p.w, 1.0f + 1e-6f);
}

// ---- occlusion culling ---------------------------------------------------------------------------

// Many overlapping translucent and opaque thin hairs (one-segment polylines: they occlude at
// once) in a small image.
Scene hairScene(int W, int H, std::uint64_t seed, float opacity) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Scene scene = baseScene(W, H);
  for (int k = 0; k < 3; ++k) {
    SceneWire w = plainWire({}, 0.6 + 0.5 * k, 10.0, W, H);
    w.opacity = k == 0 ? 1.0f : opacity;
    w.colour = glm::vec3(0.2f + 0.4f * k, 1.0f - 0.3f * k, 0.5f);
    for (int i = 0; i < 400; ++i) {
      const V2 p(W * U(rng), H * U(rng));
      const double a = 2 * std::numbers::pi * U(rng), len = 4 + 10 * U(rng);
      const V2 q = p + len * V2(std::cos(a), std::sin(a));
      w.lines.add({world(p, 2 + 20 * U(rng), W, H), world(q, 2 + 20 * U(rng), W, H)});
    }
    scene.wires.push_back(w);
  }
  return scene;
}

TEST(RenderReview, OcclusionEpsilonBoundsTheDifferenceToEpsilonZero) {
  // Doc: "What is skipped adds at most epsilon to the pixel." Against epsilon = 0 (exact
  // culling), epsilon = 1e-2 must change no channel of any pixel by more than 1e-2 (colours
  // <= 1, no budget overflow: K = 64 holds every list here).
  const int W = 48, H = 48;
  const Scene scene = hairScene(W, H, 7, 0.6f);
  RenderOptions o = smallOptions(W, H);
  o.occlusionEpsilon = 0.0;
  const RenderResult exact = render(scene, o);
  ASSERT_EQ(exact.stats.abuffer.tail, 0u);
  for (double eps : {1e-4, 1e-2, 0.1}) {
    o.occlusionEpsilon = eps;
    const RenderResult r = render(scene, o);
    int at = -1;
    EXPECT_LE(maxDiff(exact.image, r.image, &at), eps * (1 + 1e-3)) << "epsilon " << eps << " pixel " << at;
    EXPECT_GE(r.stats.abuffer.culled + r.stats.primitivesOccluded, exact.stats.abuffer.culled + exact.stats.primitivesOccluded);
  }
}

TEST(RenderReview, ImagesAreBitIdenticalAcrossThreadCountsWithTinyBudgetsAndEpsilon) {
  // Translucent hairs, K = 2 (most pixels overflow into their tails), epsilon 1e-2: 1, 3 and 16
  // threads give the same bits (tile-local state only, deterministic orders).
  const int W = 48, H = 48;
  const Scene scene = hairScene(W, H, 11, 0.5f);
  RenderOptions o = smallOptions(W, H);
  o.budget = 2;
  o.occlusionEpsilon = 1e-2;
  std::vector<RenderResult> rs;
  for (int t : {1, 3, 16}) {
    o.threads = t;
    rs.push_back(render(scene, o));
  }
  EXPECT_GT(rs[0].stats.abuffer.tail, 100u);
  for (size_t i = 1; i < rs.size(); ++i)
    EXPECT_EQ(0, std::memcmp(rs[0].image.pixels.data(), rs[i].image.pixels.data(), rs[0].image.pixels.size() * sizeof(glm::vec4)));
}

TEST(RenderReview, OverBudgetPixelKeepsFlatOccludersAtTheirDepth) {
  // K = 2, orthographic, one-segment Plain wires (one piece each: they count for occlusion at
  // once). A (red) covers y in [4, 8.5], B (green) y in [8.5, 13], both opaque at depth 10;
  // C (blue, opacity 0.5) crosses them vertically at x in [10, 12], depth 5. Pixel (10, 8):
  // C whole (0.5), A the top half, B the bottom half. With K = 2, C and one half are kept and
  // the other half goes to the tail: 0.5 + 0.5 * 0.5 + tail 0.5 * mean T (0.25) = 0.875
  // (exact: 1). Bug (abuffer.cpp:361): when B settles the pixel at depth 10, pushList prunes
  // "wholly hidden" entries with zmin >= 10 -- A itself, which lies exactly at that depth --
  // and alpha is 0.75: the top half shows C over the background.
  const int W = 32, H = 32;
  Scene scene = baseScene(W, H);
  SceneWire a = plainWire({{{2, 6.25}, {30, 6.25}}}, 4.5, 10.0, W, H);
  SceneWire b = plainWire({{{2, 10.75}, {30, 10.75}}}, 4.5, 10.0, W, H);
  SceneWire c = plainWire({{{11, 1}, {11, 30}}}, 2, 5.0, W, H);
  a.colour = {1, 0, 0}, b.colour = {0, 1, 0}, c.colour = {0, 0, 1};
  c.opacity = 0.5f;
  scene.wires = {a, b, c};
  RenderOptions o = smallOptions(W, H);
  o.budget = 2;
  o.occlusionEpsilon = 0;
  const RenderResult r = render(scene, o);
  EXPECT_NEAR(r.image.at(20, 8).w, 1.0f, 1e-5f) << "A and B alone fill the pixel";
  const glm::vec4 p = r.image.at(10, 8);
  EXPECT_NEAR(p.z, 0.5f, 1e-5f);
  EXPECT_GE(p.w, 0.87f) << "pixel (10, 8): (" << p.x << ", " << p.y << ", " << p.z << ", " << p.w << ")";
}

// ---- view grid -------------------------------------------------------------------------------

TEST(RenderReview, ViewGridCornerWeightsArePartitionOfUnityEverywhere) {
  // n = 1: node 0 with weight 1. n = 2, 3, 5: at every point of the image (borders, corners,
  // outside, non-finite) the four weights are in [0, 1] and sum to 1, the nodes are valid
  // indices, and at a node's centre that node has weight 1.
  ViewTransform v = ViewTransform::make(Camera{}, 64, 48);
  {
    const ViewGrid g(v, 1);
    int node[4];
    double w[4];
    g.corners(-5, 1e9, node, w);
    EXPECT_EQ(node[0], 0);
    EXPECT_EQ(w[0], 1.0);
  }
  for (int n : {2, 3, 5}) {
    const ViewGrid g(v, n);
    const double pts[][2] = {{0, 0}, {64, 48}, {63.999, 0}, {-10, 20}, {100, 100}, {32, 24}, {NAN, 5}, {5, INFINITY}};
    for (const auto& p : pts) {
      int node[4];
      double w[4];
      g.corners(p[0], p[1], node, w);
      double sum = 0;
      for (int c = 0; c < 4; ++c) {
        EXPECT_GE(node[c], 0);
        EXPECT_LT(node[c], n * n);
        EXPECT_GE(w[c], 0.0);
        EXPECT_LE(w[c], 1.0);
        sum += w[c];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12) << "n " << n << " at " << p[0] << "," << p[1];
    }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        int node[4];
        double w[4];
        g.corners(64.0 * (i + 0.5) / n, 48.0 * (j + 0.5) / n, node, w);
        double at = 0;
        for (int c = 0; c < 4; ++c)
          if (node[c] == j * n + i) at += w[c];
        EXPECT_NEAR(at, 1.0, 1e-12) << "n " << n << " node " << i << "," << j;
      }
  }
  // An orthographic view has one direction: one node whatever n.
  Camera oc = orthoCamera(48, 48);
  EXPECT_EQ(ViewGrid(ViewTransform::make(oc, 64, 48), 4).size(), 1);
}

// ---- degenerate cameras ------------------------------------------------------------------------

TEST(RenderReview, DegenerateCameraDoesNotCrashOrProduceNaN) {
  // A camera whose up is parallel to its view direction is reported by Camera::problem(); if a
  // caller renders anyway, the image must still be finite (the background here).
  const int W = 16, H = 16;
  Scene scene = baseScene(W, H);
  scene.surfaces.push_back(screenRect(2, 2, 10, 10, 10.0, W, H, glm::vec3(1)));
  Camera c = *scene.camera;
  c.up = glm::normalize(c.target - c.eye);
  ASSERT_FALSE(c.problem().empty());
  scene.camera = c;
  const RenderResult r = render(scene, smallOptions(W, H));
  EXPECT_TRUE(allFinite(r.image));
}

}  // namespace
}  // namespace wf
