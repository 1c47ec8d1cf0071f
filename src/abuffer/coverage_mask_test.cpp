// Tests of the coverage masks (coverage_mask.h) and of the screen-polygon clipping they sit
// beside (screen_polygon.h). Every mask is checked against brute-force point tests of the
// sample positions x0 + (i + 0.5) / w, y0 + (j + 0.5) / h, written out here from cross
// products, not from the code under test; areas against the shoelace formula.
#include "abuffer/coverage_mask.h"
#include "abuffer/screen_polygon.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <random>
#include <vector>

namespace wf {
namespace {

const MaskLayout kLayouts[] = {MaskLayout{4, 4}, MaskLayout{8, 4}, MaskLayout{8, 8}};

struct P2 {
  double x, y;
};

ScreenPolygon makePolygon(const std::vector<P2>& v) {
  ScreenPolygon p;
  for (const P2& q : v) p.add(q.x, q.y);
  return p;
}

// cross(b - a, c - a), written independently of EdgeFunction.
double cross3(const P2& a, const P2& b, const P2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

double shoelace(const std::vector<P2>& v) {
  double s = 0;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) s += v[j].x * v[i].y - v[i].x * v[j].y;
  return 0.5 * s;
}

// Closed convex polygon membership: every turn towards the point has the orientation's sign
// (or is zero).
bool insideConvex(const std::vector<P2>& v, const P2& s) {
  const double orient = shoelace(v) > 0 ? 1.0 : -1.0;
  for (size_t i = 0; i < v.size(); ++i)
    if (orient * cross3(v[i], v[(i + 1) % v.size()], s) < 0) return false;
  return true;
}

// Euclidean distance from s to the infinite line through a and b.
double lineDistance(const P2& a, const P2& b, const P2& s) {
  return std::abs(cross3(a, b, s)) / std::hypot(b.x - a.x, b.y - a.y);
}

double minEdgeDistance(const std::vector<P2>& v, const P2& s) {
  double d = INFINITY;
  for (size_t i = 0; i < v.size(); ++i) d = std::min(d, lineDistance(v[i], v[(i + 1) % v.size()], s));
  return d;
}

P2 samplePoint(const MaskLayout& L, int x0, int y0, int bit) {
  const int i = bit % L.w, j = bit / L.w;
  return {x0 + (i + 0.5) / L.w, y0 + (j + 0.5) / L.h};
}

MaskBits maskOf(const std::vector<P2>& v, const MaskLayout& L, int x0, int y0) {
  const ScreenPolygon p = makePolygon(v);
  EdgeFunction e[ScreenPolygon::kMaxVertices];
  const int n = polygonEdges(p, e);
  return polygonMask(e, n, L, x0, y0);
}

// A random convex quad: four sorted angles on a random ellipse (an affine image of a circle,
// so the vertices stay in convex position).
std::vector<P2> randomConvexQuad(std::mt19937_64& rng, double cx, double cy, double size) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double a = size * (0.3 + U(rng)), b = size * (0.3 + U(rng)), phi = U(rng) * std::numbers::pi;
  std::vector<double> t(4);
  for (double& x : t) x = U(rng) * 2 * std::numbers::pi;
  std::sort(t.begin(), t.end());
  std::vector<P2> v;
  for (double x : t) {
    const double ex = a * std::cos(x), ey = b * std::sin(x);
    v.push_back({cx + ex * std::cos(phi) - ey * std::sin(phi), cy + ex * std::sin(phi) + ey * std::cos(phi)});
  }
  if (U(rng) < 0.5) std::reverse(v.begin(), v.end());  // both orientations
  return v;
}

TEST(MaskLayout, ParsesTheThreeLayoutsAndRejectsOthers) {
  // The three layouts of coverage_mask.h, by name; anything else is refused and leaves `out`.
  for (const auto& [text, w, h] : {std::tuple{"4x4", 4, 4}, std::tuple{"8x4", 8, 4}, std::tuple{"8x8", 8, 8}}) {
    MaskLayout m{1, 1};
    ASSERT_TRUE(MaskLayout::parse(text, m)) << text;
    EXPECT_EQ(m.w, w);
    EXPECT_EQ(m.h, h);
    EXPECT_TRUE(m.valid());
    EXPECT_EQ(m.name(), text);
  }
  for (const char* bad : {"4x8", "16x16", "8x2", "2x2", "", "8X4", " 8x4", "8x4 ", "8x", "x4", "8*4", "08x4"}) {
    MaskLayout m{8, 4};
    EXPECT_FALSE(MaskLayout::parse(bad, m)) << "'" << bad << "'";
    EXPECT_EQ(m.w, 8);  // untouched on failure
    EXPECT_EQ(m.h, 4);
  }
  EXPECT_FALSE((MaskLayout{4, 8}).valid());
  EXPECT_FALSE((MaskLayout{16, 4}).valid());
}

TEST(MaskLayout, FullMaskHasOneBitPerSample) {
  for (const MaskLayout& m : kLayouts) {
    // w * h samples: 16, 32 or 64 bits set, and nothing above them.
    EXPECT_EQ(maskCount(m.full()), m.w * m.h) << m.name();
    EXPECT_EQ(m.samples(), m.w * m.h);
    if (m.samples() < 64) {
      EXPECT_EQ(m.full() >> m.samples(), 0u) << m.name();
    }
    // One row is w bits.
    EXPECT_EQ(maskCount(m.rowFull()), m.w);
    // Sample positions are the subpixel centres (i + 0.5) / w, (j + 0.5) / h.
    EXPECT_DOUBLE_EQ(m.sampleX(0), 0.5 / m.w);
    EXPECT_DOUBLE_EQ(m.sampleY(m.h - 1), 1.0 - 0.5 / m.h);
  }
}

TEST(PolygonMask, MatchesBruteForceSampleTestsOnRandomConvexPolygons) {
  // 2000 random triangles and convex quads, a few random pixels each (mostly ones the polygon
  // touches): every bit equals the point-in-polygon test of its sample, except samples within
  // 1e-9 of an edge line, where rounding may decide either way.
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  long checked = 0, partial = 0, nearEdge = 0;
  for (int k = 0; k < 2000; ++k) {
    const double cx = -100 + 200 * U(rng), cy = -100 + 200 * U(rng);
    const double size = k % 10 == 0 ? 0.3 * U(rng) : 0.5 + 4 * U(rng);  // some sub-pixel ones
    std::vector<P2> v;
    if (k % 2 == 0) {
      for (int i = 0; i < 3; ++i) v.push_back({cx + size * (2 * U(rng) - 1), cy + size * (2 * U(rng) - 1)});
      if (std::abs(shoelace(v)) < 1e-6) continue;
    } else {
      v = randomConvexQuad(rng, cx, cy, size);
      ASSERT_TRUE(isConvex(makePolygon(v)));
    }
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const P2& p : v) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    for (int t = 0; t < 4; ++t) {
      const int px = int(std::floor(x0 - 1 + (x1 - x0 + 2) * U(rng)));
      const int py = int(std::floor(y0 - 1 + (y1 - y0 + 2) * U(rng)));
      for (const MaskLayout& L : kLayouts) {
        const MaskBits m = maskOf(v, L, px, py);
        ASSERT_EQ(m & ~L.full(), 0u);  // no bits beyond the layout
        if (m != 0 && m != L.full()) ++partial;
        for (int b = 0; b < L.samples(); ++b) {
          const P2 s = samplePoint(L, px, py, b);
          if (minEdgeDistance(v, s) < 1e-9) {
            ++nearEdge;
            continue;
          }
          ++checked;
          ASSERT_EQ(bool((m >> b) & 1), insideConvex(v, s))
              << "polygon " << k << " pixel (" << px << "," << py << ") layout " << L.name() << " bit " << b;
        }
      }
    }
  }
  // The test must have looked at edges, not only at empty or full pixels.
  EXPECT_GT(checked, 500000);
  EXPECT_GT(partial, 5000);
  EXPECT_LT(nearEdge, 10);  // random coordinates almost never put a sample on an edge
}

