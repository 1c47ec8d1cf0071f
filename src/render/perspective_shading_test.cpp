// Shading in perspective (render/renderer.h: ShadingPath). The closed path (the default) against
// the exact path, pixel for pixel, where the paper's orthographic maps are visibly wrong: a
// brushed plate seen with a wide field of view (the highlight band sweeps across it; under the
// orthographic assumption the plate is one flat tone) and a wire crossing the whole image (its
// shading at the corners, where the view vector is furthest from the axis).
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace wf {
namespace {

constexpr int W = 96, H = 64;

double luminance(const glm::vec4& p) { return 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z; }

double maxDifference(const ImageRGBA& a, const ImageRGBA& b) {
  double m = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 4; ++c) m = std::max(m, double(std::abs(a.pixels[i][c] - b.pixels[i][c])));
  return m;
}

Camera wideCamera() {
  Camera c;
  c.eye = {0.0, 0.0, 3.0};
  c.target = {0.0, 0.0, 0.0};
  c.fovYDegrees = 70.0;
  c.nearPlane = 0.5;
  c.farPlane = 10.0;
  return c;
}

// The plane z = 0 filling the image, brushed along x (grain U, (u, v) = (x, y)), one light
// tilted towards +x: the highlight is where T.V = -T.L, a band right of the centre.
Scene brushedPlate() {
  Scene s;
  s.camera = wideCamera();
  s.background = glm::vec4(0.0f);
  s.lights.ambient = glm::dvec3(0.02);
  s.lights.lights.push_back({glm::normalize(glm::dvec3(0.3, 0.0, 1.0)), glm::dvec3(1.0)});
  Material m;
  m.phong.diffuse = glm::dvec3(0.1);
  m.phong.specular = glm::dvec3(0.8);
  m.phong.exponent = 30.0;
  m.burnish.grain = Burnish::Grain::U;
  s.materials = {m};
  SceneSurface plate;
  TriangleMesh& mesh = plate.mesh;
  for (const glm::dvec2 p : {glm::dvec2(-6, -4), glm::dvec2(6, -4), glm::dvec2(6, 4), glm::dvec2(-6, 4)}) {
    mesh.positions.push_back({p.x, p.y, 0.0});
    mesh.normals.push_back({0, 0, 1});
    mesh.uvs.push_back(p);
    mesh.derivU.push_back({1, 0, 0});
    mesh.derivV.push_back({0, 1, 0});
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.surfaces = {plate};
  return s;
}

RenderOptions options(ShadingPath path) {
  RenderOptions o;
  o.width = W;
  o.height = H;
  o.shading = path;
  return o;
}

TEST(PerspectiveShading, BrushedPlateHighlightBandLiesWhereTheExactPathPutsIt) {
  const Scene s = brushedPlate();
  const RenderResult closed = render(s, options(ShadingPath::Closed));
  const RenderResult exact = render(s, options(ShadingPath::Exact));
  const RenderResult maps = render(s, options(ShadingPath::Maps));
  EXPECT_LE(maxDifference(closed.image, exact.image), 1e-6);  // the lobe table's ~1e-9, float images
  EXPECT_LE(closed.stats.lobeError, 1e-8);
  for (int row : {8, H / 2, H - 9}) {
    int peakClosed = 0, peakExact = 0;
    double lo = 1e9, hi = 0.0, mapsLo = 1e9, mapsHi = 0.0;
    for (int x = 0; x < W; ++x) {
      const double c = luminance(closed.image.at(x, row)), e = luminance(exact.image.at(x, row));
      if (c > luminance(closed.image.at(peakClosed, row))) peakClosed = x;
      if (e > luminance(exact.image.at(peakExact, row))) peakExact = x;
      lo = std::min(lo, c), hi = std::max(hi, c);
      const double mp = luminance(maps.image.at(x, row));
      mapsLo = std::min(mapsLo, mp), mapsHi = std::max(mapsHi, mp);
    }
    EXPECT_LE(std::abs(peakClosed - peakExact), 1) << row;
    EXPECT_GT(peakClosed, W / 2) << row;       // right of the centre: the light leans towards +x
    EXPECT_LT(peakClosed, W - 4) << row;       // a band inside the image, not its edge
    EXPECT_GT(hi, 2.0 * lo) << row;            // a band, not a flat tone
    EXPECT_LT(mapsHi - mapsLo, 1e-3) << row;   // the orthographic map: one flat tone
  }
}

TEST(PerspectiveShading, WireAcrossTheImageMatchesExactAtTheCorners) {
  Scene s;
  s.camera = wideCamera();
  s.background = glm::vec4(0.0f);
  s.lights = LightRig::studioRig(7);
  s.lightsFollowCamera = true;
  s.materials[0].phong.diffuse = glm::dvec3(0.3, 0.2, 0.1);
  s.materials[0].phong.specular = glm::dvec3(0.9);
  s.materials[0].phong.exponent = 60.0;
  SceneWire w;
  w.thickness = 3.0;
  w.thicknessInPixels = true;
  // Corner to corner of the image plane at depth 3 (half height tan(35 deg) * 3), and beyond.
  const double hy = std::tan(glm::radians(35.0)) * 3.0 * 1.1, hx = hy * W / H;
  w.lines.add({{-hx, -hy, 0.0}, {hx, hy, 0.0}});
  w.lines.add({{-hx, hy, 0.0}, {hx, -hy, 0.0}});
  s.wires = {w};
  const RenderResult closed = render(s, options(ShadingPath::Closed));
  const RenderResult exact = render(s, options(ShadingPath::Exact));
  const RenderResult maps = render(s, options(ShadingPath::Maps));
  double worstClosed = 0.0, worstMaps = 0.0;
  int seen = 0;
  for (int x : {0, 1, 2, W - 3, W - 2, W - 1})
    for (int y : {0, 1, 2, H - 3, H - 2, H - 1}) {
      const glm::vec4 c = closed.image.at(x, y), e = exact.image.at(x, y), m = maps.image.at(x, y);
      if (e.w < 0.5f) continue;  // only where the wire covers the corner pixel
      ++seen;
      for (int k = 0; k < 3; ++k) {
        worstClosed = std::max(worstClosed, double(std::abs(c[k] - e[k])));
        worstMaps = std::max(worstMaps, double(std::abs(m[k] - e[k])));
      }
    }
  EXPECT_GE(seen, 8);
  EXPECT_LE(worstClosed, 1e-6);
  EXPECT_GT(worstMaps, 1e-2);  // the orthographic map is off there: the test can tell
  EXPECT_LE(maxDifference(closed.image, exact.image), 1e-6);
}

}  // namespace
}  // namespace wf
