// Tessellation of a Surface into the renderer's TriangleMesh, and its iso-parameter lines.
#pragma once

#include "render/scene.h"
#include "surface/surface.h"

#include <string>

namespace wf {

/// Most vertices one tessellation may make ((nu + 1) x (nv + 1)): 4,194,304, about 1 GB of mesh.
constexpr double kMaxTessellationVertices = 4194304.0;

/// Empty when tessellate(surface, resolutionU, resolutionV) can run; otherwise what is wrong
/// (a resolution below 1, or more than kMaxTessellationVertices vertices).
std::string tessellationProblem(int resolutionU, int resolutionV);

/// The surface sampled on a (resolutionU + 1) x (resolutionV + 1) grid, evenly in (u, v) over its
/// domain, vertex (i, j) at index j (resolutionU + 1) + i. Seam vertices are duplicated so that
/// the uvs run continuously (u = u1 on the last column), with positions (and every other
/// attribute) copied bit for bit from the first column/row of a periodic direction: no cracks.
/// At each of the surface's creasesV() two more rows are put in, at the crease itself, one with
/// the frame just below it and one with the frame just above (the same positions): the
/// triangles between them have no area and are left out, so each side keeps its own normals.
/// Per vertex: positions, normals (frame(): the limit normal at poles), tangents (unit Tu),
/// derivU / derivV (Su, Sv as evaluated, zero at a pole) and uvs (the surface's own u, v).
/// Each grid cell is two triangles (i,j)-(i+1,j)-(i+1,j+1) and (i,j)-(i+1,j+1)-(i,j+1), wound
/// counter-clockwise about the front normal N (Su x Sv times normalSign()); a triangle collapsed to zero area (a pole, a cusp, a
/// degenerate cell: |cross| <= 1e-12 x its longest edge squared) is left out.
/// Vertices are computed in parallel (oneTBB), the result is the same for any thread count.
/// Throws std::invalid_argument with tessellationProblem()'s message for a bad resolution.
TriangleMesh tessellate(const Surface& surface, int resolutionU, int resolutionV);

/// Iso-parameter lines: linesU lines of constant u (running along v) then linesV lines of constant
/// v (running along u), each samplesPerLine + 1 points (closed, last point = first, along a
/// periodic direction). Constant values are spread evenly: k / n along a periodic direction;
/// k / (n - 1) along an open one (both edges drawn, the middle for n = 1), or (k + 1) / (n + 1)
/// when an edge of that direction collapses to a point (a pole), so no line is a point.
PolylineSet isoparametricLines(const Surface& surface, int linesU, int linesV, int samplesPerLine = 64);

}  // namespace wf