TEST(PolygonMask, AxisAlignedRectangleCoversTheSamplesItContains) {
  // Rectangle [0.3, 2.7] x [0.1, 1.55] over pixel (1, 1), layout 8x4: sample columns at x =
  // 1 + (i + 0.5) / 8 are all < 2.7, rows at y = 1 + (j + 0.5) / 4 = 1.125, 1.375 < 1.55 <
  // 1.625: rows 0 and 1 fully covered, rows 2 and 3 empty.
  const std::vector<P2> rect{{0.3, 0.1}, {2.7, 0.1}, {2.7, 1.55}, {0.3, 1.55}};
  const MaskLayout L{8, 4};
  EXPECT_EQ(maskOf(rect, L, 1, 1), MaskBits(0xFFFF));
  // Pixel (2, 0): x < 2.7 keeps columns with 2 + (i + 0.5) / 8 < 2.7, i.e. i <= 5 (2.6875);
  // y in [0.1, 1]: all four rows (0.125 ... 0.875).
  EXPECT_EQ(maskOf(rect, L, 2, 0), MaskBits(0x3F3F3F3F));
}

// ---- shared edges --------------------------------------------------------------------------

// Checks that every sample of pixel (px, py) inside the union of the given triangles, and not
// within 1e-9 of an outer edge or an excluded point, is covered by exactly one triangle's mask,
// and that samples outside it are covered by none. Returns the number of samples checked that
// lie within 1e-9 of some inner (shared) edge.
int checkPartition(const std::vector<std::vector<P2>>& tris, const std::vector<std::pair<P2, P2>>& outer,
                   const MaskLayout& L, int px, int py, const P2* excludePoint = nullptr) {
  std::vector<MaskBits> masks;
  for (const auto& t : tris) masks.push_back(maskOf(t, L, px, py));
  int onShared = 0;
  for (int b = 0; b < L.samples(); ++b) {
    const P2 s = samplePoint(L, px, py, b);
    bool nearOuter = false;
    for (const auto& [a, c] : outer) {
      // Near the outer edge's infinite line: may skip a few more samples than needed, never
      // fewer.
      if (lineDistance(a, c, s) < 1e-9) nearOuter = true;
    }
    if (nearOuter) continue;
    if (excludePoint && std::hypot(s.x - excludePoint->x, s.y - excludePoint->y) < 1e-9) continue;
    bool inUnion = false, nearInner = false;
    for (const auto& t : tris) {
      inUnion = inUnion || insideConvex(t, s);
      if (minEdgeDistance(t, s) < 1e-9) nearInner = true;
    }
    int count = 0;
    for (MaskBits m : masks) count += int((m >> b) & 1);
    EXPECT_EQ(count, inUnion ? 1 : 0) << "pixel (" << px << "," << py << ") layout " << L.name() << " sample " << b
                                      << " at (" << s.x << "," << s.y << ")";
    if (inUnion && nearInner) ++onShared;
  }
  return onShared;
}

