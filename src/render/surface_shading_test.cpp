// Burnished, textured and bumped surfaces through the whole renderer, against closed forms:
// the exact cylinder model at the analytic grain tangent, Phong at the analytic bumped normal,
// the colour map on the diffuse part only, grooves scaling diffuse and specular together, and
// the box-filtered texture footprint against the point-sampling reference.
#include "render/renderer.h"
#include "shading/cylinder_shading.h"
#include "shading/phong.h"
#include "texture/grooves.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace wf {
namespace {

using test::V2;
constexpr int W = 48, H = 32;

// One light from the upper right, some ambient: eye space equals world space for orthoCamera.
LightRig testLights() {
  LightRig r;
  r.ambient = glm::dvec3(0.05);
  r.lights.push_back({glm::normalize(glm::dvec3(0.4, 0.5, 0.8)), glm::dvec3(0.9)});
  return r;
}

// The whole image covered by the plane z = 0 (view depth 10), (u, v) = world (x, y), with
// dS/du = (1, 0, 0) rotated by `angle` about z and dS/dv perpendicular to it.
Scene planeScene(const Material& m, double angle = 0.0) {
  Scene s = test::baseScene(W, H);
  s.lights = testLights();
  s.materials[0] = m;
  SceneSurface plane = test::screenRect(-4, -4, W + 4, H + 4, 10.0, W, H, glm::vec3(1.0f));
  const glm::dvec3 du(std::cos(angle), std::sin(angle), 0.0), dv(-std::sin(angle), std::cos(angle), 0.0);
  for (const glm::dvec3& p : plane.mesh.positions) {
    plane.mesh.normals.push_back({0, 0, 1});
    plane.mesh.uvs.push_back({p.x, p.y});
    plane.mesh.derivU.push_back(du);
    plane.mesh.derivV.push_back(dv);
  }
  s.surfaces.push_back(plane);
  return s;
}

Material metal(double diffuse, double specular, double exponent) {
  Material m;
  m.phong.diffuse = glm::dvec3(diffuse);
  m.phong.specular = glm::dvec3(specular);
  m.phong.exponent = exponent;
  return m;
}

RenderOptions exactOptions() {
  RenderOptions o = test::smallOptions(W, H);
  o.shading = ShadingPath::Exact;
  return o;
}

// World / eye point at the centre of pixel (px, py) on the plane.
glm::dvec3 planePoint(int px, int py) { return test::world(V2(px + 0.5, py + 0.5), 10.0, W, H); }

TEST(SurfaceShading, BurnishedGrainAlongUIsTheCylinderModelAtDsDu) {
  Material m = metal(0.3, 0.8, 30);
  m.burnish.grain = Burnish::Grain::U;
  for (double angle : {0.0, 0.7, 2.0}) {
    const Scene s = planeScene(m, angle);
    const RenderResult r = render(s, exactOptions());
    const glm::dvec3 T(std::cos(angle), std::sin(angle), 0.0);
    const glm::dvec3 expect = cylinderRadianceExact(T, {0, 0, 1}, m.phong, testLights().canonical(), 1e-10);
    for (auto [px, py] : {std::pair{5, 5}, {24, 16}, {40, 30}})
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.image.at(px, py)[c], expect[c], 2e-5) << angle << " " << px << "," << py;
    // The closed path (the default) agrees with exact to its lobe table's error; the map path
    // within the map's own error estimate.
    const RenderResult rc = render(s, test::smallOptions(W, H));
    EXPECT_EQ(rc.stats.lobeTables, 1);
    for (auto [px, py] : {std::pair{5, 5}, {24, 16}, {40, 30}})
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(rc.image.at(px, py)[c], r.image.at(px, py)[c], 1e-6) << angle;
    RenderOptions o = test::smallOptions(W, H);
    o.shading = ShadingPath::Maps;
    o.map.resolution = 128;
    o.map.samples = 64;
    const RenderResult rm = render(s, o);
    EXPECT_GT(rm.stats.pseudoReflectanceMaps, 0);
    EXPECT_NEAR(rm.image.at(24, 16).x, expect.x, std::max(2e-3, 2 * rm.stats.mapError));
  }
}

TEST(SurfaceShading, BurnishedGrainAlongVIsPerpendicular) {
  Material m = metal(0.3, 0.8, 30);
  m.burnish.grain = Burnish::Grain::V;
  const Scene s = planeScene(m, 0.4);
  const RenderResult r = render(s, exactOptions());
  const glm::dvec3 T(-std::sin(0.4), std::cos(0.4), 0.0);
  const glm::dvec3 expect = cylinderRadianceExact(T, {0, 0, 1}, m.phong, testLights().canonical(), 1e-10);
  EXPECT_NEAR(r.image.at(20, 10).y, expect.y, 2e-5);
}

