// Stage "fragments" (render/pipeline.h): one primitive's convex screen polygon into the pixels of
// one tile, with each pixel's exact covered area, coverage mask and depth range, in the order
// that lets hidden work stop early: a row is tested against what already hides it before its
// pixels are visited, a pixel before its area is computed, and its coverage mask before its
// depths and shading.
//
// Area without clipping: for a closed contour, the integral of min(x, X) dy is the area of the
// polygon left of the line x = X (for a convex polygon each horizontal line meets the contour
// twice, and min() traces the clipped contour). Restricted to the row's band of y, each edge
// contributes a closed form, and a pixel's area is the difference of that integral at its two
// sides: the areas of the pixels of a row telescope to the band's area exactly, so adjacent
// pixels neither lose nor double any of it. Pixels wholly inside the polygon (between the
// innermost points of its left and right sides in the band) are 1 without any of that.
#pragma once

#include "abuffer/coverage_mask.h"
#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>

namespace wf {

/// Depth of a triangle over screen rectangles: its screen-linear key plane, clamped to the
/// triangle's depth range.
struct TriangleDepth {
  const ViewTransform* view;
  double qa, qb, qc;
  double zlo, zhi;
  TriangleDepth(const ViewTransform& v, const TrianglePrim& t) : view(&v), qa(t.qa), qb(t.qb), qc(t.qc), zlo(t.zlo), zhi(t.zhi) {}
  double depthAt(double x, double y) const { return std::clamp(view->depthFromKey(qa * x + qb * y + qc), zlo, zhi); }
  /// The nearest depth over [x0, x1] x [y0, y1]: at the corner of the largest key (1/d) under
  /// perspective, of the smallest (d) when orthographic.
  double nearest(double x0, double y0, double x1, double y1) const {
    const bool big = view->perspective;
    return depthAt((qa > 0) == big ? x1 : x0, (qb > 0) == big ? y1 : y0);
  }
  double farthest(double x0, double y0, double x1, double y1) const {
    const bool big = view->perspective;
    return depthAt((qa > 0) == big ? x0 : x1, (qb > 0) == big ? y0 : y1);
  }
  /// Where the polygon may lie across rows [ya, yb]: false, the whole rectangle being rasterised.
  bool bandSpan(double, double, double&, double&) const { return false; }
  /// A pixel's nearest depth, as the rasteriser asks it before range().
  struct Near {
    double z;
  };
  Near pixelNearest(int col, int row) const { return {nearest(col, row, col + 1.0, row + 1.0)}; }
  void range(int col, int row, double cx, double cy, const Near& n, float& zmin, float& zmax, float& zkey) const {
    range(col, row, cx, cy, n.z, zmin, zmax, zkey);
  }
  /// The pixel's depth range and its depth at (cx, cy), given zNear = nearest(col, row, col + 1,
  /// row + 1) (the rasteriser's pixelNearest).
  void range(int col, int row, double cx, double cy, double zNear, float& zmin, float& zmax, float& zkey) const {
    const double a = zNear, b = farthest(col, row, col + 1.0, row + 1.0);
    zmin = float(a);
    zmax = float(b);
    zkey = float(std::clamp(depthAt(cx, cy), a, b));
  }
};

/// [a, b]: every value clamp(l, -w, w) takes for l in [llo, lhi] and w in [wlo, whi], 0 <= wlo
/// <= whi (the model clamps the offset across a wire to the half width where it is; over a
/// pixel that half width varies, and a pixel wholly to one side beyond it clamps to the
/// narrowest: clamping to the widest, as this did before, gave a tilt range that could miss it).
inline void clampedRange(double llo, double lhi, double wlo, double whi, double& a, double& b) {
  a = llo >= 0.0 ? std::min(llo, wlo) : std::max(llo, -whi);
  b = lhi <= 0.0 ? std::max(lhi, -wlo) : std::min(lhi, whi);
}

/// Depth of a wire segment over screen rectangles. Flat: the paper's polygon, its front plane (a
/// radius before the axis) bounding it from the near side, its axis from the far side. Round:
/// the axis taken up to `slide` pixels along itself, less the largest radius, bounds it from the
/// near side, and the same axis from the far side, both moved by the tilt across the wire
/// (SegmentTilt, zero when orthographic); in between lies the round surface (segmentDepthAt),
/// whose depth at the fragment's centroid orders it.
struct SegmentDepth {
  const ViewTransform* view;
  const SegmentPrim* seg;
  SegmentFrame frame;
  WireDepth model;
  double fa, fb, fc, flo, fhi;  // front key plane, its depth range
  double aa, ab, ac, alo, ahi;  // axis key plane, its depth range
  SegmentEndKeys keys;
  SegmentTilt tilt;
  /// `exact`: the wire's depth is its exact solid where a ray meets it (a hair in the round
  /// model: segmentUsesCapsule), the bounds grown to hold it.
  /// `widthInPixels`: ShaderSlot::widthInPixels (the solid's radius).
  SegmentDepth(const ViewTransform& v, const SegmentPrim& s, WireDepth m, bool exact = false, bool widthInPixels = false)
      : view(&v), seg(&s), frame(s), model(m), keys(v, s), tilt(v, s, frame) {
    const double kf0 = keys.front(0.0), kf1 = keys.front(1.0);
    const double ka0 = keys.axis(0.0), ka1 = keys.axis(1.0);
    fa = (kf1 - kf0) * frame.ux, fb = (kf1 - kf0) * frame.uy, fc = kf0 - fa * frame.ax - fb * frame.ay;
    aa = (ka1 - ka0) * frame.ux, ab = (ka1 - ka0) * frame.uy, ac = ka0 - aa * frame.ax - ab * frame.ay;
    const double f0 = v.depthFromKey(kf0), f1 = v.depthFromKey(kf1);
    flo = std::min(f0, f1), fhi = std::max(f0, f1);
    alo = std::min(double(s.d0), double(s.d1)), ahi = std::max(double(s.d0), double(s.d1));
    reach = segmentReach(s);
    rmax = std::max(double(s.r0), double(s.r1));
    slide = m == WireDepth::Round ? tilt.shiftBound(v, s, frame) * frame.length : 0.0;
    if (exact && m == WireDepth::Round) {
      capsule = WireCapsule(v, s, widthInPixels);
      if (capsule.valid) {
        // The model is within 0.03 radii of the solid along the body, farther from its ends
        // than endMargin (docs/abuffer.md, "The exact solid at the ends"): there the round range
        // holds the solid grown by kCapsuleSlack radii. Within the margin the far side reaches
        // the end's sphere (sphereFar), and wherever the solid gives the depth the near side is
        // also bounded by the solid alone (capsuleNearest).
        pad = kCapsuleSlack * capsule.radius();
        rmax = std::max(rmax, capsule.radius() + pad);
        endMargin = capsule.endMargin(s);
        const double tan2 = v.maxRayTan2(), sinRay = std::sqrt(tan2 / (1.0 + tan2));  // of the widest ray angle
        capsuleReach = wf::capsuleReach(v, capsule.radius(), std::min(double(s.d0), double(s.d1)));
        sphereFar0 = double(s.d0) + capsule.r0 * sinRay + pad;
        sphereFar1 = double(s.d1) + capsule.r1 * sinRay + pad;
        ballFar = capsule.radius() * sinRay + pad;
      }
    }
  }
  WireCapsule capsule;    // valid: the depth is the solid's where a ray meets it
  double pad = 0.0;       // the bounds' growth for the solid (kCapsuleSlack radii)
  double endMargin = 0.0; // pixels from either end within which the solid's end may show (WireCapsule::endMargin)
  double sphereFar0 = 0.0, sphereFar1 = 0.0;  // the farthest the end spheres' surfaces lie where rays enter them
  double ballFar = 0.0;  // the farthest a ray enters any of the solid's balls behind its centre (capsuleFarthest)
  double capsuleReach = 0.0;  // pixels: how far from a point of the solid the axis points within its radius project (capsuleNearest)
  /// Whether the solid may give a depth somewhere in the rectangle (the resolve's and the
  /// rasteriser's choice: WireCapsule::nearEnd).
  bool solidIn(double x0, double y0, double x1, double y1) const {
    if (!capsule.valid) return false;
    if (!(frame.length > 0) || endMargin == INFINITY) return true;
    const double tx0 = (x0 - frame.ax) * frame.ux, tx1 = (x1 - frame.ax) * frame.ux;
    const double ty0 = (y0 - frame.ay) * frame.uy, ty1 = (y1 - frame.ay) * frame.uy;
    const double m = endMargin + WireCapsule::kRangeSpread;
    return WireCapsule::nearP0(std::min(tx0, tx1) + std::min(ty0, ty1), frame.length, m) ||
           WireCapsule::nearP1(std::max(tx0, tx1) + std::max(ty0, ty1), frame.length, m);
  }
  /// A bound on the solid's depth over the rectangle from the solid alone: a point of it lies
  /// within its radius of an axis point, so no nearer than that point less the radius, and that
  /// point projects within capsuleReach pixels of it (the axis's nearest over the rectangle grown
  /// by that; the nearer end for a segment of no screen length). Whatever the model's depth radius
  /// (capped, ramped or end-on: WireCapsule::everywhere).
  double capsuleNearest(double x0, double y0, double x1, double y1) const {
    const double rc = capsule.radius() * (1.0 + kCapsuleSlack);
    if (!(frame.length > 0) || capsuleReach == INFINITY) return std::max(view->nearPlane, alo - rc);
    return std::max(view->nearPlane, axisNearestGrown(x0, y0, x1, y1, capsuleReach) - rc);
  }
  /// The far side of the same: where a ray first meets the solid it enters the ball of some
  /// axis point, no farther than that point's depth and ballFar, and the point projects within
  /// capsuleReach pixels (the axis's farthest over the rectangle grown by that). Along a hair
  /// seen nearly end-on, axis points well beyond the pixel's own part of the axis show in it.
  double capsuleFarthest(double x0, double y0, double x1, double y1) const {
    if (!(frame.length > 0) || capsuleReach == INFINITY) return ahi + ballFar;
    return axisFarthestGrown(x0, y0, x1, y1, capsuleReach) + ballFar;
  }
  double slide;  // how far along the axis (pixels) the round model takes its axis depth (SegmentTilt)
  double reach;  // how far the polygon lies from the axis (segmentReach)
  double rmax;   // the largest radius
  /// The x extent of the polygon across rows [ya, yb]: the part of the axis within the reach of
  /// those rows, widened by the reach.
  bool bandSpan(double ya, double yb, double& xl, double& xr) const {
    const double y0 = seg->p0.y, y1 = seg->p1.y, x0 = seg->p0.x, x1 = seg->p1.x;
    double ta = 0.0, tb = 1.0;
    if (y1 != y0) {
      double u = (ya - reach - y0) / (y1 - y0), w = (yb + reach - y0) / (y1 - y0);
      if (u > w) std::swap(u, w);
      ta = std::max(ta, u), tb = std::min(tb, w);
      if (!(ta <= tb)) {
        xl = 1.0, xr = 0.0;  // empty
        return true;
      }
    }
    const double xa = x0 + (x1 - x0) * ta, xb = x0 + (x1 - x0) * tb;
    xl = std::min(xa, xb) - reach, xr = std::max(xa, xb) + reach;
    return true;
  }
  /// The nearest depth over the rectangle: the paper's polygon's front plane (Flat); the axis
  /// where nearest, less the tilt, less the largest radius (Round: the radius is interpolated
  /// along the screen, the axis depth perspective-correctly, so the front plane would not bound it).
  double nearest(double x0, double y0, double x1, double y1) const {
    if (model == WireDepth::Round) {
      const double z = nearestFromAxis(nearestAxis(x0, y0, x1, y1));
      return solidIn(x0, y0, x1, y1) ? std::min(z, capsuleNearest(x0, y0, x1, y1)) : z;
    }
    const bool big = view->perspective;
    const double k = fa * ((fa > 0) == big ? x1 : x0) + fb * ((fb > 0) == big ? y1 : y0) + fc;
    return std::clamp(view->depthFromKey(k), flo, fhi);
  }
  /// The axis's nearest depth over the rectangle grown by `grow` pixels on every side (its key
  /// plane at the corner of the largest key under perspective, of the smallest when
  /// orthographic), and its farthest (the opposite corner).
  double axisNearestGrown(double x0, double y0, double x1, double y1, double grow) const {
    x0 -= grow, y0 -= grow, x1 += grow, y1 += grow;
    const bool big = view->perspective;
    const double k = aa * ((aa > 0) == big ? x1 : x0) + ab * ((ab > 0) == big ? y1 : y0) + ac;
    return std::clamp(view->depthFromKey(k), alo, ahi);
  }
  double axisFarthestGrown(double x0, double y0, double x1, double y1, double grow) const {
    x0 -= grow, y0 -= grow, x1 += grow, y1 += grow;
    const bool big = view->perspective;
    const double k = aa * ((aa > 0) == big ? x0 : x1) + ab * ((ab > 0) == big ? y0 : y1) + ac;
    return std::clamp(view->depthFromKey(k), alo, ahi);
  }
  /// The axis's nearest depth over the rectangle, where the round model may take it (grown by
  /// the slide along the axis).
  double nearestAxis(double x0, double y0, double x1, double y1) const { return axisNearestGrown(x0, y0, x1, y1, slide); }
  /// The farthest depth over the rectangle: the axis where farthest (Flat: the front plane lies
  /// before it), farther by the tilt (Round: the side of a wire towards the image centre).
  double farthest(double x0, double y0, double x1, double y1) const { return farthestFromAxis(farthestAxis(x0, y0, x1, y1)); }
  /// The round model's nearest() and either model's farthest() from the axis's nearest and
  /// farthest depths over the same rectangle.
  double nearestFromAxis(double axis) const { return std::max(view->nearPlane, axis * (1.0 - tilt.bound) - rmax); }
  double farthestFromAxis(double axis) const { return model == WireDepth::Round ? axis * (1.0 + tilt.bound) + pad : axis; }
  double farthestAxis(double x0, double y0, double x1, double y1) const { return axisFarthestGrown(x0, y0, x1, y1, slide); }
  /// A pixel's nearest depth (nearest() over it) and, for the round model, the axis's nearest
  /// depth it came from, which range() needs again.
  struct Near {
    double z;
    double axis;              ///< nearestAxis over the pixel (Round)
    double solid = INFINITY;  ///< capsuleNearest over the pixel where the solid may give its depth (solidIn)
  };
  Near pixelNearest(int col, int row) const {
    if (model != WireDepth::Round) return {nearest(col, row, col + 1.0, row + 1.0), 0.0};
    const double axis = nearestAxis(col, row, col + 1.0, row + 1.0);
    const double solid = solidIn(col, row, col + 1.0, row + 1.0) ? capsuleNearest(col, row, col + 1.0, row + 1.0) : INFINITY;
    return {std::min(nearestFromAxis(axis), solid), axis, solid};
  }
  /// range() given only zNear = nearest(col, row, col + 1, row + 1): the axis's nearest depth is
  /// formed again (the rasteriser passes pixelNearest's instead; the same values).
  void range(int col, int row, double cx, double cy, double zNear, float& zmin, float& zmax, float& zkey) const {
    const bool solid = model == WireDepth::Round && solidIn(col, row, col + 1.0, row + 1.0);
    const Near n{zNear, model == WireDepth::Round ? nearestAxis(col, row, col + 1.0, row + 1.0) : 0.0,
                 solid ? capsuleNearest(col, row, col + 1.0, row + 1.0) : INFINITY};
    range(col, row, cx, cy, n, zmin, zmax, zkey);
  }
  void range(int col, int row, double cx, double cy, const Near& n, float& zmin, float& zmax, float& zkey) const {
    double a = n.z;
    // The axis's farthest depth over the pixel, once (farthest() is it, moved by the tilt).
    const double axisFar = farthestAxis(col, row, col + 1.0, row + 1.0);
    double b = std::max(a, farthestFromAxis(axisFar));
    if (model == WireDepth::Round) {
      // The round surface over the pixel: between the axis a radius times sqrt(1 - q^2) nearer,
      // q the distance from the axis in half widths, smallest and largest over the pixel's
      // corners (q is linear in the lateral distance; zero where the axis crosses the pixel).
      // Much tighter than [nearest, farthest] inside the wire, where most of its pixels are, so that
      // what it hides is culled against its true depth there.
      // t and l are linear: their extremes over the pixel are sums of the extremes of their x and
      // y terms (each term is the same product the corner's own t and l would form, and rounding
      // a sum is monotonic, so the bounds are the corners' own to the bit where nothing contracts
      // the products into fused multiply-adds: the build enables none).
      const double tx0 = (col - frame.ax) * frame.ux, tx1 = (col + 1.0 - frame.ax) * frame.ux;
      const double ty0 = (row - frame.ay) * frame.uy, ty1 = (row + 1.0 - frame.ay) * frame.uy;
      const double lx0 = (col - frame.ax) * frame.nx, lx1 = (col + 1.0 - frame.ax) * frame.nx;
      const double ly0 = (row - frame.ay) * frame.ny, ly1 = (row + 1.0 - frame.ay) * frame.ny;
      const double tlo = std::min(tx0, tx1) + std::min(ty0, ty1), thi = std::max(tx0, tx1) + std::max(ty0, ty1);
      const double llo = std::min(lx0, lx1) + std::min(ly0, ly1), lhi = std::max(lx0, lx1) + std::max(ly0, ly1);
      if (frame.length > 0 && tlo >= 0.0 && thi <= 1.0) {  // the caps (beyond the ends) keep [nearest, farthest]
        const double wlo = std::min(double(seg->w0) + (double(seg->w1) - double(seg->w0)) * tlo,
                                    double(seg->w0) + (double(seg->w1) - double(seg->w0)) * thi);
        const double whi = std::max(double(seg->w0) + (double(seg->w1) - double(seg->w0)) * tlo,
                                    double(seg->w0) + (double(seg->w1) - double(seg->w0)) * thi);
        const double rlo = std::min(seg->r0, seg->r1), rhi = std::max(seg->r0, seg->r1);
        const double lmin = (llo <= 0.0 && lhi >= 0.0) ? 0.0 : std::min(std::abs(llo), std::abs(lhi));
        const double lmax = std::max(std::abs(llo), std::abs(lhi));
        const double qmin = std::min(1.0, lmin / whi), qmax = std::min(1.0, lmax / wlo);
        // The tilt (SegmentTilt) over the pixel: along is zero between the ends, lat in [llo, lhi]
        // clamped to a half width.
        double la, lb;
        clampedRange(llo, lhi, wlo, whi, la, lb);
        const double slack = 1e-6 * std::abs(tilt.lateral) * whi;
        const double tiltLo = std::min(tilt.lateral * la, tilt.lateral * lb) - slack;
        const double tiltHi = std::max(tilt.lateral * la, tilt.lateral * lb) + slack;
        a = std::max(a, std::max(view->nearPlane, n.axis * (1.0 + tiltLo) - rhi * std::sqrt(1.0 - qmin * qmin) - pad));
        double round = axisFar * (1.0 + tiltHi) - rlo * std::sqrt(1.0 - qmax * qmax) + pad;
        if (capsule.valid) {
          // Within endMargin of an end the ray may meet the end's sphere instead of the body: no
          // farther than its centre and a radius times the sine of the ray's angle to the view
          // axis (sphereFar).
          // (at each end where solidIn holds)
          const double m = endMargin + WireCapsule::kRangeSpread;
          if (WireCapsule::nearP0(tlo, frame.length, m)) round = std::max(round, sphereFar0);
          if (WireCapsule::nearP1(thi, frame.length, m)) round = std::max(round, sphereFar1);
        }
        b = std::max(a, std::min(b, round));
      }
      // The round range is the model's; where the solid may give the depth, its own bounds hold
      // its sides (the model's depth radius may be capped, ramped or end-on).
      a = std::min(a, n.solid);
      if (n.solid < INFINITY && endMargin == INFINITY) b = std::max(b, capsuleFarthest(col, row, col + 1.0, row + 1.0));
    }
    zmin = float(a);
    zmax = float(b);
    zkey = float(std::clamp(depthAt(cx, cy), a, b));
  }
  /// The solid's depth near the ends (WireCapsule), else segmentDepthAt (pipeline.h), with the
  /// end keys formed once.
  double depthAt(double x, double y) const {
    if (capsule.valid && WireCapsule::nearEnd(frame.t(x, y), frame.length, endMargin, 0.0))
      return std::max(view->nearPlane, capsule.depthAt(*view, x, y));
    return segmentDepthAt(*view, *seg, frame, keys, tilt, x, y, model);
  }
};

/// The centroid (sx, sy) in the pixel of the samples a non-empty mask covers, a mask row at a
/// time (one byte of 8 columns, or a nibble of 4, through a table of counts and column sums).
inline void maskCentroid(MaskBits mask, const MaskLayout& layout, double& sx, double& sy) {
  struct RowTable {
    std::uint8_t count[256];
    std::uint8_t columnSum[256];  // sum of the set bits' column indices
    constexpr RowTable() : count{}, columnSum{} {
      for (int b = 0; b < 256; ++b)
        for (int i = 0; i < 8; ++i)
          if ((b >> i) & 1) ++count[b], columnSum[b] = std::uint8_t(columnSum[b] + i);
    }
  };
  static constexpr RowTable kRows{};
  int n = 0, cols = 0, rows = 0;
  const MaskBits rowFull = layout.rowFull();
  for (int j = 0; j < layout.h; ++j, mask >>= layout.w) {
    const unsigned bits = unsigned(mask & rowFull);
    n += kRows.count[bits];
    cols += kRows.columnSum[bits];
    rows += kRows.count[bits] * j;
  }
  sx = n ? (cols + 0.5 * n) / (double(n) * layout.w) : 0.5;
  sy = n ? (rows + 0.5 * n) / (double(n) * layout.h) : 0.5;
}

/// Rasterises the convex polygon `poly` (depth `depth`) over pixel columns [rx0, rx1] and rows
/// [ry0, ry1] (inclusive). Callbacks, in the order a pixel meets them:
///   cullBand(x0, y0, x1, y1, z)  true: every pixel of the rectangle hides what lies behind z
///                             (asked for bands of 4 rows from blockOriginY, the tile's top)
///   cullRow(row, c0, c1, z)   true: every pixel c0 ... c1 of the row hides what lies behind z
///   cullPixel(col, row, z)    true: the pixel hides what lies behind z (z: the polygon's nearest)
///   hidden(col, row, mask, subpixel, z)  true: the subpixels of the mask (or the stand-in) do
///   emit(coverage)
template <class Depth, class CullBand, class CullRow, class CullPixel, class Hidden, class Emit>
void rasterizePolygon(const ScreenPolygon& poly, const Depth& depth, int rx0, int ry0, int rx1, int ry1,
                      int blockOriginY, const MaskLayout& layout, RenderStats::RasterWork& work, CullBand&& cullBand,
                      CullRow&& cullRow, CullPixel&& cullPixel, Hidden&& hidden, Emit&& emit) {
  constexpr int kBlockRows = 4;
  // The edges as inside->=0 functions with their y extents (the coverage masks: along a sample
  // row only the edges whose closed y extent holds the row can bound the convex polygon there).
  const int n = poly.count;
  const double signedArea = poly.signedArea();
  if (!(std::abs(signedArea) > 0.0)) return;
  const double orient = signedArea > 0 ? 1.0 : -1.0;
  EdgeFunction edges[ScreenPolygon::kMaxVertices];
  double edgeLo[ScreenPolygon::kMaxVertices], edgeHi[ScreenPolygon::kMaxVertices];
  int edgeCount = 0;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 == n ? 0 : i + 1;
    const EdgeFunction e = EdgeFunction::through(poly.x[i], poly.y[i], poly.x[j], poly.y[j]);
    if (e.a == 0.0 && e.b == 0.0) continue;
    edges[edgeCount] = signedArea > 0 ? e : e.negated();
    edgeLo[edgeCount] = std::min(poly.y[i], poly.y[j]);
    edgeHi[edgeCount] = std::max(poly.y[i], poly.y[j]);
    ++edgeCount;
  }
  if (edgeCount < 3) return;
  // The polygon's run of sample columns [lo, hi) along the sample row at height y (coverage_mask.h).
  // `near` lists (in order) the edges that may meet the row: the others' y extents miss it.
  auto rowSpan = [&](double y, const int* near, int nearCount, std::int64_t& lo, std::int64_t& hi) {
    lo = std::numeric_limits<std::int64_t>::min() / 2;
    hi = std::numeric_limits<std::int64_t>::max() / 2;
    bool any = false;
    for (int q = 0; q < nearCount; ++q) {
      const int k = near[q];
      if (y < edgeLo[k] || y > edgeHi[k]) continue;
      any = true;
      const EdgeFunction& e = edges[k];
      if (e.a == 0.0) {
        const double v = e.b * y + e.c;
        if (!(v > 0.0 || (v == 0.0 && e.b > 0.0))) hi = lo;  // horizontal edge: row outside
        continue;
      }
      const std::int64_t f = edgeFirstColumn(e, layout, y);
      if (e.a > 0.0) lo = std::max(lo, f);
      else hi = std::min(hi, f);
    }
    if (!any) hi = lo;
  };
  double slopes[ScreenPolygon::kMaxVertices], elo[ScreenPolygon::kMaxVertices], ehi[ScreenPolygon::kMaxVertices];
  double ymin = 1e300, ymax = -1e300;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 == n ? 0 : i + 1;
    slopes[i] = poly.y[j] != poly.y[i] ? (poly.x[j] - poly.x[i]) / (poly.y[j] - poly.y[i]) : 0.0;
    elo[i] = std::min(poly.y[i], poly.y[j]);
    ehi[i] = std::max(poly.y[i], poly.y[j]);
    ymin = std::min(ymin, poly.y[i]);
    ymax = std::max(ymax, poly.y[i]);
  }
  const int row0 = int(std::max<std::int64_t>(ry0, floorToInt(std::max(ymin, -1e15))));
  const int row1 = int(std::min<std::int64_t>(ry1, ceilToInt(std::min(ymax, 1e15)) - 1));
  struct SubEdge {
    double xa, xb;    // the edge's part inside the band, in contour order (its ends' x)
    double dy;        // its signed height
    double lo, hi;    // min and max of xa, xb
    double whole;     // the integral when X is right of it: 0.5 (xa + xb) dy
    double invDx;     // 1 / (xb - xa), or 0 for a vertical edge
  };
  SubEdge sub[ScreenPolygon::kMaxVertices];
  // Integral over one sub-edge of min(x, X) dy, oriented (what depends on the sub-edge alone is
  // formed once per row).
  auto leftOf = [](const SubEdge& e, double X) {
    const double dy = e.dy;
    if (X >= e.hi) return e.whole;
    if (X <= e.lo) return X * dy;
    const double s = (X - e.xa) * e.invDx;  // where the edge crosses x = X
    const double mean = e.xa < e.xb ? s * 0.5 * (e.xa + X) + (1.0 - s) * X : s * X + (1.0 - s) * 0.5 * (X + e.xb);
    return mean * dy;
  };
  const int N = layout.samples();
  const MaskBits full = layout.full();
  for (int row = row0; row <= row1; ++row) {
    // Whole bands of rows (the rows of one line of the occlusion blocks) first: skipped at once
    // when the polygon's part across them is behind what hides them.
    if (row == row0 || ((row - blockOriginY) & (kBlockRows - 1)) == 0) {
      const int bandEnd = std::min(row1, blockOriginY + ((row - blockOriginY) / kBlockRows + 1) * kBlockRows - 1);
      double xl = rx0, xr = rx1 + 1.0;
      if (depth.bandSpan(row, bandEnd + 1.0, xl, xr)) {
        xl = std::max(xl, double(rx0)), xr = std::min(xr, rx1 + 1.0);
      }
      const int bx0 = int(std::floor(xl)), bx1 = int(std::ceil(xr)) - 1;
      if (bx0 > bx1 || cullBand(bx0, row, bx1, bandEnd, depth.nearest(bx0, row, bx1 + 1.0, bandEnd + 1.0))) {
        work.rows += std::uint64_t(bandEnd - row + 1);
        work.rowsCulled += std::uint64_t(bandEnd - row + 1);
        row = bandEnd;
        continue;
      }
    }
    const double y0 = row, y1 = row + 1.0;
    int ns = 0;
    double xmin = 1e300, xmax = -1e300;
    double innerLo = -1e300, innerHi = 1e300;  // the band is wholly inside between these
    for (int i = 0; i < n; ++i) {
      if (ehi[i] <= y0 || elo[i] >= y1 || elo[i] == ehi[i]) continue;
      const int j = i + 1 == n ? 0 : i + 1;
      const double xa = poly.x[i], ya = poly.y[i], xb = poly.x[j], yb = poly.y[j];
      // Clip the edge to the band (its x at the band's lines, from the same formula both ways).
      auto xAt = [&](double y) { return xa + (y - ya) * slopes[i]; };
      const double ca = std::clamp(ya, y0, y1), cb = std::clamp(yb, y0, y1);
      const double xca = ca == ya ? xa : xAt(ca), xcb = cb == yb ? xb : xAt(cb);
      const double lo = std::min(xca, xcb), hi = std::max(xca, xcb);
      sub[ns++] = {xca, xcb, cb - ca, lo, hi, 0.0, 0.0};  // (whole and invDx at the row's first partial pixel)
      xmin = std::min(xmin, lo);
      xmax = std::max(xmax, hi);
      // Oriented downwards the contour runs along the polygon's right side, upwards its left.
      if (orient * (cb - ca) > 0) innerHi = std::min(innerHi, lo);
      else innerLo = std::max(innerLo, hi);
    }
    if (ns < 2) continue;
    int c0, c1;
    pixelColumns(xmin, xmax, rx0, rx1 + 1, c0, c1);
    if (c0 > c1) continue;
    ++work.rows;
    const double zRow = depth.nearest(c0, y0, c1 + 1.0, y1);
    if (cullRow(row, c0, c1, zRow)) {
      ++work.rowsCulled;
      continue;
    }
    // Whole pixels: the band is covered from its top to its bottom between innerLo and innerHi.
    int in0 = INT_MAX, in1 = INT_MIN;
    if (ymin <= y0 && ymax >= y1 && innerLo < innerHi) {
      in0 = int(std::clamp<std::int64_t>(ceilToInt(std::max(innerLo, -1e15)), INT_MIN / 2, INT_MAX / 2));
      in1 = int(std::clamp<std::int64_t>(floorToInt(std::min(innerHi, 1e15)) - 1, INT_MIN / 2, INT_MAX / 2));
    }
    std::int64_t spanLo[8], spanHi[8];  // the polygon's sample runs on this row's sample rows
    bool spansDone = false;              // computed at the row's first partial pixel that survives culling
    bool subDone = false;                // the sub-edges' integrals and slopes: the same
    double left = 0;                     // area of the band left of x = leftAt
    int leftAt = INT_MIN;
    for (int col = c0; col <= c1; ++col) {
      // Before any arithmetic (most are hidden): first against the row's nearest depth, then, if
      // need be, the pixel's own.
      ++work.pixels;
      if (cullPixel(col, row, zRow)) {
        ++work.pixelsCulled;
        continue;
      }
      const typename Depth::Near pixelNear = depth.pixelNearest(col, row);
      const double zNear = pixelNear.z;
      if (zNear > zRow && cullPixel(col, row, zNear)) {
        ++work.pixelsCulled;
        continue;
      }
      PixelCoverage pc;
      pc.x = col;
      pc.y = row;
      pc.subpixel = N / 2;
      if (col >= in0 && col <= in1) {
        pc.area = 1.0;
        pc.mask = full;
        pc.cx = col + 0.5;
        pc.cy = row + 0.5;
      } else {
        if (!subDone) {
          // (a division per sub-edge: most rows, or all their pixels, are culled before this)
          for (int k = 0; k < ns; ++k) {
            SubEdge& e = sub[k];
            e.whole = 0.5 * (e.xa + e.xb) * e.dy;
            e.invDx = e.xb != e.xa ? 1.0 / (e.xb - e.xa) : 0.0;
          }
          subDone = true;
        }
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
        pc.area = area;
        if (!spansDone) {
          // The sample rows lie strictly inside the band (y0, y1): only edges reaching into it count.
          int near[ScreenPolygon::kMaxVertices], nearCount = 0;
          for (int k = 0; k < edgeCount; ++k)
            if (edgeHi[k] > y0 && edgeLo[k] < y1) near[nearCount++] = k;
          for (int j = 0; j < layout.h; ++j) rowSpan(row + layout.sampleY(j), near, nearCount, spanLo[j], spanHi[j]);
          spansDone = true;
        }
        pc.mask = 0;
        for (int j = 0; j < layout.h; ++j)
          pc.mask |= spanRowBits(spanLo[j], spanHi[j], std::int64_t(col) * layout.w, layout) << (j * layout.w);
        if (pc.mask != 0) {
          // Shaded and ordered at the centroid of the samples it covers.
          double sx, sy;
          maskCentroid(pc.mask, layout, sx, sy);
          pc.cx = col + sx;
          pc.cy = row + sy;
        } else {
          // Thinner than the sample spacing here: the stand-in subpixel and the shading point
          // are the centroid of the covered part (the rare slow path: clip to the pixel).
          pc.cx = col + 0.5;
          pc.cy = row + 0.5;
          ScreenPolygon cell;
          clipRect(poly, cell, col, row, col + 1.0, row + 1.0);
          if (cell.count >= 3) cell.centroid(pc.cx, pc.cy);
          const int si = std::clamp(int((pc.cx - col) * layout.w), 0, layout.w - 1);
          const int sj = std::clamp(int((pc.cy - row) * layout.h), 0, layout.h - 1);
          pc.subpixel = sj * layout.w + si;
        }
      }
      depth.range(col, row, pc.cx, pc.cy, pixelNear, pc.zmin, pc.zmax, pc.zkey);
      if (hidden(col, row, pc.mask, pc.subpixel, std::max(zNear, double(pc.zmin)))) {
        ++work.masksHidden;
        continue;
      }
      ++work.emitted;
      emit(pc);
    }
  }
}