TEST(PolygonMask, TrianglesSharingAnEdgeNeitherCrackNorOverlap) {
  // Random shared edge PQ, opposite vertices R1 and R2 on either side. Along the edge, the two
  // masks are disjoint; every sample of the union (away from its four outer edges) is in
  // exactly one of them; and when the union PR1QR2 is convex their OR is exactly its mask
  // (the quad computes the very same outer edge functions).
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int convexCases = 0;
  for (int k = 0; k < 300; ++k) {
    const P2 P{-50 + 100 * U(rng), -50 + 100 * U(rng)};
    const double len = 1 + 10 * U(rng), ang = 2 * std::numbers::pi * U(rng);
    const P2 Q{P.x + len * std::cos(ang), P.y + len * std::sin(ang)};
    const double nx = -std::sin(ang), ny = std::cos(ang);
    auto side = [&](double sign) {
      const double t = -0.3 + 1.6 * U(rng), h = sign * (0.2 + 5 * U(rng));
      return P2{P.x + t * (Q.x - P.x) + h * nx, P.y + t * (Q.y - P.y) + h * ny};
    };
    const P2 R1 = side(+1), R2 = side(-1);
    const std::vector<P2> A{P, Q, R1}, B{Q, P, R2};
    const std::vector<std::pair<P2, P2>> outer{{P, R1}, {R1, Q}, {Q, R2}, {R2, P}};
    const std::vector<P2> quad{P, R2, Q, R1};
    const bool convex = isConvex(makePolygon(quad));
    convexCases += convex;
    for (const MaskLayout& L : kLayouts) {
      for (int step = 0; step <= 40; ++step) {
        const double t = step / 40.0;
        const int px = int(std::floor(P.x + t * (Q.x - P.x))), py = int(std::floor(P.y + t * (Q.y - P.y)));
        const MaskBits ma = maskOf(A, L, px, py), mb = maskOf(B, L, px, py);
        // Complementary runs on the shared edge: no sample in both.
        ASSERT_EQ(ma & mb, 0u) << k << " " << L.name();
        checkPartition({A, B}, outer, L, px, py);
        // Exactly the union's own mask when the union is a convex quad.
        if (convex) {
          EXPECT_EQ(ma | mb, maskOf(quad, L, px, py)) << k << " " << L.name();
        }
      }
    }
  }
  EXPECT_GT(convexCases, 30);  // the OR == quad check ran
}

