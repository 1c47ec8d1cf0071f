// Review tests of surface shading (burnish, textures, bumps, grooves, footprints) and of the
// reference renderer's per-sample shading of textured primitives.
#include "render/renderer.h"
#include "shading/phong.h"
#include "texture/grooves.h"
#include "texture/textures.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>

namespace wf {
namespace {

using test::V2;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A bump height h = g u (a constant gradient): Blinn's bump on a flat plane is then exactly the
// plane tilted by atan(g).
class RampHeight final : public ScalarTexture {
 public:
  explicit RampHeight(double g) : g_(g) {}
  double value(const glm::dvec2& uv) const override { return g_ * uv.x; }
  glm::dvec2 gradient(const glm::dvec2&) const override { return {g_, 0.0}; }
  std::string describe() const override { return "ramp"; }

 private:
  double g_;
};

// The rectangle covering [x0, x1] x [y0, y1] (screen) with (u, v) = world (x, y), derivatives
// along world x and y, normal +z.
SceneSurface parametricRect(double x0, double y0, double x1, double y1, double depth, int W, int H, int material) {
  SceneSurface s = test::screenRect(x0, y0, x1, y1, depth, W, H, glm::vec3(1.0f), material);
  for (const glm::dvec3& p : s.mesh.positions) {
    s.mesh.normals.push_back({0, 0, 1});
    s.mesh.derivU.push_back({1, 0, 0});
    s.mesh.derivV.push_back({0, 1, 0});
    s.mesh.uvs.push_back({p.x, p.y});
  }
  return s;
}

LightRig oneLight() {
  LightRig r;
  r.ambient = glm::dvec3(0.05);
  r.lights.push_back({glm::normalize(glm::dvec3(0.3, 0.5, 1.0)), glm::dvec3(0.9)});
  return r;
}

Material burnishedU() {
  Material m;
  m.phong.diffuse = glm::dvec3(0.5);
  m.phong.specular = glm::dvec3(0.5);
  m.phong.exponent = 20;
  m.burnish.grain = Burnish::Grain::U;
  return m;
}

double maxDiff(const ImageRGBA& a, const ImageRGBA& b) {
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 4; ++c) m = std::max(m, double(std::abs(a.pixels[i][c] - b.pixels[i][c])));
  return m;
}

bool anyNonBlack(const ImageRGBA& im) {
  for (const glm::vec4& p : im.pixels)
    if (p.x + p.y + p.z > 1e-4f) return true;
  return false;
}

// --- The reference renderer ------------------------------------------------------------------

// The reference shades a textured primitive at every sample but then composites every sample
// with the AVERAGE of those shadings: a translucent black strip over the white half of each
// pixel (the chequer's black half uncovered) must give 0.5 * 0.1 = 0.05, not 0.1 * 0.5 + 0.5 / 2.
TEST(SurfaceShadingReview, ReferenceCompositesTexturedSamplesWithTheirOwnColour) {
  constexpr int W = 4, H = 4;
  Scene s = test::baseScene(W, H);
  Material textured = s.materials[0];
  // Two squares per unit of u: each pixel (u = world x) is white on its left half, black on its right.
  textured.colourMap = std::make_shared<ChequerTexture>(2, 1, glm::vec3(1.0f), glm::vec3(0.0f));
  Material veil = s.materials[0];
  veil.opacity = 0.9f;
  veil.phong.diffuse = glm::dvec3(0.0);
  s.materials = {textured, veil};
  SceneSurface back = test::screenRect(0, 0, W, H, 20.0, W, H, glm::vec3(1.0f), 0);
  for (const glm::dvec3& p : back.mesh.positions) back.mesh.uvs.push_back({p.x + W / 2.0, 0.25});
  s.surfaces.push_back(back);
  // Translucent black strips over the left half of every pixel column.
  std::vector<test::Poly> strips;
  for (int k = 0; k < W; ++k) {
    strips.push_back({V2(k, 0), V2(k + 0.5, 0), V2(k + 0.5, H)});
    strips.push_back({V2(k, 0), V2(k + 0.5, H), V2(k, H)});
  }
  SceneSurface front = test::screenSurface(strips, 5.0, W, H, glm::vec3(0.0f), 1);
  s.surfaces.push_back(front);
  RenderOptions o = test::smallOptions(W, H);
  o.referenceSamples = 16;
  const RenderResult ref = renderReference(s, o);
  ASSERT_TRUE(test::allFinite(ref.image));
  double worst = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) worst = std::max(worst, std::abs(ref.image.at(x, y).x - 0.05));
  EXPECT_LT(worst, 0.01) << "pixel (1, 1) = " << ref.image.at(1, 1).x << ", want 0.05";
}

