// Parametric sources for scenes: the surfaces a scene file names (sphere, torus, lathe, plane,
// box; loft, Bezier and B-spline patches for the loader to name), tessellated with (u, v),
// normals, tangents and dS/du, dS/dv per vertex, and their isolines as wire-frames. Every type but
// the box is a Surface of src/surface/patches.h and goes through src/surface/tessellate.h.
#pragma once

#include "render/scene.h"
#include "surface/patches.h"
#include "surface/surface.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace wf {

struct ParametricSource {
  enum class Type { Sphere, Torus, Lathe, Plane, Box, Loft, Bezier, BSpline };
  Type type = Type::Sphere;
  double radius = 1.0;                ///< sphere
  double major = 1.0, minor = 0.35;   ///< torus: tube centre radius, tube radius
  /// lathe (a RevolutionPatch): (radius, height) points, bottom to top, through which a smooth
  /// curve passes (a repeated point makes a corner); points on the axis close the surface.
  std::vector<glm::dvec2> profile;
  std::vector<bool> profileCorners;   ///< lathe: optional, one per profile point: a crisp corner there
  bool profileLinear = false;         ///< lathe: straight segments between the points instead
  /// lathe: a point where the profile polyline turns by more than this (degrees) is a corner. A
  /// scene's sparse profile means a sharp turn as a crease: the jugs' base rim (55 degrees) stays
  /// crisp and their base flat (a smooth curve there would sag 0.02 below the base); 180: none.
  double profileCornerAngle = 50.0;
  glm::dvec3 size{2.0, 2.0, 2.0};     ///< plane (x, y), box (x, y, z)
  std::vector<LoftSection> sections;  ///< loft: cross-sections along the spine (LoftPatch)
  glm::dvec3 up{0.0};                 ///< loft: the sections' up vector; zero picks an axis
  /// Bezier (16, controlPoints[4 j + i]) and B-spline (controlCountU x controlCountV) control nets.
  std::vector<glm::dvec3> controlPoints;
  int controlCountU = 4, controlCountV = 4;
  bool periodicU = false, periodicV = false;  ///< B-spline: closed directions
  int resolutionU = 48, resolutionV = 24;
  /// Empty when usable; otherwise what is wrong.
  std::string problem() const;
};

/// The source as a Surface (nullptr for a box, which is not one parametric patch).
std::unique_ptr<Surface> makeSurface(const ParametricSource& source);

/// The surface, tessellated on a resolutionU x resolutionV grid (u around, v along) by
/// wf::tessellate(const Surface&, ...): (resolutionU + 1) x (resolutionV + 1) vertices, seams
/// duplicated. Poles (sphere, lathe ends on the axis, closed loft ends) get the limit normal,
/// never NaN. A box: six faces of four vertices each.
TriangleMesh tessellate(const ParametricSource& source);

/// Iso-parameter lines: resolutionU lines of constant u and resolutionV of constant v (each
/// sampled finely enough to look smooth: `samplesPerLine` points), as a wire-frame. For a box,
/// its 12 edges.
PolylineSet isolines(const ParametricSource& source, int linesU, int linesV, int samplesPerLine = 64);

/// Every distinct edge of a triangle mesh as a two-point polyline (a mesh's wire-frame).
PolylineSet meshEdges(const TriangleMesh& mesh);

/// Applies an affine transform: positions by M; tangents (unit) and derivU, derivV (dS/du, dS/dv,
/// as they are) by its linear part A, as directions along the surface; normals by the inverse
/// transpose of A (its cofactor matrix, flipped for a mirror).
void transformMesh(TriangleMesh& mesh, const glm::dmat4& M);
void transformPolylines(PolylineSet& lines, const glm::dmat4& M);

}  // namespace wf