TEST(PolygonMask, SharedEdgeThroughSamplePointsCoversEachExactlyOnce) {
  // The shared edge runs exactly through sample points (dyadic coordinates on the sample
  // lattice, so every edge function is computed without rounding): the tie rule must give
  // each sample on the edge to exactly one of the two triangles.
  for (const MaskLayout& L : kLayouts) {
    const double sx = 1.0 / L.w, sy = 1.0 / L.h;
    auto lattice = [&](int i, int j) { return P2{(i + 0.5) * sx, (j + 0.5) * sy}; };
    // Edge directions (in lattice steps) including horizontal, vertical and both diagonals.
    const int dirs[][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}, {3, 2}, {-2, 5}, {5, -1}, {-4, -3}};
    int onEdgeTotal = 0;
    for (const auto& d : dirs) {
      const P2 P = lattice(3, 5), Q = lattice(3 + 6 * d[0], 5 + 6 * d[1]);
      // Opposite vertices off the lattice line, on either side (also dyadic).
      const P2 R1{0.5 * (P.x + Q.x) - 3.25 * d[1] * sy, 0.5 * (P.y + Q.y) + 3.25 * d[0] * sx};
      const P2 R2{0.5 * (P.x + Q.x) + 2.75 * d[1] * sy, 0.5 * (P.y + Q.y) - 2.75 * d[0] * sx};
      ASSERT_LT(cross3(P, Q, R1) * cross3(P, Q, R2), 0.0);  // opposite sides
      const std::vector<P2> A{P, Q, R1}, B{Q, P, R2};
      const std::vector<std::pair<P2, P2>> outer{{P, R1}, {R1, Q}, {Q, R2}, {R2, P}};
      int onEdge = 0;
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const P2& p : {P, Q, R1, R2})
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
      for (int py = int(std::floor(y0)) - 1; py <= int(std::floor(y1)) + 1; ++py)
        for (int px = int(std::floor(x0)) - 1; px <= int(std::floor(x1)) + 1; ++px) {
          onEdge += checkPartition({A, B}, outer, L, px, py);
          EXPECT_EQ(maskOf(A, L, px, py) & maskOf(B, L, px, py), 0u);
        }
      // The 5 lattice samples strictly between P and Q lie exactly on the edge (plus any other
      // samples within 1e-9 of the two triangles' outer edges' inner neighbourhood).
      EXPECT_GE(onEdge, 5) << L.name() << " dir " << d[0] << "," << d[1];
      onEdgeTotal += onEdge;
    }
    EXPECT_GE(onEdgeTotal, 40);
  }
}

