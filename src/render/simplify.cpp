// Stage "simplification" (render/pipeline.h), before the primitives: stochastic simplification
// of aggregate detail (Cook, Halstead, Planck and Ryu 2007; RenderOptions::simplify).
//
// For each aggregate wire (fur), every hair is placed on a coarse grid of screen cells by its
// root, with its projected area (width times length, pixels). A cell's depth complexity is the
// hair area in it per pixel of the cell. Where that is at least minDepthComplexity (the hairs
// overlap: what a pixel shows is their aggregate, not any one of them) and a hair is thinner than
// targetWidth, its lambda is width / targetWidth: that fraction of the hairs around it is drawn,
// each widened by 1 / lambda, so that the expected projected area, and with it the expected
// coverage of any region (hairs placed independently: 1 - exp(-area density)), stays the same.
//
// Which hairs: u, a hash of the wire's and the hair's index, uniform in [0, 1). A hair is drawn
// with weight kappa = clamp((lambda + D/2 - u) / D, 0, 1) and width factor kappa / lambda: the
// expected weight is lambda, and as lambda changes with the view a hair fades in or out over a
// range D = fade * lambda of it instead of popping. The same hairs are kept frame after frame.
//
// Colours: the mean over n hairs in a pixel has a variance proportional to 1 / n; with lambda n
// of them it rises by 1 / lambda, so each hair's colour is pulled toward the wire's mean by
// sqrt(lambda) (Cook et al.'s contrast correction).
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

SimplificationPlan planSimplification(const Scene& scene, const ViewTransform& view, const SimplifyOptions& o) {
  SimplificationPlan plan;
  plan.wires.resize(scene.wires.size());
  if (!o.enabled) return plan;
  const double target = std::isfinite(o.targetWidth) ? std::clamp(o.targetWidth, 1e-3, 1e6) : 2.0;
  const double minComplexity = std::isfinite(o.minDepthComplexity) ? std::max(0.0, o.minDepthComplexity) : 4.0;
  const double fade = std::isfinite(o.fade) ? std::clamp(o.fade, 0.0, 1.0) : 0.25;
  // Cells of at least 32 pixels, at most 4,096 of them.
  const double cell = std::max(32.0, std::ceil(std::sqrt(double(view.width) * view.height / 4096.0)));
  const int cx = int(std::ceil(view.width / cell)), cy = int(std::ceil(view.height / cell));
  for (size_t wi = 0; wi < scene.wires.size(); ++wi) {
    const SceneWire& w = scene.wires[wi];
    const PolylineSet& L = w.lines;
    const size_t n = L.polylineCount();
    if (!w.aggregate || n == 0 || !(w.thickness > 0) || !std::isfinite(w.thickness)) continue;
    // Per hair: its cell (-1: not on screen) and its projected width and area.
    std::vector<std::int32_t> cellOf(n, -1);
    std::vector<float> width(n, 0.0f), area(n, 0.0f);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t li = r.begin(); li < r.end(); ++li) {
        const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
        if (b < a + 2) continue;
        const glm::dvec3 e0 = view.toEye(L.points[a]), e1 = view.toEye(L.points[b - 1]);
        const double d0 = -e0.z, d1 = -e1.z;
        if (!finite3(e0) || !finite3(e1) || !(d0 >= view.nearPlane) || !(d0 <= view.farPlane)) continue;
        const glm::dvec2 p0 = view.project(e0);
        const double wpx = w.thicknessInPixels ? w.thickness : w.thickness * view.pixelsPerWorld(d0);
        double len = 0.0;
        if (d1 >= view.nearPlane) len = glm::length(view.project(e1) - p0);
        if (!std::isfinite(wpx) || !std::isfinite(len) || !(p0.x >= 0 && p0.x < view.width && p0.y >= 0 && p0.y < view.height))
          continue;
        cellOf[li] = std::int32_t(int(p0.y / cell) * cx + int(p0.x / cell));
        width[li] = float(wpx);
        area[li] = float(wpx * std::max(len, wpx));
      }
    });
    // Depth complexity per cell (summed in hair order: the same for any thread count).
    std::vector<double> complexity(size_t(cx) * cy, 0.0);
    for (size_t li = 0; li < n; ++li)
      if (cellOf[li] >= 0) complexity[size_t(cellOf[li])] += area[li];
    for (double& c : complexity) c /= cell * cell;
    // The wire's mean colour (the contrast correction's centre).
    WireSimplification& ws = plan.wires[wi];
    if (L.colours.size() == L.points.size() && !L.colours.empty()) {
      glm::dvec3 sum(0.0);
      size_t count = 0;
      for (const glm::vec3& c : L.colours) {
        const glm::vec3 s = safeColour(c);
        sum += glm::dvec3(s), ++count;
      }
      ws.meanColour = glm::vec3(sum / double(count));
    }
    ws.scale.assign(n, 1.0f);
    ws.lambda.assign(n, 1.0f);
    for (size_t li = 0; li < n; ++li) {
      ++plan.hairs;
      double lambda = 1.0;
      if (cellOf[li] >= 0 && width[li] < target) {
        // Full simplification from twice the threshold down, none below it: no step where the
        // depth complexity crosses it.
        const double c = complexity[size_t(cellOf[li])];
        const double on = std::clamp((c - minComplexity) / std::max(minComplexity, 1e-9), 0.0, 1.0);
        lambda = 1.0 - on * (1.0 - std::max(double(width[li]) / target, 1.0 / 64.0));
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
