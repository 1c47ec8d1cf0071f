// Scales grown on a parametric surface (paper §4.2, images 17 and 21): "One scale was placed in
// the bottom left corner of each rectangle in parameter space. A second scale was placed in the
// centre of the rectangle. Two triangles were used for each scale and the normals at the
// triangle vertices were deflected outwards to give a rounded appearance. The scale intensities
// were also varied to prevent the scales from looking too uniform." No dithering (as the paper).
#pragma once

#include "render/scene.h"
#include "surface/surface.h"
#include "texture/texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace wf {

struct ScaleParams {
  /// The parametric grid: the domain is cut into cellsU x cellsV rectangles (1 ... 16384 each,
  /// at most 2^24 cells in all).
  int cellsU = 16, cellsV = 16;
  /// Scale length along +u and full width along v, as a fraction of the cell's extent at the
  /// root (|Su| du_cell, |Sv| dv_cell). 1 makes the corner and centre scales just touch
  /// diagonally; > 1 makes them overlap like roof tiles. (0, 16].
  double size = 1.5;
  /// Height of the tip above the surface along N, as a fraction of the scale's length: the scale
  /// is a kite tilted by atan(lift) about its root. [0, 16].
  double lift = 0.25;
  /// Outward bend of the vertex normals: a vertex normal is the scale's plane normal plus
  /// `deflection` times the unit outward direction (away from the scale's centre line, in its
  /// plane), normalised: atan(deflection) of bend. 0 gives flat-shaded scales. [0, 16].
  double deflection = 0.6;
  /// Per-scale intensity 1 + intensityVariation * (2 xi - 1), xi uniform: within
  /// +-intensityVariation of 1. [0, 1].
  double intensityVariation = 0.25;
  /// Position of the two side vertices along the scale, as a fraction of its length, (0, 1).
  double shoulder = 0.4;
  /// Base colour (linear, >= 0); each vertex colour is colour * the scale's intensity.
  glm::vec3 colour{1.0f};
  std::uint64_t seed = 1;
  /// Where scales grow, over the unit square (s, t) of the domain (like FurParams::densityMap):
  /// a scale whose root has mask < 0.5 is left out (a CAD face's trimming). Optional.
  std::shared_ptr<const ScalarTexture> mask;
  /// The most triangles the scales may make (4 per cell), checked before anything is allocated:
  /// growScales throws std::length_error past it. Callers with a memory budget pass less.
  double maxTriangles = 67108864.0;
  /// A share of the scales (a distributed piece's, like FurParams::rootFilter): when set, a scale
  /// grows only where this returns true for its root's (u, v). Empty: every scale.
  std::function<bool(const glm::dvec2& uv)> rootFilter;

  /// Empty when the parameters are usable, else one line naming the field and what is wrong
  /// ("cellsU must be in [1, 16384] (got 0)").
  std::string problem() const;
};

/// Grows the scales of one patch. Cell (i, j) (unit coordinates s = i / cellsU, t = j / cellsV
/// mapped through the surface's domain) holds scale 2c (its corner, (i, j)) and scale 2c + 1
/// (its centre, (i + 1/2, j + 1/2)), c = j cellsU + i. A scale is four vertices:
///
///     0 root  R = S(u, v)                                  (on the surface)
///     1 right R + shoulder L Tu - W/2 Tv + shoulder lift L N
///     2 tip   R + L Tu + lift L N
///     3 left  R + shoulder L Tu + W/2 Tv + shoulder lift L N
///
/// with L = size |Su| du_cell, W = size |Sv| dv_cell, and two triangles (0, 1, 2), (0, 2, 3)
/// facing +N. Normals: the kite's plane normal deflected outward (see ScaleParams::deflection);
/// colours: colour * intensity (HashRandom(seed, patchIndex, scale index): independent of the
/// thread count, and of the other patches); uvs: the root's (u, v) on all four vertices (one
/// texture colour per scale); derivU / derivV: the root's Su, Sv; tangents: Tu.
/// A scale whose root is degenerate (a pole, |Su x Sv| = 0, a non-finite point) or whose
/// length or width is not positive and finite is left out; the others keep their order.
/// Generated in parallel (oneTBB) into fixed slots, then compacted: deterministic.
/// Throws std::invalid_argument with problem() for unusable parameters.
TriangleMesh growScales(const Surface& surface, const ScaleParams& params,
                        std::uint32_t patchIndex = 0);

}  // namespace wf
