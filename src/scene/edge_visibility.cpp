#include "scene/edge_visibility.h"

#include <algorithm>
#include <cmath>

namespace wf {

OcclusionGrid::OcclusionGrid(const Scene& scene, const Camera& camera, int width, int height)
    : view_(ViewTransform::make(camera, std::max(width, 1), std::max(height, 1))) {
  viewDir_ = glm::normalize(camera.target - camera.eye);
  for (const SceneSurface& s : scene.surfaces) {
    const bool opaque = s.holdout || s.material < 0 || std::size_t(s.material) >= scene.materials.size() ||
                        scene.materials[std::size_t(s.material)].opacity >= 1.0f;
    if (!opaque) continue;
    const TriangleMesh& m = s.mesh;
    for (const glm::uvec3& t : m.triangles) {
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
      const glm::dvec3 p0 = m.positions[t.x], p1 = m.positions[t.y], p2 = m.positions[t.z];
      const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
      const double area = glm::length(glm::cross(e1, e2));
      if (!(area > 0) || !std::isfinite(area)) continue;
      a_.push_back(p0), e1_.push_back(e1), e2_.push_back(e2);
    }
  }
  const std::size_t n = a_.size();
  // Cells of about 8 triangles each over the image, 4 to 64 pixels.
  const double w = std::max(width, 1), h = std::max(height, 1);
  cell_ = std::clamp(std::sqrt(w * h * 8.0 / std::max<double>(double(n), 1.0)), 4.0, 64.0);
  nx_ = std::max(1, int(std::ceil(w / cell_)));
  ny_ = std::max(1, int(std::ceil(h / cell_)));
  // Screen boxes; a triangle with a corner at or behind the eye plane goes everywhere.
  std::vector<glm::ivec4> boxes(n);
  std::vector<std::uint32_t> counts(std::size_t(nx_) * std::size_t(ny_) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    bool ok = true;
    for (const glm::dvec3& p : {a_[i], a_[i] + e1_[i], a_[i] + e2_[i]}) {
      const glm::dvec3 q = view_.toEye(p);
      if (view_.perspective && !(-q.z > 0)) ok = false;
      const glm::dvec2 s = ok ? view_.project(q) : glm::dvec2(0.0);
      if (!std::isfinite(s.x) || !std::isfinite(s.y)) ok = false;
      lo = glm::min(lo, s), hi = glm::max(hi, s);
    }
    if (!ok) {
      boxes[i] = glm::ivec4(-1);
      everywhere_.push_back(std::uint32_t(i));
      continue;
    }
    auto cx = [&](double x) { return std::clamp(int(std::floor(x / cell_)), 0, nx_ - 1); };
    auto cy = [&](double y) { return std::clamp(int(std::floor(y / cell_)), 0, ny_ - 1); };
    boxes[i] = glm::ivec4(cx(lo.x), cy(lo.y), cx(hi.x), cy(hi.y));
    for (int y = boxes[i].y; y <= boxes[i].w; ++y)
      for (int x = boxes[i].x; x <= boxes[i].z; ++x) ++counts[std::size_t(y) * std::size_t(nx_) + std::size_t(x)];
  }
  cellStart_.assign(counts.size(), 0);
  for (std::size_t c = 1; c < counts.size(); ++c) cellStart_[c] = cellStart_[c - 1] + counts[c - 1];
  cellItems_.resize(cellStart_.back());
  std::vector<std::uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (boxes[i].x < 0) continue;
    for (int y = boxes[i].y; y <= boxes[i].w; ++y)
      for (int x = boxes[i].x; x <= boxes[i].z; ++x) cellItems_[fill[std::size_t(y) * std::size_t(nx_) + std::size_t(x)]++] = std::uint32_t(i);
  }
}

