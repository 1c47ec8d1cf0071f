// Fur (paper §4.2, §5): roots on the surface, the paper's tip formula, area-correct density,
// reproducibility, degenerate input, length, wind, clumping and colour regions. The test surfaces
// are small analytic ones defined here (plane, torus, sphere with poles, a double cone with a pole
// in the middle of its domain, surfaces with zero-area and NaN regions, a translated surface), so
// these tests depend on nothing but the Surface interface.
#include "growth/fur.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>
#include <tuple>

namespace wf {
namespace {

using glm::dvec2;
using glm::dvec3;
constexpr double kPi = std::numbers::pi;

// --- analytic test surfaces ------------------------------------------------------------------

// S = O + u A + v B on [0, 1]^2.
class PlaneSurface final : public Surface {
 public:
  PlaneSurface(dvec3 o, dvec3 a, dvec3 b) : o_(o), a_(a), b_(b) {}
  ParameterDomain domain() const override { return {}; }
  SurfacePoint evaluate(double u, double v) const override { return {o_ + u * a_ + v * b_, a_, b_}; }
  std::string describe() const override { return "test plane"; }

 private:
  dvec3 o_, a_, b_;
};

// Ring radius R, tube radius r, u around the ring, v around the tube; |Su| = R + r cos v.
class TorusSurface final : public Surface {
 public:
  TorusSurface(double R, double r) : R_(R), r_(r) {}
  ParameterDomain domain() const override { return {0, 2 * kPi, 0, 2 * kPi, true, true}; }
  SurfacePoint evaluate(double u, double v) const override {
    const double w = R_ + r_ * std::cos(v);
    return {{w * std::cos(u), w * std::sin(u), r_ * std::sin(v)},
            {-w * std::sin(u), w * std::cos(u), 0.0},
            {-r_ * std::sin(v) * std::cos(u), -r_ * std::sin(v) * std::sin(u), r_ * std::cos(v)}};
  }
  std::string describe() const override { return "test torus"; }

 private:
  double R_, r_;
};

// Radius r, v from the north pole (v = 0) to the south pole (v = pi), outward normal; poles where
// Su = 0. Area element r^2 sin v.
class SphereSurface final : public Surface {
 public:
  explicit SphereSurface(double r) : r_(r) {}
  ParameterDomain domain() const override { return {0, 2 * kPi, 0, kPi, true, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    const double su = std::sin(u), cu = std::cos(u), sv = std::sin(v), cv = std::cos(v);
    return {r_ * dvec3(sv * cu, -sv * su, cv), r_ * dvec3(-sv * su, -sv * cu, 0.0), r_ * dvec3(cv * cu, -cv * su, -sv)};
  }
  std::string describe() const override { return "test sphere"; }

 private:
  double r_;
};

// A double cone through the z axis: the row v = 0.5 collapses to a point (Su = 0), a pole in the
// middle of the domain, where cell centres of an odd grid land exactly.
class DoubleConeSurface final : public Surface {
 public:
  ParameterDomain domain() const override { return {0, 2 * kPi, 0, 1, true, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    const double r = v - 0.5;
    return {{r * std::cos(u), r * std::sin(u), v}, {-r * std::sin(u), r * std::cos(u), 0.0}, {std::cos(u), std::sin(u), 1.0}};
  }
  std::string describe() const override { return "test double cone"; }
};

// The unit square with the strips u < 1/4 and v < 1/4 clamped onto its edges: there Su or Sv (both
// in the corner) vanish, so those cells have zero area.
class ClampedPlaneSurface final : public Surface {
 public:
  ParameterDomain domain() const override { return {}; }
  SurfacePoint evaluate(double u, double v) const override {
    return {{std::max(u, 0.25), std::max(v, 0.25), 0.0}, {u > 0.25 ? 1.0 : 0.0, 0, 0}, {0, v > 0.25 ? 1.0 : 0.0, 0}};
  }
  std::string describe() const override { return "test clamped plane"; }
};

// The unit square, NaN everywhere for u > 1/2 (a broken adapter).
class HalfNaNSurface final : public Surface {
 public:
  ParameterDomain domain() const override { return {}; }
  SurfacePoint evaluate(double u, double v) const override {
    if (u > 0.5) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return {dvec3(nan), dvec3(nan), dvec3(nan)};
    }
    return {{u, v, 0.0}, {1, 0, 0}, {0, 1, 0}};
  }
  std::string describe() const override { return "test half-NaN plane"; }
};

// Another surface moved by an offset: the patch animated.
class TranslatedSurface final : public Surface {
 public:
  TranslatedSurface(const Surface& s, dvec3 offset) : s_(s), offset_(offset) {}
  ParameterDomain domain() const override { return s_.domain(); }
  SurfacePoint evaluate(double u, double v) const override {
    SurfacePoint p = s_.evaluate(u, v);
    p.P += offset_;
    return p;
  }
  std::string describe() const override { return "translated " + s_.describe(); }