TEST(SurfaceShading, CircularGrainRunsAroundTheAxis) {
  // A record on a turntable: grain tangent = axis x (P - axis point), per pixel.
  Material m = metal(0.2, 1.0, 60);
  m.burnish.grain = Burnish::Grain::Circular;
  m.burnish.axisPoint = glm::dvec3(3.0, -2.0, 0.0);
  m.burnish.axisDirection = glm::dvec3(0.0, 0.0, 5.0);  // need not be unit
  const Scene s = planeScene(m);
  const RenderResult r = render(s, exactOptions());
  for (auto [px, py] : {std::pair{3, 4}, {30, 20}, {44, 6}, {10, 28}}) {
    const glm::dvec3 P = planePoint(px, py) - m.burnish.axisPoint;
    const glm::dvec3 T = glm::normalize(glm::dvec3(-P.y, P.x, 0.0));
    const glm::dvec3 expect = cylinderRadianceExact(T, {0, 0, 1}, m.phong, testLights().canonical(), 1e-10);
    EXPECT_NEAR(r.image.at(px, py).z, expect.z, 2e-5) << px << "," << py;
  }
  // Radial grain: the tangent points away from the axis instead (at a pixel the quad's diagonal
  // does not cross: its two pieces are shaded each at its own centroid).
  m.burnish.grain = Burnish::Grain::Radial;
  const RenderResult rr = render(planeScene(m), exactOptions());
  const glm::dvec3 P = planePoint(30, 8) - m.burnish.axisPoint;
  const glm::dvec3 expect = cylinderRadianceExact(glm::normalize(glm::dvec3(P.x, P.y, 0)), {0, 0, 1}, m.phong,
                                                  testLights().canonical(), 1e-10);
  EXPECT_NEAR(rr.image.at(30, 8).x, expect.x, 2e-5);
}

TEST(SurfaceShading, GroovesScaleDiffuseAndSpecularTogether) {
  // The paper modulates both parts by the groove texture (self-shadowing): the ratio grooved /
  // smooth at a pixel is the same for a diffuse-only and a specular-only metal.
  auto grooves = std::make_shared<GrooveTexture>(GrooveTexture{0.5, 0.8, 7});  // one groove per 2 px of v
  double ratios[2][4];
  int k = 0;
  for (auto [d, sp] : {std::pair{0.9, 0.0}, {0.0, 1.0}}) {
    Material m = metal(d, sp, 8);
    m.burnish.grain = Burnish::Grain::U;
    const RenderResult smooth = render(planeScene(m, 0.3), exactOptions());
    m.burnish.grooves = grooves;
    const RenderResult grooved = render(planeScene(m, 0.3), exactOptions());
    int j = 0;
    for (auto [px, py] : {std::pair{10, 3}, {10, 9}, {20, 17}, {33, 25}}) {
      ratios[k][j] = grooved.image.at(px, py).x / smooth.image.at(px, py).x;
      ++j;
    }
    ++k;
  }
  bool anyDarker = false;
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(ratios[0][j], ratios[1][j], 1e-4) << j;
    EXPECT_GE(ratios[0][j], 0.2 - 1e-6);
    EXPECT_LE(ratios[0][j], 1.0 + 1e-6);
    anyDarker = anyDarker || ratios[0][j] < 0.95;
  }
  EXPECT_TRUE(anyDarker);
}

class ConstantColour : public ColourTexture {
 public:
  explicit ConstantColour(glm::vec3 c) : c_(c) {}
  glm::vec3 sample(const glm::dvec2&, const UvFootprint&) const override { return c_; }
  std::string describe() const override { return "constant"; }

 private:
  glm::vec3 c_;
};