// --- Non-finite and degenerate mesh attributes ----------------------------------------------

// derivU NaN at ONE vertex: 0 * NaN = NaN in the barycentric mix, so the whole triangle's grain
// tangent is dropped and replaced by an arbitrary perpendicular of N (here the y axis): every
// pixel of both triangles changes, although the other vertices (and the uvs) define the grain.
TEST(SurfaceShadingReview, NanDerivativeAtOneVertexKeepsTheGrainOfTheOthers) {
  constexpr int W = 16, H = 16;
  Scene s = test::baseScene(W, H);
  s.lights = oneLight();
  s.materials[0] = burnishedU();
  s.surfaces.push_back(parametricRect(-2, -2, W + 2, H + 2, 10.0, W, H, 0));
  RenderOptions o = test::smallOptions(W, H);
  o.shading = ShadingPath::Exact;
  const RenderResult clean = render(s, o);
  s.surfaces[0].mesh.derivU[0] = glm::dvec3(kNaN, 0.0, 0.0);
  const RenderResult bad = render(s, o);
  ASSERT_TRUE(test::allFinite(bad.image));
  EXPECT_LT(maxDiff(clean.image, bad.image), 1e-3);
}

// The same through the normals: one NaN vertex normal turns the whole triangle's normal into V.
TEST(SurfaceShadingReview, NanNormalAtOneVertexKeepsTheOthers) {
  constexpr int W = 16, H = 16;
  Scene s = test::baseScene(W, H);
  s.lights = oneLight();
  s.lights.lights[0].direction = glm::normalize(glm::dvec3(0.8, 0.0, 0.6));
  s.materials[0].phong.diffuse = glm::dvec3(0.8);
  SceneSurface r = parametricRect(-2, -2, W + 2, H + 2, 10.0, W, H, 0);
  for (auto& n : r.mesh.normals) n = glm::normalize(glm::dvec3(0.3, 0.0, 1.0));
  s.surfaces.push_back(r);
  RenderOptions o = test::smallOptions(W, H);
  o.shading = ShadingPath::Exact;
  const RenderResult clean = render(s, o);
  s.surfaces[0].mesh.normals[0] = glm::dvec3(kNaN);
  const RenderResult bad = render(s, o);
  ASSERT_TRUE(test::allFinite(bad.image));
  // Pixels next to vertex 2 (far corner, barycentric weight of vertex 0 ~ 0) must be unchanged.
  EXPECT_NEAR(bad.image.at(W - 1, 0).x, clean.image.at(W - 1, 0).x, 1e-3);
}

// Grain tangent exactly along the normal, degenerate uvs (uv gradient path), NaN uv at a vertex:
// defined, finite, lit.
TEST(SurfaceShadingReview, DegenerateGrainInputsStayFinite) {
  constexpr int W = 8, H = 8;
  for (int variant = 0; variant < 4; ++variant) {
    Scene s = test::baseScene(W, H);
    s.lights = oneLight();
    Material m = burnishedU();
    m.bumpMap = std::make_shared<RampHeight>(0.3);
    s.materials[0] = m;
    SceneSurface r = parametricRect(-1, -1, W + 1, H + 1, 10.0, W, H, 0);
    if (variant == 0)
      for (auto& d : r.mesh.derivU) d = {0, 0, 1};  // along N
    if (variant == 1) {
      r.mesh.derivU.clear(), r.mesh.derivV.clear();
      for (auto& uv : r.mesh.uvs) uv = {0.5, 0.5};  // triangle uv gradient: det 0
    }
    if (variant == 2) {
      r.mesh.derivU.clear(), r.mesh.derivV.clear();
      r.mesh.uvs[1] = {kNaN, 0.0};
    }
    if (variant == 3) {
      r.mesh.derivU.clear(), r.mesh.derivV.clear();
      r.mesh.uvs[1] = {1e300, -1e300};  // gradient overflows
    }
    s.surfaces.push_back(r);
    RenderOptions o = test::smallOptions(W, H);
    for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
      o.shading = path;
      const RenderResult a = render(s, o);
      EXPECT_TRUE(test::allFinite(a.image)) << variant;
      EXPECT_TRUE(anyNonBlack(a.image)) << variant;
      const RenderResult b = renderReference(s, o);
      EXPECT_TRUE(test::allFinite(b.image)) << variant;
    }
  }
}

