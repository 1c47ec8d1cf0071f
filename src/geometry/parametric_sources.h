// Parametric sources for scenes: tessellated surfaces with (u, v), normals and tangents per
// vertex, and their isolines as wire-frames. A first, small set (sphere, torus, lathe,
// plane, box) that the scene format names directly; the general surface concept of
// DESIGN.md (S(u,v), Su, Sv) comes with the surface issue and will take these over.
#pragma once

#include "render/scene.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wf {

struct ParametricSource {
  enum class Type { Sphere, Torus, Lathe, Plane, Box };
  Type type = Type::Sphere;
  double radius = 1.0;                ///< sphere
  double major = 1.0, minor = 0.35;   ///< torus: tube centre radius, tube radius
  std::vector<glm::dvec2> profile;    ///< lathe: (radius, height) points, bottom to top
  glm::dvec3 size{2.0, 2.0, 2.0};     ///< plane (x, y), box (x, y, z)
  int resolutionU = 48, resolutionV = 24;
  /// Empty when usable; otherwise what is wrong.
  std::string problem() const;
};

/// The surface, tessellated on a resolutionU x resolutionV grid (u around, v along).
/// Poles (sphere, lathe ends on the axis) get the limit normal, never NaN.
TriangleMesh tessellate(const ParametricSource& source);

/// Iso-parameter lines: resolutionU lines of constant u and resolutionV of constant v (each
/// sampled finely enough to look smooth: `samplesPerLine` points), as a wire-frame. For a box,
/// its 12 edges.
PolylineSet isolines(const ParametricSource& source, int linesU, int linesV, int samplesPerLine = 64);

/// Every distinct edge of a triangle mesh as a two-point polyline (a mesh's wire-frame).
PolylineSet meshEdges(const TriangleMesh& mesh);

/// Applies an affine transform (positions by M, normals and tangents by its inverse transpose).
void transformMesh(TriangleMesh& mesh, const glm::dmat4& M);
void transformPolylines(PolylineSet& lines, const glm::dmat4& M);

}  // namespace wf