TEST(SurfaceShading, ColourMapMultipliesTheDiffusePartOnly) {
  Material m = metal(0.7, 0.6, 10);
  const glm::vec3 k(0.25f, 0.5f, 1.0f);
  m.colourMap = std::make_shared<ConstantColour>(k);
  const Scene s = planeScene(m);
  const LightRig rig = testLights().canonical();
  PhongMaterial d = m.phong, sp = m.phong;
  d.specular = glm::dvec3(0.0);
  sp.diffuse = glm::dvec3(0.0);
  const glm::dvec3 D = phongRadiance({0, 0, 1}, {0, 0, 1}, d, rig), S = phongRadiance({0, 0, 1}, {0, 0, 1}, sp, rig);
  ASSERT_GT(S.x, 0.01);  // a highlight to keep
  const RenderResult r = render(s, exactOptions());
  RenderOptions om = test::smallOptions(W, H);
  om.shading = ShadingPath::Maps;
  const RenderResult rm = render(s, om);
  EXPECT_EQ(rm.stats.reflectanceSpheres, 2);  // diffuse and specular parts
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.image.at(20, 20)[c], k[c] * D[c] + S[c], 1e-5) << c;
    EXPECT_NEAR(rm.image.at(20, 20)[c], k[c] * D[c] + S[c], 2e-2) << c;
  }
}

// h(u, v) = a u: the bumped plane is the plane tilted to z = a x, normal (-a, 0, 1).
class LinearHeight : public ScalarTexture {
 public:
  explicit LinearHeight(double a) : a_(a) {}
  double value(const glm::dvec2& uv) const override { return a_ * uv.x; }
  glm::dvec2 gradient(const glm::dvec2&) const override { return {a_, 0.0}; }
  std::string describe() const override { return "linear"; }

 private:
  double a_;
};

TEST(SurfaceShading, BumpMapTiltsTheNormalAsTheDisplacedSurface) {
  Material m = metal(0.8, 0.5, 20);
  m.bumpMap = std::make_shared<LinearHeight>(0.6);
  m.bumpScale = 1.0;
  const RenderResult r = render(planeScene(m), exactOptions());
  const glm::dvec3 N = glm::normalize(glm::dvec3(-0.6, 0.0, 1.0));
  const glm::dvec3 expect = phongRadiance(N, {0, 0, 1}, m.phong, testLights().canonical());
  const RenderResult flat = render(planeScene(metal(0.8, 0.5, 20)), exactOptions());
  EXPECT_GT(std::abs(flat.image.at(12, 12).x - expect.x), 0.02);  // the bump is visible
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.image.at(12, 12)[c], expect[c], 1e-5);
}

// Stripes across u, 0.3 px wide (far below a pixel): white where frac(u / 0.6) < 0.5, with the
// exact box filter over the footprint.
class FineStripes : public ColourTexture {
 public:
  static double integral(double u) {  // of the indicator, from 0 to u (period 0.6, duty 0.5)
    const double p = 0.6, k = std::floor(u / p), f = u - k * p;
    return k * 0.3 + std::min(f, 0.3);
  }
  glm::vec3 sample(const glm::dvec2& uv, const UvFootprint& fp) const override {
    const double w = fp.halfBox().x;
    if (w <= 0) return glm::vec3(std::fmod(std::fmod(uv.x, 0.6) + 0.6, 0.6) < 0.3 ? 1.0f : 0.0f);
    return glm::vec3(float((integral(uv.x + w) - integral(uv.x - w)) / (2 * w)));
  }
  std::string describe() const override { return "stripes"; }
};

TEST(SurfaceShading, SubPixelTextureIsBoxFilteredLikeTheReference) {
  Material m = metal(1.0, 0.0, 1);
  m.colourMap = std::make_shared<FineStripes>();
  Scene s = planeScene(m);
  s.lights.lights.clear();
  s.lights.ambient = glm::dvec3(1.0);  // radiance = texture
  RenderOptions o = exactOptions();
  const RenderResult a = render(s, o);
  o.referenceSamples = 12;
  const RenderResult ref = renderReference(s, o);
  double se = 0, worst = 0;
  int exactPixels = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double d = a.image.at(x, y).x - ref.image.at(x, y).x;
      se += d * d;
      worst = std::max(worst, std::abs(d));
      // The exact box filter over the pixel: u runs over [x - W/2, x + 1 - W/2]. Pixels cut by
      // the quad's diagonal hold two fragments, each shaded at its own centroid with a whole
      // pixel's footprint (an approximation, bounded below).
      const double u0 = x - W / 2.0, exact = FineStripes::integral(u0 + 1) - FineStripes::integral(u0);
      exactPixels += std::abs(a.image.at(x, y).x - exact) < 1e-5;
      EXPECT_NEAR(a.image.at(x, y).x, exact, 0.1);
    }
  EXPECT_GE(exactPixels, W * H - 2 * (W + H));  // all but those along the diagonal
  // The reference's own error: 12 strata per pixel of a 0.3 px pattern, about 1/12.
  EXPECT_LT(std::sqrt(se / (W * H)), 0.05);
  EXPECT_LT(worst, 0.1);
}

}  // namespace
}  // namespace wf
