// Scales (paper §4.2, images 17 and 21) on small analytic surfaces defined here.
#include "growth/scales.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>
#include <tuple>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace wf {
namespace {

constexpr double kPi = std::numbers::pi;

/// S(u, v) = (2u, 3v, 0) over [0, 1]^2.
class TestPlane final : public Surface {
 public:
  ParameterDomain domain() const override { return {}; }
  SurfacePoint evaluate(double u, double v) const override {
    return {{2 * u, 3 * v, 0.0}, {2, 0, 0}, {0, 3, 0}};
  }
  std::string describe() const override { return "test plane 2x3"; }
};

/// Torus R = 2, r = 0.5, periodic in u and v over [0, 2 pi]^2.
class TestTorus final : public Surface {
 public:
  ParameterDomain domain() const override {
    ParameterDomain d{0.0, 2 * kPi, 0.0, 2 * kPi};
    d.periodicU = d.periodicV = true;
    return d;
  }
  SurfacePoint evaluate(double u, double v) const override {
    const double R = 2.0, r = 0.5, w = R + r * std::cos(v);
    return {{w * std::cos(u), w * std::sin(u), r * std::sin(v)},
            {-w * std::sin(u), w * std::cos(u), 0.0},
            {-r * std::sin(v) * std::cos(u), -r * std::sin(v) * std::sin(u), r * std::cos(v)}};
  }
  std::string describe() const override { return "test torus"; }
};

/// Unit sphere, u longitude in [0, 2 pi] (periodic), v latitude in [-pi/2, pi/2]: poles at
/// v = -pi/2 (the corner row of scales) and v = pi/2, where Su = 0.
class TestSphere final : public Surface {
 public:
  ParameterDomain domain() const override {
    ParameterDomain d{0.0, 2 * kPi, -kPi / 2, kPi / 2};
    d.periodicU = true;
    return d;
  }
  SurfacePoint evaluate(double u, double v) const override {
    const double cv = std::cos(v), sv = std::sin(v), cu = std::cos(u), su = std::sin(u);
    if (std::fabs(v) >= kPi / 2) return {{0, 0, v > 0 ? 1.0 : -1.0}, {0, 0, 0}, {-sv * cu, -sv * su, 0}};
    return {{cv * cu, cv * su, sv}, {-cv * su, cv * cu, 0.0}, {-sv * cu, -sv * su, cv}};
  }
  std::string describe() const override { return "test sphere"; }
};

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(Scales, TwoScalesOfTwoTrianglesPerCell) {
  const TestPlane plane;
  ScaleParams p;
  p.cellsU = 7;
  p.cellsV = 5;
  const TriangleMesh m = growScales(plane, p);
  EXPECT_EQ(m.triangles.size(), size_t(4 * 7 * 5));
  EXPECT_EQ(m.positions.size(), size_t(8 * 7 * 5));
  for (auto* attr : {&m.normals, &m.tangents, &m.derivU, &m.derivV})
    EXPECT_EQ(attr->size(), m.positions.size());
  EXPECT_EQ(m.uvs.size(), m.positions.size());
  EXPECT_EQ(m.colours.size(), m.positions.size());
}

// The mask trims scales as a CAD face's trimming does: on 8 x 4 cells with the left half of the
// unit square masked in, the corners (i / 8 < 1/2: i = 0 ... 3) and the centres ((i + 1/2) / 8 <
// 1/2: i = 0 ... 3) of every row grow, 32 scales of 64 triangles, every root at x = 2u < 1.
TEST(Scales, MaskLeavesOutScalesRootedOutside) {
  struct LeftHalf final : ScalarTexture {
    double value(const glm::dvec2& st) const override { return st.x < 0.5 ? 1.0 : 0.0; }
    glm::dvec2 gradient(const glm::dvec2&) const override { return glm::dvec2(0.0); }
    std::string describe() const override { return "left half"; }
  };
  const TestPlane plane;
  ScaleParams p;
  p.cellsU = 8;
  p.cellsV = 4;
  p.mask = std::make_shared<LeftHalf>();
  const TriangleMesh m = growScales(plane, p);
  EXPECT_EQ(m.triangles.size(), size_t(64));
  for (size_t k = 0; k < m.positions.size(); k += 4) EXPECT_LT(m.positions[k].x, 1.0);  // vertex 0: the root
}

// maxTriangles bounds the scales before anything is allocated: 10 x 10 cells make 400
// triangles, refused at 399 and grown at 400.
TEST(Scales, MaxTrianglesIsCheckedBeforeGrowing) {
  const TestTorus torus;
  ScaleParams p;
  p.cellsU = 10;
  p.cellsV = 10;
  p.maxTriangles = 399;
  EXPECT_THROW(growScales(torus, p), std::length_error);
  p.maxTriangles = 400;
  EXPECT_EQ(growScales(torus, p).triangles.size(), 400u);
}

TEST(Scales, CornerAndCentreRootsOnTheSurfaceAtTheirUv) {
  const TestTorus torus;
  ScaleParams p;
  p.cellsU = 12;
  p.cellsV = 6;
  const TriangleMesh m = growScales(torus, p, 3);
  ASSERT_EQ(m.triangles.size(), size_t(4 * 12 * 6));
  const ParameterDomain d = torus.domain();
  double worst = 0.0;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 12; ++i) {
      const size_t c = size_t(j) * 12 + size_t(i);
      const glm::dvec2 corner = d.fromUnit(i / 12.0, j / 6.0);
      const glm::dvec2 centre = d.fromUnit((i + 0.5) / 12.0, (j + 0.5) / 6.0);
      for (int k = 0; k < 2; ++k) {
        const size_t root = 4 * (2 * c + k);
        const glm::dvec2 uv = k == 0 ? corner : centre;
        EXPECT_NEAR(m.uvs[root].x, uv.x, 1e-12);
        EXPECT_NEAR(m.uvs[root].y, uv.y, 1e-12);
        const glm::dvec3 S = torus.evaluate(uv.x, uv.y).P;
        worst = std::max(worst, glm::length(m.positions[root] - S));
        EXPECT_LT(glm::length(m.positions[root] - S), 1e-12);
        // The tip lies along +u and above the surface.
        const SurfaceFrame f = torus.frame(uv.x, uv.y);
        const glm::dvec3 tip = m.positions[root + 2] - S;
        EXPECT_GT(glm::dot(tip, f.Tu), 0.0);
        EXPECT_NEAR(glm::dot(tip, f.N), p.lift * glm::dot(tip, f.Tu), 1e-12);
        // The sides straddle the centre line along Tv.
        EXPECT_LT(glm::dot(m.positions[root + 1] - S, f.Tv), 0.0);
        EXPECT_GT(glm::dot(m.positions[root + 3] - S, f.Tv), 0.0);
        // Triangles face +N.
        const glm::uvec3 t = m.triangles[2 * (2 * c + k)];
        const glm::dvec3 fn = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
        EXPECT_GT(glm::dot(fn, f.N), 0.0);
        EXPECT_EQ(m.derivU[root], f.Su);
      }
    }
  RecordProperty("worst_root_distance", testing::PrintToString(worst));
}

