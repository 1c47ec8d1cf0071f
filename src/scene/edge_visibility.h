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
};

struct VisibilityStats {
  std::size_t samples = 0, rayTests = 0, splits = 0;
  double visibleLength = 0, hiddenLength = 0;  ///< world units
};

/// A wire's polylines cut into pieces, each all visible or all hidden.
struct VisibleLines {
  PolylineSet lines;
  std::vector<std::uint32_t> source;  ///< the polyline of the input each piece comes from
  std::vector<std::uint8_t> visible;  ///< 1 visible, 0 hidden
};

/// The opaque triangles of a scene, binned by where they fall on the screen of a view, for
/// exact occlusion queries. A point is hidden when the segment from the eye (perspective) or
/// from the near plane along the view direction (orthographic) to it crosses a triangle more
/// than a relative 1e-7 of its distance in front of it: a point on a triangle (an edge on its
/// own face's tessellation) is not hidden by that triangle.
class OcclusionGrid {
 public:
  /// Every surface of the scene but those whose material is not opaque (opacity < 1); hold-outs
  /// occlude.
  OcclusionGrid(const Scene& scene, const Camera& camera, int width, int height);
  bool hidden(const glm::dvec3& p, std::size_t* tests = nullptr) const;
  const ViewTransform& view() const { return view_; }

 private:
  ViewTransform view_;
  glm::dvec3 viewDir_{0, 0, -1};
  std::vector<glm::dvec3> a_, e1_, e2_;   // triangle p0, p1 - p0, p2 - p0
  std::vector<std::uint32_t> cellStart_, cellItems_, everywhere_;
  int nx_ = 1, ny_ = 1;
  double cell_ = 16;
};

/// Splits `lines` by visibility against `grid` (see VisibleLines). Non-finite points end a piece
/// and are left out.
VisibleLines splitByVisibility(const PolylineSet& lines, const OcclusionGrid& grid, const VisibilityOptions& options,
                               VisibilityStats& stats);

}  // namespace wf