TEST(PolygonMask, FanOfEightTrianglesCoversEachSampleOnce) {
  // Eight triangles around a shared centre C (random angles, random radii: a star-shaped
  // union): every sample inside the union and not within 1e-9 of its outer rim is covered by
  // exactly one triangle, samples outside by none. Samples on the spokes are the point.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int k = 0; k < 60; ++k) {
    const P2 C{-30 + 60 * U(rng), -30 + 60 * U(rng)};
    std::vector<P2> V;
    for (int i = 0; i < 8; ++i) {
      const double a = (i + 0.4 * (2 * U(rng) - 1)) * 2 * std::numbers::pi / 8, r = 1 + 4 * U(rng);
      V.push_back({C.x + r * std::cos(a), C.y + r * std::sin(a)});
    }
    std::vector<std::vector<P2>> tris;
    std::vector<std::pair<P2, P2>> outer;
    for (int i = 0; i < 8; ++i) {
      tris.push_back(i % 2 ? std::vector<P2>{C, V[i], V[(i + 1) % 8]} : std::vector<P2>{V[(i + 1) % 8], V[i], C});
      outer.push_back({V[i], V[(i + 1) % 8]});
    }
    for (const MaskLayout& L : kLayouts)
      for (int py = int(std::floor(C.y)) - 6; py <= int(std::floor(C.y)) + 6; ++py)
        for (int px = int(std::floor(C.x)) - 6; px <= int(std::floor(C.x)) + 6; ++px)
          checkPartition(tris, outer, L, px, py, &C);
  }
}

TEST(PolygonMask, FanAroundASamplePointCoversItOnce) {
  // A fan whose centre is itself a sample point, all coordinates dyadic (exact edge
  // functions): the consistent tie rule (a > 0, or b > 0 for horizontal edges) is the
  // symbolic perturbation (x + eps, y + eps^2), which lies in exactly one triangle of a full
  // fan, so the centre sample too is covered exactly once.
  for (const MaskLayout& L : kLayouts) {
    const double sx = 1.0 / L.w, sy = 1.0 / L.h;
    const P2 C{2 + 3.5 * sx, 1 + 1.5 * sy};  // a sample point of pixel (2, 1)
    // Rim vertices in lattice steps, counter-clockwise, including axis-aligned spokes.
    const int rim[][2] = {{8, 0}, {6, 6}, {0, 7}, {-5, 5}, {-9, 0}, {-4, -4}, {0, -6}, {7, -7}};
    std::vector<std::vector<P2>> tris;
    std::vector<std::pair<P2, P2>> outer;
    for (int i = 0; i < 8; ++i) {
      const P2 a{C.x + rim[i][0] * sx, C.y + rim[i][1] * sy};
      const P2 b{C.x + rim[(i + 1) % 8][0] * sx, C.y + rim[(i + 1) % 8][1] * sy};
      tris.push_back({C, a, b});
      outer.push_back({a, b});
    }
    int onSpokes = 0;
    for (int py = -2; py <= 4; ++py)
      for (int px = -1; px <= 5; ++px) onSpokes += checkPartition(tris, outer, L, px, py);
    // C itself and the lattice samples along the 8 spokes were checked.
    EXPECT_GE(onSpokes, 8) << L.name();
    // And directly: the centre sample is in exactly one mask.
    int count = 0;
    const int bit = 1 * L.w + 3;
    for (const auto& t : tris) count += int((maskOf(t, L, 2, 1) >> bit) & 1);
    EXPECT_EQ(count, 1) << L.name();
  }
}

// ---- exact areas ---------------------------------------------------------------------------

