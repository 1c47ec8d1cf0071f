#include "scene/edge_visibility.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>

namespace wf {

namespace {

// The distance from p to the triangle a, a + e1, a + e2 (the closest point by the regions of the
// triangle's plane: a vertex, an edge, or the inside).
double distanceToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& e1, const glm::dvec3& e2) {
  const glm::dvec3 b = a + e1, c = a + e2;
  const glm::dvec3 ap = p - a;
  const double d1 = glm::dot(e1, ap), d2 = glm::dot(e2, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(ap);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(e1, bp), d4 = glm::dot(e2, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + e1 * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(e1, cp), d6 = glm::dot(e2, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + e2 * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = 1.0 / (va + vb + vc);
  return glm::length(p - (a + e1 * (vb * denom) + e2 * (vc * denom)));
}

}  // namespace

OcclusionGrid::OcclusionGrid(const Scene& scene, const Camera& camera, int width, int height)
    : view_(ViewTransform::make(withDepthRange(camera, scene), std::max(width, 1), std::max(height, 1))) {
  viewDir_ = -glm::transpose(view_.eyeFromWorld)[2];  // eye space looks down -z
  const double nearD = view_.nearPlane, farD = view_.farPlane;
  const double w = std::max(width, 1), h = std::max(height, 1);
  std::vector<glm::dvec4> boxes;  // screen boxes of the kept triangles (x0, y0, x1, y1)
  for (const SceneSurface& s : scene.surfaces) {
    const bool opaque = s.holdout || s.material < 0 || std::size_t(s.material) >= scene.materials.size() ||
                        scene.materials[std::size_t(s.material)].opacity >= 1.0f;
    if (!opaque) continue;
    const TriangleMesh& m = s.mesh;
    for (const glm::uvec3& t : m.triangles) {
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
      const glm::dvec3 p[3] = {m.positions[t.x], m.positions[t.y], m.positions[t.z]};
      const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
      // Degenerate or not finite: judged on the edges scaled to about 1 (no overflow at 1e200).
      const double sc = std::max(maxAbs(e1), maxAbs(e2));
      if (!(sc > 0) || !std::isfinite(sc) || !std::isfinite(maxAbs(p[0]))) continue;
      if (glm::cross(e1 / sc, e2 / sc) == glm::dvec3(0.0)) continue;
      // Only what lies between the near and the far plane can hide anything there (the renderer
      // clips the rest): the part in front of the near plane is binned by its screen box.
      glm::dvec3 q[3];
      double d[3];
      for (int k = 0; k < 3; ++k) q[k] = view_.toEye(p[k]), d[k] = -q[k].z;
      if (std::max({d[0], d[1], d[2]}) <= nearD || std::min({d[0], d[1], d[2]}) >= farD) continue;
      glm::dvec2 lo(INFINITY), hi(-INFINITY);
      auto addPoint = [&](const glm::dvec3& e) {
        const glm::dvec2 sp = view_.project(e);
        lo = glm::min(lo, sp), hi = glm::max(hi, sp);
      };
      for (int k = 0; k < 3; ++k) {
        const int j = (k + 1) % 3;
        if (d[k] >= nearD) addPoint(q[k]);
        if ((d[k] < nearD) != (d[j] < nearD)) addPoint(q[k] + (q[j] - q[k]) * ((nearD - d[k]) / (d[j] - d[k])));
      }
      if (!std::isfinite(lo.x + lo.y + hi.x + hi.y)) continue;
      if (hi.x < 0 || hi.y < 0 || lo.x > w || lo.y > h) continue;  // off the image: hides nothing seen
      a_.push_back(p[0]), e1_.push_back(e1), e2_.push_back(e2);
      const double longest = std::max({glm::length(e1), glm::length(e2), glm::length(e2 - e1)});
      const glm::dvec3 n = glm::cross(e1, e2);
      width_.push_back(glm::length(n) / longest);
      reach_.push_back(0.1 * longest);
      normal_.push_back(glm::normalize(n));
      boxes.push_back({lo.x, lo.y, hi.x, hi.y});
    }
  }
  const std::size_t n = a_.size();
  // Cells of about 8 triangles each, 4 to 64 pixels; coarser while the boxes would fill more than
  // 16 entries a triangle and a million (long slivers, fans: each box covers many cells).
  cell_ = std::clamp(std::sqrt(w * h * 8.0 / std::max<double>(double(n), 1.0)), 4.0, 64.0);
  auto cellRange = [&](const glm::dvec4& b, int& x0, int& y0, int& x1, int& y1) {
    x0 = std::clamp(int(std::floor(b.x / cell_)), 0, nx_ - 1), y0 = std::clamp(int(std::floor(b.y / cell_)), 0, ny_ - 1);
    x1 = std::clamp(int(std::floor(b.z / cell_)), 0, nx_ - 1), y1 = std::clamp(int(std::floor(b.w / cell_)), 0, ny_ - 1);
  };
  std::uint64_t total = 0;
  for (;;) {
    nx_ = std::max(1, int(std::ceil(w / cell_)));
    ny_ = std::max(1, int(std::ceil(h / cell_)));
    total = 0;
    for (const glm::dvec4& b : boxes) {
      int x0, y0, x1, y1;
      cellRange(b, x0, y0, x1, y1);
      total += std::uint64_t(x1 - x0 + 1) * std::uint64_t(y1 - y0 + 1);
    }
    if (total <= 16 * std::uint64_t(n) + 1000000 || (nx_ == 1 && ny_ == 1)) break;
    cell_ *= 2;
  }
  cellStart_.assign(std::size_t(nx_) * std::size_t(ny_) + 1, 0);
  for (const glm::dvec4& b : boxes) {
    int x0, y0, x1, y1;
    cellRange(b, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) ++cellStart_[std::size_t(y) * std::size_t(nx_) + std::size_t(x) + 1];
  }
  for (std::size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  cellItems_.resize(std::size_t(total));
  std::vector<std::uint64_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    int x0, y0, x1, y1;
    cellRange(boxes[i], x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) cellItems_[std::size_t(fill[std::size_t(y) * std::size_t(nx_) + std::size_t(x)]++)] = std::uint32_t(i);
  }
}

std::size_t OcclusionGrid::cellOf(const glm::dvec2& s) const {
  const int x = std::clamp(int(std::floor(s.x / cell_)), 0, nx_ - 1), y = std::clamp(int(std::floor(s.y / cell_)), 0, ny_ - 1);
  return std::size_t(y) * std::size_t(nx_) + std::size_t(x);
}

double OcclusionGrid::localWidth(const glm::dvec3& p) const {
  const glm::dvec3 q = view_.toEye(p);
  if (!(-q.z > view_.nearPlane)) return 0.0;
  const glm::dvec2 s = view_.project(q);
  if (!std::isfinite(s.x) || !std::isfinite(s.y)) return 0.0;
  const std::size_t c = cellOf(s);
  double width = 0.0;
  for (std::uint64_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
    const std::uint32_t i = cellItems_[std::size_t(k)];
    // The point's own surface: near the triangle (a tenth of its longest edge bounds the
    // tessellation's deviation) and grazing the ray (an occluder facing the viewer is not).
    const glm::dvec3 ray = view_.perspective ? glm::normalize(view_.eye - p) : viewDir_;
    if (width_[i] > width && std::abs(glm::dot(normal_[i], ray)) < 0.5 &&
        distanceToTriangle(p, a_[i], e1_[i], e2_[i]) <= reach_[i])
      width = width_[i];
  }
  return width;
}

bool OcclusionGrid::hidden(const glm::dvec3& p, double slack, std::size_t* tests, bool localSlack) const {
  const glm::dvec3 q = view_.toEye(p);
  const double d = -q.z;
  if (!(d > view_.nearPlane)) return false;  // (not seen either: the caller clips to the view)
  const glm::dvec2 s = view_.project(q);
  if (!std::isfinite(s.x) || !std::isfinite(s.y)) return false;
  if (localSlack) slack = std::max(slack, localWidth(p));
  // The ray from the point towards the viewer, as far as the near plane: to the eye, or
  // (orthographic) back along the view direction.
  glm::dvec3 dir;
  double reach;
  if (view_.perspective) {
    dir = view_.eye - p;
    const double len = glm::length(dir);
    dir /= len;
    reach = len * (d - view_.nearPlane) / d;
  } else {
    dir = -viewDir_;
    reach = d - view_.nearPlane;
  }
  const double minT = std::max(slack, 1e-7 * (view_.perspective ? glm::length(view_.eye - p) : std::max(1.0, maxAbs(p - view_.eye))));
  auto test = [&](std::uint32_t i) {
    // Moller-Trumbore in double, from p along dir: a hit at distance t in (minT, reach).
    const glm::dvec3 pv = glm::cross(dir, e2_[i]);
    const double det = glm::dot(e1_[i], pv);
    if (det == 0.0 || !std::isfinite(det)) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 tv = p - a_[i];
    const double u = glm::dot(tv, pv) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 qv = glm::cross(tv, e1_[i]);
    const double v = glm::dot(dir, qv) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(e2_[i], qv) * inv;
    return t > minT && t < reach;
  };
  const std::size_t c = cellOf(s);
  std::size_t n = 0;
  bool hit = false;
  for (std::uint64_t k = cellStart_[c]; k < cellStart_[c + 1] && !hit; ++k, ++n) hit = test(cellItems_[std::size_t(k)]);
  if (tests) *tests += n;
  return hit;
}

bool OcclusionGrid::clipToView(const glm::dvec3& p0, const glm::dvec3& p1, double& t0, double& t1) const {
  // Liang-Barsky on constraints linear in eye space: near <= d <= far, and the image rectangle
  // (perspective: its sides multiplied by d > 0, which the near constraint ensures).
  const glm::dvec3 a = view_.toEye(p0), b = view_.toEye(p1);
  const double W = double(view_.width), H = double(view_.height);
  t0 = 0.0, t1 = 1.0;
  auto clip = [&](double g0, double g1) {  // keep g(t) = g0 + (g1 - g0) t >= 0
    if (!std::isfinite(g0) || !std::isfinite(g1)) return false;
    if (g0 < 0 && g1 < 0) return false;
    if (g0 >= 0 && g1 >= 0) return true;
    const double t = g0 / (g0 - g1);
    if (g0 < 0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
    return t0 <= t1;
  };
  auto g = [&](const glm::dvec3& e, int which) {
    const double d = -e.z;
    const double f = view_.perspective ? view_.focal : view_.orthoScale, s = view_.perspective ? d : 1.0;
    switch (which) {
      case 0: return d - view_.nearPlane;
      case 1: return view_.farPlane - d;
      case 2: return f * e.x + view_.cx * s;        // screen x >= 0
      case 3: return (W - view_.cx) * s - f * e.x;  // screen x <= W
      case 4: return view_.cy * s - f * e.y;        // screen y >= 0
      default: return f * e.y + (H - view_.cy) * s;  // screen y <= H
    }
  };
  for (int k = 0; k < 6; ++k)
    if (!clip(g(a, k), g(b, k))) return false;
  return t0 < t1;
}

VisibleLines splitByVisibility(const PolylineSet& lines, const OcclusionGrid& grid, const VisibilityOptions& o,
                               VisibilityStats& stats) {
  VisibleLines out;
  const ViewTransform& view = grid.view();
  auto screen = [&](const glm::dvec3& p) { return view.project(view.toEye(p)); };
  auto seen = [&](const glm::dvec3& p) {
    ++stats.samples;
    return !grid.hidden(p, o.slack, &stats.rayTests, o.localSlack);
  };
  std::vector<glm::dvec3> piece;
  bool pieceSeen = true;
  std::uint32_t src = 0;
  auto flush = [&] {
    if (piece.size() >= 2) {
      out.lines.add(piece);
      out.source.push_back(src);
      out.visible.push_back(std::uint8_t(pieceSeen));
    }
    piece.clear();
  };
  // Continues the current piece to p, which starts a stretch seen or not.
  auto to = [&](const glm::dvec3& p, bool s) {
    if (piece.empty()) {
      pieceSeen = s;
      piece.push_back(p);
      return;
    }
    if (piece.back() != p) piece.push_back(p);
    if (s != pieceSeen) {
      const glm::dvec3 last = piece.back();
      flush();
      ++stats.splits;
      pieceSeen = s;
      piece.push_back(last);
    }
  };
  for (std::size_t k = 0; k < lines.polylineCount(); ++k) {
    src = std::uint32_t(k);
    const std::uint32_t a = lines.starts[k], b = std::min<std::uint32_t>(lines.starts[k + 1], std::uint32_t(lines.points.size()));
    for (std::uint32_t i = a; i + 1 < b; ++i) {
      const glm::dvec3 p0 = lines.points[i], p1 = lines.points[i + 1];
      if (!std::isfinite(maxAbs(p0) + maxAbs(p1))) {
        flush();
        continue;
      }
      double c0, c1;
      if (!grid.clipToView(p0, p1, c0, c1)) {
        to(p0, false);  // outside the view: not seen
        to(p1, false);
        continue;
      }
      auto at = [&](double t) { return p0 + (p1 - p0) * t; };
      if (c0 > 0) to(p0, false);
      // The part in the view, sampled by its own length on the screen.
      const glm::dvec3 q0 = at(c0), q1 = at(c1);
      const double px = glm::length(screen(q1) - screen(q0));
      const double count = std::isfinite(px) ? std::ceil(px / o.samplePx) : 1.0;
      const int n = int(std::clamp(count, 1.0, double(1 << 20)));
      bool prev = seen(q0);
      to(q0, prev);
      for (int j = 1; j <= n; ++j) {
        const double s0 = c0 + (c1 - c0) * (j - 1) / n, s1 = c0 + (c1 - c0) * j / n;
        const bool now = seen(at(s1));
        if (now == prev) continue;
        // Bisect between s0 and s1 to the tolerance on the screen.
        double lo = s0, hi = s1;
        const double pxPerT = std::isfinite(px) && c1 > c0 ? px / (c1 - c0) : 1e6;
        for (int it = 0; it < 60 && (hi - lo) * pxPerT > o.tolerancePx; ++it) {
          const double mid = 0.5 * (lo + hi);
          (seen(at(mid)) == prev ? lo : hi) = mid;
        }
        to(at(0.5 * (lo + hi)), now);
        prev = now;
      }
      if (c1 < 1) to(q1, false);
      to(p1, piece.empty() ? false : pieceSeen);
    }
    flush();
  }
  for (std::size_t k = 0; k < out.lines.polylineCount(); ++k) {
    double len = 0;
    for (std::uint32_t i = out.lines.starts[k] + 1; i < out.lines.starts[k + 1]; ++i)
      len += glm::length(out.lines.points[i] - out.lines.points[i - 1]);
    (out.visible[k] ? stats.visibleLength : stats.hiddenLength) += len;
  }
  return out;
}

}  // namespace wf