// A burnished, grooved, bumped triangle seen exactly edge-on, orthographic and perspective.
TEST(SurfaceShadingReview, EdgeOnBurnishedTriangleIsFinite) {
  constexpr int W = 16, H = 16;
  for (bool persp : {false, true}) {
    Scene s = test::baseScene(W, H);
    s.lights = oneLight();
    Material m = burnishedU();
    m.burnish.grooves = std::make_shared<GrooveTexture>(50, 0.8);
    m.bumpMap = std::make_shared<RampHeight>(2.0);
    m.colourMap = std::make_shared<ChequerTexture>(8, 8, glm::vec3(1.0f), glm::vec3(0.2f));
    s.materials[0] = m;
    if (persp) {
      s.camera->projection = Camera::Projection::Perspective;
      s.camera->eye = {0, 0, 10};
      s.camera->fovYDegrees = 60;
    }
    SceneSurface t;
    // The plane x = 0 contains the view direction (and the eye under perspective).
    t.mesh.positions = {{0, -5, 0}, {0, 5, 0}, {0, 0, -5}};
    t.mesh.normals = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
    t.mesh.derivU = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    t.mesh.derivV = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
    t.mesh.uvs = {{0, 0}, {0, 1}, {1, 0.5}};
    t.mesh.triangles = {{0, 1, 2}};
    s.surfaces.push_back(t);
    RenderOptions o = test::smallOptions(W, H);
    EXPECT_TRUE(test::allFinite(render(s, o).image)) << persp;
    EXPECT_TRUE(test::allFinite(renderReference(s, o).image)) << persp;
  }
}

// Circular and radial grain with grooves, the axis through a pixel centre (the fragment on the
// axis: radial offset 0, the turn undefined).
TEST(SurfaceShadingReview, GrainAxisThroughAFragmentIsFinite) {
  constexpr int W = 9, H = 9;
  for (Burnish::Grain grain : {Burnish::Grain::Circular, Burnish::Grain::Radial}) {
    Scene s = test::baseScene(W, H);
    s.lights = oneLight();
    Material m = burnishedU();
    m.burnish.grain = grain;
    m.burnish.axisPoint = test::world(V2(4.5, 4.5), 10.0, W, H);
    m.burnish.axisDirection = {0, 0, 1};
    m.burnish.grooves = std::make_shared<GrooveTexture>(3, 1.0);
    s.materials[0] = m;
    s.surfaces.push_back(parametricRect(0, 0, W, H, 10.0, W, H, 0));
    RenderOptions o = test::smallOptions(W, H);
    for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
      o.shading = path;
      const RenderResult a = render(s, o);
      ASSERT_TRUE(test::allFinite(a.image));
      EXPECT_GT(a.image.at(4, 4).x, 0.0f);
      EXPECT_TRUE(test::allFinite(renderReference(s, o).image));
    }
  }
}

// Grooves far finer than a pixel (1e9 per unit, depth 1): the A-buffer's box filter gives the
// mean intensity 1/2; a groove coordinate of 1e6 (beyond 2^52 grooves) still filters.
TEST(SurfaceShadingReview, BillionGroovesFilterToTheirMean) {
  constexpr int W = 8, H = 8;
  for (double offset : {0.0, 1e6}) {
    Scene s = test::baseScene(W, H);  // ambient 1, diffuse 1: radiance = groove intensity
    Material m = s.materials[0];
    m.burnish.grain = Burnish::Grain::U;  // grooves indexed by v
    m.burnish.grooves = std::make_shared<GrooveTexture>(1e9, 1.0);
    s.materials[0] = m;
    SceneSurface r = parametricRect(0, 0, W, H, 10.0, W, H, 0);
    for (auto& uv : r.mesh.uvs) uv.y += offset;
    s.surfaces.push_back(r);
    RenderOptions o = test::smallOptions(W, H);
    o.shading = ShadingPath::Exact;
    const RenderResult a = render(s, o);
    ASSERT_TRUE(test::allFinite(a.image));
    // The cylinder model under ambient light alone: the same factor for every pixel; compare
    // with a groove-free render.
    Scene plain = s;
    plain.materials[0].burnish.grooves.reset();
    const RenderResult p = render(plain, o);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        EXPECT_NEAR(a.image.at(x, y).x / p.image.at(x, y).x, 0.5, 0.02) << offset << " " << x << "," << y;
    if (HasFailure()) return;
  }
}

