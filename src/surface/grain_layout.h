// Brushed steel that follows a CAD part (docs/cad.md "Brushed steel"): each face's grain along
// its u or its v, or along the longer of the two by the face's extent in the world, and the
// groove coordinate across the grain made a world length, so that `--grooves-per-mm` means
// grooves per millimetre on every face whatever its parametrisation (a plane's u in mm, a
// cylinder's in radians, a B-spline's in [0, 1]) and however finely it is meshed.
#pragma once

#include "render/scene.h"

#include <cstdint>
#include <vector>

namespace wf {

struct GrainLayoutStats {
  std::size_t faces = 0, alongU = 0, alongV = 0;
};

/// Rewrites the mesh so that a burnish of grain U (Burnish::Grain::U) runs as `layout` says on
/// every face: a face (the triangles of one id in `triangleFace`; the whole mesh when it is empty)
/// whose grain runs along v has u and v swapped, with dS/du and dS/dv; then u and v are scaled
/// by the face's mean |dS/du| and |dS/dv| (dS/du and dS/dv divided by them), so that v, the groove
/// coordinate, is about the world distance across the grain (exact on planes, cylinders and
/// cones' axial lines, within the variation of |dS/dv| over the face elsewhere). Needs uvs,
/// derivU and derivV on every vertex (else nothing is done); a face where a mean is zero or not
/// finite keeps that scale. Vertices used by triangles of two faces follow the first.
GrainLayoutStats layoutGrain(TriangleMesh& mesh, const std::vector<int>& triangleFace, GrainLayout layout);

}  // namespace wf