TEST(ScreenPolygonClip, PixelAreasOfATriangleSumToItsArea) {
  // The triangle clipped to every pixel of its bounding box (clipRect) partitions it: the
  // pieces' shoelace areas sum to the triangle's own, up to rounding (1e-9 relative), and no
  // piece exceeds the pixel.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int k = 0; k < 300; ++k) {
    const double cx = -200 + 400 * U(rng), cy = -200 + 400 * U(rng), size = k % 5 == 0 ? U(rng) : 1 + 12 * U(rng);
    std::vector<P2> v;
    for (int i = 0; i < 3; ++i) v.push_back({cx + size * (2 * U(rng) - 1), cy + size * (2 * U(rng) - 1)});
    const double want = std::abs(shoelace(v));
    if (want < 1e-6) continue;
    // Rounding: the clipped pieces' shoelace sums multiply coordinates of magnitude M, so each
    // piece carries an absolute error of a few eps * M^2 whatever its area; 1e-9 relative on
    // top of 16 eps M^2 per piece (a generous count of roundings per piece).
    const double M = std::max(std::abs(cx), std::abs(cy)) + size + 1;
    const double perPiece = 16 * std::numeric_limits<double>::epsilon() * M * M;
    const ScreenPolygon tri = makePolygon(v);
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const P2& p : v) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    double sum = 0;
    int pieces = 0;
    for (int py = int(std::floor(y0)); py < int(std::ceil(y1)); ++py)
      for (int px = int(std::floor(x0)); px < int(std::ceil(x1)); ++px) {
        ScreenPolygon piece;
        clipRect(tri, piece, px, py, px + 1, py + 1);
        const double a = piece.area();
        EXPECT_LE(a, 1.0 + 1e-12);
        for (int i = 0; i < piece.count; ++i) {
          // Clipped vertices lie in the pixel (new ones exactly on its sides).
          EXPECT_GE(piece.x[i], px);
          EXPECT_LE(piece.x[i], px + 1);
          EXPECT_GE(piece.y[i], py);
          EXPECT_LE(piece.y[i], py + 1);
        }
        sum += a;
        pieces += piece.count >= 3;
      }
    EXPECT_NEAR(sum, want, 1e-9 * want + pieces * perPiece) << "triangle " << k;
    EXPECT_LT(pieces * perPiece, 1e-5 * want + 1e-9);  // the allowance stays small
  }
}

TEST(ScreenPolygonClip, KnownPieces) {
  // Right triangle (0,0), (2,0), (0,2): pixel [0,1]^2 holds all of it below x + y = 2, i.e. the
  // whole unit square (area 1); pixel [1,2] x [0,1] holds the half below the diagonal (0.5).
  const ScreenPolygon tri = makePolygon({{0, 0}, {2, 0}, {0, 2}});
  ScreenPolygon piece;
  clipRect(tri, piece, 0, 0, 1, 1);
  EXPECT_NEAR(piece.area(), 1.0, 1e-15);
  clipRect(tri, piece, 1, 0, 2, 1);
  EXPECT_NEAR(piece.area(), 0.5, 1e-15);
  clipRect(tri, piece, 1, 1, 2, 2);
  EXPECT_NEAR(piece.area(), 0.0, 1e-15);  // only the corner point (1,1) touches it
  // Centroid of the half-pixel piece (1,0), (2,0), (1,1): the vertex mean (4/3, 1/3).
  clipRect(tri, piece, 1, 0, 2, 1);
  piece.removeDuplicates();
  double cx, cy;
  piece.centroid(cx, cy);
  EXPECT_NEAR(cx, 4.0 / 3.0, 1e-14);
  EXPECT_NEAR(cy, 1.0 / 3.0, 1e-14);
}

// isConvex against its definition written out (the turn at every vertex, indices modulo the
// count), on regular polygons (convex), the same with one vertex pulled inwards past its
// neighbours' chord (not convex), and the small counts whose indices wrap more than once.
TEST(ScreenPolygonConvex, MatchesTheTurnAtEveryVertex) {
  auto turnsOneWay = [](const ScreenPolygon& p) {
    int sign = 0;
    for (int i = 0; i < p.count; ++i) {
      const int j = (i + 1) % p.count, k = (i + 2) % p.count;
      const double cr = (p.x[j] - p.x[i]) * (p.y[k] - p.y[j]) - (p.y[j] - p.y[i]) * (p.x[k] - p.x[j]);
      const int s = cr > 0 ? 1 : (cr < 0 ? -1 : 0);
      if (s != 0 && sign != 0 && s != sign) return false;
      if (s != 0) sign = s;
    }
    return true;
  };
  for (int n = 1; n <= 12; ++n)
    for (int dent = -1; dent < n; ++dent) {
      std::vector<P2> v;
      for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.141592653589793 * i / n, r = i == dent ? 0.2 : 1.0;
        v.push_back({r * std::cos(a), r * std::sin(a)});
      }
      const ScreenPolygon p = makePolygon(v);
      EXPECT_EQ(isConvex(p), turnsOneWay(p)) << n << " vertices, vertex " << dent << " pulled in";
      if (n >= 5) {
        EXPECT_EQ(isConvex(p), dent < 0) << n << " vertices, vertex " << dent << " pulled in";
      }
    }
}

}  // namespace
}  // namespace wf