// A bump of enormous scale tilts the normal into the tangent plane (and beyond, to the back):
// the pixel is finite and lit by something (not black).
TEST(SurfaceShadingReview, HugeBumpScaleIsFiniteAndLit) {
  constexpr int W = 8, H = 8;
  for (double scale : {1e3, 1e8, -1e8, 1e300}) {
    for (bool burnished : {false, true}) {
      Scene s = test::baseScene(W, H);
      s.lights = oneLight();
      Material m = burnished ? burnishedU() : s.materials[0];
      m.phong.diffuse = glm::dvec3(0.6);
      m.bumpMap = std::make_shared<RampHeight>(1.0);
      m.bumpScale = scale;
      s.materials[0] = m;
      s.surfaces.push_back(parametricRect(0, 0, W, H, 10.0, W, H, 0));
      RenderOptions o = test::smallOptions(W, H);
      for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact}) {
        o.shading = path;
        const RenderResult a = render(s, o);
        ASSERT_TRUE(test::allFinite(a.image)) << scale;
        EXPECT_GT(a.image.at(3, 3).x, 0.01f) << scale << " " << burnished;
      }
    }
  }
}

// Blinn's bump is a height along the surface's normal: the same displaced surface must shade
// the same whichever side it is seen from. A ramp height h = g u on the flat plane z = 0 is
// exactly the plane tilted to normal (-g, 0, 1)/|.|. From the front both agree; from the back
// the renderer flips the normal to the viewer BEFORE bumping, so the bump is taken along the
// back normal and the back of the ramp tilts the wrong way.
TEST(SurfaceShadingReview, BumpIsTheSameSurfaceFromBothSides) {
  constexpr int W = 8, H = 8;
  const double g = 0.5;
  for (bool fromBack : {false, true}) {
    auto scene = [&](bool bumped) {
      Scene s = test::baseScene(W, H);
      s.lights.ambient = glm::dvec3(0.0);
      s.lights.lights = {{glm::normalize(glm::dvec3(1, 0, 1)), glm::dvec3(1.0)},
                         {glm::normalize(glm::dvec3(1, 0, -1)), glm::dvec3(1.0)}};
      if (fromBack) s.camera->eye = {0, 0, -10};
      Material m = s.materials[0];
      m.phong.diffuse = glm::dvec3(1.0);
      m.phong.specular = glm::dvec3(0.0);
      if (bumped) m.bumpMap = std::make_shared<RampHeight>(g);
      s.materials[0] = m;
      SceneSurface r = parametricRect(-20, -20, 20, 20, 10.0, W, H, 0);
      for (auto& p : r.mesh.positions) p.z = 0.0;
      if (!bumped)
        for (auto& n : r.mesh.normals) n = glm::normalize(glm::dvec3(-g, 0, 1));
      s.surfaces.push_back(r);
      return s;
    };
    RenderOptions o = test::smallOptions(W, H);
    o.shading = ShadingPath::Exact;
    const RenderResult bumped = render(scene(true), o), tilted = render(scene(false), o);
    EXPECT_NEAR(bumped.image.at(4, 4).x, tilted.image.at(4, 4).x, 1e-4) << (fromBack ? "back" : "front");
  }
}

// Perspective view of a chequered ceiling reaching (almost) the horizon. In the row just above
// the horizon, one pixel down lies beyond the horizon: footprintOf gives up and the chequer is
// POINT-sampled (0 or 1 per pixel) although the true footprint there is enormous (its mean, 1/2,
// is what the reference averages to). Measured as the RMS difference from the reference over
// that row.
TEST(SurfaceShadingReview, FootprintAtTheHorizonFiltersInsteadOfPointSampling) {
  constexpr int W = 48, H = 32;
  Scene s = test::baseScene(W, H);
  s.camera->projection = Camera::Projection::Perspective;
  s.camera->eye = {0, 0, 0};
  s.camera->target = {0, 0, -1};
  s.camera->fovYDegrees = 40;
  s.camera->nearPlane = 0.1;
  s.camera->farPlane = 1e5;
  Material m = s.materials[0];
  m.colourMap = std::make_shared<ChequerTexture>(1, 1, glm::vec3(1.0f), glm::vec3(0.0f));
  s.materials[0] = m;
  SceneSurface c;
  const double L = 1e6;
  c.mesh.positions = {{-L, 1, -0.2}, {L, 1, -0.2}, {L, 1, -L}, {-L, 1, -L}};
  c.mesh.uvs = {{-L, -0.2}, {L, -0.2}, {L, -L}, {-L, -L}};
  c.mesh.normals = {{0, -1, 0}, {0, -1, 0}, {0, -1, 0}, {0, -1, 0}};
  c.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.surfaces.push_back(c);
  RenderOptions o = test::smallOptions(W, H);
  o.referenceSamples = 16;
  const RenderResult a = render(s, o), ref = renderReference(s, o);
  ASSERT_TRUE(test::allFinite(a.image));
  const int row = H / 2 - 1;  // just above the horizon (image centre line y = H/2)
  double e2 = 0;
  for (int x = 0; x < W; ++x) {
    const double d = a.image.at(x, row).x - ref.image.at(x, row).x;
    e2 += d * d;
  }
  const double rms = std::sqrt(e2 / W);
  std::printf("horizon row: rms(A-buffer - reference) = %.4f\n", rms);
  EXPECT_LT(rms, 0.15);
}

