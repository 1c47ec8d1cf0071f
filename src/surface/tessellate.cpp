// Tessellation of a Surface: a regular (u, v) grid, limit normals at poles, collapsed triangles
// left out. See tessellate.h and docs/surfaces.md.
#include "surface/tessellate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wf {

std::string tessellationProblem(int resolutionU, int resolutionV) {
  if (resolutionU < 1 || resolutionV < 1) return "tessellation resolution must be at least 1 x 1";
  if ((double(resolutionU) + 1.0) * (double(resolutionV) + 1.0) > kMaxTessellationVertices)
    return "tessellation of " + std::to_string(resolutionU) + " x " + std::to_string(resolutionV) +
           " makes more than 4,194,304 vertices (about 1 GB of mesh); use a lower resolution";
  return {};
}

TriangleMesh tessellate(const Surface& surface, int resolutionU, int resolutionV) {
  if (const std::string p = tessellationProblem(resolutionU, resolutionV); !p.empty()) throw std::invalid_argument(p);
  const int nu = resolutionU, cols = nu + 1;
  const ParameterDomain d = surface.domain();
  // Parameter of grid line k of n: exact at both ends.
  auto param = [](double a, double b, int k, int n) { return k == n ? b : a + (b - a) * (double(k) / n); };
  // The rows: resolutionV + 1 evenly in v, plus two at every crease (one per side, same
  // positions, each with its side's normal; a grid row within 1e-9 of a crease gives way).
  struct Row {
    double v;
    int side;  // -1: the crease seen from below, +1: from above, 0: a regular row
  };
  std::vector<Row> rowList;
  {
    std::vector<double> creases;
    for (double c : surface.creasesV())
      if (std::isfinite(c) && c > d.v0 && c < d.v1) creases.push_back(c);
    std::sort(creases.begin(), creases.end());
    creases.erase(std::unique(creases.begin(), creases.end()), creases.end());
    size_t next = 0;
    for (int j = 0; j <= resolutionV; ++j) {
      const double v = param(d.v0, d.v1, j, resolutionV);
      bool replaced = false;
      while (next < creases.size() && creases[next] <= v + 1e-9 * d.dv()) {
        replaced = replaced || std::abs(creases[next] - v) <= 1e-9 * d.dv();
        rowList.push_back({creases[next], -1});
        rowList.push_back({creases[next], +1});
        ++next;
      }
      if (!replaced || j == 0 || j == resolutionV) rowList.push_back({v, 0});
    }
  }
  const int nv = int(rowList.size()) - 1, rows = nv + 1;
  if (double(rows) * double(cols) > kMaxTessellationVertices) throw std::invalid_argument(tessellationProblem(nu, nv));
  const size_t count = size_t(cols) * size_t(rows);
  TriangleMesh m;
  m.positions.resize(count);
  m.normals.resize(count);
  m.tangents.resize(count);
  m.derivU.resize(count);
  m.derivV.resize(count);
  m.uvs.resize(count);
  auto vertex = [&](size_t at, int i, int j) {
    const double u = param(d.u0, d.u1, i, nu), v = rowList[size_t(j)].v;
    const int side = rowList[size_t(j)].side;
    // At a crease: the position there, the frame just to its side (the one-sided limit).
    const SurfaceFrame f = surface.frame(u, side == 0 ? v : v + side * 1e-9 * d.dv());
    m.positions[at] = side == 0 ? f.P : surface.frame(u, v).P;
    m.normals[at] = f.N;
    m.tangents[at] = f.Tu;
    m.derivU[at] = f.Su;
    m.derivV[at] = f.Sv;
    m.uvs[at] = glm::dvec2(u, v);
  };
  auto copyVertex = [&](size_t to, size_t from) {
    m.positions[to] = m.positions[from];
    m.normals[to] = m.normals[from];
    m.tangents[to] = m.tangents[from];
    m.derivU[to] = m.derivU[from];
    m.derivV[to] = m.derivV[from];
  };
  const int lastRow = d.periodicV ? nv - 1 : nv;
  tbb::parallel_for(tbb::blocked_range<int>(0, lastRow + 1), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) {
      const int lastCol = d.periodicU ? nu - 1 : nu;
      for (int i = 0; i <= lastCol; ++i) vertex(size_t(j) * cols + i, i, j);
      if (d.periodicU) {  // the seam column: the first column's geometry, u = u1
        const size_t to = size_t(j) * cols + nu;
        copyVertex(to, size_t(j) * cols);
        m.uvs[to] = glm::dvec2(d.u1, rowList[size_t(j)].v);
      }
    }
  });
  if (d.periodicV)  // the seam row: the first row's geometry, v = v1
    for (int i = 0; i <= nu; ++i) {
      const size_t to = size_t(nv) * cols + i;
      copyVertex(to, size_t(i));
      m.uvs[to] = glm::dvec2(m.uvs[size_t(i)].x, d.v1);
    }

  // Triangles in grid order (serial: cheap, and the order is fixed).
  m.triangles.reserve(size_t(2) * nu * nv);
  const bool flip = surface.normalSign() < 0;
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    const glm::dvec3 e0 = m.positions[b] - m.positions[a], e1 = m.positions[c] - m.positions[a],
                     e2 = m.positions[c] - m.positions[b];
    // Scale-free: compare the doubled area with the longest edge squared (after normalising
    // by the largest coordinate difference, so that 1e-160 and 1e160 behave alike).
    const double s = std::max({std::abs(e0.x), std::abs(e0.y), std::abs(e0.z), std::abs(e1.x), std::abs(e1.y),
                               std::abs(e1.z)});
    if (!(s > 0) || !std::isfinite(s)) return;
    const glm::dvec3 a0 = e0 / s, a1 = e1 / s, a2 = e2 / s;
    const double longest = std::max({glm::dot(a0, a0), glm::dot(a1, a1), glm::dot(a2, a2)});
    if (glm::length(glm::cross(a0, a1)) <= 1e-12 * longest) return;
    if (flip) m.triangles.emplace_back(a, c, b);  // wound about the front normal
    else m.triangles.emplace_back(a, b, c);
  };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = uint32_t(j * cols + i), b = a + 1, c = a + 1 + uint32_t(cols), e = a + uint32_t(cols);
      add(a, b, c);
      add(a, c, e);
    }
  return m;
}