TEST(Scales, NormalsAreUnitAndDeflectedOutward) {
  const TestTorus torus;
  ScaleParams p;
  p.cellsU = 10;
  p.cellsV = 4;
  p.deflection = 0.5;
  ScaleParams flat = p;
  flat.deflection = 0.0;
  const TriangleMesh m = growScales(torus, p), mf = growScales(torus, flat);
  ASSERT_EQ(m.positions.size(), mf.positions.size());
  for (size_t s = 0; s < m.positions.size() / 4; ++s) {
    glm::dvec3 centre(0.0);
    for (int k = 0; k < 4; ++k) centre += 0.25 * m.positions[4 * s + k];
    for (int k = 0; k < 4; ++k) {
      const size_t i = 4 * s + k;
      EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
      // Flat normals are the kite's plane normal; deflection adds an outward component.
      const glm::dvec3 offset = m.positions[i] - centre;
      EXPECT_GT(glm::dot(m.normals[i] - mf.normals[i], offset), 0.0) << "scale " << s << " vertex " << k;
      EXPECT_GT(glm::dot(m.normals[i], mf.normals[i]), std::cos(std::atan(0.5)) - 1e-12);
    }
  }
}

TEST(Scales, IntensitiesVaryWithinTheVariation) {
  const TestPlane plane;
  ScaleParams p;
  p.cellsU = 20;
  p.cellsV = 20;
  p.intensityVariation = 0.3;
  p.colour = glm::vec3(0.5f, 1.0f, 0.25f);
  const TriangleMesh m = growScales(plane, p);
  double lo = 10.0, hi = -10.0;
  for (size_t s = 0; s < m.positions.size() / 4; ++s) {
    const double intensity = m.colours[4 * s].y;  // colour.y = 1
    for (int k = 1; k < 4; ++k) EXPECT_EQ(m.colours[4 * s + k], m.colours[4 * s]);
    EXPECT_NEAR(m.colours[4 * s].x, 0.5 * intensity, 1e-6);
    lo = std::min(lo, intensity);
    hi = std::max(hi, intensity);
  }
  EXPECT_GE(lo, 0.7 - 1e-6);
  EXPECT_LE(hi, 1.3 + 1e-6);
  EXPECT_GT(hi - lo, 0.5);  // 800 scales spread over most of [0.7, 1.3]
}