// The A-buffer against its reference on a perspective sphere: chequered Phong, burnished along u
// with grooves, circular grain. Sphere of radius 1 filling ~40 px.
TEST(SurfaceShadingReview, SphereUnderPerspectiveMatchesTheReference) {
  constexpr int W = 48, H = 48, nu = 96, nv = 48;
  const double pi = std::numbers::pi;
  SceneSurface sphere;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const double u = double(i) / nu, v = double(j) / nv;
      const double st = std::sin(pi * v), ct = std::cos(pi * v), cp = std::cos(2 * pi * u), sp = std::sin(2 * pi * u);
      sphere.mesh.positions.push_back({st * cp, st * sp, -ct});
      sphere.mesh.normals.push_back({st * cp, st * sp, -ct});
      sphere.mesh.derivU.push_back({-2 * pi * st * sp, 2 * pi * st * cp, 0});
      sphere.mesh.derivV.push_back({pi * ct * cp, pi * ct * sp, pi * st});
      sphere.mesh.uvs.push_back({u, v});
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const unsigned a = j * (nu + 1) + i, b = a + 1, c = b + nu + 1, d = a + nu + 1;
      if (j > 0) sphere.mesh.triangles.push_back({a, b, c});
      if (j < nv - 1) sphere.mesh.triangles.push_back({a, c, d});
    }
  for (int variant = 0; variant < 3; ++variant) {
    Scene s;
    s.background = glm::vec4(0.0f);
    s.camera = Camera{};
    s.camera->eye = {0.3, -2.6, 1.2};
    s.camera->fovYDegrees = 50;
    s.camera->up = {0, 0, 1};
    s.lights = LightRig::studioRig(3);
    Material m;
    m.phong.diffuse = glm::dvec3(0.6);
    m.phong.specular = glm::dvec3(0.4);
    m.phong.exponent = 30;
    if (variant == 0) m.colourMap = std::make_shared<ChequerTexture>(16, 8, glm::vec3(1.0f), glm::vec3(0.1f));
    if (variant == 1) {
      m.burnish.grain = Burnish::Grain::U;
      m.burnish.grooves = std::make_shared<GrooveTexture>(200, 0.6);
    }
    if (variant == 2) {
      m.burnish.grain = Burnish::Grain::Circular;
      m.burnish.axisDirection = {0, 0, 1};
      m.burnish.grooves = std::make_shared<GrooveTexture>(30, 0.6);
    }
    s.materials = {m};
    s.surfaces = {sphere};
    RenderOptions o = test::smallOptions(W, H);
    o.shading = ShadingPath::Exact;
    o.referenceSamples = 12;
    const RenderResult a = render(s, o), ref = renderReference(s, o);
    ASSERT_TRUE(test::allFinite(a.image));
    double e2 = 0, peak = 0;
    int n = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (ref.image.at(x, y).w < 0.999f || a.image.at(x, y).w < 0.999f) continue;  // interior only
        const double d = a.image.at(x, y).x - ref.image.at(x, y).x;
        e2 += d * d, ++n;
        peak = std::max(peak, std::abs(d));
      }
    const double rms = std::sqrt(e2 / std::max(n, 1));
    std::printf("sphere variant %d: interior pixels %d, rms %.4f, max %.4f\n", variant, n, rms, peak);
    // Per-fragment (A-buffer) versus per-sample (reference) shading of a pattern filtered over
    // the pixel: the difference is the nonlinearity of the shading across one pixel plus the
    // reference's sampling noise (~ contrast / (2 * 12) for 144 samples).
    EXPECT_LT(rms, 0.02) << variant;
  }
}

}  // namespace
}  // namespace wf