/// The A-buffer's questions about a fragment's primitive (abuffer.h), answered from the prepared
/// scene: shading at the fragment's shading point and depth, depths at the subpixel samples.
class PreparedFragmentSource final : public FragmentSource {
 public:
  explicit PreparedFragmentSource(const PreparedScene& ps) : ps_(ps), serial_(nextSerial()) {}
  /// The per-thread cache of wire depth bases, allocated on a thread's first wire and kept:
  /// its bytes (the renderer's peak and estimate count it for every thread that resolves).
  static std::size_t cacheBytesPerThread();
  glm::vec3 shade(const Fragment& f, int x, int y) const override {
    if (f.prim == Fragment::kNoPrimitive) return f.colour;
    return shadeFragment(ps_, f.prim, x + f.pointX(), y + f.pointY(), f.zkey);
  }
  bool onSurface(std::uint32_t prim) const override {
    return prim < ps_.primitiveCount() && ps_.isSegment(prim) && ps_.shaderOf(prim).restsOnSurface;
  }
  bool surfaceDepth(std::uint32_t prim, int x, int y, SurfaceDepth& d) const override {
    if (prim >= ps_.primitiveCount()) return false;
    if (ps_.isSegment(prim)) {
      // What depends on the segment alone (its frame, end keys and tilt: a square root and a
      // dozen divisions) comes from a small per-thread cache, the pixel's offsets from it with
      // the same arithmetic as ever, so the same floats.
      const WireDepthBasis& b = wireDepthBasis(prim);
      d = b.depth;
      if (b.hasLength) {
        d.t0 = float((x - b.ax) * b.ux + (y - b.ay) * b.uy);
        d.l0 = float((x - b.ax) * b.nx + (y - b.ay) * b.ny);
      } else {  // seen exactly end-on: its end point, radially (t is the x offset, held at 0)
        d.t0 = float(x - b.ax);
        d.l0 = float(y - b.ay);
      }
      if (d.capsule) capsuleRay(b, x, y, d);
      return true;
    }
    const TrianglePrim& t = ps_.triangles[prim];
    d.perspective = ps_.view.perspective;
    d.nearPlane = float(ps_.view.nearPlane);
    d.kind = SurfaceDepth::Kind::Plane;
    d.k0 = float(t.depthKeyAt(x, y)), d.kx = float(t.qa), d.ky = float(t.qb);
    d.lo = t.zlo, d.hi = t.zhi;
    return true;
  }

