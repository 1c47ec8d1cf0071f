#include "geometry/parametric_sources.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>
#include <numbers>
#include <utility>

namespace wf {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Point and derivative directions of the surface at (u, v) in [0,1]^2.
struct SurfacePoint {
  glm::dvec3 p, n;
};

glm::dvec3 safeNormalize(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double l = glm::length(v);
  return (l > 0 && std::isfinite(l)) ? v / l : fallback;
}

// Cumulative arc lengths of a lathe profile (empty for other sources): made once per
// tessellation, not per vertex.
std::vector<double> latheLengths(const ParametricSource& s) {
  std::vector<double> len;
  if (s.type != ParametricSource::Type::Lathe) return len;
  len.assign(s.profile.size(), 0.0);
  for (size_t i = 1; i < s.profile.size(); ++i) len[i] = len[i - 1] + glm::length(s.profile[i] - s.profile[i - 1]);
  return len;
}

SurfacePoint evaluate(const ParametricSource& s, double u, double v, const std::vector<double>& len) {
  const double a = kTwoPi * u;
  switch (s.type) {
    case ParametricSource::Type::Sphere: {
      const double th = std::numbers::pi * v;  // from the south pole (v = 0) to the north
      // Exactly on the axis at the poles (sin(pi) is 1e-16, not 0): the pole's vertices coincide
      // and the triangles collapsed there are recognised and left out.
      const double st = (v <= 0.0 || v >= 1.0) ? 0.0 : std::sin(th);
      const double ct = v <= 0.0 ? 1.0 : (v >= 1.0 ? -1.0 : std::cos(th));
      const glm::dvec3 n(st * std::cos(a), st * std::sin(a), -ct);
      return {s.radius * n, n};
    }
    case ParametricSource::Type::Torus: {
      const double b = kTwoPi * v;
      const glm::dvec3 n(std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b));
      return {glm::dvec3(s.major * std::cos(a), s.major * std::sin(a), 0.0) + s.minor * n, n};
    }
    case ParametricSource::Type::Lathe: {
      // Piecewise-linear profile by arc length (cumulative lengths made once per source, found
      // by binary search); normals from the profile's direction, blended across vertices.
      const auto& P = s.profile;
      const double t = v * len.back();
      size_t i = size_t(std::upper_bound(len.begin(), len.end(), t) - len.begin());
      i = std::clamp<size_t>(i, 1, P.size() - 1);
      while (i > 1 && len[i] == len[i - 1] && t <= len[i - 1]) --i;  // skip repeated points
      const double seg = len[i] - len[i - 1];
      const double f = seg > 0 ? std::clamp((t - len[i - 1]) / seg, 0.0, 1.0) : 0.0;
      const glm::dvec2 q = glm::mix(P[i - 1], P[i], f);
      auto dirAt = [&](size_t k) { return safeNormalize(glm::dvec3(P[k] - P[k - 1], 0.0), glm::dvec3(0, 1, 0)); };
      glm::dvec3 d = dirAt(i);
      if (f < 0.5 && i > 1) d = safeNormalize(glm::mix(dirAt(i - 1), d, 0.5 + f), d);
      if (f >= 0.5 && i + 1 < P.size()) d = safeNormalize(glm::mix(d, dirAt(i + 1), f - 0.5), d);
      // Profile normal (outward): rotate the tangent (dr, dz) by -90 degrees: (dz, -dr).
      const glm::dvec2 pn(d.y, -d.x);
      const glm::dvec3 n(pn.x * std::cos(a), pn.x * std::sin(a), pn.y);
      return {glm::dvec3(q.x * std::cos(a), q.x * std::sin(a), q.y), safeNormalize(n, glm::dvec3(0, 0, 1))};
    }
    case ParametricSource::Type::Plane: {
      const glm::dvec3 p((u - 0.5) * s.size.x, (v - 0.5) * s.size.y, 0.0);
      return {p, glm::dvec3(0, 0, 1)};
    }
    case ParametricSource::Type::Box:
      break;
  }
  return {glm::dvec3(0), glm::dvec3(0, 0, 1)};
}

