#include "geometry/parametric_sources.h"

#include "surface/tessellate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>
#include <numbers>
#include <utility>

namespace wf {

namespace {

glm::dvec3 safeNormalize(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double l = glm::length(v);
  return (l > 0 && std::isfinite(l)) ? v / l : fallback;
}

std::array<glm::dvec3, 16> bezierNet(const ParametricSource& s) {
  std::array<glm::dvec3, 16> net{};
  for (size_t k = 0; k < 16 && k < s.controlPoints.size(); ++k) net[k] = s.controlPoints[k];
  return net;
}

}  // namespace

std::string ParametricSource::problem() const {
  if (resolutionU < 3 || resolutionV < 2 || resolutionU > 4096 || resolutionV > 4096)
    return "resolution must be at least [3, 2] and at most [4096, 4096]";
  if (double(resolutionU) * double(resolutionV) > 4194304.0)
    return "resolution u x v must be at most 4,194,304 (2048 x 2048): about 1 GB of mesh";
  if (type != Type::Box)
    if (std::string p = tessellationProblem(resolutionU, resolutionV); !p.empty()) return p;
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
      if (!(profileCornerAngle > 0)) return "profile corner angle must be positive (degrees)";
      return RevolutionPatch::problem(profile, profileCorners);
    case Type::Plane:
    case Type::Box:
      if (!positive(size.x) || !positive(size.y) || (type == Type::Box && !positive(size.z)))
        return "size must be positive";
      break;
    case Type::Loft:
      return LoftPatch::problem(sections, up);
    case Type::Bezier:
      if (controlPoints.size() != 16) return "a Bezier patch needs 16 (4 x 4) control points";
      return BezierPatch::problem(bezierNet(*this));
    case Type::BSpline:
      return BSplinePatch::problem(controlPoints, controlCountU, controlCountV, periodicU, periodicV);
  }
  return {};
}

std::unique_ptr<Surface> makeSurface(const ParametricSource& s) {
  switch (s.type) {
    case ParametricSource::Type::Sphere:
      return std::make_unique<SpherePatch>(s.radius);
    case ParametricSource::Type::Torus:
      return std::make_unique<TorusPatch>(s.major, s.minor);
    case ParametricSource::Type::Lathe:
      return std::make_unique<RevolutionPatch>(
          s.profile, s.profileCorners, s.profileLinear ? ProfileInterpolation::Linear : ProfileInterpolation::Smooth,
          s.profileCornerAngle);
    case ParametricSource::Type::Plane:
      return std::make_unique<PlanePatch>(s.size.x, s.size.y);
    case ParametricSource::Type::Loft:
      return std::make_unique<LoftPatch>(s.sections, s.up);
    case ParametricSource::Type::Bezier:
      return std::make_unique<BezierPatch>(bezierNet(s));
    case ParametricSource::Type::BSpline:
      return std::make_unique<BSplinePatch>(s.controlPoints, s.controlCountU, s.controlCountV, s.periodicU, s.periodicV);
    case ParametricSource::Type::Box:
      break;
  }
  return nullptr;
}

TriangleMesh tessellate(const ParametricSource& s) {
  TriangleMesh m;
  if (s.type == ParametricSource::Type::Box) {
    // Six faces, each its own four vertices (flat normals); dS/du, dS/dv of the face's (u, v).
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
          m.derivU.push_back(2.0 * tu * h);
          m.derivV.push_back(2.0 * tv * h);
          m.uvs.emplace_back((su + 1) / 2, (sv + 1) / 2);
        }
        m.triangles.emplace_back(base, base + 1, base + 3);
        m.triangles.emplace_back(base, base + 3, base + 2);
      }
    return m;
  }
  const std::unique_ptr<Surface> surface = makeSurface(s);
  return tessellate(*surface, s.resolutionU, s.resolutionV);
}

PolylineSet isolines(const ParametricSource& s, int linesU, int linesV, int samplesPerLine) {
  if (s.type == ParametricSource::Type::Box) {
    PolylineSet out;
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
  const std::unique_ptr<Surface> surface = makeSurface(s);
  return isoparametricLines(*surface, linesU, linesV, samplesPerLine);
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
  // Tangents and dS/du, dS/dv are directions along the surface: dS'/du = A dS/du (not the
  // inverse transpose). Tangents stay unit; the derivatives keep their length change.
  for (glm::dvec3& t : mesh.tangents) t = safeNormalize(A * t, t);
  for (glm::dvec3& d : mesh.derivU) d = A * d;
  for (glm::dvec3& d : mesh.derivV) d = A * d;
}

void transformPolylines(PolylineSet& lines, const glm::dmat4& M) {
  for (glm::dvec3& p : lines.points) p = glm::dvec3(M * glm::dvec4(p, 1.0));
}

}  // namespace wf
