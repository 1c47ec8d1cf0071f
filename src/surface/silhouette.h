// Silhouettes of curved surfaces from the exact surface (docs/cad.md, "Silhouettes"): the curves
// where the surface turns away from the viewer, N . (P - eye) = 0 in perspective (N . d = 0 for
// an orthographic view along d), traced on the surface's (u, v) domain and mapped through S(u, v).
//
//   1. g(u, v) = N . (P - eye) / |P - eye| (a cosine, so the tolerances below are scale-free) on a
//      grid over the domain; periodic directions wrap.
//   2. Marching squares: every grid edge where g changes sign holds a root, found by the Illinois
//      method along the edge to 1e-13 of the domain; a cell with four roots is split as its
//      centre's sign says. The roots chain into curves (open ones end on the domain's border).
//   3. Between two consecutive points the curve is found again halfway, along the chord's
//      normal in (u, v); the chord is split there while that point lies more than `tolerancePx`
//      pixels on screen from the chord (so every drawn chord is within it of the true curve).
//   4. Trimmed to where the face is (`inside` >= 0.5), the border found by bisection.
//
// Defined on bad input: non-finite values of g split the curves there and are counted; a face
// whose g is zero everywhere (a plane seen edge-on) has no silhouette; poles (N a limit,
// Surface::frame) and seams (periodic wrap) need nothing special.
#pragma once

#include "render/camera.h"
#include "render/scene.h"
#include "surface/surface.h"
#include "texture/texture.h"

#include <cstddef>

namespace wf {

struct SilhouetteOptions {
  int grid = 32;             ///< grid cells per parameter direction of a face (4 ... 1024)
  double tolerancePx = 0.1;  ///< largest distance on screen of a drawn chord from the curve
  int maxDepth = 12;         ///< most halvings of one grid chord
  std::size_t maxPoints = 1u << 20;  ///< per face: a face that would make more is cut short (counted)
};

struct SilhouetteStats {
  std::size_t faces = 0;       ///< faces traced
  std::size_t curves = 0;      ///< polylines made
  std::size_t points = 0;      ///< their points
  std::size_t nonFinite = 0;   ///< grid values that were not finite (the curve split there)
  std::size_t cutShort = 0;    ///< faces that reached maxPoints
  std::size_t evaluations = 0; ///< surface evaluations
  void add(const SilhouetteStats& o) {
    faces += o.faces, curves += o.curves, points += o.points, nonFinite += o.nonFinite, cutShort += o.cutShort;
    evaluations += o.evaluations;
  }
};

/// Appends the silhouette curves of `surface` (world space), seen by `view`, to `out`, trimmed
/// to where `inside` (over the unit square of the surface's domain, as fur reads a density map)
/// is at least 0.5 when it is given.
void traceSilhouette(const Surface& surface, const ScalarTexture* inside, const ViewTransform& view,
                     const SilhouetteOptions& options, PolylineSet& out, SilhouetteStats& stats);

}  // namespace wf