bool periodicU(const ParametricSource& s) {
  return s.type != ParametricSource::Type::Plane;
}

}  // namespace

std::string ParametricSource::problem() const {
  if (resolutionU < 3 || resolutionV < 2 || resolutionU > 4096 || resolutionV > 4096)
    return "resolution must be at least [3, 2] and at most [4096, 4096]";
  if (double(resolutionU) * double(resolutionV) > 4194304.0)
    return "resolution u x v must be at most 4,194,304 (2048 x 2048): about 1 GB of mesh";
  auto positive = [](double x) { return x > 0 && std::isfinite(x); };
  switch (type) {
    case Type::Sphere:
      if (!positive(radius)) return "radius must be positive";
      break;
    case Type::Torus:
      if (!positive(major) || !positive(minor)) return "major and minor radii must be positive";
      break;
    case Type::Lathe:
      if (profile.size() < 2) return "profile needs at least two [radius, height] points";
      {
        double length = 0, maxRadius = 0;
        for (size_t i = 0; i < profile.size(); ++i) {
          const glm::dvec2& p = profile[i];
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || p.x < 0) return "profile points must be finite with radius >= 0";
          if (i > 0) length += glm::length(p - profile[i - 1]);
          maxRadius = std::max(maxRadius, p.x);
        }
        if (!(length > 0) || !(maxRadius > 0)) return "profile must have length and leave the axis somewhere";
      }
      break;
    case Type::Plane:
    case Type::Box:
      if (!positive(size.x) || !positive(size.y) || (type == Type::Box && !positive(size.z)))
        return "size must be positive";
      break;
  }
  return {};
}

TriangleMesh tessellate(const ParametricSource& s) {
  TriangleMesh m;
  if (s.type == ParametricSource::Type::Box) {
    // Six faces, each its own four vertices (flat normals).
    const glm::dvec3 h = 0.5 * s.size;
    for (int axis = 0; axis < 3; ++axis)
      for (int sign = -1; sign <= 1; sign += 2) {
        glm::dvec3 n(0.0);
        n[axis] = sign;
        glm::dvec3 tu(0.0), tv(0.0);
        tu[(axis + 1) % 3] = 1;
        tv[(axis + 2) % 3] = 1;
        const uint32_t base = uint32_t(m.positions.size());
        for (int k = 0; k < 4; ++k) {
          const double su = (k & 1) ? 1 : -1, sv = (k & 2) ? 1 : -1;
          m.positions.push_back(n * h + su * tu * h + sv * tv * h);
          m.normals.push_back(n);
          m.tangents.push_back(tu);
          m.uvs.emplace_back((su + 1) / 2, (sv + 1) / 2);
        }
        m.triangles.emplace_back(base, base + 1, base + 3);
        m.triangles.emplace_back(base, base + 3, base + 2);
      }
    return m;
  }
  const int nu = s.resolutionU, nv = s.resolutionV;
  const std::vector<double> len = latheLengths(s);
  const bool wrap = periodicU(s);
  const int cols = wrap ? nu : nu + 1;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < cols; ++i) {
      const double u = double(i) / nu, v = double(j) / nv;
      const SurfacePoint sp = evaluate(s, u, v, len);
      m.positions.push_back(sp.p);
      m.normals.push_back(sp.n);
      m.uvs.emplace_back(u, v);
      // Tangent along u (the direction of increasing u), finite at poles.
      const SurfacePoint q = evaluate(s, u + 1e-4, v, len);
      m.tangents.push_back(safeNormalize(q.p - sp.p, glm::dvec3(-std::sin(kTwoPi * u), std::cos(kTwoPi * u), 0)));
    }
  auto id = [&](int i, int j) { return uint32_t(j * cols + (wrap ? i % nu : i)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      // Skip triangles collapsed at a pole (two vertices at the same point).
      auto add = [&](uint32_t p, uint32_t q, uint32_t r) {
        const glm::dvec3 cr = glm::cross(m.positions[q] - m.positions[p], m.positions[r] - m.positions[p]);
        if (glm::length(cr) > 0) m.triangles.emplace_back(p, q, r);
      };
      add(a, b, c);
      add(a, c, d);
    }
  return m;
}

