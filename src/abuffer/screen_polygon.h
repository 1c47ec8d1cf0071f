// Convex polygons in screen space (pixels, y down) and what the A-buffer asks of them: exact
// area clipped to a pixel or a band of pixels, their edges, their depth.
#pragma once

#include "abuffer/coverage_mask.h"

#include <algorithm>
#include <cmath>

namespace wf {

/// A convex polygon with at most kMaxVertices vertices (a 16-gon disc, or a clipped triangle,
/// plus the four sides of a clip rectangle).
struct ScreenPolygon {
  static constexpr int kMaxVertices = 40;
  int count = 0;
  double x[kMaxVertices], y[kMaxVertices];

  void add(double px, double py) {
    if (count < kMaxVertices) {
      x[count] = px;
      y[count] = py;
      ++count;
    }
  }
  /// Signed area by the shoelace formula over (x, y) taken as plain coordinates.
  double signedArea() const {
    double s = 0;
    for (int i = 0, j = count - 1; i < count; j = i++) s += x[j] * y[i] - x[i] * y[j];
    return 0.5 * s;
  }
  double area() const { return std::abs(signedArea()); }
  /// Area-weighted centroid (falls back to the vertex mean for a degenerate polygon).
  void centroid(double& cx, double& cy) const {
    double a = 0, sx = 0, sy = 0;
    for (int i = 0, j = count - 1; i < count; j = i++) {
      const double cr = x[j] * y[i] - x[i] * y[j];
      a += cr;
      sx += (x[j] + x[i]) * cr;
      sy += (y[j] + y[i]) * cr;
    }
    if (std::abs(a) > 1e-300) {
      cx = sx / (3 * a);
      cy = sy / (3 * a);
      return;
    }
    cx = cy = 0;
    for (int i = 0; i < count; ++i) {
      cx += x[i] / count;
      cy += y[i] / count;
    }
  }
  /// Removes consecutive duplicate vertices (they would make zero edges).
  void removeDuplicates() {
    int n = 0;
    for (int i = 0; i < count; ++i) {
      if (n > 0 && x[i] == x[n - 1] && y[i] == y[n - 1]) continue;
      x[n] = x[i];
      y[n] = y[i];
      ++n;
    }
    while (n > 1 && x[n - 1] == x[0] && y[n - 1] == y[0]) --n;
    count = n;
  }
};

/// Clips `in` to the half-plane {axis coordinate >= value} (keepGreater) or {<= value};
/// the new vertices lie exactly on the line (their clipped coordinate is `value`).
inline void clipAxis(const ScreenPolygon& in, ScreenPolygon& out, bool alongX, double value,
                     bool keepGreater) {
  out.count = 0;
  const int n = in.count;
  if (n == 0) return;
  auto coord = [&](int i) { return alongX ? in.x[i] : in.y[i]; };
  auto inside = [&](int i) { return keepGreater ? coord(i) >= value : coord(i) <= value; };
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 == n ? 0 : i + 1;
    const bool ii = inside(i), ij = inside(j);
    if (ii) out.add(in.x[i], in.y[i]);
    if (ii != ij) {
      const double t = (value - coord(i)) / (coord(j) - coord(i));
      if (alongX) out.add(value, in.y[i] + t * (in.y[j] - in.y[i]));
      else out.add(in.x[i] + t * (in.x[j] - in.x[i]), value);
    }
  }
}

/// The pixel columns c0 ... c1 (inclusive; empty when c0 > c1) of [xmin, xmax] inside the tile
/// columns [tx0, tx1). Clamped in 64 bits before narrowing: a polygon may reach billions of
/// pixels off screen.
inline void pixelColumns(double xmin, double xmax, int tx0, int tx1, int& c0, int& c1) {
  c0 = int(std::clamp<std::int64_t>(floorToInt(std::max(xmin, -1e15)), tx0, tx1));
  c1 = int(std::clamp<std::int64_t>(ceilToInt(std::min(xmax, 1e15)) - 1, tx0 - 1, tx1 - 1));
}

/// Clips to the rectangle [x0, x1] x [y0, y1].
inline void clipRect(const ScreenPolygon& in, ScreenPolygon& out, double x0, double y0, double x1,
                     double y1) {
  ScreenPolygon a, b;
  clipAxis(in, a, true, x0, true);
  clipAxis(a, b, true, x1, false);
  clipAxis(b, a, false, y0, true);
  clipAxis(a, out, false, y1, false);
}

/// The polygon's edges as inside->=0 functions (the polygon must be convex, with duplicates
/// removed). Returns the number of edges written (0 for a degenerate polygon).
inline int polygonEdges(const ScreenPolygon& p, EdgeFunction* edges) {
  const double s = p.signedArea();
  if (!(std::abs(s) > 0.0)) return 0;
  int n = 0;
  for (int i = 0; i < p.count; ++i) {
    const int j = i + 1 == p.count ? 0 : i + 1;
    EdgeFunction e = EdgeFunction::through(p.x[i], p.y[i], p.x[j], p.y[j]);
    if (e.a == 0.0 && e.b == 0.0) continue;
    // through(p, q)(r) = cross(q - p, r - p): >= 0 inside when the signed area is positive.
    edges[n++] = s > 0 ? e : e.negated();
  }
  return n;
}

/// The turn at (xj, yj) from (xi, yi) to (xk, yk): 1 left, -1 right, 0 none (or NaN). isConvex
/// and set-up's mitre check (segmentPolygonConvex) share it, so that they round alike.
inline int turnSign(double xi, double yi, double xj, double yj, double xk, double yk) {
  const double cr = (xj - xi) * (yk - yj) - (yj - yi) * (xk - xj);
  return cr > 0 ? 1 : (cr < 0 ? -1 : 0);
}

/// Whether the polygon is convex (all turns one way; collinear turns allowed).
inline bool isConvex(const ScreenPolygon& p) {
  int sign = 0;
  for (int i = 0; i < p.count; ++i) {
    // i + 1 and i + 2 modulo the count without dividing (set-up asks this of every mitred
    // segment's polygon)
    int j = i + 1;
    if (j == p.count) j = 0;
    int k = j + 1;
    if (k == p.count) k = 0;
    const int s = turnSign(p.x[i], p.y[i], p.x[j], p.y[j], p.x[k], p.y[k]);
    if (s == 0) continue;
    if (sign == 0) sign = s;
    else if (s != sign) return false;
  }
  return true;
}

}  // namespace wf
