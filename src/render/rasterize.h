// Stage "fragments" (render/pipeline.h): one convex screen polygon into the pixels of one tile,
// with each pixel's exact covered area, coverage mask and depth range.
#pragma once

#include "abuffer/coverage_mask.h"
#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

namespace wf {

// Rasterises one convex screen polygon into the pixels of one tile: for every pixel it touches,
// the exact covered area, the coverage mask from its edges and the depth range over the pixel.
//
// Area without clipping: for a closed contour, the integral of min(x, X) dy is the area of the
// polygon left of the line x = X (for a convex polygon each horizontal line meets the contour
// twice, and min() traces the clipped contour). Restricted to the row's band of y, each edge
// contributes a closed form, and a pixel's area is the difference of that integral at its two
// sides: the areas of the pixels of a row telescope to the band's area exactly, so adjacent
// pixels neither lose nor double any of it.
template <class OccludedRow, class Occluded, class Emit>
void rasterizePolygon(const PreparedScene& ps, const Primitive& prim, int tx0, int ty0, int tx1,
                      int ty1, const MaskLayout& layout, OccludedRow&& occludedRow, Occluded&& occluded,
                      Emit&& emit) {
  const ScreenPolygon poly = screenPolygonOf(ps, prim);
  EdgeFunction edges[ScreenPolygon::kMaxVertices];
  const int edgeCount = polygonEdges(poly, edges);
  if (edgeCount < 3) return;
  const double orient = poly.signedArea() > 0 ? 1.0 : -1.0;
  double slopes[ScreenPolygon::kMaxVertices];
  for (int i = 0; i < poly.count; ++i) {
    const int j = i + 1 == poly.count ? 0 : i + 1;
    slopes[i] = poly.y[j] != poly.y[i] ? (poly.x[j] - poly.x[i]) / (poly.y[j] - poly.y[i]) : 0.0;
  }
  const int row0 = std::max(ty0, int(std::floor(prim.bbox[1])));
  const int row1 = std::min(ty1 - 1, int(std::ceil(prim.bbox[3])) - 1);
  struct SubEdge {
    double xa, ya, xb, yb;  // the edge's part inside the band, in contour order
    double invDx;           // 1 / (xb - xa), or 0 for a vertical edge
  };
  SubEdge sub[ScreenPolygon::kMaxVertices];
  // Integral over one sub-edge of min(x, X) dy, oriented.
  auto leftOf = [](const SubEdge& e, double X) {
    const double dy = e.yb - e.ya;
    const double lo = std::min(e.xa, e.xb), hi = std::max(e.xa, e.xb);
    if (X >= hi) return 0.5 * (e.xa + e.xb) * dy;
    if (X <= lo) return X * dy;
    const double s = (X - e.xa) * e.invDx;  // where the edge crosses x = X
    const double mean = e.xa < e.xb ? s * 0.5 * (e.xa + X) + (1.0 - s) * X : s * X + (1.0 - s) * 0.5 * (X + e.xb);
    return mean * dy;
  };
  for (int row = row0; row <= row1; ++row) {
    const double y0 = row, y1 = row + 1.0;
    int ns = 0;
    double xmin = 1e300, xmax = -1e300;
    for (int i = 0; i < poly.count; ++i) {
      const int j = i + 1 == poly.count ? 0 : i + 1;
      double xa = poly.x[i], ya = poly.y[i], xb = poly.x[j], yb = poly.y[j];
      const double lo = std::min(ya, yb), hi = std::max(ya, yb);
      if (hi <= y0 || lo >= y1 || ya == yb) continue;
      // Clip the edge to the band (its x at the band's lines, from the same formula both ways).
      const double slope = slopes[i];  // dx / dy of the edge, once per primitive
      auto xAt = [&](double y) { return xa + (y - ya) * slope; };
      const double ca = std::clamp(ya, y0, y1), cb = std::clamp(yb, y0, y1);
      const double xca = ca == ya ? xa : xAt(ca), xcb = cb == yb ? xb : xAt(cb);
      sub[ns++] = {xca, ca, xcb, cb, xcb != xca ? 1.0 / (xcb - xca) : 0.0};
      xmin = std::min({xmin, xca, xcb});
      xmax = std::max({xmax, xca, xcb});
    }
    if (ns < 2) continue;
    int c0, c1;
    pixelColumns(xmin, xmax, tx0, tx1, c0, c1);
    if (c0 > c1 || occludedRow(row, c0, c1, prim.zlo)) continue;
    std::int64_t spanLo[8], spanHi[8];  // the polygon's sample runs on this row's sample rows
    bool spansDone = false;              // computed at the row's first pixel that survives culling
    double left = 0;      // area of the band left of x = leftAt
    int leftAt = INT_MIN;
    for (int col = c0; col <= c1; ++col) {
      if (occluded(col, row, prim.zlo)) continue;  // before any arithmetic: most are hidden
      if (leftAt != col) {
        left = 0;
        for (int k = 0; k < ns; ++k) left += leftOf(sub[k], col);
        left *= orient;
      }
      double right = 0;
      for (int k = 0; k < ns; ++k) right += leftOf(sub[k], col + 1.0);
      right *= orient;
      const double area = std::clamp(right - left, 0.0, 1.0);
      left = right;
      leftAt = col + 1;
      if (!(area > 1e-12)) continue;
      PixelCoverage pc;
      pc.x = col;
      pc.y = row;
      // Depth over the pixel square (the plane at its corners), clamped to the primitive's.
      const double k00 = prim.depthKeyAt(col, row), k11 = prim.depthKeyAt(col + 1, row + 1);
      const double k10 = prim.depthKeyAt(col + 1, row), k01 = prim.depthKeyAt(col, row + 1);
      pc.keyMin = std::min({k00, k10, k01, k11});
      pc.keyMax = std::max({k00, k10, k01, k11});
      if (prim.zlo < prim.zhi) {
        const double near = ps.view.perspective ? pc.keyMax : pc.keyMin;
        if (occluded(col, row, std::clamp(ps.view.depthFromKey(near), double(prim.zlo), double(prim.zhi)))) continue;
      }
      pc.area = area;
      if (!spansDone) {
        for (int j = 0; j < layout.h; ++j)
          sampleRowSpan(edges, edgeCount, layout, row + layout.sampleY(j), spanLo[j], spanHi[j]);
        spansDone = true;
      }
      pc.mask = 0;
      for (int j = 0; j < layout.h; ++j)
        pc.mask |= spanRowBits(spanLo[j], spanHi[j], std::int64_t(col) * layout.w, layout) << (j * layout.w);
      pc.cx = col + 0.5;
      pc.cy = row + 0.5;
      pc.subpixel = layout.samples() / 2;
      if (pc.mask == 0) {
        // Thinner than the sample spacing here: the stand-in subpixel and the shading point are
        // the centroid of the covered part (the rare slow path: clip to the pixel).
        ScreenPolygon cell;
        clipRect(poly, cell, col, row, col + 1.0, row + 1.0);
        if (cell.count >= 3) cell.centroid(pc.cx, pc.cy);
        const int si = std::clamp(int((pc.cx - col) * layout.w), 0, layout.w - 1);
        const int sj = std::clamp(int((pc.cy - row) * layout.h), 0, layout.h - 1);
        pc.subpixel = sj * layout.w + si;
      }
      emit(pc);
    }
  }
}

inline void depthRange(const PreparedScene& ps, const Primitive& prim, const PixelCoverage& pc,
                float& zmin, float& zmax, float& zkey) {
  // Depths from the screen-linear key, extrapolated over the pixel square (the near end is the
  // larger key under perspective, 1/d, and the smaller one under orthographic, d).
  const ViewTransform& v = ps.view;
  double a = v.depthFromKey(v.perspective ? pc.keyMax : pc.keyMin);
  double b = v.depthFromKey(v.perspective ? pc.keyMin : pc.keyMax);
  a = std::clamp(a, double(prim.zlo), double(prim.zhi));
  b = std::clamp(b, double(prim.zlo), double(prim.zhi));
  if (a > b) std::swap(a, b);
  const double c = std::clamp(v.depthFromKey(prim.depthKeyAt(pc.cx, pc.cy)), a, b);
  zmin = float(a);
  zmax = float(b);
  zkey = float(c);
}

}  // namespace wf