TEST(Scales, SameForOneAndTwoThreadsAndDeterministic) {
  const TestTorus torus;
  ScaleParams p;
  p.cellsU = 40;
  p.cellsV = 30;
  TriangleMesh one, two;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = growScales(torus, p, 2);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    two = growScales(torus, p, 2);
  }
  EXPECT_EQ(one.positions, two.positions);
  EXPECT_EQ(one.normals, two.normals);
  EXPECT_EQ(one.colours, two.colours);
  EXPECT_EQ(one.triangles, two.triangles);
  // Another patch index gives another intensity series, same geometry.
  const TriangleMesh other = growScales(torus, p, 5);
  EXPECT_EQ(other.positions, one.positions);
  EXPECT_NE(other.colours, one.colours);
}

TEST(Scales, PoleGivesNoNaNAndSkipsOnlyDegenerateRoots) {
  const TestSphere sphere;
  ScaleParams p;
  p.cellsU = 8;
  p.cellsV = 6;
  const TriangleMesh m = growScales(sphere, p);
  // The corner scales of row j = 0 sit on the south pole (Su = 0): 8 scales, 16 triangles left
  // out; every other root is regular.
  EXPECT_EQ(m.triangles.size(), size_t(4 * 8 * 6 - 2 * 8));
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_TRUE(finite3(m.positions[i]));
    EXPECT_TRUE(finite3(m.normals[i]));
    EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
  }
  for (const glm::uvec3& t : m.triangles) EXPECT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
}

TEST(Scales, ProblemNamesTheField) {
  EXPECT_EQ(ScaleParams{}.problem(), "");
  ScaleParams p;
  p.cellsU = 0;
  EXPECT_NE(p.problem().find("cellsU"), std::string::npos);
  p = {};
  p.size = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(p.problem().find("size"), std::string::npos);
  p = {};
  p.intensityVariation = 1.5;
  EXPECT_NE(p.problem().find("intensityVariation"), std::string::npos);
  p = {};
  p.deflection = -1.0;
  EXPECT_NE(p.problem().find("deflection"), std::string::npos);
  p = {};
  p.cellsV = 16385;
  EXPECT_NE(p.problem().find("cellsV"), std::string::npos);
  EXPECT_THROW(growScales(TestPlane{}, p), std::invalid_argument);
}

// Two shares of the torus's scales by a band across v: the union, put together by (root uv, first
// point), is the whole set of scales bit for bit, each scale in exactly one share.
TEST(Scales, UnionOfTwoSharesIsTheWholeBitForBit) {
  const TestTorus torus;
  ScaleParams p;
  p.cellsU = 24;
  p.cellsV = 9;
  const TriangleMesh whole = growScales(torus, p, 2);
  auto key = [](const TriangleMesh& m, std::size_t s) {
    const glm::dvec3 q = m.positions[4 * s + 2];
    return std::make_tuple(m.uvs[4 * s].x, m.uvs[4 * s].y, q.x, q.y, q.z);
  };
  std::map<std::tuple<double, double, double, double, double>, int> seen;
  std::size_t scales = 0;
  for (int share = 0; share < 2; ++share) {
    ScaleParams q = p;
    q.rootFilter = [share](const glm::dvec2& uv) { return (uv.y < kPi) == (share == 0); };
    const TriangleMesh m = growScales(torus, q, 2);
    ASSERT_EQ(m.positions.size() % 4, 0u);
    EXPECT_GT(m.positions.size(), whole.positions.size() / 4);
    scales += m.positions.size() / 4;
    for (std::size_t s = 0; s < m.positions.size() / 4; ++s) EXPECT_TRUE(seen.emplace(key(m, s), share).second);
  }
  ASSERT_EQ(scales, whole.positions.size() / 4);
  for (std::size_t s = 0; s < scales; ++s) EXPECT_EQ(seen.count(key(whole, s)), 1u) << "scale " << s;
}

}  // namespace
}  // namespace wf
