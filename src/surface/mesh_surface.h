// A triangle mesh as a wf::Surface (surface/surface.h), so that fur and scales grow on meshes as on
// parametric patches: over the mesh's texture coordinates, or over an automatic layout when it has
// none.
//
// Over texture coordinates: (u, v) are the mesh's uvs, the domain their bounding box (not
// periodic). evaluate(u, v) finds the triangle holding (u, v) in texture space (a uniform grid over
// the uv triangles, about one triangle per cell), P by barycentric interpolation, and Su = dP/du,
// Sv = dP/dv from that triangle's affine map (constant per triangle). On a shared edge the triangle
// with the largest smallest barycentric coordinate wins (on an exact tie, the one with the smaller
// corners: independent of the order of the triangles).
// Where (u, v) lies in no triangle (a hole in the layout) P is NaN and Su = Sv = 0: the generators
// skip such roots. Where the layout overlaps itself one of the overlapping triangles is used. Left
// out of the lookup: triangles of zero area in uv or in space (below 1e-12 of the squared bounding
// box diagonal: the joined corner of a closed layout), and triangles wound in uv against the
// majority (by uv area): a seam that wraps back across the layout, the mirrored half of an
// overlapping layout; a fold-over of a distorted map becomes a hole.
//
// The automatic layout (a mesh without uvs): every triangle laid flat at the scale of the world
// (one uv unit is one world unit, so |Su| = |Sv| = 1 and area-correct placement is exact), its u
// along the up axis (+z, or +x where the triangle faces along z) projected onto its plane, v = N x u,
// the triangles packed on shelves. So hairs combed along u and scales pointing along u lean the
// same way all over the mesh; a grid of scale cells has the same world size everywhere, but its
// lattice does not continue across triangle edges (each triangle sits at its own place in uv).
#pragma once

#include "render/scene.h"
#include "surface/surface.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace wf {

class MeshSurface final : public Surface {
 public:
  /// Over mesh.uvs when the mesh has one per vertex and they cover at least 90% of its area
  /// (not mirrored or overlapping charts) without overlapping themselves too much for the
  /// lookup; else over the automatic layout. Triangles with a NaN / Inf corner are left out.
  /// gridCells 0 picks about one lookup cell per triangle.
  explicit MeshSurface(const TriangleMesh& mesh, int gridCells = 0);
  /// Over the given texture coordinates (one per position); a NaN / Inf point or texture
  /// coordinate, or a layout that overlaps itself too much (its lookup would pass 16 entries a
  /// triangle), is the problem.
  MeshSurface(std::vector<glm::dvec3> positions, std::vector<glm::dvec2> uvs, const std::vector<glm::uvec3>& triangles,
              int gridCells = 0);

  /// Empty when usable; else one line (no triangles, a NaN point or texture coordinate, no
  /// triangle with a non-zero uv area).
  const std::string& problem() const { return problem_; }
  /// True when the (u, v) are the automatic layout's rather than the mesh's own.
  bool automaticLayout() const { return automatic_; }
  ParameterDomain domain() const override { return domain_; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

  std::size_t triangleCount() const { return triangles_.size(); }
  /// The triangle holding (u, v) and its barycentric coordinates; false when none does. The
  /// index counts the triangles kept for the lookup; sourceTriangle turns it into the index in
  /// the constructor's triangle list (with given texture coordinates; the laid-out list else).
  bool locate(double u, double v, std::size_t& triangle, glm::dvec3& barycentric) const;
  std::size_t sourceTriangle(std::size_t located) const { return triangles_[located].source; }

 private:
  MeshSurface() = default;
  /// The lookup over triangles; false (and problem_) when unusable. skipNonFinite: triangles with
  /// a NaN / Inf corner are left out (else such a point is the problem).
  bool build(const std::vector<glm::uvec3>& triangles, int gridCells, bool skipNonFinite);
  void layOut(const TriangleMesh& mesh);
  double keptArea_ = 0.0, totalArea_ = 0.0;  ///< space area of the looked-up / all finite triangles

  struct Triangle {
    std::uint32_t v[3];
    std::uint32_t source;  ///< index in the constructor's triangle list
    glm::dvec3 Su, Sv;  ///< dP/du, dP/dv of the triangle's affine map
    glm::dmat2 toBary;  ///< (u, v) - uv[v0] -> (b1, b2)
    glm::dvec2 lo, hi;  ///< uv bounding box
  };
  std::vector<glm::dvec3> positions_;
  std::vector<glm::dvec2> uvs_;
  std::vector<Triangle> triangles_;
  ParameterDomain domain_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> cellStart_, cellTriangles_;  ///< CSR: triangles overlapping each cell
  std::string problem_;
  bool automatic_ = false;
};

}  // namespace wf
