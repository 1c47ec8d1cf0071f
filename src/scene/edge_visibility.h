// Which parts of a wire-frame a view sees: every polyline split where the scene's opaque surfaces
// begin and stop hiding it, as exact ray tests against their triangles (`wirefur export
// --visibility`, the hidden-line drawing a CAD engineer prints; docs/cad.md "Edge classes and
// visibility"). The A-buffer decides the same per subpixel when it draws (HiddenLines); this is
// the geometric answer, with the split points located to a thousandth of a pixel.
#pragma once

#include "render/camera.h"
#include "render/scene.h"

#include <cstdint>
#include <vector>

namespace wf {

struct VisibilityOptions {
  /// Screen spacing of the samples along each segment, pixels: a hidden or visible stretch
  /// shorter than this between two samples of the same answer can be missed.
  double samplePx = 0.5;
  /// The split points are bisected to this screen distance, pixels.
  double tolerancePx = 1e-3;
  /// Hits nearer than this to the point (world units) do not hide it. Silhouettes lie on the
  /// exact surface, and its tessellation's chords can pass in front of a grazing ray within about
  /// sqrt(2 deflection R) of the point, R the surface's radius of curvature along the ray (large
  /// along the saddle inside a torus): `wirefur export` gives CAD silhouettes sqrt(2 deflection
  /// r), r the scene's bounding radius (an upper bound that grows with an assembly's size).
  double slack = 0.0;
  /// A point's slack is at least the width (twice the area over the longest edge) of the
  /// triangles it lies on: near them (a tenth of their longest edge) and grazing its ray (|n.ray| <
  /// 1/2). That is about a chord across a silhouette, which bounds the chords that cross its
  /// grazing ray where the surface curves across it; it is what a mesh's silhouettes (traced from
  /// its normals inside the triangles) need, where no deflection is known.
  bool localSlack = false;
};

struct VisibilityStats {
  std::size_t samples = 0, rayTests = 0, splits = 0;
  double visibleLength = 0, hiddenLength = 0;  ///< world units (not seen: hidden or outside the view)
};

/// A wire's polylines cut into pieces, each all visible or all hidden.
struct VisibleLines {
  PolylineSet lines;
  std::vector<std::uint32_t> source;  ///< the polyline of the input each piece comes from
  std::vector<std::uint8_t> visible;  ///< 1 seen, 0 not seen (hidden, or outside the view)
};

/// The opaque triangles of a scene, binned by where they fall on the screen of a view, for
/// exact occlusion queries. A point is hidden when the ray from it towards the viewer (to the
/// eye, or back along the view direction), as far as the near plane, crosses a triangle more than
/// a relative 1e-7 of its distance (or `slack`) in front of it: a point on a triangle (an edge on
/// its own face's tessellation) is not hidden by that triangle, and what the renderer clips away
/// (before the near plane, beyond the far one) hides nothing. Triangles off the image are left
/// out; the grid coarsens where long triangles would fill too many cells (at most 16 entries a
/// triangle and a million). Coordinates up to about 1e150.
class OcclusionGrid {
 public:
  /// Every surface of the scene but those whose material is not opaque (opacity < 1); hold-outs
  /// occlude. The camera's open near and far planes are chosen as a render chooses them.
  OcclusionGrid(const Scene& scene, const Camera& camera, int width, int height);
  bool hidden(const glm::dvec3& p, double slack = 0.0, std::size_t* tests = nullptr, bool localSlack = false) const;
  /// The largest width (2 area / longest edge) of the triangles within a tenth of their longest
  /// edge of p whose normal is at more than 60 degrees to p's ray, among those binned where p falls
  /// on the screen; 0 if none.
  double localWidth(const glm::dvec3& p) const;
  /// The part [t0, t1] of the segment p0 p1 in the view (between the near and far planes, on the
  /// image); false if none.
  bool clipToView(const glm::dvec3& p0, const glm::dvec3& p1, double& t0, double& t1) const;
  const ViewTransform& view() const { return view_; }
  /// Triangles kept, and entries in the grid's cells (at most 16 a triangle and a million, or one a
  /// triangle on a single cell).
  std::size_t triangles() const { return a_.size(); }
  std::size_t entries() const { return cellItems_.size(); }

 private:
  ViewTransform view_;
  glm::dvec3 viewDir_{0, 0, -1};
  std::vector<glm::dvec3> a_, e1_, e2_;   // triangle p0, p1 - p0, p2 - p0
  std::vector<double> width_, reach_;      // 2 area / longest edge; a tenth of the longest edge
  std::vector<glm::dvec3> normal_;         // unit
  std::size_t cellOf(const glm::dvec2& s) const;
  std::vector<std::uint64_t> cellStart_;
  std::vector<std::uint32_t> cellItems_;
  int nx_ = 1, ny_ = 1;
  double cell_ = 16;
};

/// Splits `lines` by visibility against `grid` (see VisibleLines): each segment clipped to the view
/// (the parts outside it are not seen), the part inside sampled every samplePx of its own length
/// on the screen (at most 2^20 samples) and each change bisected. Non-finite points end a piece and
/// are left out.
VisibleLines splitByVisibility(const PolylineSet& lines, const OcclusionGrid& grid, const VisibilityOptions& options,
                               VisibilityStats& stats);

}  // namespace wf
