// Stage "primitives" (render/pipeline.h), triangles: clipped to the near and far planes in eye
// space, projected into convex screen polygons with a screen-linear depth key plane.
#include "render/pipeline.h"

#include <algorithm>
#include <cmath>

namespace wf {

namespace {

// Intersection of the segment a-b with the plane depth = plane, computed from the endpoints in
// a canonical order so that the two triangles sharing an edge get the very same point.
glm::dvec3 depthIntersection(glm::dvec3 a, glm::dvec3 b, double plane) {
  if (b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && b.z < a.z)))) std::swap(a, b);
  const double t = (plane - (-a.z)) / ((-b.z) - (-a.z));
  return a + t * (b - a);
}

// Keeps the part of a convex eye-space polygon with depth >= plane (keepFar) or <= plane.
int clipDepth(const glm::dvec3* in, int n, glm::dvec3* out, double plane, bool keepFar) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 &a = in[i], &b = in[(i + 1) % n];
    const bool ia = keepFar ? -a.z >= plane : -a.z <= plane;
    const bool ib = keepFar ? -b.z >= plane : -b.z <= plane;
    if (ia) out[m++] = a;
    if (ia != ib) out[m++] = depthIntersection(a, b, plane);
  }
  return m;
}

}  // namespace

namespace {

// The polygon's bounding box within the image into prim, the polygon into the sink; false when
// it covers nothing inside the image.
bool finishPolygon(const ScreenPolygon& poly, const ViewTransform& view, TrianglePrim& prim, TriangleSink& out) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (int i = 0; i < poly.count; ++i) {
    x0 = std::min(x0, poly.x[i]);
    x1 = std::max(x1, poly.x[i]);
    y0 = std::min(y0, poly.y[i]);
    y1 = std::max(y1, poly.y[i]);
  }
  x0 = std::max(x0, 0.0);
  y0 = std::max(y0, 0.0);
  x1 = std::min(x1, double(view.width));
  y1 = std::min(y1, double(view.height));
  if (!(x1 > x0) || !(y1 > y0) || poly.count < 3 || !(poly.area() > 0)) return false;
  // Rounded outwards: a box shrunk by float rounding would drop a row of thin coverage.
  auto down = [](double v) { float f = float(v); return double(f) > v ? std::nextafter(f, -INFINITY) : f; };
  auto up = [](double v) { float f = float(v); return double(f) < v ? std::nextafter(f, INFINITY) : f; };
  prim.bbox[0] = down(x0);
  prim.bbox[1] = down(y0);
  prim.bbox[2] = up(x1);
  prim.bbox[3] = up(y1);
  prim.firstVertex = std::uint32_t(out.vertexCount);
  prim.vertexCount = std::uint8_t(poly.count);
  for (int i = 0; i < poly.count; ++i) out.vertices[out.vertexCount++] = {poly.x[i], poly.y[i]};
  return true;
}

}  // namespace

void setupTriangles(const PreparedScene& ps, const SceneSurface& surf, std::uint32_t surfaceIndex,
                    std::uint16_t shader, std::uint32_t tag, size_t begin, size_t end, TriangleSink& out,
                    SetupCounts& counts) {
  const ViewTransform& view = ps.view;
  const TriangleMesh& mesh = surf.mesh;
  for (size_t t = begin; t < end; ++t) {
    const glm::uvec3 tri = mesh.triangles[t];
    if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() ||
        tri.z >= mesh.positions.size()) {
      ++counts.rejected;
      continue;
    }
    glm::dvec3 e[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& w = mesh.positions[tri[k]];
      ok = ok && finite3(w);
      e[k] = view.toEye(w);
    }
    if (!ok || !finite3(e[0]) || !finite3(e[1]) || !finite3(e[2])) {
      ++counts.rejected;
      continue;
    }
    ++counts.triangles;
    glm::dvec3 a[8], b[8];
    int n = clipDepth(e, 3, a, view.nearPlane, true);
    n = clipDepth(a, n, b, view.farPlane, false);
    if (n < 3) {
      ++counts.clipped;
      continue;
    }
    ScreenPolygon poly;
    float zlo = 1e30f, zhi = 0;
    for (int k = 0; k < n; ++k) {
      const glm::dvec2 p = view.project(b[k]);
      poly.add(p.x, p.y);
      zlo = std::min(zlo, float(-b[k].z));
      zhi = std::max(zhi, float(-b[k].z));
    }
    poly.removeDuplicates();
    // Depth key plane from the eye-space plane n.P = k of the triangle.
    const glm::dvec3 e1 = e[1] - e[0], e2 = e[2] - e[0];
    const glm::dvec3 nrm = glm::cross(e1, e2);
    const double k = glm::dot(nrm, e[0]);
    TrianglePrim prim;
    // Seen edge-on (the plane through the eye, or perpendicular to the screen): no area. The
    // test is relative, so that it means the same at any scale (1e-100 ... 1e100).
    const double nrmLength = glm::length(nrm);
    if (view.perspective) {
      if (!(std::abs(k) > 1e-14 * nrmLength * glm::length(e[0]))) {
        ++counts.clipped;
        continue;
      }
      const double f = view.focal;
      prim.qa = nrm.x / (f * k);
      prim.qb = -nrm.y / (f * k);
      prim.qc = (-nrm.x * view.cx / f + nrm.y * view.cy / f - nrm.z) / k;
    } else {
      if (!(std::abs(nrm.z) > 1e-14 * nrmLength)) {
        ++counts.clipped;
        continue;
      }
      const double s = view.orthoScale;
      prim.qa = nrm.x / (s * nrm.z);
      prim.qb = -nrm.y / (s * nrm.z);
      prim.qc = (-nrm.x * view.cx / s + nrm.y * view.cy / s - k) / nrm.z;
    }
    prim.zlo = zlo;
    prim.zhi = zhi;
    prim.tag = tag;
    prim.shader = shader;
    prim.mayMerge = true;
    if (!finishPolygon(poly, view, prim, out)) {
      ++counts.clipped;
      continue;
    }
    TriangleAttributes ta;
    ta.p0 = e[0];
    ta.e1 = e1;
    ta.e2 = e2;
    ta.d00 = glm::dot(e1, e1);
    ta.d01 = glm::dot(e1, e2);
    ta.d11 = glm::dot(e2, e2);
    const double den = ta.d00 * ta.d11 - ta.d01 * ta.d01;
    ta.invDen = den > 0 ? 1.0 / den : 0.0;
    ta.surface = surfaceIndex;
    ta.triangle = std::uint32_t(t);
    out.prims[out.count] = prim;
    out.attributes[out.count] = ta;
    ++out.count;
  }
}

}  // namespace wf