namespace {

// True when the edge v = const (constU = false) or u = const (constU = true) at parameter x
// collapses to one point: the surface has a pole there.
bool edgeCollapses(const Surface& s, const ParameterDomain& d, bool constU, double x) {
  const SurfacePoint first = constU ? s.evaluate(x, d.v0) : s.evaluate(d.u0, x);
  double extent = 0.0, size = 0.0;
  for (int k = 1; k <= 8; ++k) {
    const double y = k / 8.0;
    const SurfacePoint p = constU ? s.evaluate(x, d.v0 + y * d.dv()) : s.evaluate(d.u0 + y * d.du(), x);
    extent = std::max(extent, glm::length(p.P - first.P));
    size = std::max(size, glm::length(p.Su) * std::abs(d.du()) + glm::length(p.Sv) * std::abs(d.dv()));
  }
  return extent <= 1e-12 * size;
}

std::vector<double> lineParameters(const Surface& s, const ParameterDomain& d, bool alongU, int n) {
  std::vector<double> out;
  const double a = alongU ? d.u0 : d.v0, b = alongU ? d.u1 : d.v1;
  const bool periodic = alongU ? d.periodicU : d.periodicV;
  // Lines of constant u: an edge u = a collapses when the curve u = a, v varying, is a point.
  const bool pole = !periodic && (edgeCollapses(s, d, alongU, a) || edgeCollapses(s, d, alongU, b));
  for (int k = 0; k < n; ++k) {
    double f;
    if (periodic) f = double(k) / n;
    else if (pole) f = double(k + 1) / (n + 1);
    else f = n > 1 ? double(k) / (n - 1) : 0.5;
    out.push_back(a + f * (b - a));
  }
  return out;
}

}  // namespace

PolylineSet isoparametricLines(const Surface& surface, int linesU, int linesV, int samplesPerLine) {
  PolylineSet out;
  const ParameterDomain d = surface.domain();
  const int n = std::max(2, samplesPerLine);
  auto sample = [&](double u, double v) {
    const glm::dvec3 p = surface.evaluate(u, v).P;
    return std::isfinite(p.x + p.y + p.z) ? p : glm::dvec3(0.0);
  };
  for (double u : lineParameters(surface, d, true, std::max(0, linesU))) {
    std::vector<glm::dvec3> line;
    for (int k = 0; k < n; ++k) line.push_back(sample(u, d.v0 + d.dv() * (double(k) / n)));
    line.push_back(d.periodicV ? line.front() : sample(u, d.v1));
    out.add(line);
  }
  for (double v : lineParameters(surface, d, false, std::max(0, linesV))) {
    std::vector<glm::dvec3> line;
    for (int k = 0; k < n; ++k) line.push_back(sample(d.u0 + d.du() * (double(k) / n), v));
    line.push_back(d.periodicU ? line.front() : sample(d.u1, v));
    out.add(line);
  }
  return out;
}

}  // namespace wf
