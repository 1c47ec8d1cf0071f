// Poles of patches and zero-length hairs in the generators (issue 7): the frame, tessellation,
// fur and scales at a sphere's poles and at a loft that closes with radius 0. Expectations: every
// number finite, normals unit (|N| - 1 within 1e-12), the limit normal at a pole equal to the
// closed form (the sphere's outward axis) or, at the loft's cone tip, the limit along the meridian, hairs of the stated length
// (closed form), zero-length hairs counted and dropped (FurCounts), and renders without NaN.
#include "growth/fur.h"
#include "growth/scales.h"
#include "render/renderer.h"
#include "surface/patches.h"
#include "surface/tessellate.h"

#include "render_test_scenes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

LoftPatch closingLoft() {
  // Sections along +z; the last one radius 0: a pole at (0, 0, 2).
  std::vector<LoftSection> sections;
  for (int k = 0; k < 5; ++k) {
    LoftSection s;
    s.centre = {0.0, 0.0, 0.5 * k};
    s.a = s.b = k == 4 ? 0.0 : 0.6 - 0.1 * k;
    sections.push_back(s);
  }
  return LoftPatch(sections);
}

void expectUnit(const glm::dvec3& n, const std::string& what) {
  ASSERT_TRUE(test::finite3(n)) << what;
  EXPECT_NEAR(glm::length(n), 1.0, 1e-12) << what << " " << test::str(n);
}

// The frame at and next to the poles: the sphere's normal there is -z (south, v = 0) and +z
// (north, v = 1) for every u; the closing loft's is the limit along each meridian. Tangents
// unit and orthogonal to N (1e-12).
TEST(RobustGrowth, FrameAtPolesIsTheClosedFormLimit) {
  const SpherePatch sphere(1.5);
  for (double u : {0.0, 0.125, 0.5, 0.99})
    for (const auto& [v, nz] : {std::pair{0.0, -1.0}, {1.0, 1.0}, {1e-12, -1.0}, {1.0 - 1e-12, 1.0}}) {
      const SurfaceFrame f = sphere.frame(u, v);
      expectUnit(f.N, "sphere N");
      expectUnit(f.Tu, "sphere Tu");
      expectUnit(f.Tv, "sphere Tv");
      EXPECT_NEAR(f.N.z, nz, 1e-9) << "u " << u << " v " << v;
      EXPECT_NEAR(glm::dot(f.N, f.Tu), 0.0, 1e-12);
      EXPECT_NEAR(glm::dot(f.N, f.Tv), 0.0, 1e-12);
      ASSERT_TRUE(test::finite3(f.P));
    }
  const LoftPatch loft = closingLoft();
  ASSERT_EQ(loft.problem(), "");
  // The loft closes in a cone tip (radius falling linearly to 0), where no single normal
  // exists: the limit is taken along each meridian, so it must equal the normal just below the
  // tip on the same meridian (finite difference: within 1e-4 at 1e-6 from it).
  for (double u : {0.0, 0.3, 0.75}) {
    const SurfaceFrame f = loft.frame(u, 1.0), below = loft.frame(u, 1.0 - 1e-6);
    expectUnit(f.N, "loft N");
    EXPECT_LT(glm::length(f.N - below.N), 1e-4) << "u " << u << " " << test::str(f.N) << " vs " << test::str(below.N);
    EXPECT_GT(f.N.z, 0.0);  // outward: towards the closed end
    EXPECT_NEAR(glm::length(f.P - glm::dvec3(0, 0, 2)), 0.0, 1e-12);
  }
}

// Tessellations through poles: finite, unit normals, pole vertices carry the closed-form limit
// normal, no triangle of zero area (collapsed ones are left out: every kept triangle has area
// above 1e-12 x its longest edge squared).
TEST(RobustGrowth, TessellationThroughPolesIsFiniteWithUnitNormals) {
  const SpherePatch sphere(1.0);
  const LoftPatch loft = closingLoft();
  for (const Surface* s : {static_cast<const Surface*>(&sphere), static_cast<const Surface*>(&loft)}) {
    const TriangleMesh m = tessellate(*s, 24, 12);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
      ASSERT_TRUE(test::finite3(m.positions[i]));
      expectUnit(m.normals[i], s->describe());
      ASSERT_TRUE(test::finite3(m.tangents[i]));
    }
    for (const glm::uvec3& t : m.triangles) {
      const glm::dvec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
      const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
      EXPECT_GT(glm::length(glm::cross(b - a, c - a)), 1e-12 * longest * longest);
    }
  }
  const TriangleMesh sm = tessellate(sphere, 24, 12);
  for (size_t i = 0; i < sm.positions.size(); ++i)
    if (std::abs(std::abs(sm.positions[i].z) - 1.0) < 1e-15) {
      EXPECT_NEAR(sm.normals[i].z, sm.positions[i].z, 1e-9);
    }
}

double hairLength(const Fur& fur, size_t h) {
  double l = 0;
  for (std::uint32_t k = fur.hairs.starts[h] + 1; k < fur.hairs.starts[h + 1]; ++k)
    l += glm::length(fur.hairs.points[k] - fur.hairs.points[k - 1]);
  return l;
}

// A length map that is 0 on the left half of the patch.
class HalfZero final : public ScalarTexture {
 public:
  double value(const glm::dvec2& st) const override { return st.x < 0.5 ? 0.0 : 1.0; }
  glm::dvec2 gradient(const glm::dvec2&) const override { return glm::dvec2(0.0); }
  std::string describe() const override { return "half zero"; }
};

