// Adapters from VTK data to wf::Surface; see wf_vtk_surfaces.h.
#include "wf_vtk_surfaces.h"

#include "core/srgb.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkParametricFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace wf::vtkio {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTwoPi = 6.283185307179586476925286766559;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// VTK's closed-form parametric functions: Evaluate reads only their double parameters (checked
// against VTK 9.1's sources), so they may be evaluated from several threads at once. Matched by
// exact class name: a subclass may override Evaluate with anything.
constexpr std::array<const char*, 20> kConcurrentParametricClasses = {
  "vtkParametricBohemianDome", "vtkParametricBour", "vtkParametricBoy", "vtkParametricCatalanMinimal",
  "vtkParametricConicSpiral", "vtkParametricCrossCap", "vtkParametricDini", "vtkParametricEllipsoid",
  "vtkParametricEnneper", "vtkParametricFigure8Klein", "vtkParametricHenneberg", "vtkParametricKlein",
  "vtkParametricKuen", "vtkParametricMobius", "vtkParametricPluckerConoid", "vtkParametricPseudosphere",
  "vtkParametricRoman", "vtkParametricSuperEllipsoid", "vtkParametricSuperToroid", "vtkParametricTorus",
};

// Any unit vector perpendicular to unit n (the core's choice, surface_shading.cpp).
glm::dvec3 anyPerpendicular(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

glm::dvec3 radialOffset(const glm::dvec3& P, const glm::dvec3& axisPoint, const glm::dvec3& unitAxis) {
  const glm::dvec3 d = P - axisPoint;
  return d - glm::dot(d, unitAxis) * unitAxis;
}

}  // namespace

// --- vtkParametricFunction --------------------------------------------------------------------

ParametricFunctionSurface::ParametricFunctionSurface(vtkParametricFunction* function) : function_(function) {
  if (!function) {
    problem_ = "no parametric function";
    return;
  }
  domain_.u0 = function->GetMinimumU();
  domain_.u1 = function->GetMaximumU();
  domain_.v0 = function->GetMinimumV();
  domain_.v1 = function->GetMaximumV();
  domain_.periodicU = function->GetJoinU() != 0;
  domain_.periodicV = function->GetJoinV() != 0;
  const char* name = function->GetClassName();
  concurrent_ = std::any_of(kConcurrentParametricClasses.begin(), kConcurrentParametricClasses.end(),
                            [&](const char* c) { return std::strcmp(c, name) == 0; });
  if (!(std::isfinite(domain_.u0) && std::isfinite(domain_.u1) && std::isfinite(domain_.v0) &&
        std::isfinite(domain_.v1)) ||
      !(domain_.u1 > domain_.u0) || !(domain_.v1 > domain_.v0)) {
    std::ostringstream o;
    o << name << ": parameter domain [" << domain_.u0 << ", " << domain_.u1 << "] x [" << domain_.v0 << ", "
      << domain_.v1 << "] must be finite and non-empty";
    problem_ = o.str();
    return;
  }
  if (function->GetDimension() != 2) {
    problem_ = std::string(name) + ": a surface needs a 2-D parametric function (dimension " +
               std::to_string(function->GetDimension()) + ")";
    return;
  }
  // Probe the function's own derivatives against central differences (see the header).
  exact_ = true;
  bool anyNonZero = false;
  const double hu = 1e-5 * domain_.du(), hv = 1e-5 * domain_.dv();
  for (double s : {0.21, 0.5, 0.79})
    for (double t : {0.23, 0.5, 0.77}) {
      const glm::dvec2 uv = domain_.fromUnit(s, t);
      double P[3], D[9];
      raw(uv.x, uv.y, P, D);
      const glm::dvec3 du(D[0], D[1], D[2]), dv(D[3], D[4], D[5]);
      const glm::dvec3 fu = (point(uv.x + hu, uv.y) - point(uv.x - hu, uv.y)) / (2 * hu);
      const glm::dvec3 fv = (point(uv.x, uv.y + hv) - point(uv.x, uv.y - hv)) / (2 * hv);
      if (!finite3(fu) || !finite3(fv)) continue;
      const double scale = glm::length(fu) + glm::length(fv);
      anyNonZero = anyNonZero || glm::length(du) + glm::length(dv) > 0;
      if (!(glm::length(du - fu) <= 1e-4 * scale) || !(glm::length(dv - fv) <= 1e-4 * scale)) exact_ = false;
    }
  exact_ = exact_ && anyNonZero;
}

ParametricFunctionSurface::~ParametricFunctionSurface() = default;

