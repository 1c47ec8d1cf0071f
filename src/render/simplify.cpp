// Stage "simplification" (render/pipeline.h), before the primitives: stochastic simplification
// of aggregate detail (Cook, Halstead, Planck and Ryu 2007; RenderOptions::simplify).
//
// For each aggregate wire (fur), every hair is placed on a coarse grid of screen cells by its
// root, with its projected area (width times length, pixels: the length clipped to the image,
// the width at most a cell's side, so that a hair reaching toward the lens or far off the image
// counts only what it shows). A cell's depth complexity is the hair area rooted in it per pixel
// of the cell (a hair longer than a cell counts whole in its root's cell: a field of long hair
// has its density, each cell the hairs rooted in it). Where that is at least minDepthComplexity (the hairs
// overlap: what a pixel shows is their aggregate, not any one of them) and a hair is thinner than
// targetWidth, its lambda is width / targetWidth: that fraction of the hairs around it is drawn,
// each widened by 1 / lambda, so that the expected projected area, and with it the expected
// coverage of any region (hairs placed independently: 1 - exp(-area density)), stays the same.
//
// Which hairs: u, a hash of the wire's and the hair's index, uniform in [0, 1). A hair is drawn
// with weight kappa = clamp((lambda + D/2 - u) / D, 0, 1) and width factor kappa / lambda: the
// expected weight is lambda, and as lambda changes with the view a hair fades in or out over a
// range D = fade * lambda of it (narrowed to 2 (1 - lambda) near lambda = 1, so that kappa stays
// in [0, 1] there) instead of popping. The same hairs are kept frame after frame.
//
// Colours: the mean over n hairs in a pixel has a variance proportional to 1 / n; with lambda n
// of them it rises by 1 / lambda, so each hair's colour is pulled by sqrt(lambda) toward the
// mean colour of the hairs around it (Cook et al.'s contrast correction). The mean is the
// cells', so a pattern keeps its colours where it is two cells (64 pixels or more) across; a
// finer pattern, or a colour gradient along the hairs, is pulled toward the cell's mean as well
// (docs/abuffer.md).
//
// The cells' complexity and mean colour are interpolated bilinearly between cell centres, so a
// hair's lambda changes smoothly as its root moves across the screen; a root just off the image
// takes the edge's. Hairs rooted behind the near plane or beyond the far one are drawn as they are.
#include "render/pipeline.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace wf {

namespace {

// The weight of a hair with hash u where a fraction lambda is drawn: expected value lambda over
// u in [0, 1) (the ramp is narrowed near 1 so that it never leaves [0, 1]).
double keepWeight(double lambda, double u, double fade) {
  if (lambda >= 1.0) return 1.0;
  const double ramp = std::min(fade * lambda, 2.0 * (1.0 - lambda));
  if (!(ramp > 0.0)) return u < lambda ? 1.0 : 0.0;
  return std::clamp((lambda + 0.5 * ramp - u) / ramp, 0.0, 1.0);
}

}  // namespace