// Fur on a sphere and on the closing loft, roots up to the poles (a fine grid, no jitter):
// every point finite; with a fixed length every hair is length x (1 +- variation) (closed form),
// measured along its polyline within 1e-9 relative; with length proportional to |Su| (zero at a
// pole) hairs at the pole are counted as zero-length and left out. Counts add up: hairs +
// skipped = roots tried. With a length map 0 on half the patch, that half's roots are counted as
// zero-length, and none of the hairs made has zero length.
TEST(RobustGrowth, FurAtPolesIsFiniteAndZeroLengthHairsAreCounted) {
  const SpherePatch sphere(1.0);
  const LoftPatch loft = closingLoft();
  for (const Surface* s : {static_cast<const Surface*>(&sphere), static_cast<const Surface*>(&loft)}) {
    FurParams p;
    p.gridU = 40;
    p.gridV = 41;
    p.jitter = 0.0;
    p.lengthMode = FurParams::LengthMode::Fixed;
    p.length = 0.2;
    p.lengthVariation = 0.25;
    p.segments = 3;
    p.gravity = 0.5;
    const Fur fur = growFur(*s, p);
    const FurCounts& c = fur.counts;
    EXPECT_EQ(c.hairs + c.skippedDegenerate + c.skippedZeroLength + c.skippedCapacity, c.rootsTried);
    ASSERT_GT(c.hairs, 1000u);
    for (const glm::dvec3& q : fur.hairs.points) ASSERT_TRUE(test::finite3(q));
    for (size_t h = 0; h < fur.hairs.polylineCount(); ++h) {
      const double l = hairLength(fur, h);
      ASSERT_GE(l, 0.2 * 0.75 * (1 - 1e-9)) << s->describe() << " hair " << h;
      ASSERT_LE(l, 0.2 * 1.25 * (1 + 1e-9)) << s->describe() << " hair " << h;
    }
    // Roots exactly at the poles: the grid with an odd count puts none there, so ask the
    // proportional length, which vanishes towards the pole, on a grid whose rows include it.
    FurParams q = p;
    q.lengthMode = FurParams::LengthMode::ProportionalToSu;
    q.lengthPerSu = 1e-30;  // every hair vanishingly short relative to the surface: all zero-length
    const Fur none = growFur(*s, q);
    EXPECT_EQ(none.counts.hairs, 0u);
    EXPECT_EQ(none.counts.skippedZeroLength + none.counts.skippedDegenerate, none.counts.rootsTried);
    EXPECT_GT(none.counts.skippedZeroLength, 0u);
    FurParams half = p;
    half.lengthMap = std::make_shared<HalfZero>();
    const Fur h = growFur(*s, half);
    EXPECT_EQ(h.counts.hairs + h.counts.skippedZeroLength + h.counts.skippedDegenerate, h.counts.rootsTried);
    EXPECT_NEAR(double(h.counts.skippedZeroLength), 0.5 * double(h.counts.rootsTried), 0.02 * double(h.counts.rootsTried));
    for (size_t k = 0; k < h.hairs.polylineCount(); ++k) ASSERT_GT(hairLength(h, k), 0.0);
  }
}

// Scales on the sphere and the closing loft: scales at degenerate roots are left out, the rest
// finite with unit normals; the furry sphere (pole included) renders without a NaN pixel and
// its coverage is a disc of the sphere's projected size (alpha sum within 5% of pi r^2 in
// pixels, orthographic: the sphere's outline plus its short hairs).
TEST(RobustGrowth, ScalesAndFurAtPolesRenderWithoutNaN) {
  const SpherePatch sphere(1.0);
  const LoftPatch loft = closingLoft();
  for (const Surface* s : {static_cast<const Surface*>(&sphere), static_cast<const Surface*>(&loft)}) {
    ScaleParams sp;
    sp.cellsU = 24;
    sp.cellsV = 12;
    const TriangleMesh m = growScales(*s, sp);
    ASSERT_FALSE(m.triangles.empty());
    ASSERT_LE(m.triangles.size(), size_t(4 * 24 * 12));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      ASSERT_TRUE(test::finite3(m.positions[i]));
      expectUnit(m.normals[i], "scale normal");
    }
  }
  Scene sc;
  sc.background = glm::vec4(0.0f);
  sc.lights = LightRig::studioRig(3);
  sc.lightsFollowCamera = true;
  SceneSurface body;
  body.mesh = tessellate(sphere, 48, 24);
  sc.surfaces.push_back(body);
  FurParams p;
  p.gridU = 60;
  p.gridV = 30;
  p.length = 0.02;
  p.thickness = 0.004;
  const Fur fur = growFur(sphere, p);
  SceneWire hairs;
  hairs.lines = fur.hairs;
  hairs.thickness = fur.thickness;
  sc.wires.push_back(hairs);
  Camera cam;
  cam.projection = Camera::Projection::Orthographic;
  cam.eye = {0, 0, 5};  // looking straight down at the north pole
  cam.target = {0, 0, 0};
  cam.up = {0, 1, 0};
  cam.orthoHeight = 3.0;
  cam.nearPlane = 1;
  cam.farPlane = 10;
  sc.camera = cam;
  RenderOptions o;
  o.width = 96;
  o.height = 96;
  for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
    o.shading = path;
    const RenderResult r = render(sc, o);
    ASSERT_TRUE(test::allFinite(r.image));
    const double pxPerUnit = 96 / 3.0, disc = 3.14159265358979 * pxPerUnit * pxPerUnit;
    EXPECT_NEAR(test::sumAlpha(r.image) / disc, 1.0, 0.05);
  }
}

}  // namespace
}  // namespace wf