void ParametricFunctionSurface::raw(double u, double v, double P[3], double D[9]) const {
  double uvw[3] = {u, v, 0.0};
  std::fill(D, D + 9, 0.0);
  P[0] = P[1] = P[2] = 0.0;
  if (concurrent_) {
    function_->Evaluate(uvw, P, D);
  } else {
    std::lock_guard<std::mutex> lock(mutex_);
    function_->Evaluate(uvw, P, D);
  }
}

glm::dvec3 ParametricFunctionSurface::point(double u, double v) const {
  double P[3], D[9];
  raw(u, v, P, D);
  return {P[0], P[1], P[2]};
}

glm::dvec2 ParametricFunctionSurface::wrap(double u, double v) const {
  auto one = [](double x, double lo, double hi, bool periodic) {
    if (!std::isfinite(x)) return x;
    if (periodic) {
      const double p = hi - lo;
      double r = std::fmod(x - lo, p);
      if (r < 0) r += p;
      return lo + r;
    }
    return std::clamp(x, lo, hi);
  };
  return {one(u, domain_.u0, domain_.u1, domain_.periodicU), one(v, domain_.v0, domain_.v1, domain_.periodicV)};
}

SurfacePoint ParametricFunctionSurface::evaluate(double u, double v) const {
  SurfacePoint sp;
  if (!problem_.empty()) {
    sp.P = glm::dvec3(kNaN);
    return sp;
  }
  const glm::dvec2 uv = wrap(u, v);
  double P[3], D[9];
  raw(uv.x, uv.y, P, D);
  sp.P = {P[0], P[1], P[2]};
  if (exact_) {
    sp.Su = {D[0], D[1], D[2]};
    sp.Sv = {D[3], D[4], D[5]};
    return sp;
  }
  // Central differences, one-sided where a step would leave a non-periodic domain.
  auto diff = [&](bool alongU) {
    const double h = 1e-5 * (alongU ? domain_.du() : domain_.dv());
    const double x = alongU ? uv.x : uv.y, lo = alongU ? domain_.u0 : domain_.v0, hi = alongU ? domain_.u1 : domain_.v1;
    const bool periodic = alongU ? domain_.periodicU : domain_.periodicV;
    double a = x - h, b = x + h;
    if (!periodic) {
      a = std::max(a, lo);
      b = std::min(b, hi);
    }
    const glm::dvec3 pa = alongU ? point(a, uv.y) : point(uv.x, a);
    const glm::dvec3 pb = alongU ? point(b, uv.y) : point(uv.x, b);
    return (pb - pa) / (b - a);
  };
  sp.Su = diff(true);
  sp.Sv = diff(false);
  return sp;
}

std::string ParametricFunctionSurface::describe() const {
  std::ostringstream o;
  o << (function_ ? function_->GetClassName() : "no function") << " [" << domain_.u0 << ", " << domain_.u1 << "] x ["
    << domain_.v0 << ", " << domain_.v1 << "]" << (exact_ ? " exact derivatives" : " finite-difference derivatives");
  return o.str();
}

// --- mesh with texture coordinates --------------------------------------------------------------

vtkDataArray* textureCoordinates(vtkPolyData* mesh) {
  if (!mesh) return nullptr;
  vtkPointData* pd = mesh->GetPointData();
  vtkDataArray* tc = pd->GetTCoords();
  if (!tc) tc = pd->GetArray("TCoords");
  if (!tc) tc = pd->GetArray("TextureCoordinates");
  if (tc && (tc->GetNumberOfComponents() < 2 || tc->GetNumberOfTuples() != mesh->GetNumberOfPoints())) return nullptr;
  return tc;
}

std::vector<glm::uvec3> triangulate(vtkPolyData* mesh) {
  std::vector<glm::uvec3> out;
  if (!mesh) return out;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  if (vtkCellArray* polys = mesh->GetPolys()) {
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
      it->GetCurrentCell(n, ids);
      for (vtkIdType k = 1; k + 1 < n; ++k)
        out.push_back({std::uint32_t(ids[0]), std::uint32_t(ids[k]), std::uint32_t(ids[k + 1])});
    }
  }
  if (vtkCellArray* strips = mesh->GetStrips()) {
    auto it = vtk::TakeSmartPointer(strips->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
      it->GetCurrentCell(n, ids);
      for (vtkIdType k = 0; k + 2 < n; ++k) {
        if (k % 2 == 0)
          out.push_back({std::uint32_t(ids[k]), std::uint32_t(ids[k + 1]), std::uint32_t(ids[k + 2])});
        else
          out.push_back({std::uint32_t(ids[k + 1]), std::uint32_t(ids[k]), std::uint32_t(ids[k + 2])});
      }
    }
  }
  return out;
}