SimplificationPlan planSimplification(const Scene& scene, const ViewTransform& view, const SimplifyOptions& o,
                                      double pixelScale) {
  SimplificationPlan plan;
  plan.wires.resize(scene.wires.size());
  if (!o.enabled) return plan;
  const double target = std::isfinite(o.targetWidth) ? std::clamp(o.targetWidth, 1e-3, 1e6) : 2.0;
  const double minComplexity = std::isfinite(o.minDepthComplexity) ? std::max(0.0, o.minDepthComplexity) : 4.0;
  const double fade = std::isfinite(o.fade) ? std::clamp(o.fade, 0.0, 1.0) : 0.25;
  // Cells of about 32 pixels or more a side, about 4,096 of them at most; every cell whole (the
  // image divided evenly), so that no sliver of a cell at the image's edge takes its density
  // from a few hairs.
  const double side = std::max(32.0, std::ceil(std::sqrt(double(view.width) * view.height / 4096.0)));
  const int cx = std::max(1, int(std::floor(view.width / side))), cy = std::max(1, int(std::floor(view.height / side)));
  const double cellW = double(view.width) / cx, cellH = double(view.height) / cy;
  for (size_t wi = 0; wi < scene.wires.size(); ++wi) {
    const SceneWire& w = scene.wires[wi];
    const PolylineSet& L = w.lines;
    const size_t n = L.polylineCount();
    if (!w.aggregate || n == 0 || !(w.thickness > 0) || !std::isfinite(w.thickness)) continue;
    // Per hair: its root on screen (clamped into the image; NaN: behind the near plane, beyond
    // the far one, or not finite) and its projected width and area.
    std::vector<glm::vec2> root(n, glm::vec2(NAN));
    std::vector<float> width(n, 0.0f);
    std::vector<double> area(n, 0.0);
    std::vector<char> onScreen(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t li = r.begin(); li < r.end(); ++li) {
        const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
        if (b < a + 2) continue;
        const glm::dvec3 e0 = view.toEye(L.points[a]), e1 = view.toEye(L.points[b - 1]);
        const double d0 = -e0.z, d1 = -e1.z;
        if (!finite3(e0) || !finite3(e1) || !(d0 >= view.nearPlane) || !(d0 <= view.farPlane)) continue;
        const glm::dvec2 p0 = view.project(e0);
        const double wpx = w.thicknessInPixels ? w.thickness * pixelScale
                                               : w.thickness * view.pixelsPerWorld(d0) * wireWidthFactor(view, e0, e1);
        // Its length on the image (Liang-Barsky: the part of root to tip inside the image).
        double len = 0.0;
        if (d1 >= view.nearPlane) {
          const glm::dvec2 p1 = view.project(e1), d = p1 - p0;
          double t0 = 0.0, t1 = 1.0;
          if (std::isfinite(p1.x) && std::isfinite(p1.y) && clipLineToRect(p0, p1, 0.0, 0.0, view.width, view.height, t0, t1))
            len = glm::length((p0 + t1 * d) - (p0 + t0 * d));  // (both ends on the image: no overflow)
        }
        if (!std::isfinite(wpx) || !std::isfinite(len) || !std::isfinite(p0.x) || !std::isfinite(p0.y)) continue;
        onScreen[li] = p0.x >= 0 && p0.x < view.width && p0.y >= 0 && p0.y < view.height;
        // A root just off the image takes the edge's density, as its neighbours inside do.
        root[li] = glm::vec2(float(std::clamp(p0.x, 0.0, double(view.width))), float(std::clamp(p0.y, 0.0, double(view.height))));
        width[li] = float(wpx);
        const double w = std::min(wpx, std::min(cellW, cellH));
        area[li] = w * std::max(len, w);
      }
    });
    // Depth complexity per cell: the hair area rooted in it (summed in hair order: the same for
    // any thread count) per pixel of the cell; and its mean hair colour,
    // weighted by area (what the cell's pixels show), the contrast correction's centre.
    const bool hasColours = L.colours.size() == L.points.size() && !L.colours.empty();
    std::vector<double> complexity(size_t(cx) * cy, 0.0);
    std::vector<glm::dvec3> colourSum(hasColours ? size_t(cx) * cy : 0, glm::dvec3(0.0));
    auto cellIndex = [&](glm::vec2 q) {
      const int i = std::min(cx - 1, int(q.x / cellW)), j = std::min(cy - 1, int(q.y / cellH));
      return size_t(j) * size_t(cx) + size_t(i);
    };
    auto hairColour = [&](size_t li) {
      const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
      glm::dvec3 c(0.0);
      for (size_t k = a; k < b; ++k) c += glm::dvec3(safeColour(L.colours[k]));
      return c / double(std::max<size_t>(1, b - a));
    };
    for (size_t li = 0; li < n; ++li) {
      if (!onScreen[li]) continue;
      const size_t c = cellIndex(root[li]);
      complexity[c] += area[li];
      if (hasColours) colourSum[c] += hairColour(li) * area[li];
    }
    const std::vector<double> areaSum = complexity;
    for (double& c : complexity) c /= cellW * cellH;
    // Bilinear between cell centres, so that a hair's lambda (and its colour's centre) changes
    // smoothly as its root moves across the screen: no step at a cell's border.
    auto bilinear = [&](glm::vec2 q, auto&& at) {
      const double gx = std::clamp(q.x / cellW - 0.5, 0.0, double(cx - 1)), gy = std::clamp(q.y / cellH - 0.5, 0.0, double(cy - 1));
      const int i0 = int(gx), j0 = int(gy), i1 = std::min(i0 + 1, cx - 1), j1 = std::min(j0 + 1, cy - 1);
      const double fx = gx - i0, fy = gy - j0;
      auto v = [&](int i, int j) { return at(size_t(j) * size_t(cx) + size_t(i)); };
      return (v(i0, j0) * (1 - fx) + v(i1, j0) * fx) * (1 - fy) + (v(i0, j1) * (1 - fx) + v(i1, j1) * fx) * fy;
    };
    WireSimplification& ws = plan.wires[wi];
    ws.scale.assign(n, 1.0f);
    ws.lambda.assign(n, 1.0f);
    if (hasColours) ws.meanColour.assign(n, glm::vec3(1.0f));
    for (size_t li = 0; li < n; ++li) {
      ++plan.hairs;
      double lambda = 1.0;
      if (!std::isnan(root[li].x) && width[li] < target) {
        // Full simplification where the depth complexity is twice the threshold or more, none
        // below the threshold, a ramp between: no step where it crosses the threshold.
        const double c = bilinear(root[li], [&](size_t k) { return complexity[k]; });
        const double on = std::clamp((c - minComplexity) / std::max(minComplexity, 1e-9), 0.0, 1.0);
        lambda = 1.0 - on * (1.0 - std::max(double(width[li]) / target, 1.0 / 64.0));
        if (hasColours && lambda < 1.0) {
          // Area-weighted, so that a cell without hairs pulls toward nothing.
          const double wsum = bilinear(root[li], [&](size_t k) { return areaSum[k]; });
          ws.meanColour[li] = wsum > 0.0 ? glm::vec3(bilinear(root[li], [&](size_t k) { return colourSum[k]; }) / wsum)
                                         : glm::vec3(hairColour(li));
        }
      }
      const double u = unitFromHash(hashWords(0x5157A7C4ull, wi, li));
      const double kappa = keepWeight(lambda, u, fade);
      ws.lambda[li] = float(lambda);
      ws.scale[li] = float(kappa / lambda);
      if (kappa > 0.0) ++plan.kept;
      plan.minLambda = std::min(plan.minLambda, lambda);
    }
  }
  return plan;
}

}  // namespace wf