bool OcclusionGrid::hidden(const glm::dvec3& p, std::size_t* tests) const {
  const glm::dvec3 q = view_.toEye(p);
  if (view_.perspective && !(-q.z > 0)) return false;  // behind the eye: not seen, not hidden
  const glm::dvec2 s = view_.project(q);
  if (!std::isfinite(s.x) || !std::isfinite(s.y)) return false;
  // The ray from the point towards the viewer: to the eye, or (orthographic) back along the
  // view direction to beyond everything.
  glm::dvec3 dir;
  double reach;
  if (view_.perspective) {
    dir = view_.eye - p;
    reach = glm::length(dir);
    dir /= reach;
  } else {
    dir = -viewDir_;
    reach = INFINITY;
  }
  const double slack = 1e-7 * (view_.perspective ? reach : std::max(1.0, glm::length(p - view_.eye)));
  auto test = [&](std::uint32_t i) {
    // Moller-Trumbore in double, from p along dir: a hit at distance t in (slack, reach).
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
    return t > slack && t < reach;
  };
  std::size_t n = 0;
  bool hit = false;
  for (std::uint32_t i : everywhere_) {
    ++n;
    if ((hit = test(i))) break;
  }
  if (!hit) {
    const int x = std::clamp(int(std::floor(s.x / cell_)), 0, nx_ - 1), y = std::clamp(int(std::floor(s.y / cell_)), 0, ny_ - 1);
    const std::size_t c = std::size_t(y) * std::size_t(nx_) + std::size_t(x);
    for (std::uint32_t k = cellStart_[c]; k < cellStart_[c + 1] && !hit; ++k, ++n) hit = test(cellItems_[k]);
  }
  if (tests) *tests += n;
  return hit;
}

VisibleLines splitByVisibility(const PolylineSet& lines, const OcclusionGrid& grid, const VisibilityOptions& o,
                               VisibilityStats& stats) {
  VisibleLines out;
  const ViewTransform& view = grid.view();
  auto screen = [&](const glm::dvec3& p) {
    const glm::dvec3 q = view.toEye(p);
    return view.perspective && !(-q.z > 0) ? glm::dvec2(NAN) : view.project(q);
  };
  auto isHidden = [&](const glm::dvec3& p) {
    ++stats.samples;
    return grid.hidden(p, &stats.rayTests);
  };
  std::vector<glm::dvec3> piece;
  bool pieceVisible = true;
  auto flush = [&](std::uint32_t src) {
    if (piece.size() >= 2) {
      out.lines.add(piece);
      out.source.push_back(src);
      out.visible.push_back(std::uint8_t(pieceVisible));
    }
    piece.clear();
  };
  for (std::size_t k = 0; k < lines.polylineCount(); ++k) {
    const std::uint32_t src = std::uint32_t(k);
    const std::uint32_t a = lines.starts[k], b = std::min<std::uint32_t>(lines.starts[k + 1], std::uint32_t(lines.points.size()));
    for (std::uint32_t i = a; i + 1 < b; ++i) {
      const glm::dvec3 p0 = lines.points[i], p1 = lines.points[i + 1];
      if (!std::isfinite(p0.x + p0.y + p0.z + p1.x + p1.y + p1.z)) {
        flush(src);
        continue;
      }
      if (piece.empty()) {
        pieceVisible = !isHidden(p0);
        piece.push_back(p0);
      }
      const double px = glm::length(screen(p1) - screen(p0));
      const int n = std::isfinite(px) ? std::clamp(int(std::ceil(px / o.samplePx)), 1, 1 << 20) : 64;
      for (int j = 1; j <= n; ++j) {
        const double t0 = double(j - 1) / n, t1 = double(j) / n;
        const bool vis = !isHidden(p0 + (p1 - p0) * t1);
        if (vis == pieceVisible) continue;
        // Bisect between t0 and t1 to the tolerance on the screen.
        double lo = t0, hi = t1;
        for (int it = 0; it < 60 && (hi - lo) * (std::isfinite(px) ? px : 1e6) > o.tolerancePx; ++it) {
          const double mid = 0.5 * (lo + hi);
          (!isHidden(p0 + (p1 - p0) * mid) == pieceVisible ? lo : hi) = mid;
        }
        const glm::dvec3 cut = p0 + (p1 - p0) * (0.5 * (lo + hi));
        piece.push_back(cut);
        flush(src);
        ++stats.splits;
        piece.push_back(cut);
        pieceVisible = vis;
      }
      piece.push_back(p1);
    }
    flush(src);
  }
  // Lengths by piece.
  for (std::size_t k = 0; k < out.lines.polylineCount(); ++k) {
    double len = 0;
    for (std::uint32_t i = out.lines.starts[k] + 1; i < out.lines.starts[k + 1]; ++i) len += glm::length(out.lines.points[i] - out.lines.points[i - 1]);
    (out.visible[k] ? stats.visibleLength : stats.hiddenLength) += len;
  }
  return out;
}

}  // namespace wf