std::int64_t firstCellWithMissingPoints(vtkPolyData* mesh) {
  if (!mesh) return -1;
  const vtkIdType np = mesh->GetNumberOfPoints();
  std::int64_t bad = -1;
  forEachCell(mesh, [&](vtkIdType cell, vtkIdType n, const vtkIdType* ids) {
    for (vtkIdType k = 0; k < n; ++k)
      if (ids[k] < 0 || ids[k] >= np) {
        bad = cell;
        return false;
      }
    return true;
  });
  return bad;
}

std::int64_t firstNonFinitePoint(vtkPolyData* mesh) {
  if (!mesh || !mesh->GetPoints()) return -1;
  vtkPoints* pts = mesh->GetPoints();
  for (vtkIdType i = 0, n = pts->GetNumberOfPoints(); i < n; ++i) {
    double p[3];
    pts->GetPoint(i, p);
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return i;
  }
  return -1;
}

MeshSurface::MeshSurface(vtkPolyData* mesh, int gridCells) {
  if (!mesh || mesh->GetNumberOfPoints() == 0) {
    problem_ = "the mesh has no points";
    return;
  }
  if (const std::int64_t bad = firstCellWithMissingPoints(mesh); bad >= 0) {
    problem_ = "cell " + std::to_string(bad) + " names a point the mesh does not have";
    return;
  }
  vtkDataArray* tc = textureCoordinates(mesh);
  if (!tc) {
    problem_ = "the mesh has no texture coordinates (active TCoords, or a 2-component point array \"TCoords\")";
    return;
  }
  const vtkIdType np = mesh->GetNumberOfPoints();
  if (np > vtkIdType(std::numeric_limits<std::uint32_t>::max())) {
    problem_ = "the mesh has more than 2^32 points";
    return;
  }
  positions_.resize(size_t(np));
  uvs_.resize(size_t(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    positions_[size_t(i)] = {p[0], p[1], p[2]};
    uvs_[size_t(i)] = {tc->GetComponent(i, 0), tc->GetComponent(i, 1)};
    if (!finite3(positions_[size_t(i)])) {
      problem_ = "point " + std::to_string(i) + " is not finite";
      return;
    }
    if (!(std::isfinite(uvs_[size_t(i)].x) && std::isfinite(uvs_[size_t(i)].y))) {
      problem_ = "texture coordinate " + std::to_string(i) + " is not finite";
      return;
    }
  }
  // Which triangles carry the texture map (see the header): non-zero area in uv and in space, and
  // the uv winding of the majority (by uv area). The others are left out of the lookup: a seam
  // that wraps back across the layout (vtkParametricFunctionSource joins its last column to its
  // first, s = 1 to s = 0: a zero-area sliver in space spanning the whole row backwards in uv) or
  // the mirrored half of an overlapping layout.
  const std::vector<glm::uvec3> all = triangulate(mesh);
  // Zero area in space is measured against the whole mesh (its bounding box), not the triangle's
  // own edges: the joined corner of a closed layout is three copies of one point, all its edges
  // rounding noise, and yet it spans half the uv square. 1e-12 L^2 is above the area of a triangle
  // made of float-rounded copies of one point ((1e-7 L)^2) and far below any real triangle.
  double diagonal2 = 0.0;
  {
    double b[6];
    mesh->GetBounds(b);
    diagonal2 = (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]);
  }
  std::vector<double> dets(all.size(), 0.0);
  double positiveArea = 0.0, negativeArea = 0.0;
  for (size_t k = 0; k < all.size(); ++k) {
    const glm::uvec3& t = all[k];
    const glm::dvec2 d1 = uvs_[t.y] - uvs_[t.x], d2 = uvs_[t.z] - uvs_[t.x];
    const double det = d1.x * d2.y - d2.x * d1.y;
    const double scale = std::max({std::abs(d1.x), std::abs(d1.y), std::abs(d2.x), std::abs(d2.y)});
    const glm::dvec3 e1 = positions_[t.y] - positions_[t.x], e2 = positions_[t.z] - positions_[t.x];
    const double area2 = glm::length(glm::cross(e1, e2));
    const double edge2 = std::max(glm::dot(e1, e1), glm::dot(e2, e2));
    if (!(std::abs(det) > 1e-14 * scale * scale) || !(area2 > 1e-12 * std::max(edge2, diagonal2))) continue;
    dets[k] = det;
    (det > 0 ? positiveArea : negativeArea) += std::abs(det);
  }
  const double winding = positiveArea >= negativeArea ? 1.0 : -1.0;
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (size_t k = 0; k < all.size(); ++k) {
    if (!(dets[k] * winding > 0)) continue;
    const glm::uvec3& t = all[k];
    Triangle tri;
    tri.v[0] = t.x, tri.v[1] = t.y, tri.v[2] = t.z;
    const glm::dvec2 a = uvs_[t.x], b = uvs_[t.y], c = uvs_[t.z];
    const glm::dvec2 d1 = b - a, d2 = c - a;
    const double det = dets[k];
    const glm::dvec3 e1 = positions_[t.y] - positions_[t.x], e2 = positions_[t.z] - positions_[t.x];
    // [e1 e2] = [Su Sv] [d1 d2]  =>  [Su Sv] = [e1 e2] [d1 d2]^-1
    tri.Su = (e1 * d2.y - e2 * d1.y) / det;
    tri.Sv = (e2 * d1.x - e1 * d2.x) / det;
    // (b1, b2) with uv - a = b1 d1 + b2 d2.
    tri.toBary = glm::inverse(glm::dmat2(d1, d2));
    tri.lo = glm::min(a, glm::min(b, c));
    tri.hi = glm::max(a, glm::max(b, c));
    lo = glm::min(lo, tri.lo);
    hi = glm::max(hi, tri.hi);
    triangles_.push_back(tri);
  }
  if (triangles_.empty()) {
    problem_ = "the mesh has no triangle with a non-zero area in texture space";
    return;
  }
  if (triangles_.size() > std::numeric_limits<std::uint32_t>::max()) {
    problem_ = "the mesh has more than 2^32 triangles";
    return;
  }
  domain_.u0 = lo.x, domain_.u1 = hi.x, domain_.v0 = lo.y, domain_.v1 = hi.y;
  // Uniform grid: about one cell per triangle (or gridCells), shaped like the uv bounding box.
  const double target = gridCells > 0 ? double(gridCells) : double(triangles_.size());
  const double aspect = domain_.du() / domain_.dv();
  nx_ = std::clamp(int(std::lround(std::sqrt(target * aspect))), 1, 4096);
  ny_ = std::clamp(int(std::lround(std::sqrt(target / aspect))), 1, 4096);
  auto cellRange = [&](const Triangle& t, int& i0, int& i1, int& j0, int& j1) {
    auto ix = [&](double u) { return std::clamp(int(std::floor((u - domain_.u0) / domain_.du() * nx_)), 0, nx_ - 1); };
    auto iy = [&](double v) { return std::clamp(int(std::floor((v - domain_.v0) / domain_.dv() * ny_)), 0, ny_ - 1); };
    i0 = ix(t.lo.x), i1 = ix(t.hi.x), j0 = iy(t.lo.y), j1 = iy(t.hi.y);
  };
  cellStart_.assign(size_t(nx_) * size_t(ny_) + 1, 0);
  for (const Triangle& t : triangles_) {
    int i0, i1, j0, j1;
    cellRange(t, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) ++cellStart_[size_t(j) * nx_ + i + 1];
  }
  for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  cellTriangles_.resize(cellStart_.back());
  std::vector<std::uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (std::uint32_t k = 0; k < triangles_.size(); ++k) {
    int i0, i1, j0, j1;
    cellRange(triangles_[k], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cellTriangles_[fill[size_t(j) * nx_ + i]++] = k;
  }
}

bool MeshSurface::locate(double u, double v, std::size_t& triangle, glm::dvec3& barycentric) const {
  if (!problem_.empty() || !std::isfinite(u) || !std::isfinite(v)) return false;
  const int i = std::clamp(int(std::floor((u - domain_.u0) / domain_.du() * nx_)), 0, nx_ - 1);
  const int j = std::clamp(int(std::floor((v - domain_.v0) / domain_.dv() * ny_)), 0, ny_ - 1);
  const size_t c = size_t(j) * nx_ + i;
  // Inside with a relative tolerance, so that a point on a shared edge is found by one of its two
  // triangles despite rounding; the most interior candidate wins.
  constexpr double kInside = -1e-9;
  double best = -std::numeric_limits<double>::infinity();
  for (std::uint32_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
    const Triangle& t = triangles_[cellTriangles_[k]];
    const glm::dvec2 b = t.toBary * (glm::dvec2(u, v) - uvs_[t.v[0]]);
    const double b0 = 1.0 - b.x - b.y;
    const double m = std::min({b0, b.x, b.y});
    if (m > best) {
      best = m;
      triangle = cellTriangles_[k];
      barycentric = {b0, b.x, b.y};
    }
  }
  return best >= kInside;
}

SurfacePoint MeshSurface::evaluate(double u, double v) const {
  SurfacePoint sp;
  u = std::clamp(u, domain_.u0, domain_.u1);
  v = std::clamp(v, domain_.v0, domain_.v1);
  std::size_t k = 0;
  glm::dvec3 b(0.0);
  if (!locate(u, v, k, b)) {
    sp.P = glm::dvec3(kNaN);
    return sp;
  }
  const Triangle& t = triangles_[k];
  sp.P = b.x * positions_[t.v[0]] + b.y * positions_[t.v[1]] + b.z * positions_[t.v[2]];
  sp.Su = t.Su;
  sp.Sv = t.Sv;
  return sp;
}

std::string MeshSurface::describe() const {
  std::ostringstream o;
  o << "mesh of " << triangles_.size() << " uv triangles over [" << domain_.u0 << ", " << domain_.u1 << "] x ["
    << domain_.v0 << ", " << domain_.v1 << "]";
  return o.str();
}

// --- choosing the surface -----------------------------------------------------------------------

std::shared_ptr<const Surface> growthSurfaceAsGiven(vtkParametricFunction* function, vtkPolyData* mesh,
                                                    std::string& problem);

std::shared_ptr<const Surface> growthSurface(vtkParametricFunction* function, vtkPolyData* mesh,
                                             std::string& problem, bool flip) {
  std::shared_ptr<const Surface> s = growthSurfaceAsGiven(function, mesh, problem);
  if (s && flip) s = std::make_shared<FlippedSurface>(s);
  return s;
}

std::shared_ptr<const Surface> growthSurfaceAsGiven(vtkParametricFunction* function, vtkPolyData* mesh,
                                                    std::string& problem) {
  problem.clear();
  if (function) {
    auto s = std::make_shared<ParametricFunctionSurface>(function);
    if (!s->problem().empty()) {
      problem = s->problem();
      return nullptr;
    }
    return s;
  }
  if (!mesh) {
    problem = "no surface: connect a vtkPolyData with texture coordinates to input 0, or set a ParametricFunction";
    return nullptr;
  }
  if (mesh->GetNumberOfPoints() == 0 || mesh->GetNumberOfCells() == 0) {
    problem = "the input mesh is empty";
    return nullptr;
  }
  auto s = std::make_shared<MeshSurface>(mesh);
  if (!s->problem().empty()) {
    problem = "input mesh: " + s->problem();
    return nullptr;
  }
  return s;
}

unsigned char srgb8(float linear) { return wf::srgb8(linear); }

// --- burnish grain ------------------------------------------------------------------------------

glm::dvec3 grainTangent(Grain grain, const glm::dvec3& P, const glm::dvec3& N, const glm::dvec3& Su,
                        const glm::dvec3& Sv, const glm::dvec3& axisPoint, const glm::dvec3& unitAxis) {
  glm::dvec3 t(0.0);
  switch (grain) {
    case Grain::U: t = Su; break;
    case Grain::V: t = Sv; break;
    case Grain::Radial: t = radialOffset(P, axisPoint, unitAxis); break;
    case Grain::Circular: t = glm::cross(unitAxis, radialOffset(P, axisPoint, unitAxis)); break;
  }
  const double ln = glm::length(N);
  const bool haveN = ln > 0 && std::isfinite(ln);
  const glm::dvec3 n = haveN ? N / ln : glm::dvec3(0.0);
  // Scale-free: unit t first, so that coordinates of 1e-6 and 1e6 behave alike.
  const double lt = glm::length(t);
  if (lt > 0 && std::isfinite(lt)) {
    const glm::dvec3 ut = t / lt;
    const glm::dvec3 p = ut - glm::dot(ut, n) * n;
    const double lp = glm::length(p);
    if (lp > 1e-12) return p / lp;
  }
  return haveN ? anyPerpendicular(n) : glm::dvec3(1.0, 0.0, 0.0);
}

double grooveCoordinate(Grain grain, const glm::dvec3& P, const glm::dvec2& uv, const glm::dvec3& axisPoint,
                        const glm::dvec3& unitAxis) {
  switch (grain) {
    case Grain::U: return uv.y;
    case Grain::V: return uv.x;
    case Grain::Radial: {
      const glm::dvec3 r = radialOffset(P, axisPoint, unitAxis);
      const glm::dvec3 e1 = anyPerpendicular(unitAxis);
      const glm::dvec3 e2 = glm::cross(unitAxis, e1);
      const double a = std::atan2(glm::dot(r, e2), glm::dot(r, e1)) / kTwoPi;
      return a < 0 ? a + 1.0 : a;
    }
    case Grain::Circular: return glm::length(radialOffset(P, axisPoint, unitAxis));
  }
  return 0.0;
}

}  // namespace wf::vtkio