PolylineSet isolines(const ParametricSource& s, int linesU, int linesV, int samplesPerLine) {
  PolylineSet out;
  if (s.type == ParametricSource::Type::Box) {
    const glm::dvec3 h = 0.5 * s.size;
    for (int axis = 0; axis < 3; ++axis)
      for (int k = 0; k < 4; ++k) {
        glm::dvec3 a(0.0), b(0.0);
        const int p = (axis + 1) % 3, q = (axis + 2) % 3;
        a[p] = b[p] = (k & 1) ? h[p] : -h[p];
        a[q] = b[q] = (k & 2) ? h[q] : -h[q];
        a[axis] = -h[axis];
        b[axis] = h[axis];
        out.add({a, b});
      }
    return out;
  }
  const int n = std::max(2, samplesPerLine);
  const std::vector<double> len = latheLengths(s);
  const bool wrap = periodicU(s);
  const bool wrapV = s.type == ParametricSource::Type::Torus;
  // Lines of constant u run along v; lines of constant v run around u.
  for (int i = 0; i < linesU; ++i) {
    const double u = wrap ? double(i) / linesU : (linesU > 1 ? double(i) / (linesU - 1) : 0.0);
    std::vector<glm::dvec3> line;
    for (int k = 0; k <= n; ++k) {
      if (wrapV && k == n) break;
      line.push_back(evaluate(s, u, double(k) / n, len).p);
    }
    if (wrapV) line.push_back(line.front());
    out.add(line);
  }
  for (int j = 0; j < linesV; ++j) {
    double v = wrapV ? double(j) / linesV : (linesV > 1 ? double(j) / (linesV - 1) : 0.5);
    if (s.type == ParametricSource::Type::Sphere || s.type == ParametricSource::Type::Lathe)
      v = double(j + 1) / (linesV + 1);  // parallels between the poles, not the poles themselves
    std::vector<glm::dvec3> line;
    for (int k = 0; k < n; ++k) line.push_back(evaluate(s, double(k) / n, v, len).p);
    if (wrap) line.push_back(line.front());
    else line.push_back(evaluate(s, 1.0, v, len).p);
    out.add(line);
  }
  return out;
}

PolylineSet meshEdges(const TriangleMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> seen;
  PolylineSet out;
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a >= mesh.positions.size() || b >= mesh.positions.size()) continue;
      if (a > b) std::swap(a, b);
      if (seen.emplace(std::make_pair(a, b), 0).second) out.add({mesh.positions[a], mesh.positions[b]});
    }
  return out;
}

void transformMesh(TriangleMesh& mesh, const glm::dmat4& M) {
  // Normals by the cofactor matrix: the inverse transpose times det(A), without the division,
  // so that it keeps its direction for scales like [1e-160, 1e-160, 1] where det underflows.
  // Its columns are c1 x c2, c2 x c0, c0 x c1 for the columns c of A; the sign of det (a mirror
  // turns the outside in) comes from A with its columns normalised, which cannot underflow.
  const glm::dmat3 A(M);
  glm::dmat3 N(glm::cross(A[1], A[2]), glm::cross(A[2], A[0]), glm::cross(A[0], A[1]));
  glm::dmat3 unitColumns = A;
  for (int c = 0; c < 3; ++c) {
    const double l = glm::length(unitColumns[c]);
    if (l > 0 && std::isfinite(l)) unitColumns[c] /= l;
  }
  if (glm::determinant(unitColumns) < 0) N = -N;
  for (glm::dvec3& p : mesh.positions) p = glm::dvec3(M * glm::dvec4(p, 1.0));
  for (glm::dvec3& n : mesh.normals) n = safeNormalize(N * n, n);
  for (glm::dvec3& t : mesh.tangents) t = safeNormalize(glm::dmat3(M) * t, t);
}

void transformPolylines(PolylineSet& lines, const glm::dmat4& M) {
  for (glm::dvec3& p : lines.points) p = glm::dvec3(M * glm::dvec4(p, 1.0));
}

}  // namespace wf
