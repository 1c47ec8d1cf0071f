#include "surface/mesh_edges.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/gtc/type_precision.hpp>

namespace wf {
namespace {

struct HalfEdge {
  std::uint32_t a, b;    // welded vertex ids, a < b
  std::uint32_t tri;     // triangle index into `normals`
  bool forward;          // the triangle runs a -> b
};

}  // namespace

ClassifiedEdges classifyMeshEdges(const TriangleMesh& mesh, const EdgeSelection& selection) {
  std::vector<std::uint32_t> starts(mesh.triangles.size() + 1), ids(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    starts[t + 1] = std::uint32_t(3 * (t + 1));
    for (int k = 0; k < 3; ++k) ids[3 * t + std::size_t(k)] = mesh.triangles[t][k];
  }
  return classifyPolygonEdges(mesh.positions, starts, ids, selection);
}

ClassifiedEdges classifyPolygonEdges(const std::vector<glm::dvec3>& positions, const std::vector<std::uint32_t>& starts,
                                     const std::vector<std::uint32_t>& ids, const EdgeSelection& selection) {
  ClassifiedEdges out;
  // Weld vertices within 1e-9 of the mesh's size of each other (in each coordinate) (a tessellation's seam computes
  // the same point twice, cos(2 pi) != 1): a hash grid of that cell size, the 27 cells around
  // each vertex searched, vertices taken in index order so that the first one within reach
  // stands for the rest. The size is the largest extent of the vertices the polygons use (a stray
  // unused vertex far away does not weld the mesh into a point); no overflow up to 1e308.
  const std::size_t nv = positions.size();
  std::vector<std::uint32_t> weld(nv);
  std::vector<char> used(nv, 0);
  for (std::uint32_t id : ids)
    if (id < nv) used[id] = 1;
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (std::size_t i = 0; i < nv; ++i)
    if (used[i] && std::isfinite(maxAbs(positions[i]))) lo = glm::min(lo, positions[i]), hi = glm::max(hi, positions[i]);
  const double size = lo.x <= hi.x ? std::max({hi.x / 2 - lo.x / 2, hi.y / 2 - lo.y / 2, hi.z / 2 - lo.z / 2}) * 2 : 0.0;
  const double eps = size > 0 && std::isfinite(size) ? 1e-9 * size : 0.0;
  struct KeyHash {
    std::size_t operator()(const glm::i64vec3& k) const {
      return std::size_t(k.x * 73856093LL) ^ std::size_t(k.y * 19349663LL) ^ std::size_t(k.z * 83492791LL);
    }
  };
  std::unordered_map<glm::i64vec3, std::vector<std::uint32_t>, KeyHash> cells;
  for (std::size_t i = 0; i < nv; ++i) {
    const glm::dvec3& p = positions[i];
    weld[i] = std::uint32_t(i);
    if (!used[i] || !std::isfinite(maxAbs(p))) continue;
    // (eps 0: all used vertices are one point, or the size overflowed: exact matches only, in
    // one cell where the first vertex answers at once.)
    glm::i64vec3 key(0);
    if (eps > 0)
      for (int c = 0; c < 3; ++c) key[c] = std::int64_t(std::clamp(std::floor(p[c] / eps - lo[c] / eps), -1e18, 1e18));
    std::uint32_t best = std::uint32_t(i);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells.find(key + glm::i64vec3(dx, dy, dz));
          if (it == cells.end()) continue;
          for (std::uint32_t j : it->second)
            if (maxAbs(positions[j] - p) <= eps) {
              best = std::min(best, weld[j]);
              break;  // the first within reach in this cell (index order)
            }
        }
    weld[i] = best;
    cells[key].push_back(std::uint32_t(i));
  }

  std::vector<HalfEdge> halves;
  std::vector<glm::dvec3> normals;
  halves.reserve(ids.size());
  std::vector<std::uint32_t> w;
  for (std::size_t f = 0; f + 1 < starts.size(); ++f) {
    const std::uint32_t a0 = starts[f], a1 = std::min<std::uint32_t>(starts[f + 1], std::uint32_t(ids.size()));
    if (a1 < a0 + 3) continue;
    bool ok = true;
    for (std::uint32_t k = a0; k < a1 && ok; ++k) ok = ids[k] < nv;
    if (!ok) continue;
    // Welded, a polygon must keep all its corners distinct (a sliver whose two corners weld
    // together is no polygon: its edges would count twice). Repeated neighbours are one corner
    // (a quad with a collapsed edge at a pole is a triangle).
    w.clear();
    for (std::uint32_t k = a0; k < a1; ++k)
      if (w.empty() || w.back() != weld[ids[k]]) w.push_back(weld[ids[k]]);
    while (w.size() > 1 && w.back() == w.front()) w.pop_back();
    if (w.size() < 3) continue;
    std::vector<std::uint32_t> sorted = w;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
    // Newell's normal about the first vertex, on edges scaled to about 1 (no cancellation far
    // from the origin, no overflow or underflow at 1e+-150 and beyond): exact for planar
    // polygons, the best plane's for the rest.
    const glm::dvec3 o = positions[ids[a0]];
    double sc = 0;
    for (std::uint32_t k = a0 + 1; k < a1; ++k) sc = std::max(sc, maxAbs(positions[ids[k]] - o));
    if (!(sc > 0) || !std::isfinite(sc)) continue;
    glm::dvec3 n(0.0);
    for (std::uint32_t k = a0 + 1; k + 1 < a1; ++k)
      n += glm::cross((positions[ids[k]] - o) / sc, (positions[ids[k + 1]] - o) / sc);
    const double len = glm::length(n);
    if (!(len > 0) || !std::isfinite(len)) continue;
    const std::uint32_t tri = std::uint32_t(normals.size());
    normals.push_back(n / len);
    for (std::size_t k = 0; k < w.size(); ++k) {
      const std::uint32_t a = w[k], b = w[(k + 1) % w.size()];
      if (a == b) continue;
      halves.push_back({std::min(a, b), std::max(a, b), tri, a < b});
    }
  }
  std::stable_sort(halves.begin(), halves.end(),
                   [](const HalfEdge& x, const HalfEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });

  // One entry per edge: its class and angle.
  struct Edge {
    std::uint32_t a, b;
    EdgeClass cls;
    float angle;
  };
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < halves.size();) {
    std::size_t j = i + 1;
    while (j < halves.size() && halves[j].a == halves[i].a && halves[j].b == halves[i].b) ++j;
    const std::size_t n = j - i;
    Edge e{halves[i].a, halves[i].b, EdgeClass::Boundary, std::numeric_limits<float>::quiet_NaN()};
    if (n == 2) {
      // Consistently oriented neighbours run the edge in opposite directions; if they run it
      // the same way, one of them is flipped and its normal is turned back for the comparison.
      const glm::dvec3 n0 = normals[halves[i].tri];
      const glm::dvec3 n1 = halves[i].forward != halves[i + 1].forward ? normals[halves[i + 1].tri] : -normals[halves[i + 1].tri];
      // The angle from atan2 of |cross| and dot: accurate near 0 and 180, unlike acos.
      const double angle = std::atan2(glm::length(glm::cross(n0, n1)), glm::dot(n0, n1)) * (180.0 / 3.14159265358979323846);
      e.angle = float(angle);
      e.cls = EdgeSelection::byAngle(angle, selection.featureAngle);
    } else if (n > 2) {
      e.cls = EdgeClass::NonManifold;
    }
    ++out.counts[std::size_t(e.cls)];
    if (selection.keeps(e.cls, e.angle)) edges.push_back(e);
    i = j;
  }

  // Chains: through a vertex where exactly two kept edges of one class meet. Incidence as a
  // sorted list of (vertex, edge) pairs.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> incident;
  incident.reserve(2 * edges.size());
  for (std::uint32_t k = 0; k < edges.size(); ++k) {
    incident.push_back({edges[k].a, k});
    incident.push_back({edges[k].b, k});
  }
  std::sort(incident.begin(), incident.end());
  auto around = [&](std::uint32_t v) {
    const auto lo = std::lower_bound(incident.begin(), incident.end(), std::make_pair(v, 0u));
    auto hi = lo;
    while (hi != incident.end() && hi->first == v) ++hi;
    return std::make_pair(lo, hi);
  };
  // The other edge through v that continues edge k, or -1.
  auto next = [&](std::uint32_t v, std::uint32_t k) -> long long {
    const auto [lo, hi] = around(v);
    if (hi - lo != 2) return -1;
    const std::uint32_t other = lo->second == k ? (lo + 1)->second : lo->second;
    return edges[other].cls == edges[k].cls ? (long long)(other) : -1;
  };
  std::vector<char> done(edges.size(), 0);
  std::vector<glm::dvec3> line;
  auto walk = [&](std::uint32_t k, std::uint32_t from) {
    line.assign(1, positions[from]);
    float worst = edges[k].angle;
    const EdgeClass cls = edges[k].cls;
    std::uint32_t v = from;
    for (long long e = k; e >= 0 && !done[std::size_t(e)];) {
      done[std::size_t(e)] = 1;
      const Edge& ed = edges[std::size_t(e)];
      v = ed.a == v ? ed.b : ed.a;
      line.push_back(positions[v]);
      worst = std::isnan(worst) || ed.angle > worst ? ed.angle : worst;
      e = next(v, std::uint32_t(e));
    }
    out.lines.add(line);
    out.classes.push_back(cls);
    out.angles.push_back(worst);
  };
  // Open chains first (from an end that does not continue), then closed loops.
  for (std::uint32_t k = 0; k < edges.size(); ++k) {
    if (done[k]) continue;
    if (next(edges[k].a, k) < 0) walk(k, edges[k].a);
    else if (next(edges[k].b, k) < 0) walk(k, edges[k].b);
  }
  for (std::uint32_t k = 0; k < edges.size(); ++k)
    if (!done[k]) walk(k, edges[k].a);
  return out;
}

}  // namespace wf
