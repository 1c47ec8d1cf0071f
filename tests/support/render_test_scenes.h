// Small scenes for the renderer's tests: an orthographic camera with one pixel per world unit,
// so that screen positions and pixel areas can be written down exactly; expected per-pixel
// areas by clipping (the independent reference); image comparisons.
#pragma once

#include "abuffer/screen_polygon.h"
#include "core/image.h"
#include "render/renderer.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace wf::test {

using V2 = glm::dvec2;
using Poly = std::vector<V2>;

inline Camera orthoCamera(int W, int H) {
  Camera c;
  c.projection = Camera::Projection::Orthographic;
  c.eye = {0, 0, 10};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.orthoHeight = H;  // 1 pixel per world unit
  c.nearPlane = 1;
  c.farPlane = 100;
  (void)W;
  return c;
}

// World point seen at screen (X, Y) and view depth `depth` by orthoCamera.
inline glm::dvec3 world(const V2& s, double depth, int W, int H) { return {s.x - W / 2.0, H / 2.0 - s.y, 10.0 - depth}; }

inline Scene baseScene(int W, int H) {
  Scene s;
  s.camera = orthoCamera(W, H);
  s.background = glm::vec4(0.0f);
  s.lights.ambient = glm::dvec3(1.0);
  s.materials[0].phong.diffuse = glm::dvec3(1.0);
  s.materials[0].phong.specular = glm::dvec3(0.0);
  return s;
}

inline RenderOptions smallOptions(int W, int H) {
  RenderOptions o;
  o.width = W;
  o.height = H;
  o.tileSize = 16;  // several tiles even in small images
  o.sphereResolution = 32;
  o.map.resolution = 32;
  o.map.samples = 16;
  return o;
}

// A surface of triangles given in screen coordinates, all at view depth `depth`.
inline SceneSurface screenSurface(const std::vector<Poly>& tris, double depth, int W, int H, glm::vec3 colour = glm::vec3(1),
                           int material = 0) {
  SceneSurface s;
  s.material = material;
  for (const Poly& t : tris) {
    const std::uint32_t b = std::uint32_t(s.mesh.positions.size());
    for (const V2& p : t) {
      s.mesh.positions.push_back(world(p, depth, W, H));
      s.mesh.colours.push_back(colour);
    }
    s.mesh.triangles.push_back({b, b + 1, b + 2});
  }
  return s;
}

// The triangles of an (n + 1) x (n + 1) grid of vertices laid out row by row, two per cell.
inline void addGridTriangles(TriangleMesh& mesh, int n) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i);
      mesh.triangles.push_back({a, a + 1, a + std::uint32_t(n) + 2});
      mesh.triangles.push_back({a, a + std::uint32_t(n) + 2, a + std::uint32_t(n) + 1});
    }
}

// An axis-aligned screen rectangle [x0, x1] x [y0, y1] as one mesh of two triangles sharing
// the diagonal (shared vertices).
inline SceneSurface screenRect(double x0, double y0, double x1, double y1, double depth, int W, int H, glm::vec3 colour,
                        int material = 0) {
  SceneSurface s;
  s.material = material;
  for (const V2& p : {V2(x0, y0), V2(x1, y0), V2(x1, y1), V2(x0, y1)}) {
    s.mesh.positions.push_back(world(p, depth, W, H));
    s.mesh.colours.push_back(colour);
  }
  s.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return s;
}

inline SceneWire plainWire(const std::vector<std::vector<V2>>& lines, double thicknessPx, double depth, int W, int H) {
  SceneWire w;
  w.style = WireStyle::Plain;
  w.thickness = thicknessPx;
  w.thicknessInPixels = true;
  w.colour = glm::vec3(1.0f);
  for (const auto& l : lines) {
    std::vector<glm::dvec3> pts;
    for (const V2& p : l) pts.push_back(world(p, depth, W, H));
    w.lines.add(pts);
  }
  return w;
}

// Exact covered area of every pixel by a set of convex polygons with disjoint interiors.
inline std::vector<double> pixelAreas(const std::vector<Poly>& polys, int W, int H) {
  std::vector<double> a(size_t(W) * H, 0.0);
  for (const Poly& v : polys) {
    ScreenPolygon p;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const V2& q : v) {
      p.add(q.x, q.y);
      x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
    }
    // Bounds clamped in double first: a vertex may lie billions of pixels away.
    const int r0 = int(std::clamp(std::floor(y0), 0.0, double(H))), r1 = int(std::clamp(std::ceil(y1), 0.0, double(H)));
    const int c0 = int(std::clamp(std::floor(x0), 0.0, double(W))), c1 = int(std::clamp(std::ceil(x1), 0.0, double(W)));
    for (int py = r0; py < r1; ++py)
      for (int px = c0; px < c1; ++px) {
        ScreenPolygon piece;
        clipRect(p, piece, px, py, px + 1, py + 1);
        a[size_t(py) * W + px] += piece.area();
      }
  }
  return a;
}

inline double sumAlpha(const ImageRGBA& im) {
  double s = 0;
  for (const glm::vec4& p : im.pixels) s += p.w;
  return s;
}

inline bool allFinite(const ImageRGBA& im) {
  for (const glm::vec4& p : im.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w)) return false;
  return true;
}

// Largest |alpha - expected| over the image, and where.
inline double maxAlphaError(const ImageRGBA& im, const std::vector<double>& want, int* where = nullptr) {
  double m = 0;
  for (size_t i = 0; i < im.pixels.size(); ++i) {
    const double e = std::abs(double(im.pixels[i].w) - want[i]);
    if (e > m) {
      m = e;
      if (where) *where = int(i);
    }
  }
  return m;
}

inline double maxDiff(const ImageRGBA& a, const ImageRGBA& b, int* where = nullptr) {
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      const double e = std::abs(double(a.pixels[i][c]) - double(b.pixels[i][c]));
      if (e > m || std::isnan(e)) {
        m = std::isnan(e) ? INFINITY : e;
        if (where) *where = int(i);
      }
    }
  return m;
}

}  // namespace wf::test
