// Adapters from VTK data to the core's one surface concept (src/surface/surface.h, docs/design.md "One
// surface concept"): a vtkParametricFunction (exact derivatives where the function gives them) and
// a triangle mesh with texture coordinates (piecewise linear, derivatives constant per triangle).
// The fur and scale generators and the burnish filter of this module only ever see wf::Surface.
//
// Thread safety. The core generators call Surface::evaluate from oneTBB threads.
// - vtkParametricFunction::Evaluate is not const. The closed-form functions VTK ships
//   (vtkParametricTorus, ...Ellipsoid, ...Klein, ...: see kConcurrentParametricClasses in the .cxx)
//   only read their parameters in Evaluate, so they are called concurrently. Any other class (a
//   user subclass, vtkParametricSpline whose splines rebuild themselves lazily, vtkParametricRandomHills
//   which reads a vtkDoubleArray through its shared tuple buffer) is called under a mutex: exact, but
//   serial. The class name is matched exactly, so a subclass of vtkParametricTorus takes the mutex.
// - MeshSurface copies the mesh into its own arrays when built and is read-only afterwards.
// Neither adapter may outlive a change of its VTK object: build a new one per RequestData.
#pragma once

#include "surface/mesh_surface.h"
#include "surface/surface.h"

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "WireFurFiltersModule.h"  // exported for the module's tests
#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkPolyData.h"
#include "vtkSetGet.h"
#include "vtkSmartPointer.h"

class vtkDataArray;
class vtkParametricFunction;
class vtkInformationVector;
class vtkPolyData;

namespace wf::vtkio {

/// A vtkParametricFunction as a wf::Surface. Domain MinimumU..MaximumU x MinimumV..MaximumV,
/// periodic where JoinU / JoinV (TwistU / TwistV are not modelled: the wrap is plain). Outside the
/// domain (u, v) is clamped, or wrapped where periodic.
///
/// Derivatives: VTK's DerivativesAvailable flag is not reliable (vtkParametricTorus documents 0 and
/// fills Duvw exactly). So the adapter probes: at 9 interior points it compares Duvw with central
/// differences; when they agree (relative 1e-4) the function's own derivatives are used (exact),
/// otherwise central differences of the point with step h = 1e-5 of the domain (one-sided at the
/// border), error O(h^2) relative to the surface's curvature: exactDerivatives() says which.
class WIREFURFILTERS_EXPORT ParametricFunctionSurface final : public Surface {
 public:
  explicit ParametricFunctionSurface(vtkParametricFunction* function);
  ~ParametricFunctionSurface() override;

  /// Empty when usable; else one line (no function, a domain bound NaN / infinite, an empty domain).
  const std::string& problem() const { return problem_; }
  ParameterDomain domain() const override { return domain_; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

  bool exactDerivatives() const { return exact_; }
  /// True when Evaluate is called from several threads at once (see top), false under a mutex.
  bool concurrent() const { return concurrent_; }

 private:
  void raw(double u, double v, double P[3], double D[9]) const;
  glm::dvec3 point(double u, double v) const;
  glm::dvec2 wrap(double u, double v) const;

  vtkSmartPointer<vtkParametricFunction> function_;
  ParameterDomain domain_;
  std::string problem_;
  bool exact_ = false, concurrent_ = false;
  mutable std::mutex mutex_;
};

/// A vtkPolyData with texture coordinates as a wf::Surface over texture space: the core's
/// wf::MeshSurface (surface/mesh_surface.h: the lookup, the seams, mirrored halves and holes of
/// the layout) over the mesh's points, its polygons fanned from their first vertex (convex
/// polygons: vtkPlaneSource, vtkDiskSource quads) and strips split. Where (u, v) lies in no
/// triangle the point is NaN: the generators skip such roots (fur counts them in
/// FurCounts::skippedDegenerate, scales leave them out).
class WIREFURFILTERS_EXPORT MeshSurface final : public Surface {
 public:
  /// Texture coordinates: the active TCoords, else a point array named "TCoords" or
  /// "TextureCoordinates" with at least 2 components. gridCells 0 picks about one cell per triangle.
  explicit MeshSurface(vtkPolyData* mesh, int gridCells = 0);

  /// Empty when usable; else one line (no texture coordinates, a NaN point or texture coordinate,
  /// no triangle with a non-zero uv area).
  const std::string& problem() const { return problem_; }
  ParameterDomain domain() const override;
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

  std::size_t triangleCount() const;
  /// The triangle holding (u, v) and its barycentric coordinates; false when none does.
  bool locate(double u, double v, std::size_t& triangle, glm::dvec3& barycentric) const;
  /// A located triangle's index in triangulate(mesh)'s list.
  std::size_t sourceTriangle(std::size_t located) const;

