// Bounds of a scene's geometry (what the camera frames and the near / far planes enclose).
//
// Dense fur is millions of points, visited twice (the box, then the radius about its centre):
// in parallel over runs of the points and of the triangles. The result is the serial pass's to
// the bit for any thread count: minimum and maximum round nothing, and the one case where the
// order could show, -0 against +0 (equal: glm::min and max keep the first), keeps the serial
// order, since tbb::parallel_reduce joins each left part with the part to its right (it asks for
// associativity, not commutativity).
#include "render/scene.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace wf {

namespace {

// A run of the scene's points: polyline points [begin, end) of one wire (`points`), or the
// vertices of triangles [begin, end) of one surface (`surface`; a vertex once per triangle that
// uses it, indices past the positions skipped). The other pointer is null.
struct PointRun {
  const SceneSurface* surface;
  const glm::dvec3* points;
  size_t begin, end;
};

template <class F>
void visitRun(const PointRun& r, F&& f) {
  if (!r.surface) {
    for (size_t k = r.begin; k < r.end; ++k) f(r.points[k]);
    return;
  }
  const TriangleMesh& m = r.surface->mesh;
  const size_t n = m.positions.size();
  for (size_t t = r.begin; t < r.end; ++t)
    for (int k = 0; k < 3; ++k)
      if (m.triangles[t][k] < n) f(m.positions[m.triangles[t][k]]);
}

// The scene's points in runs of at most kRun items, in scene order.
std::vector<PointRun> pointRuns(const Scene& scene) {
  constexpr size_t kRun = 1 << 15;
  std::vector<PointRun> runs;
  for (const SceneSurface& s : scene.surfaces)
    for (size_t b = 0; b < s.mesh.triangles.size(); b += kRun)
      runs.push_back({&s, nullptr, b, std::min(b + kRun, s.mesh.triangles.size())});
  for (const SceneWire& w : scene.wires)
    for (size_t b = 0; b < w.lines.points.size(); b += kRun)
      runs.push_back({nullptr, w.lines.points.data(), b, std::min(b + kRun, w.lines.points.size())});
  return runs;
}

// reduce(identity, visit each point of a run into the value, join two values) over all runs.
template <class T, class Visit, class Join>
T reduceRuns(const std::vector<PointRun>& runs, T identity, Visit&& visit, Join&& join) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, runs.size()), identity,
      [&](const tbb::blocked_range<size_t>& r, T v) {
        for (size_t i = r.begin(); i != r.end(); ++i) visitRun(runs[i], [&](const glm::dvec3& p) { visit(v, p); });
        return v;
      },
      join);
}

struct Box {
  glm::dvec3 lo{1e300}, hi{-1e300};
  bool any = false;
};

Box boundsOf(const std::vector<PointRun>& runs) {
  return reduceRuns(
      runs, Box{},
      [](Box& v, const glm::dvec3& p) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
        v.lo = glm::min(v.lo, p);
        v.hi = glm::max(v.hi, p);
        v.any = true;
      },
      [](const Box& a, const Box& c) { return Box{glm::min(a.lo, c.lo), glm::max(a.hi, c.hi), a.any || c.any}; });
}

}  // namespace

bool Scene::bounds(glm::dvec3& lo, glm::dvec3& hi) const {
  const Box b = boundsOf(pointRuns(*this));
  lo = b.lo;
  hi = b.hi;
  return b.any;
}

bool Scene::boundingSphere(glm::dvec3& centre, double& radius) const {
  const std::vector<PointRun> runs = pointRuns(*this);
  const Box b = boundsOf(runs);
  if (!b.any) return false;
  centre = 0.5 * b.lo + 0.5 * b.hi;
  const glm::dvec3 c = centre;
  const double r2 = reduceRuns(
      runs, 0.0,
      [&](double& v, const glm::dvec3& p) {
        const glm::dvec3 d = p - c;
        const double q = glm::dot(d, d);
        if (std::isfinite(q)) v = std::max(v, q);
      },
      [](double a, double e) { return std::max(a, e); });
  radius = std::sqrt(r2);
  return true;
}

}  // namespace wf
