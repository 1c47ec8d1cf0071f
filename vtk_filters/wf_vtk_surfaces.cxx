// Adapters from VTK data to wf::Surface; see wf_vtk_surfaces.h.
#include "wf_vtk_surfaces.h"

#include "core/srgb.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkParametricFunction.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
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

bool isEmpty(vtkPolyData* data) { return data && data->GetNumberOfPoints() == 0 && data->GetNumberOfCells() == 0; }

bool wholeDataRequested(vtkInformationVector* outputVector) {
  vtkInformation* info = outputVector ? outputVector->GetInformationObject(0) : nullptr;
  return !info || !info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) ||
         info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) <= 1;
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

std::string inputProblem(vtkPolyData* mesh, const std::string& what) {
  if (const std::int64_t bad = firstCellWithMissingPoints(mesh); bad >= 0)
    return what + " cell " + std::to_string(bad) + " names a point the input does not have";
  if (const std::int64_t bad = firstNonFinitePoint(mesh); bad >= 0)
    return what + " point " + std::to_string(bad) + " is not finite";
  return {};
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
  std::vector<glm::dvec3> positions(static_cast<size_t>(np));
  std::vector<glm::dvec2> uvs(static_cast<size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    positions[size_t(i)] = {p[0], p[1], p[2]};
    uvs[size_t(i)] = {tc->GetComponent(i, 0), tc->GetComponent(i, 1)};
  }
  // The uv layout's rules (seams, mirrored halves, zero-area triangles) are the core's
  // (surface/mesh_surface.h).
  core_ = std::make_unique<wf::MeshSurface>(std::move(positions), std::move(uvs), triangulate(mesh), gridCells);
  problem_ = core_->problem();
}

ParameterDomain MeshSurface::domain() const { return core_ ? core_->domain() : ParameterDomain{}; }

bool MeshSurface::locate(double u, double v, std::size_t& triangle, glm::dvec3& barycentric) const {
  return problem_.empty() && core_->locate(u, v, triangle, barycentric);
}

std::size_t MeshSurface::sourceTriangle(std::size_t located) const { return core_->sourceTriangle(located); }

std::size_t MeshSurface::triangleCount() const { return core_ ? core_->triangleCount() : 0; }

SurfacePoint MeshSurface::evaluate(double u, double v) const {
  if (!problem_.empty()) {
    SurfacePoint sp;
    sp.P = glm::dvec3(kNaN);
    return sp;
  }
  return core_->evaluate(u, v);
}

std::string MeshSurface::describe() const { return core_ ? core_->describe() : "mesh (" + problem_ + ")"; }

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
  if (isEmpty(mesh)) return nullptr;  // an empty piece: no problem (the caller may warn)
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