 private:
  /// A segment's SurfaceDepth less its pixel's offsets t0 and l0, and its frame for them.
  struct WireDepthBasis {
    std::uint64_t serial = 0;  ///< the source that filled it (0: empty)
    std::uint32_t prim = 0;
    bool hasLength = false;
    double ax = 0, ay = 0, ux = 0, uy = 0, nx = 0, ny = 0;
    double axis0 = 0, axis1 = 0;  ///< the axis's depth keys at the ends (capsule: the pixel's reference depth)
    glm::dvec3 e0{0.0};           ///< capsule: the solid's p0 end, eye space
    double endMargin = 0, length = 0;  ///< capsule: WireCapsule::endMargin, the screen length
    SurfaceDepth depth;
  };
  /// Segment `prim`'s basis, from the per-thread cache (fragment_shading.cpp).
  const WireDepthBasis& wireDepthBasis(std::uint32_t prim) const;
  /// Fills `b` for segment `prim` (the cache's miss path).
  void fillWireDepthBasis(std::uint32_t prim, WireDepthBasis& b) const;
  /// The ray of pixel (x, y)'s samples relative to the solid's p0 end, about the axis's depth at
  /// the pixel's centre (SurfaceDepth::capsule; fragment_shading.cpp).
  void capsuleRay(const WireDepthBasis& b, int x, int y, SurfaceDepth& d) const;
  static std::uint64_t nextSerial();
  const PreparedScene& ps_;
  const std::uint64_t serial_;  ///< tells this render's cache entries from an earlier one's
};

}  // namespace wf
