// Subpixel coverage masks of the A-buffer (Carpenter 1984): one bit per subpixel sample on a
// regular W x H grid of sample points at the subpixel centres, bit index j * W + i for sample
// column i, row j (row 0 at the top of the pixel). 8x4 (32 bits) is Carpenter's; 4x4 and 8x8
// trade accuracy of hidden-surface decisions against time (see `wirefur accuracy`).
//
// Masks are built from the polygon's edges, not by testing sample points one by one: along each
// sample row an edge a x + b y + c >= 0 leaves a contiguous run of samples inside, starting at
// the column where the edge crosses the row, so a convex polygon covers one run per sample row,
// computed once per row of the polygon and shared by all its pixels on that row. Both polygons on either side of a shared edge
// compute that crossing from coefficients that are exact negations of each other, so they get
// the same floating-point value and take complementary runs (ties go to the side with a > 0, or
// for a horizontal edge b > 0): every sample belongs to exactly one of them. No crack, no
// double coverage, whatever the rounding.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace wf {

using MaskBits = std::uint64_t;

struct MaskLayout {
  int w = 8, h = 4;  ///< sample columns and rows per pixel: 4x4, 8x4 (default) or 8x8

  int samples() const { return w * h; }
  MaskBits full() const { return samples() == 64 ? ~MaskBits(0) : (MaskBits(1) << samples()) - 1; }
  MaskBits rowFull() const { return (MaskBits(1) << w) - 1; }
  /// Subpixel sample position inside the pixel, in [0, 1).
  double sampleX(int i) const { return (i + 0.5) / w; }
  double sampleY(int j) const { return (j + 0.5) / h; }
  bool valid() const { return (w == 4 && h == 4) || (w == 8 && h == 4) || (w == 8 && h == 8); }
  std::string name() const { return std::to_string(w) + "x" + std::to_string(h); }
  /// Parses "4x4", "8x4" or "8x8"; returns false for anything else.
  static bool parse(const std::string& text, MaskLayout& out) {
    for (MaskLayout m : {MaskLayout{4, 4}, MaskLayout{8, 4}, MaskLayout{8, 8}})
      if (text == m.name()) {
        out = m;
        return true;
      }
    return false;
  }
};

/// Set subpixels of a mask. std::popcount is a call into libgcc on the x86-64 baseline (no
/// POPCNT instruction); the bit-parallel sum inline is several times cheaper in the hot loops.
inline int maskCount(MaskBits m) {
  std::uint64_t x = std::uint64_t(m);
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return int((x * 0x0101010101010101ull) >> 56);
}

/// ceil for |x| < 2^62 without a library call (the rasteriser's inner loops need many).
inline std::int64_t ceilToInt(double x) {
  const std::int64_t i = std::int64_t(x);  // truncates toward zero
  return i + (double(i) < x ? 1 : 0);
}
inline std::int64_t floorToInt(double x) {
  const std::int64_t i = std::int64_t(x);
  return i - (double(i) > x ? 1 : 0);
}

/// An edge a x + b y + c of a polygon in screen space, oriented so that the inside is >= 0.
struct EdgeFunction {
  double a, b, c;  // left uninitialised: arrays of these sit in the rasteriser's hot path
  /// The edge from p to q: the function is cross(q - p, r - p) at r, so polygons with positive
  /// shoelace area have their inside >= 0; callers flip the others with `negated`.
  static EdgeFunction through(double px, double py, double qx, double qy) {
    return {py - qy, qx - px, px * qy - qx * py};
  }
  EdgeFunction negated() const { return {-a, -b, -c}; }
  double operator()(double x, double y) const { return a * x + b * y + c; }
};

/// Sample columns are numbered globally along a sample row: column g sits at x = (g + 0.5) / w.
/// For an edge with a != 0 this returns the first global column at or right of the crossing
/// x_t = -(b y + c) / a (clamped far outside any image). The inside is g >= first for a > 0 and
/// g < first for a < 0; a negated edge yields the same x_t and so the complementary set.
inline std::int64_t edgeFirstColumn(const EdgeFunction& e, const MaskLayout& layout, double y) {
  const double xt = std::clamp(-(e.b * y + e.c) / e.a, -1e12, 1e12);
  return ceilToInt(xt * layout.w - 0.5);
}

/// The inside of a convex polygon (its edges) along one sample row at height y, as the
/// half-open range [lo, hi) of global sample columns (empty when lo >= hi).
inline void sampleRowSpan(const EdgeFunction* edges, int edgeCount, const MaskLayout& layout,
                          double y, std::int64_t& lo, std::int64_t& hi) {
  lo = std::numeric_limits<std::int64_t>::min() / 2;
  hi = std::numeric_limits<std::int64_t>::max() / 2;
  for (int k = 0; k < edgeCount; ++k) {
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
}

/// The bits of one mask row of the pixel whose first global sample column is `colBase`.
inline MaskBits spanRowBits(std::int64_t lo, std::int64_t hi, std::int64_t colBase, const MaskLayout& layout) {
  const std::int64_t a = std::max<std::int64_t>(lo - colBase, 0), b = std::min<std::int64_t>(hi - colBase, layout.w);
  if (a >= b) return 0;
  return ((MaskBits(1) << b) - 1) & ~((MaskBits(1) << a) - 1);
}

/// Coverage mask of the convex polygon bounded by `edges` over the pixel with integer origin
/// (x0, y0).
inline MaskBits polygonMask(const EdgeFunction* edges, int edgeCount, const MaskLayout& layout,
                            int x0, int y0) {
  MaskBits mask = 0;
  for (int j = 0; j < layout.h; ++j) {
    std::int64_t lo, hi;
    sampleRowSpan(edges, edgeCount, layout, y0 + layout.sampleY(j), lo, hi);
    mask |= spanRowBits(lo, hi, std::int64_t(x0) * layout.w, layout) << (j * layout.w);
  }
  return mask;
}

}  // namespace wf