 private:
  std::unique_ptr<wf::MeshSurface> core_;  ///< the mesh as the core's surface/mesh_surface.h
  std::string problem_;
};

/// Parallel loop body(first, last) over [begin, end) in blocks, on oneTBB directly. vtkSMPTools (whose
/// Debian backend is the same oneTBB) is the VTK idiom, but VTK 9.1's vtkSMPTools.h does not compile
/// as C++20 with GCC 12 (a template-id as constructor name, vtkSMPTools.h:106; CWG 2237). Call it
/// from the filter's own thread; the body must not call UpdateProgress (not thread-safe).
template <class Body>
void parallelFor(std::int64_t begin, std::int64_t end, Body&& body) {
  if (end <= begin) return;
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(begin, end, 1024),
                    [&](const tbb::blocked_range<std::int64_t>& r) { body(r.begin(), r.end()); });
}

/// A linear colour value as 8-bit sRGB (IEC 61966-2-1), clamped to [0, 1]; NaN -> 0. The module's
/// 8-bit "Colors" arrays are sRGB, as VTK shows them and as vtkWireFurRenderPass decodes them.
WIREFURFILTERS_EXPORT unsigned char srgb8(float linear);

/// The texture coordinate array of `mesh` as MeshSurface picks it (see there), or nullptr.
WIREFURFILTERS_EXPORT vtkDataArray* textureCoordinates(vtkPolyData* mesh);

/// The triangles of the polygons and strips of `mesh` (fanned, split), as point id triples.
WIREFURFILTERS_EXPORT std::vector<glm::uvec3> triangulate(vtkPolyData* mesh);

/// Calls f(cellId, n, ids) for every cell of `mesh` in VTK's id order (vertices, lines,
/// polygons, strips); f returns false to stop early.
template <class F>
void forEachCell(vtkPolyData* mesh, F&& f) {
  if (!mesh) return;
  vtkIdType cell = 0;
  for (vtkCellArray* cells : {mesh->GetVerts(), mesh->GetLines(), mesh->GetPolys(), mesh->GetStrips()}) {
    if (!cells) continue;
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cell) {
      it->GetCurrentCell(n, ids);
      if (!f(cell, n, ids)) return;
    }
  }
}

/// Index of the first cell (vertices, lines, polygons, strips in that order) naming a point
/// `mesh` does not have, or -1.
WIREFURFILTERS_EXPORT std::int64_t firstCellWithMissingPoints(vtkPolyData* mesh);

/// An input with no points and no cells. In a parallel pipeline (pvbatch under mpirun) a rank's
/// piece is often empty: the filters give an empty output and no error; when the request is for
/// the whole data set (one piece), `wholeEmptyWarning` is the warning to give.
WIREFURFILTERS_EXPORT bool isEmpty(vtkPolyData* data);
WIREFURFILTERS_EXPORT bool wholeDataRequested(vtkInformationVector* outputVector);
inline constexpr const char* wholeEmptyWarning = "the input is empty: the output is empty";

/// Index of the first point of `mesh` with a NaN or infinite coordinate, or -1.
WIREFURFILTERS_EXPORT std::int64_t firstNonFinitePoint(vtkPolyData* mesh);
/// The two checks above as one line for an error ("WHAT cell 3 names a point the input does not
/// have", "WHAT point 7 is not finite"), or empty.
WIREFURFILTERS_EXPORT std::string inputProblem(vtkPolyData* mesh, const std::string& what = "input");

/// A surface whose front is the other side: the same S, Su, Sv with normalSign() turned round
/// (vtkParametricTorus and some other VTK functions have Su x Sv pointing inward).
class FlippedSurface final : public Surface {
 public:
  explicit FlippedSurface(std::shared_ptr<const Surface> base) : base_(std::move(base)) {}
  ParameterDomain domain() const override { return base_->domain(); }
  SurfacePoint evaluate(double u, double v) const override { return base_->evaluate(u, v); }
  std::string describe() const override { return base_->describe() + " (flipped)"; }
  double normalSign() const override { return -base_->normalSign(); }
  std::vector<double> creasesV() const override { return base_->creasesV(); }

 private:
  std::shared_ptr<const Surface> base_;
};

/// The surface a generator grows on: `function` when set, else `mesh` (which needs texture
/// coordinates); its front turned round when `flip`. nullptr and a one-line `problem` when
/// neither is usable; nullptr and no problem for an empty mesh (in a parallel pipeline a rank's
/// piece is often empty: it grows nothing, and that is not an error).
WIREFURFILTERS_EXPORT std::shared_ptr<const Surface> growthSurface(vtkParametricFunction* function, vtkPolyData* mesh,
                                             std::string& problem, bool flip = false);

/// What the fur and scale generators share around the core's growth: progress from 0 to 0.8
/// around grow(), VTK's abort flag before and after, and the core's exceptions reported as one
/// error "<what> on <surface>: <why>". False when the update should end with nothing output.
template <class Grow>
bool runGrowth(vtkAlgorithm* algorithm, const char* what, const Surface& surface, Grow&& grow) {
  algorithm->UpdateProgress(0.0);
  if (algorithm->GetAbortExecute()) return false;
  try {
    grow();
  } catch (const std::exception& e) {
    vtkErrorWithObjectMacro(algorithm, << what << " on " << surface.describe() << ": " << e.what());
    return false;
  }
  algorithm->UpdateProgress(0.8);
  return !algorithm->GetAbortExecute();
}

/// Burnish grain (paper §2.2; the core renderer's rule, src/render/surface_shading.cpp): the grain
/// direction at a point, in the tangent plane of unit normal N, unit length. U: along Su; V: along
/// Sv; Radial: away from the axis; Circular: around it (axisDirection x radial offset). Where that
/// direction vanishes or is along N (on the axis, a zero derivative) the result is a fixed
/// perpendicular of N; with N zero the direction itself is normalised, or (1, 0, 0). Never NaN.
enum class Grain { U = 0, V = 1, Radial = 2, Circular = 3 };
WIREFURFILTERS_EXPORT glm::dvec3 grainTangent(Grain grain, const glm::dvec3& P, const glm::dvec3& N, const glm::dvec3& Su,
                        const glm::dvec3& Sv, const glm::dvec3& axisPoint, const glm::dvec3& unitAxis);
/// The groove coordinate of the core (render/scene.h, Burnish::grooves): v for grain U, u for grain
/// V, the turn about the axis in [0, 1) for radial grain, the distance from the axis for circular.
WIREFURFILTERS_EXPORT double grooveCoordinate(Grain grain, const glm::dvec3& P, const glm::dvec2& uv, const glm::dvec3& axisPoint,
                        const glm::dvec3& unitAxis);

}  // namespace wf::vtkio
