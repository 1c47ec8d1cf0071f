// A triangle mesh's edges, classified as a CAD model's are (render/edge_classes.h) from the
// triangles on their sides, and the ones a selection keeps chained into polylines. Vertices within
// 1e-9 of the mesh's size are joined first, so a mesh cut along its texture seams (STL, OBJ with
// split vertices, a tessellation's u = 0 and u = 2 pi) has edges between its pieces, not borders.
#pragma once

#include "render/scene.h"
#include "render/edge_classes.h"

#include <vector>

namespace wf {

struct ClassifiedEdges {
  PolylineSet lines;               ///< the kept edges, chained (see classifyMeshEdges)
  std::vector<EdgeClass> classes;  ///< per polyline
  std::vector<float> angles;       ///< per polyline: the largest angle between the triangles' normals, degrees (NaN if not two)
  std::size_t counts[7] = {};      ///< edges (segments) of each class before the selection
};

/// Every edge of the mesh's triangles with its class: one triangle, boundary; two, sharp when
/// their normals (consistently oriented across the edge) differ by more than the selection's
/// feature angle, else smooth; three or more, non-manifold. Triangles of zero area (or with
/// non-finite or out-of-range vertices) are left out. The kept edges are chained into polylines
/// through vertices where exactly two kept edges of the same class meet, so dashes run on along
/// a feature line. The same output for the same mesh, in the triangles' order.
ClassifiedEdges classifyMeshEdges(const TriangleMesh& mesh, const EdgeSelection& selection);

/// The same for polygons: polygon f is positions[ids[starts[f]]] ... positions[ids[starts[f+1]-1]],
/// its normal by Newell's method (a polygon's own edges only: no triangulation's diagonals).
ClassifiedEdges classifyPolygonEdges(const std::vector<glm::dvec3>& positions, const std::vector<std::uint32_t>& starts,
                                     const std::vector<std::uint32_t>& ids, const EdgeSelection& selection);

}  // namespace wf