 private:
  const Surface& s_;
  dvec3 offset_;
};

// --- helpers ---------------------------------------------------------------------------------

std::size_t hairCount(const Fur& f) { return f.hairs.polylineCount(); }
dvec3 root(const Fur& f, std::size_t h) { return f.hairs.points[f.hairs.starts[h]]; }
dvec3 tip(const Fur& f, std::size_t h) { return f.hairs.points[f.hairs.starts[h + 1] - 1]; }
std::uint32_t rootIndex(std::uint64_t id) { return std::uint32_t(id & 0xffffffffu); }

bool allFinite(const Fur& f) {
  for (const dvec3& p : f.hairs.points)
    if (!test::finite3(p)) return false;
  for (const glm::vec3& c : f.hairs.colours)
    if (!test::finite3(c)) return false;
  return true;
}

// Consistent shape: one polyline per id, points and colours per point, exactly sized.
void expectWellFormed(const Fur& f, int segments) {
  const std::size_t n = f.ids.size();
  EXPECT_EQ(f.counts.hairs, n);
  EXPECT_EQ(hairCount(f), n);
  EXPECT_EQ(f.rootUvs.size(), n);
  EXPECT_EQ(f.hairs.points.size(), n * (segments + 1));
  EXPECT_EQ(f.hairs.colours.size(), f.hairs.points.size());
  for (std::size_t h = 0; h <= n; ++h) ASSERT_EQ(f.hairs.starts[h], h * (segments + 1));
  // Reserved exactly (counts first).
  EXPECT_EQ(f.hairs.points.capacity(), f.hairs.points.size());
  EXPECT_EQ(f.hairs.colours.capacity(), f.hairs.colours.size());
  EXPECT_EQ(f.ids.capacity(), f.ids.size());
  EXPECT_EQ(f.hairs.starts.capacity(), f.hairs.starts.size());
  EXPECT_EQ(f.counts.rootsTried,
            f.counts.hairs + f.counts.skippedDegenerate + f.counts.skippedZeroLength + f.counts.skippedCapacity + f.counts.elsewhere);
  EXPECT_TRUE(allFinite(f));
}

bool identical(const Fur& a, const Fur& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
  return same(a.hairs.points, b.hairs.points) && same(a.hairs.colours, b.hairs.colours) &&
         same(a.hairs.starts, b.hairs.starts) && same(a.ids, b.ids) && same(a.rootUvs, b.rootUvs);
}

FurParams straight(int gridU, int gridV) {
  FurParams p;
  p.gridU = gridU;
  p.gridV = gridV;
  p.length = 0.1;
  return p;
}

// --- roots -----------------------------------------------------------------------------------

// Every root is S(u_root, v_root) (exactly: the same evaluation), and moving the patch moves every
// point of every hair by the same offset (tolerance 1e-12 relative to the offset's size) with the
// same ids: the hairs stick to the patch (paper §4.2). Curved, clumped hairs in wind included.
TEST(FurRoots, LieOnTheSurfaceAndMoveWithIt) {
  const TorusSurface torus(1.0, 0.35);
  const dvec3 offset(10.0, -5.0, 3.0);
  const TranslatedSurface moved(torus, offset);
  FurParams p = straight(60, 40);
  p.segments = 3;
  p.gravity = 0.5;
  p.windStrength = 0.3;
  p.time = 0.7;
  p.clumping = 0.5;
  p.curlAmplitude = 0.05;
  for (FurParams::Placement placement : {FurParams::Placement::Grid, FurParams::Placement::AreaCorrect}) {
    p.placement = placement;
    p.density = 500.0;
    const Fur a = growFur(torus, p, 3), b = growFur(moved, p, 3);
    expectWellFormed(a, 3);
    expectWellFormed(b, 3);
    ASSERT_GT(hairCount(a), 1000u);
    ASSERT_EQ(hairCount(a), hairCount(b));
    EXPECT_EQ(a.ids, b.ids);
    for (std::size_t h = 0; h < hairCount(a); ++h) {
      const dvec2 uv = a.rootUvs[h];
      ASSERT_EQ(root(a, h), torus.evaluate(uv.x, uv.y).P) << h;
      EXPECT_EQ(a.ids[h] >> 32, 3u);
    }
    double worst = 0;
    for (std::size_t i = 0; i < a.hairs.points.size(); ++i)
      worst = std::max(worst, test::maxAbsDiff(b.hairs.points[i] - a.hairs.points[i], offset));
    EXPECT_LT(worst, 1e-12 * 10.0 * 4) << "placement " << int(placement);
  }
}

// The paper's grid: gridU x gridV hairs, root (i, j) inside its cell of the (u, v) grid (jitter 1:
// anywhere in it; jitter 0: its centre), ids = j * gridU + i, in that order.
// maxPoints bounds the hairs' points, counted exactly before anything is allocated: a 100 x 100
// grid of 3-segment hairs has 40,000 points, refused at 39,999 and grown at 40,000; the
// area-correct count is bounded the same way.
TEST(FurLimit, MaxPointsIsCheckedExactlyBeforeGrowing) {
  const TorusSurface torus(1.0, 0.35);
  FurParams p;
  p.gridU = 100;
  p.gridV = 100;
  p.segments = 3;
  p.maxPoints = 39999;
  EXPECT_THROW(growFur(torus, p), std::length_error);
  p.maxPoints = 40000;
  EXPECT_EQ(growFur(torus, p).hairs.points.size(), 40000u);
  p.placement = FurParams::Placement::AreaCorrect;
  p.density = 1e9;  // about 1.4e10 roots: refused at once, not allocated
  p.maxPoints = 1e6;
  EXPECT_THROW(growFur(torus, p), std::length_error);
  p.maxPoints = -1;
  EXPECT_FALSE(p.problem().empty());
}

TEST(FurGrid, GivesGridUTimesGridVHairsJitteredWithinTheirCell) {
  const PlaneSurface plane({0, 0, 0}, {2, 0, 0}, {0, 3, 0});
  for (double jitter : {1.0, 0.0}) {
    FurParams p = straight(7, 5);
    p.jitter = jitter;
    const Fur f = growFur(plane, p);
    expectWellFormed(f, 1);
    ASSERT_EQ(hairCount(f), 35u);
    std::set<dvec2, bool (*)(const dvec2&, const dvec2&)> distinct(
        [](const dvec2& a, const dvec2& b) { return std::tie(a.x, a.y) < std::tie(b.x, b.y); });
    for (std::size_t h = 0; h < 35; ++h) {
      ASSERT_EQ(rootIndex(f.ids[h]), h);
      const int i = int(h % 7), j = int(h / 7);
      const dvec2 uv = f.rootUvs[h];
      if (jitter == 0.0) {
        EXPECT_NEAR(uv.x, (i + 0.5) / 7, 1e-15);
        EXPECT_NEAR(uv.y, (j + 0.5) / 5, 1e-15);
      } else {
        EXPECT_GE(uv.x, double(i) / 7);
        EXPECT_LE(uv.x, double(i + 1) / 7);
        EXPECT_GE(uv.y, double(j) / 5);
        EXPECT_LE(uv.y, double(j + 1) / 5);
        // Actually dithered: not at the centre.
        EXPECT_GT(std::abs(uv.x - (i + 0.5) / 7) + std::abs(uv.y - (j + 0.5) / 5), 1e-9);
      }
      distinct.insert(uv);
    }
    EXPECT_EQ(distinct.size(), 35u);
  }
}

// --- tips ------------------------------------------------------------------------------------

// H2 = H1 + a Su + b Sv + c N on a skewed plane, by hand: Su = A = (2, 0, 0.5), Sv = B = (0.3, 1.5, 0),
// A x B = (-0.75, 0.15, 3), |A x B| = sqrt(9.585). Literal (LengthMode::Paper) to 1e-14; Fixed length:
// the same direction, |H2 - H1| = length.
TEST(FurTip, IsThePaperFormulaOnAPlane) {
  const dvec3 A(2, 0, 0.5), B(0.3, 1.5, 0);
  const PlaneSurface plane({1, 2, 3}, A, B);
  const dvec3 N = dvec3(-0.75, 0.15, 3.0) / std::sqrt(9.585);
  const double a = 0.3, b = -0.2, c = 0.7;
  const dvec3 expected = a * A + b * B + c * N;  // (0.4869..., -0.2661..., 0.8280...)
  FurParams p = straight(4, 3);
  p.orientation = {a, b, c};
  p.lengthVariation = 0.0;
  p.lengthMode = FurParams::LengthMode::Paper;
  const Fur f = growFur(plane, p);
  expectWellFormed(f, 1);
  ASSERT_EQ(hairCount(f), 12u);
  for (std::size_t h = 0; h < 12; ++h) EXPECT_LT(test::maxAbsDiff(tip(f, h) - root(f, h), expected), 1e-14) << h;

  p.lengthMode = FurParams::LengthMode::Fixed;
  p.length = 0.25;
  const Fur g = growFur(plane, p);
  for (std::size_t h = 0; h < 12; ++h)
    EXPECT_LT(test::maxAbsDiff(tip(g, h) - root(g, h), 0.25 * glm::normalize(expected)), 1e-15) << h;
}

// Oscar (paper §4.2): length = k |Su|. On a torus |Su| = R + r cos v ranges over [0.65, 1.35]:
// every hair's length is k |Su(u_root, v_root)| to 1e-13 relative, and the lengths really vary.
TEST(FurLength, IsProportionalToSu) {
  const TorusSurface torus(1.0, 0.35);
  FurParams p = straight(50, 40);
  p.lengthMode = FurParams::LengthMode::ProportionalToSu;
  p.lengthPerSu = 0.1;
  p.lengthVariation = 0.0;
  const Fur f = growFur(torus, p);
  expectWellFormed(f, 1);
  double shortest = 1e9, longest = 0;
  for (std::size_t h = 0; h < hairCount(f); ++h) {
    const double expected = 0.1 * glm::length(torus.evaluate(f.rootUvs[h].x, f.rootUvs[h].y).Su);
    const double length = glm::length(tip(f, h) - root(f, h));
    EXPECT_NEAR(length, expected, 1e-13 * expected);
    shortest = std::min(shortest, length);
    longest = std::max(longest, length);
  }
  EXPECT_GT(longest / shortest, 1.9);  // 1.35 / 0.65 = 2.08 at the extremes

  // The random variation stays within 1 +- lengthVariation.
  p.lengthVariation = 0.3;
  const Fur g = growFur(torus, p);
  for (std::size_t h = 0; h < hairCount(g); ++h) {
    const double base = 0.1 * glm::length(torus.evaluate(g.rootUvs[h].x, g.rootUvs[h].y).Su);
    const double ratio = glm::length(tip(g, h) - root(g, h)) / base;
    EXPECT_GE(ratio, 0.7 - 1e-12);
    EXPECT_LE(ratio, 1.3 + 1e-12);
  }
}

// --- area-correct placement ------------------------------------------------------------------

int countIn(const Fur& f, double v0, double v1) {
  int n = 0;
  for (const dvec2& uv : f.rootUvs) n += uv.y >= v0 && uv.y < v1;
  return n;
}

// On a unit sphere the area element sin v is 0.2 near the poles and 1 at the equator. Hairs per unit
// area must match the density in both: counts within 4 sigma (Poisson sigma = sqrt(expected), an
// over-estimate: the per-cell counts are stratified). Uniform in (u, v) would put 1/8 of all hairs
// in the polar cap v < pi/8 (31416 instead of 9566) and fail by 200 sigma.
TEST(FurArea, HairsPerUnitAreaMatchTheDensity) {
  const SphereSurface sphere(1.0);
  FurParams p;
  p.placement = FurParams::Placement::AreaCorrect;
  p.density = 20000.0;
  p.cellsU = 64;
  p.cellsV = 32;
  const Fur f = growFur(sphere, p);
  expectWellFormed(f, 1);
  auto expectCount = [&](double v0, double v1, const char* what) {
    const double area = 2 * kPi * (std::cos(v0) - std::cos(v1));
    const double expected = p.density * area;
    const int n = countIn(f, v0, v1);
    EXPECT_NEAR(n, expected, 4 * std::sqrt(expected)) << what << ": " << n << " hairs, " << expected << " expected";
  };
  expectCount(0.0, kPi, "whole sphere");                              // 251327
  expectCount(0.0, kPi / 8, "north polar cap");                        // 9566
  expectCount(7 * kPi / 8, kPi, "south polar cap");                    // 9566
  expectCount(kPi / 2 - kPi / 16, kPi / 2 + kPi / 16, "equatorial band");  // 49029
  // Within a single cell too (placement inside a cell is area-correct by rejection): the polar row
  // of cells, v < pi/32, split at its middle: areas (1 - cos(pi/64)) : (cos(pi/64) - cos(pi/32)) = 1 : 3,
  // so 1/4 of the cell's hairs below the middle (uniform in v would give 1/2).
  const double lower = countIn(f, 0, kPi / 64), upper = countIn(f, kPi / 64, kPi / 32);
  const double total = lower + upper;
  EXPECT_NEAR(lower / total, 0.25, 4 * std::sqrt(0.25 * 0.75 / total));
}

// A higher density keeps every hair of the lower one (same id, same points, same colours) and adds
// new ones, about 2.5 times as many (within 2 %).
TEST(FurArea, HigherDensityKeepsEveryHairAndAddsNewOnes) {
  const TorusSurface torus(1.0, 0.35);
  FurParams p;
  p.placement = FurParams::Placement::AreaCorrect;
  p.segments = 2;
  p.gravity = 0.3;
  p.density = 2000.0;
  const Fur low = growFur(torus, p);
  p.density = 5000.0;
  const Fur high = growFur(torus, p);
  expectWellFormed(low, 2);
  expectWellFormed(high, 2);
  EXPECT_NEAR(double(hairCount(high)) / hairCount(low), 2.5, 0.05);
  std::map<std::uint64_t, std::size_t> index;
  for (std::size_t h = 0; h < hairCount(high); ++h) index[high.ids[h]] = h;
  EXPECT_EQ(index.size(), hairCount(high));  // ids unique
  for (std::size_t h = 0; h < hairCount(low); ++h) {
    const auto it = index.find(low.ids[h]);
    ASSERT_NE(it, index.end()) << "hair " << low.ids[h] << " lost";
    const std::size_t k = it->second;
    EXPECT_EQ(low.rootUvs[h], high.rootUvs[k]);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(low.hairs.points[3 * h + i], high.hairs.points[3 * k + i]);
      EXPECT_EQ(low.hairs.colours[3 * h + i], high.hairs.colours[3 * k + i]);
    }
  }
}

// --- reproducibility -------------------------------------------------------------------------

// Bit-identical output with 1 and 2 threads, for both placements, with every feature that draws
// random numbers on (many parallel blocks: 200 x 150 roots).
TEST(FurThreads, SameFurForOneAndTwoThreads) {
  const TorusSurface torus(1.0, 0.35);
  FurParams p = straight(200, 150);
  p.segments = 4;
  p.gravity = 0.5;
  p.curlAmplitude = 0.1;
  p.windStrength = 0.4;
  p.time = 1.3;
  p.clumping = 0.6;
  p.colourRegions.push_back({{0.5, 0.5}, 0.2, {1, 0, 0}, 0.5});
  for (FurParams::Placement placement : {FurParams::Placement::Grid, FurParams::Placement::AreaCorrect}) {
    p.placement = placement;
    p.density = 8000.0;
    Fur one, two;
    tbb::task_arena(1).execute([&] { one = growFur(torus, p, 7); });
    tbb::task_arena(2).execute([&] { two = growFur(torus, p, 7); });
    expectWellFormed(one, 4);
    ASSERT_GT(hairCount(one), 20000u);
    EXPECT_TRUE(identical(one, two)) << "placement " << int(placement);
  }
}

// --- degenerate input ------------------------------------------------------------------------

// A pole in the middle of the domain (Su = 0 on the row v = 1/2, where the centre row of a 5-row
// grid lands exactly): hairs there are finite, along the surface's limit normal (Surface::frame)
// and of the asked length; under length = k |Su| they have zero length and are dropped (counted),
// and the output is still well formed (gaps closed, exact size).
TEST(FurDegenerate, PoleGivesFiniteHairsOrNone) {
  const DoubleConeSurface cone;
  FurParams p = straight(16, 5);
  p.jitter = 0.0;
  p.lengthVariation = 0.0;
  const Fur f = growFur(cone, p);
  expectWellFormed(f, 1);
  ASSERT_EQ(hairCount(f), 80u);
  for (std::size_t h = 32; h < 48; ++h) {  // row j = 2
    const dvec2 uv = f.rootUvs[h];
    ASSERT_EQ(uv.y, 0.5);
    const SurfaceFrame fr = cone.frame(uv.x, uv.y);
    EXPECT_TRUE(fr.degenerate);
    EXPECT_LT(test::maxAbsDiff(tip(f, h) - root(f, h), 0.1 * fr.N), 1e-12);
  }

  p.lengthMode = FurParams::LengthMode::ProportionalToSu;
  const Fur g = growFur(cone, p);
  expectWellFormed(g, 1);
  EXPECT_EQ(hairCount(g), 64u);
  EXPECT_EQ(g.counts.skippedZeroLength, 16u);
  for (std::size_t h = 0; h < hairCount(g); ++h) EXPECT_NE(g.rootUvs[h].y, 0.5);
  EXPECT_EQ(rootIndex(g.ids[32]), 48u);  // the first hair after the dropped row

  // A sphere's poles, jittered grid and area-correct: finite everywhere.
  const SphereSurface sphere(2.0);
  FurParams q = straight(64, 64);
  q.unitTangents = true;
  q.orientation = {0.5, 0.5, 1.0};
  q.curlAmplitude = 0.1;
  expectWellFormed(growFur(sphere, q), 1);
  q.placement = FurParams::Placement::AreaCorrect;
  q.density = 500.0;  // 25000 hairs
  expectWellFormed(growFur(sphere, q), 1);
}

// Zero-area cells (u < 1/4 or v < 1/4 clamped onto an edge) and a surface that is NaN for u > 1/2.
// Grid: every zero-area root still grows a finite hair (limit normal); NaN roots grow none and are
// counted. Area-correct: zero-area and NaN cells get no hairs; the rest match the density (4 sigma).
TEST(FurDegenerate, ZeroAreaCellsAndNaNSurfacesGiveFiniteHairsOrNone) {
  const ClampedPlaneSurface clamped;
  FurParams p = straight(40, 40);
  const Fur grid = growFur(clamped, p);
  expectWellFormed(grid, 1);
  EXPECT_EQ(hairCount(grid), 1600u);

  p.placement = FurParams::Placement::AreaCorrect;
  p.density = 40000.0;
  p.cellsU = p.cellsV = 20;
  const Fur area = growFur(clamped, p);
  expectWellFormed(area, 1);
  const double expected = p.density * 0.75 * 0.75;
  EXPECT_NEAR(double(hairCount(area)), expected, 4 * std::sqrt(expected));
  for (const dvec2& uv : area.rootUvs) EXPECT_TRUE(uv.x >= 0.25 && uv.y >= 0.25);

  const HalfNaNSurface broken;
  p = straight(40, 40);
  const Fur half = growFur(broken, p);
  expectWellFormed(half, 1);
  EXPECT_EQ(hairCount(half), 800u);
  EXPECT_EQ(half.counts.skippedDegenerate, 800u);
  for (const dvec2& uv : half.rootUvs) EXPECT_LE(uv.x, 0.5);
  p.placement = FurParams::Placement::AreaCorrect;
  p.density = 4000.0;
  p.clumping = 1.0;
  const Fur halfArea = growFur(broken, p);
  expectWellFormed(halfArea, 1);
  EXPECT_NEAR(double(hairCount(halfArea)), 2000.0, 4 * std::sqrt(2000.0));
}

// NaN / Inf / out-of-range parameters are rejected by name; growFur then throws with that line.
TEST(FurParamsCheck, RejectsNaNAndInfByName) {
  EXPECT_EQ(FurParams{}.problem(), "");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* field;
    void (*set)(FurParams&, double);
  };
  const Case cases[] = {
      {"jitter", [](FurParams& p, double x) { p.jitter = x; }},
      {"density", [](FurParams& p, double x) { p.density = x; }},
      {"orientation", [](FurParams& p, double x) { p.orientation.y = x; }},
      {"length", [](FurParams& p, double x) { p.length = x; }},
      {"lengthPerSu", [](FurParams& p, double x) { p.lengthPerSu = x; }},
      {"lengthVariation", [](FurParams& p, double x) { p.lengthVariation = x; }},
      {"gravity", [](FurParams& p, double x) { p.gravity = x; }},
      {"gravityDirection", [](FurParams& p, double x) { p.gravityDirection.z = x; }},
      {"curlAmplitude", [](FurParams& p, double x) { p.curlAmplitude = x; }},
      {"curlFrequency", [](FurParams& p, double x) { p.curlFrequency = x; }},
      {"clumping", [](FurParams& p, double x) { p.clumping = x; }},
      {"windDirection", [](FurParams& p, double x) { p.windDirection.x = x; }},
      {"windStrength", [](FurParams& p, double x) { p.windStrength = x; }},
      {"windFrequency", [](FurParams& p, double x) { p.windFrequency = x; }},
      {"time", [](FurParams& p, double x) { p.time = x; }},
      {"rootColour", [](FurParams& p, double x) { p.rootColour.y = float(x); }},
      {"tipColour", [](FurParams& p, double x) { p.tipColour.z = float(x); }},
      {"intensityVariation", [](FurParams& p, double x) { p.intensityVariation = x; }},
      {"thickness", [](FurParams& p, double x) { p.thickness = x; }},
      {"colourRegions[0].radius", [](FurParams& p, double x) { p.colourRegions = {FurColourRegion{}}; p.colourRegions[0].radius = x; }},
      {"colourRegions[0].centre", [](FurParams& p, double x) { p.colourRegions = {FurColourRegion{}}; p.colourRegions[0].centre.x = x; }},
  };
  const PlaneSurface plane({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  for (const Case& c : cases)
    for (double bad : {nan, inf, -inf}) {
      FurParams p;
      c.set(p, bad);
      const std::string why = p.problem();
      EXPECT_NE(why.find(std::string("FurParams.") + c.field), std::string::npos) << c.field << " = " << bad << ": '" << why << "'";
      try {
        growFur(plane, p);
        ADD_FAILURE() << c.field << " = " << bad << ": grew fur";
      } catch (const std::invalid_argument& e) {
        EXPECT_EQ(e.what(), why);
      }
    }
  FurParams p;
  p.gridU = 0;
  EXPECT_NE(p.problem().find("gridU"), std::string::npos);
  p = FurParams{};
  p.segments = 65;
  EXPECT_NE(p.problem().find("segments"), std::string::npos);
  // Valid, but 65535^2 hairs of 2 points do not fit PolylineSet's 32-bit starts: refused before
  // anything is allocated.
  p = FurParams{};
  p.gridU = p.gridV = 65535;
  EXPECT_EQ(p.problem(), "");
  EXPECT_THROW(growFur(plane, p), std::length_error);
}

// --- maps ------------------------------------------------------------------------------------

// A scalar map over the patch's unit (s, t): f(s) = step at s = 1/2 (times `scale`).
class StepMap final : public ScalarTexture {
 public:
  StepMap(double low, double high) : low_(low), high_(high) {}
  double value(const dvec2& st) const override { return st.x < 0.5 ? low_ : high_; }
  dvec2 gradient(const dvec2&) const override { return dvec2(0.0); }
  std::string describe() const override { return "test step"; }

 private:
  double low_, high_;
};

class StepColour final : public ColourTexture {
 public:
  glm::vec3 sample(const dvec2& st, const UvFootprint&) const override {
    return st.x < 0.5 ? glm::vec3(0.1f, 0.2f, 0.3f) : glm::vec3(0.7f, 0.8f, 0.9f);
  }
  std::string describe() const override { return "test step colour"; }
};

// Maps over the patch's unit (s, t) (here u in [0, 2]: s = u / 2): a density map of 0 | 1 leaves the
// left half bare and the right at the density (4 sigma); a length map of 1 | 3 triples lengths; an
// orientation map replaces a; a root colour map replaces the root colour, not the tip's.
TEST(FurMaps, DensityLengthOrientationAndRootColourFollowTheirMaps) {
  const PlaneSurface plane({0, 0, 0}, {2, 0, 0}, {0, 1, 0});  // u in [0, 1] spans x in [0, 2]
  FurParams p;
  p.placement = FurParams::Placement::AreaCorrect;
  p.density = 5000.0;
  p.densityMap = std::make_shared<StepMap>(0.0, 1.0);
  const Fur dense = growFur(plane, p);
  expectWellFormed(dense, 1);
  EXPECT_NEAR(double(hairCount(dense)), 5000.0, 4 * std::sqrt(5000.0));  // area 1 on the right
  for (const dvec2& uv : dense.rootUvs) EXPECT_GE(uv.x, 0.5);

  FurParams q = straight(20, 10);
  q.lengthVariation = 0.0;
  q.intensityVariation = 0.0;
  q.lengthMap = std::make_shared<StepMap>(1.0, 3.0);
  q.orientationMapA = std::make_shared<StepMap>(0.0, 0.5);
  q.rootColourMap = std::make_shared<StepColour>();
  const Fur f = growFur(plane, q);
  expectWellFormed(f, 1);
  for (std::size_t h = 0; h < hairCount(f); ++h) {
    const bool right = f.rootUvs[h].x >= 0.5;
    const dvec3 axis = right ? glm::normalize(dvec3(0.5 * 2, 0, 1)) : dvec3(0, 0, 1);  // a Su + c N
    EXPECT_LT(test::maxAbsDiff(tip(f, h) - root(f, h), (right ? 0.3 : 0.1) * axis), 1e-15);
    EXPECT_EQ(f.hairs.colours[2 * h], right ? glm::vec3(0.7f, 0.8f, 0.9f) : glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(f.hairs.colours[2 * h + 1], q.tipColour);
  }
}

// --- wind ------------------------------------------------------------------------------------

// Wind is a pure function of time: the same t gives bit-identical hairs, a different t moves (nearly)
// every hair, windStrength 0 equals no wind whatever t, and the displacement grows towards the tip.
TEST(FurWind, IsAFunctionOfTimeStrongerAtTheTip) {
  const TorusSurface torus(1.0, 0.35);
  FurParams calm = straight(40, 30);
  calm.segments = 4;
  FurParams windy = calm;
  windy.windStrength = 0.5;
  windy.windDirection = {0.0, 1.0, 0.0};
  windy.time = 0.25;
  const Fur a = growFur(torus, windy), b = growFur(torus, windy);
  EXPECT_TRUE(identical(a, b));
  FurParams later = windy;
  later.time = 0.6;
  const Fur c = growFur(torus, later);
  std::size_t moved = 0;
  for (std::size_t h = 0; h < hairCount(a); ++h) moved += tip(a, h) != tip(c, h);
  EXPECT_GT(moved, hairCount(a) * 99 / 100);

  FurParams zero = windy;
  zero.windStrength = 0.0;
  zero.time = 3.7;
  const Fur still = growFur(torus, calm);
  EXPECT_TRUE(identical(growFur(torus, zero), still));

  // Displacement from the calm hair grows point by point towards the tip (roots do not move).
  for (std::size_t h = 0; h < hairCount(a); h += 37) {
    double previous = 0.0;
    for (int k = 0; k <= 4; ++k) {
      const double d = glm::length(a.hairs.points[5 * h + k] - still.hairs.points[5 * h + k]);
      if (k == 0) EXPECT_EQ(d, 0.0);
      else EXPECT_GT(d, previous) << "hair " << h << " point " << k;
      previous = d;
    }
  }
}

// --- clumping --------------------------------------------------------------------------------

// Clumping 1 pulls every tip onto its clump centre's tip: at most clumpCellsU x clumpCellsV distinct
// tips (16 for 400 hairs), while without clumping all 400 tips differ. Roots do not move.
TEST(FurClumping, OnePutsClumpedTipsTogether) {
  const PlaneSurface plane({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  FurParams p = straight(20, 20);
  p.clumpCellsU = p.clumpCellsV = 4;
  p.segments = 3;
  auto distinctTips = [](const Fur& f) {
    std::set<std::tuple<double, double, double>> tips;
    for (std::size_t h = 0; h < hairCount(f); ++h) {
      const dvec3 t = glm::round(tip(f, h) * 1e9) * 1e-9;
      tips.insert({t.x, t.y, t.z});
    }
    return tips.size();
  };
  const Fur loose = growFur(plane, p);
  p.clumping = 1.0;
  const Fur clumped = growFur(plane, p);
  expectWellFormed(clumped, 3);
  EXPECT_EQ(distinctTips(loose), 400u);
  EXPECT_LE(distinctTips(clumped), 16u);
  EXPECT_GE(distinctTips(clumped), 8u);  // really several clumps
  for (std::size_t h = 0; h < 400; ++h) EXPECT_EQ(root(loose, h), root(clumped, h));
}

// --- colour ----------------------------------------------------------------------------------

// Root colour at the root, tip colour at the tip, times one random intensity per hair within
// 1 +- intensityVariation. A colour region changes hairs only within its radius: outside they are
// bit-identical to the fur without it; inside the inner radius (1 - falloff) they take its colour.
TEST(FurColour, RootToTipAndRegionsOnlyWithinTheirRadius) {
  const PlaneSurface plane({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  FurParams p = straight(60, 60);
  p.segments = 2;
  p.rootColour = {0.2f, 0.4f, 0.6f};
  p.tipColour = {0.8f, 0.6f, 0.4f};
  p.intensityVariation = 0.2;
  const Fur base = growFur(plane, p);
  for (std::size_t h = 0; h < hairCount(base); ++h) {
    const glm::vec3 r = base.hairs.colours[3 * h], m = base.hairs.colours[3 * h + 1], t = base.hairs.colours[3 * h + 2];
    const float f = r.x / 0.2f;
    EXPECT_GE(f, 0.8f - 1e-6f);
    EXPECT_LE(f, 1.2f + 1e-6f);
    EXPECT_NEAR(r.z, 0.6f * f, 1e-6f);
    EXPECT_NEAR(t.x, 0.8f * f, 1e-6f);
    EXPECT_NEAR(m.y, 0.5f * f, 1e-6f);
  }

  p.intensityVariation = 0.0;
  const Fur plain = growFur(plane, p);
  p.colourRegions.push_back({{0.3, 0.6}, 0.2, {1.0f, 0.0f, 0.0f}, 0.5});
  const Fur joint = growFur(plane, p);
  int inside = 0, outside = 0;
  for (std::size_t h = 0; h < hairCount(plain); ++h) {
    const double d = glm::length(plain.rootUvs[h] - dvec2(0.3, 0.6));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 before = plain.hairs.colours[3 * h + k], after = joint.hairs.colours[3 * h + k];
      if (d >= 0.2) {
        EXPECT_EQ(before, after);
      } else if (d <= 0.1) {
        EXPECT_EQ(after, glm::vec3(1.0f, 0.0f, 0.0f));
      } else {
        EXPECT_NE(before, after);  // fading: between the two
      }
    }
    inside += d <= 0.1;
    outside += d >= 0.2;
  }
  EXPECT_GT(inside, 50);   // pi 0.1^2 * 3600 = 113
  EXPECT_GT(outside, 2000);
}

// --- shares (a distributed surface's pieces) --------------------------------------------------

// Three shares of the torus by a band across u: each share's fur, put together and ordered by id,
// is the whole fur, hair for hair and point for point (bit for bit), for the grid and the
// area-correct lattice, with clumping and curl (which read other roots' positions); every root
// is counted in exactly one share and `elsewhere` in the others.
TEST(FurShares, UnionOfTheSharesIsTheWholeFurBitForBit) {
  const TorusSurface torus(2.0, 0.6);
  for (auto placement : {FurParams::Placement::Grid, FurParams::Placement::AreaCorrect}) {
    FurParams p;
    p.placement = placement;
    p.gridU = 61;
    p.gridV = 23;
    p.density = 300.0;
    p.cellsU = 13;
    p.cellsV = 7;
    p.segments = 4;
    p.curlAmplitude = 0.01;
    p.clumping = 0.5;
    const Fur whole = growFur(torus, p, 3);
    ASSERT_GT(hairCount(whole), 500u);
    std::map<std::uint64_t, std::vector<dvec3>> pieces;
    std::uint64_t elsewhere = 0, hairs = 0;
    for (int share = 0; share < 3; ++share) {
      FurParams q = p;
      q.rootFilter = [share](const dvec2& uv) { return std::min(int(uv.x / (2 * kPi) * 3), 2) == share; };
      const Fur f = growFur(torus, q, 3);
      expectWellFormed(f, 4);
      EXPECT_GT(hairCount(f), hairCount(whole) / 5);
      EXPECT_EQ(f.counts.hairs + f.counts.elsewhere, whole.counts.hairs);
      hairs += f.counts.hairs;
      elsewhere += f.counts.elsewhere;
      for (std::size_t h = 0; h < hairCount(f); ++h) {
        std::vector<dvec3> pts(f.hairs.points.begin() + f.hairs.starts[h], f.hairs.points.begin() + f.hairs.starts[h + 1]);
        EXPECT_TRUE(pieces.emplace(f.ids[h], std::move(pts)).second) << "hair " << f.ids[h] << " in two shares";
      }
    }
    EXPECT_EQ(hairs, whole.counts.hairs);
    EXPECT_EQ(elsewhere, 2 * whole.counts.hairs);
    ASSERT_EQ(pieces.size(), hairCount(whole));
    for (std::size_t h = 0; h < hairCount(whole); ++h) {
      const auto it = pieces.find(whole.ids[h]);
      ASSERT_NE(it, pieces.end());
      ASSERT_EQ(it->second.size(), whole.hairs.starts[h + 1] - whole.hairs.starts[h]);
      EXPECT_EQ(std::memcmp(it->second.data(), whole.hairs.points.data() + whole.hairs.starts[h],
                            it->second.size() * sizeof(dvec3)),
                0)
          << "hair " << whole.ids[h];
    }
  }
}

}  // namespace
}  // namespace wf
