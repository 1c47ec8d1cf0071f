// The surface concept and its analytic patches: derivatives against finite differences, limit
// frames at poles, tessellation (normals, winding, seams, collapsed triangles, area convergence).
#include "surface/patches.h"
#include "surface/surface.h"
#include "surface/tessellate.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace wf {
namespace {

using test::finite3;
constexpr double kPi = std::numbers::pi;

const std::vector<glm::dvec2> kJugProfile = {{0.0, -1.0}, {0.55, -1.0}, {0.62, -0.9}, {0.7, -0.6},
                                             {0.72, -0.3}, {0.66, 0.0},  {0.5, 0.3},   {0.36, 0.55},
                                             {0.32, 0.75}, {0.36, 0.9},  {0.42, 1.0}};

// Oscar-like body: a curved spine, closed (radius 0) at both ends.
std::vector<LoftSection> bodySections() {
  return {{{0.0, 0.0, 0.0}, 0.0, 0.0, {}},   {{0.5, 0.0, 0.1}, 0.35, 0.3, {}}, {{1.2, 0.1, 0.25}, 0.5, 0.42, {}},
          {{2.0, 0.0, 0.2}, 0.45, 0.4, {}},  {{2.6, -0.1, 0.4}, 0.3, 0.25, {}}, {{2.9, 0.0, 0.5}, 0.0, 0.0, {}}};
}

// A leg with star-like 5-point profiles, running mostly along -z (so up = auto picks another axis).
std::vector<LoftSection> legSections() {
  auto star = [](double k) {
    std::vector<glm::dvec2> p;
    for (int i = 0; i < 5; ++i) {
      const double a = 2 * kPi * i / 5, r = (i % 2 ? 0.8 : 1.0) * k;
      p.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return p;
  };
  return {{{0, 0, 0}, 0.3, 0.25, star(1.0)},
          {{0.1, 0.05, -0.5}, 0.25, 0.2, star(0.9)},
          {{0.05, 0.1, -1.0}, 0.2, 0.2, star(1.1)},
          {{0.2, 0.1, -1.4}, 0.15, 0.18, star(1.0)}};
}

std::array<glm::dvec3, 16> bezierNet() {
  std::array<glm::dvec3, 16> n{};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) n[size_t(4 * j + i)] = {i, j, std::sin(1.3 * i + 0.7 * j) * 0.8};
  return n;
}

std::vector<glm::dvec3> bsplineNet(int cu, int cv, bool closedU, bool closedV = false) {
  std::vector<glm::dvec3> n;
  for (int j = 0; j < cv; ++j)
    for (int i = 0; i < cu; ++i) {
      if (closedU && closedV) {  // a bumpy torus
        const double a = 2 * kPi * i / cu, b = 2 * kPi * j / cv, r = 0.4 + 0.05 * std::cos(3.0 * i + j);
        n.emplace_back((1.2 + r * std::cos(b)) * std::cos(a), (1.2 + r * std::cos(b)) * std::sin(a), r * std::sin(b));
      } else if (closedU) {
        const double a = 2 * kPi * i / cu, r = 1.0 + 0.3 * std::cos(2.0 * j + i);
        n.emplace_back(r * std::cos(a), r * std::sin(a), 0.4 * j);
      } else {
        n.emplace_back(i, j, 0.5 * std::sin(0.9 * i * j + i));
      }
    }
  return n;
}

struct Named {
  std::string name;
  std::shared_ptr<Surface> surface;
};

std::vector<Named> everyPatch() {
  std::vector<Named> s;
  s.push_back({"sphere", std::make_shared<SpherePatch>(1.7)});
  s.push_back({"torus", std::make_shared<TorusPatch>(1.0, 0.35)});
  s.push_back({"plane", std::make_shared<PlanePatch>(3.0, 1.5)});
  s.push_back({"revolution-jug", std::make_shared<RevolutionPatch>(kJugProfile)});
  s.push_back({"revolution-linear", std::make_shared<RevolutionPatch>(kJugProfile, std::vector<bool>{},
                                                                      ProfileInterpolation::Linear)});
  s.push_back({"revolution-corner-vase",
               std::make_shared<RevolutionPatch>(std::vector<glm::dvec2>{{0, -1}, {0.6, -0.8}, {0.6, -0.8}, {0.4, 0.9}, {0, 1}})});
  s.push_back({"loft-body", std::make_shared<LoftPatch>(bodySections())});
  s.push_back({"loft-leg-profile", std::make_shared<LoftPatch>(legSections())});
  s.push_back({"bezier", std::make_shared<BezierPatch>(bezierNet())});
  s.push_back({"bspline-clamped", std::make_shared<BSplinePatch>(bsplineNet(6, 5, false), 6, 5)});
  s.push_back({"bspline-periodic-u", std::make_shared<BSplinePatch>(bsplineNet(7, 5, true), 7, 5, true, false)});
  s.push_back({"bspline-periodic-uv", std::make_shared<BSplinePatch>(bsplineNet(8, 6, true, true), 8, 6, true, true)});
  s.push_back({"bspline-clamped-2x3", std::make_shared<BSplinePatch>(bsplineNet(2, 3, false), 2, 3)});
  return s;
}

// Su and Sv of every patch against central differences (h = 1e-6 of the domain) at 300 seeded
// interior points. Truncation error is O(h^2 S''') ~ 1e-12 and rounding ~1e-16 |P| / h ~ 1e-10,
// so 1e-6 of the surface's scale (max |Su|, |Sv| over the samples, at least 1) is a safe bound
// that a wrong factor (2 pi, a missing chain-rule term) exceeds by orders of magnitude.
TEST(SurfacePatches, DerivativesMatchCentralDifferences) {
  for (const Named& n : everyPatch()) {
    const Surface& s = *n.surface;
    const ParameterDomain d = s.domain();
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> U(0.002, 0.998);
    double worst = 0.0, scale = 1.0;
    std::vector<std::array<glm::dvec3, 4>> samples;
    for (int k = 0; k < 300; ++k) {
      const glm::dvec2 uv = d.fromUnit(U(rng), U(rng));
      const double hu = 1e-6 * d.du(), hv = 1e-6 * d.dv();
      const SurfacePoint p = s.evaluate(uv.x, uv.y);
      const glm::dvec3 fu = (s.evaluate(uv.x + hu, uv.y).P - s.evaluate(uv.x - hu, uv.y).P) / (2 * hu);
      const glm::dvec3 fv = (s.evaluate(uv.x, uv.y + hv).P - s.evaluate(uv.x, uv.y - hv).P) / (2 * hv);
      samples.push_back({p.Su, fu, p.Sv, fv});
      scale = std::max({scale, glm::length(p.Su), glm::length(p.Sv)});
    }
    for (const auto& q : samples) worst = std::max({worst, glm::length(q[0] - q[1]), glm::length(q[2] - q[3])});
    std::printf("  %-24s max |S_analytic - S_fd| / scale = %.2e (scale %.3g)\n", n.name.c_str(), worst / scale, scale);
    EXPECT_LT(worst / scale, 1e-6) << n.name << " (" << s.describe() << ")";
  }
}

// Every patch: frames finite with unit, orthogonal N, Tu, Tv everywhere on a grid including the
// domain's edges and for NaN / Inf / huge parameters.
TEST(SurfacePatches, FramesAreFiniteEverywhereIncludingNaNAndInfParameters) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> odd = {nan, inf, -inf, 1e300, -1e300, 0.0, 1.0};
  for (const Named& n : everyPatch()) {
    const Surface& s = *n.surface;
    std::vector<glm::dvec2> uvs;
    for (int j = 0; j <= 20; ++j)
      for (int i = 0; i <= 20; ++i) uvs.push_back(s.domain().fromUnit(i / 20.0, j / 20.0));
    for (double a : odd)
      for (double b : odd) uvs.emplace_back(a, b);
    for (const glm::dvec2& uv : uvs) {
      const SurfaceFrame f = s.frame(uv.x, uv.y);
      ASSERT_TRUE(finite3(f.P) && finite3(f.N) && finite3(f.Tu) && finite3(f.Tv) && finite3(f.Su) && finite3(f.Sv))
          << n.name << " at " << uv.x << ", " << uv.y;
      EXPECT_NEAR(glm::length(f.N), 1.0, 1e-12) << n.name;
      EXPECT_NEAR(glm::length(f.Tu), 1.0, 1e-12) << n.name;
      EXPECT_NEAR(glm::length(f.Tv), 1.0, 1e-12) << n.name;
      EXPECT_NEAR(glm::dot(f.N, f.Tu), 0.0, 1e-12) << n.name;
      EXPECT_NEAR(glm::dot(f.N, f.Tv), 0.0, 1e-12) << n.name;
    }
  }
}

// Sphere poles: Su = 0 exactly, the frame is degenerate and its N is the axis (the limit), within
// 1e-9; a nearby regular point (v = 1e-4, normal tilted by pi 1e-4) agrees within 4e-4.
TEST(SurfacePatches, SpherePolesGiveTheLimitFrame) {
  const SpherePatch s(2.0);
  for (double u : {0.0, 0.1, 0.37, 0.5, 0.93}) {
    const SurfaceFrame south = s.frame(u, 0.0), north = s.frame(u, 1.0);
    EXPECT_TRUE(south.degenerate && north.degenerate);
    EXPECT_EQ(glm::length(south.Su), 0.0);
    EXPECT_EQ(south.P, glm::dvec3(0, 0, -2));
    EXPECT_EQ(north.P, glm::dvec3(0, 0, 2));
    EXPECT_LT(glm::length(south.N - glm::dvec3(0, 0, -1)), 1e-9) << test::str(south.N);
    EXPECT_LT(glm::length(north.N - glm::dvec3(0, 0, 1)), 1e-9) << test::str(north.N);
    EXPECT_LT(glm::length(south.N - s.frame(u, 1e-4).N), 4e-4);
    EXPECT_LT(glm::length(north.N - s.frame(u, 1 - 1e-4).N), 4e-4);
    // Tu at the pole is the limit of unit Su along the meridian: (-sin 2 pi u, cos 2 pi u, 0).
    EXPECT_LT(glm::length(south.Tu - glm::dvec3(-std::sin(2 * kPi * u), std::cos(2 * kPi * u), 0)), 1e-6);
  }
}

// Loft end caps (radius 0) and revolution profiles touching the axis: the row collapses to the
// spine's end point; the frame is the limit along the meridian (compared with a regular point
// 1e-5 away: within 1e-3). A loft's closed end is the apex of a cone (the radius goes to 0
// linearly), so that limit depends on u, but it always points away from the body. A revolution
// pole is smooth (the profile leaves the axis radially): its limit normal is the axis.
TEST(SurfacePatches, LoftEndCapsAndRevolutionPolesGiveTheLimitFrame) {
  const LoftPatch loft(bodySections());
  for (double v : {0.0, 1.0}) {
    const glm::dvec3 end = loft.spine(v);
    const double vn = v == 0.0 ? 1e-5 : 1.0 - 1e-5;
    for (double u : {0.0, 0.2, 0.45, 0.8}) {
      const SurfaceFrame f = loft.frame(u, v);
      EXPECT_TRUE(f.degenerate);
      EXPECT_LT(glm::length(f.P - end), 1e-12);
      EXPECT_LT(glm::length(f.N - loft.frame(u, vn).N), 1e-3) << "v " << v << " u " << u;
      // The cap's normal points away from the body: along -t at the start, +t at the end.
      const glm::dvec3 t = glm::normalize(loft.spine(v == 0.0 ? 1e-7 : 1.0) - loft.spine(v == 0.0 ? 0.0 : 1.0 - 1e-7));
      EXPECT_GT(glm::dot(f.N, v == 0.0 ? -t : t), 0.3) << test::str(f.N);
    }
  }
  const RevolutionPatch jug(kJugProfile);
  const RevolutionPatch vase({{0, -1}, {0.6, -0.8}, {0.4, 0.9}, {0, 1}});
  for (double u : {0.0, 0.3, 0.71}) {
    EXPECT_LT(glm::length(jug.frame(u, 0.0).N - glm::dvec3(0, 0, -1)), 1e-9);
    EXPECT_LT(glm::length(vase.frame(u, 0.0).N - glm::dvec3(0, 0, -1)), 1e-6) << test::str(vase.frame(u, 0.0).N);
    EXPECT_LT(glm::length(vase.frame(u, 1.0).N - glm::dvec3(0, 0, 1)), 1e-6) << test::str(vase.frame(u, 1.0).N);
    EXPECT_LT(glm::length(vase.frame(u, 1.0).N - vase.frame(u, 1 - 1e-5).N), 1e-3);
  }
}

// Scale invariance: spheres of radius 1e-6 and 1e6 (and 1) have the same unit normals and
// tangents, poles included, to 1e-12.
TEST(SurfacePatches, NormalsAreScaleInvariant) {
  const SpherePatch small(1e-6), unit(1.0), large(1e6);
  for (int j = 0; j <= 16; ++j)
    for (int i = 0; i <= 16; ++i) {
      const double u = i / 16.0, v = j / 16.0;
      const SurfaceFrame a = small.frame(u, v), b = unit.frame(u, v), c = large.frame(u, v);
      EXPECT_LT(glm::length(a.N - b.N), 1e-12);
      EXPECT_LT(glm::length(c.N - b.N), 1e-12);
      EXPECT_LT(glm::length(a.Tu - c.Tu), 1e-12);
      EXPECT_EQ(a.degenerate, c.degenerate);
    }
  const TriangleMesh ms = tessellate(small, 24, 12), ml = tessellate(large, 24, 12);
  ASSERT_EQ(ms.triangles.size(), ml.triangles.size());
  for (size_t k = 0; k < ms.normals.size(); ++k) EXPECT_LT(glm::length(ms.normals[k] - ml.normals[k]), 1e-12);
}

bool meshFinite(const TriangleMesh& m) {
  for (size_t k = 0; k < m.positions.size(); ++k)
    if (!finite3(m.positions[k]) || !finite3(m.normals[k]) || !finite3(m.tangents[k]) || !finite3(m.derivU[k]) ||
        !finite3(m.derivV[k]) || !std::isfinite(m.uvs[k].x + m.uvs[k].y))
      return false;
  return true;
}

// Tessellations of every patch: the attribute arrays are complete and finite, vertex normals are
// the analytic unit Su x Sv wherever that is regular (1e-12), the tangent is unit Su, no triangle
// has zero area, and each triangle's winding agrees with the vertex normals.
TEST(SurfaceTessellation, VertexNormalsAndWindingAgreeWithTheAnalyticNormal) {
  for (const Named& n : everyPatch()) {
    const TriangleMesh m = tessellate(*n.surface, 40, 24);
    // Each crease adds a doubled row (none of these creases falls on a grid row).
    const size_t count = size_t(41 * (25 + 2 * n.surface->creasesV().size()));
    ASSERT_EQ(m.positions.size(), count);
    ASSERT_EQ(m.normals.size(), count);
    ASSERT_EQ(m.tangents.size(), count);
    ASSERT_EQ(m.derivU.size(), count);
    ASSERT_EQ(m.derivV.size(), count);
    ASSERT_EQ(m.uvs.size(), count);
    ASSERT_TRUE(meshFinite(m)) << n.name;
    for (size_t k = 0; k < count; ++k) {
      const glm::dvec3 c = glm::cross(m.derivU[k], m.derivV[k]);
      if (glm::length(c) > 1e-6 * glm::length(m.derivU[k]) * glm::length(m.derivV[k])) {
        EXPECT_LT(glm::length(m.normals[k] - glm::normalize(c)), 1e-12) << n.name << " vertex " << k;
        EXPECT_LT(glm::length(m.tangents[k] - glm::normalize(m.derivU[k])), 1e-9) << n.name << " vertex " << k;
      }
    }
    ASSERT_FALSE(m.triangles.empty()) << n.name;
    size_t disagree = 0;
    for (const glm::uvec3& t : m.triangles) {
      const glm::dvec3 fn = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      EXPECT_GT(glm::length(fn), 0.0) << n.name;
      if (glm::dot(fn, m.normals[t.x] + m.normals[t.y] + m.normals[t.z]) <= 0) ++disagree;
    }
    EXPECT_EQ(disagree, 0u) << n.name;
  }
}

// Closed shapes are wound outward: every face normal points away from the sphere's centre / the
// torus's tube centre. The sphere's two pole rows collapse: 2 nu nv - 2 nu triangles.
TEST(SurfaceTessellation, SphereAndTorusAreWoundOutward) {
  const TriangleMesh s = tessellate(SpherePatch(1.0), 32, 16);
  EXPECT_EQ(s.triangles.size(), size_t(2 * 32 * 16 - 2 * 32));
  for (const glm::uvec3& t : s.triangles) {
    const glm::dvec3 c = (s.positions[t.x] + s.positions[t.y] + s.positions[t.z]) / 3.0;
    EXPECT_GT(glm::dot(glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]), c), 0.0);
  }
  const TriangleMesh r = tessellate(TorusPatch(1.0, 0.3), 32, 16);
  EXPECT_EQ(r.triangles.size(), size_t(2 * 32 * 16));
  for (const glm::uvec3& t : r.triangles) {
    const glm::dvec3 c = (r.positions[t.x] + r.positions[t.y] + r.positions[t.z]) / 3.0;
    const glm::dvec3 ring = glm::normalize(glm::dvec3(c.x, c.y, 0.0));
    EXPECT_GT(glm::dot(glm::cross(r.positions[t.y] - r.positions[t.x], r.positions[t.z] - r.positions[t.x]), c - ring), 0.0);
  }
}

// Poles everywhere (sphere, closed loft, jug and vase): no NaN, the collapsed triangles are left
// out (no triangle of zero area), and the pole vertices carry the limit normal.
TEST(SurfaceTessellation, PolesHaveNoNaNAndNoZeroAreaTriangles) {
  const std::vector<std::shared_ptr<Surface>> poles = {
      std::make_shared<SpherePatch>(1.0), std::make_shared<LoftPatch>(bodySections()),
      std::make_shared<RevolutionPatch>(kJugProfile),
      std::make_shared<RevolutionPatch>(std::vector<glm::dvec2>{{0, -1}, {0.6, -0.8}, {0.4, 0.9}, {0, 1}})};
  for (const auto& s : poles) {
    for (int res : {3, 17, 64}) {
      const TriangleMesh m = tessellate(*s, res, res);
      ASSERT_TRUE(meshFinite(m)) << s->describe();
      for (const glm::uvec3& t : m.triangles)
        EXPECT_GT(glm::length(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x])), 0.0);
      // Both pole rows (v = 0 and v = 1 for all but the jug, which is open at the top) lose one
      // triangle per cell.
      const size_t poleRows = s.get() == poles[2].get() ? 1 : 2;
      EXPECT_EQ(m.triangles.size(), size_t(2 * res * res) - poleRows * size_t(res)) << s->describe();
      const bool cone = s.get() == poles[1].get();  // the loft's closed ends are cone apexes
      for (int i = 0; i <= res && !cone; ++i)  // the v = 0 row: one point, one normal
        EXPECT_LT(glm::length(m.normals[size_t(i)] - m.normals[0]), 1e-9) << s->describe();
    }
  }
}

// Periodic seams: the duplicated last column (and row) has bit-identical positions and normals,
// with u = u1 (v = v1) in the uvs; evaluate(1, v) is evaluate(0, v).
TEST(SurfaceTessellation, PeriodicSeamVerticesCoincide) {
  for (const Named& n : everyPatch()) {
    const ParameterDomain d = n.surface->domain();
    if (!d.periodicU && !d.periodicV) continue;
    const int nu = 20, nv = 12;
    const TriangleMesh m = tessellate(*n.surface, nu, nv);
    if (d.periodicU)
      for (int j = 0; j <= nv; ++j) {
        const size_t a = size_t(j * (nu + 1)), b = a + nu;
        EXPECT_EQ(m.positions[a], m.positions[b]) << n.name;
        EXPECT_EQ(m.normals[a], m.normals[b]) << n.name;
        EXPECT_EQ(m.uvs[b].x, d.u1);
        EXPECT_EQ(n.surface->evaluate(d.u1, m.uvs[a].y).P, n.surface->evaluate(d.u0, m.uvs[a].y).P) << n.name;
      }
    if (d.periodicV)
      for (int i = 0; i <= nu; ++i) {
        EXPECT_EQ(m.positions[size_t(i)], m.positions[size_t(nv * (nu + 1) + i)]) << n.name;
        EXPECT_EQ(m.uvs[size_t(nv * (nu + 1) + i)].y, d.v1);
      }
  }
}

double meshArea(const TriangleMesh& m) {
  double a = 0.0;
  for (const glm::uvec3& t : m.triangles)
    a += 0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
  return a;
}

// Area of the tessellation converges to the analytic area with O(h^2): the error ratio between
// resolutions n and 2n is 4 (observed order log2 ratio within [1.9, 2.1]), and at 256 x 128 the
// relative error is below 1e-3. Sphere 4 pi r^2, torus 4 pi^2 R r.
TEST(SurfaceTessellation, AreaConvergesQuadratically) {
  struct Case {
    std::shared_ptr<Surface> s;
    double exact;
  };
  const std::vector<Case> cases = {{std::make_shared<SpherePatch>(1.3), 4 * kPi * 1.3 * 1.3},
                                   {std::make_shared<TorusPatch>(1.0, 0.35), 4 * kPi * kPi * 1.0 * 0.35}};
  for (const Case& c : cases) {
    std::vector<double> err;
    for (int n : {16, 32, 64, 128, 256}) err.push_back(std::abs(meshArea(tessellate(*c.s, n, n / 2)) - c.exact) / c.exact);
    for (size_t k = 0; k + 1 < err.size(); ++k) {
      const double order = std::log2(err[k] / err[k + 1]);
      std::printf("  %-16s n=%-4d rel. area error %.3e  order %.3f\n", c.s->describe().c_str(), 16 << k, err[k], order);
      if (k > 0) {
        EXPECT_NEAR(order, 2.0, 0.1) << c.s->describe();
      }
    }
    EXPECT_LT(err.back(), 1e-3);
  }
}

// The output does not depend on the thread count.
TEST(SurfaceTessellation, OutputDoesNotDependOnThreadCount) {
  const LoftPatch loft(bodySections());
  TriangleMesh one;
  tbb::task_arena(1).execute([&] { one = tessellate(loft, 64, 48); });
  const TriangleMesh many = tessellate(loft, 64, 48);
  EXPECT_EQ(one.positions, many.positions);
  EXPECT_EQ(one.normals, many.normals);
  EXPECT_EQ(one.triangles, many.triangles);
}

// The vertex cap and bad resolutions are reported, and tessellate throws with the same message.
TEST(SurfaceTessellation, ResolutionProblemsAreReported) {
  EXPECT_TRUE(tessellationProblem(2047, 2047).empty());   // 2048^2 = 4,194,304 vertices: at the cap
  EXPECT_FALSE(tessellationProblem(2048, 2048).empty());
  EXPECT_FALSE(tessellationProblem(0, 10).empty());
  EXPECT_THROW(tessellate(SpherePatch(1.0), 4096, 4096), std::invalid_argument);
  EXPECT_THROW(tessellate(SpherePatch(1.0), 8, 0), std::invalid_argument);
}

// Iso-parameter lines: counts, closure along periodic directions, parallels off the poles.
TEST(SurfaceTessellation, IsoparametricLines) {
  const PolylineSet t = isoparametricLines(TorusPatch(1.0, 0.3), 6, 4, 20);
  ASSERT_EQ(t.polylineCount(), 10u);
  for (size_t i = 0; i < t.polylineCount(); ++i) {
    EXPECT_EQ(t.starts[i + 1] - t.starts[i], 21u);
    EXPECT_EQ(t.points[t.starts[i]], t.points[t.starts[i + 1] - 1]);
  }
  const PolylineSet p = isoparametricLines(PlanePatch(2.0, 2.0), 3, 3, 8);
  ASSERT_EQ(p.polylineCount(), 6u);
  EXPECT_EQ(p.points[p.starts[0]], glm::dvec3(-1, -1, 0));  // open directions draw their edges
  const PolylineSet s = isoparametricLines(SpherePatch(1.0), 4, 1, 8);
  EXPECT_NEAR(s.points[s.starts[4]].z, 0.0, 1e-15);  // the one parallel is the equator
}

// Revolution profiles: the smooth curve passes through every point, never leaves r >= 0 (a
// profile pinched to the axis in the middle), and is parameterised by arc length (|Sv| within
// 1% of the profile length everywhere on the jug).
TEST(SurfacePatches, RevolutionProfileInterpolatesStaysOffTheAxisAndIsEven) {
  const RevolutionPatch jug(kJugProfile);
  for (const glm::dvec2& p : kJugProfile) {
    double best = 1e9;
    for (int k = 0; k <= 20000; ++k) best = std::min(best, glm::length(jug.profile(k / 20000.0) - p));
    EXPECT_LT(best, 1e-4) << p.x << " " << p.y;
  }
  double lo = 1e9, hi = 0;
  for (int k = 0; k <= 1000; ++k) {
    glm::dvec2 d;
    jug.profile(k / 1000.0, &d);
    lo = std::min(lo, glm::length(d));
    hi = std::max(hi, glm::length(d));
  }
  std::printf("  jug |dprofile/dv| / length in [%.5f, %.5f]\n", lo / jug.profileLength(), hi / jug.profileLength());
  EXPECT_GT(lo / jug.profileLength(), 0.99);
  EXPECT_LT(hi / jug.profileLength(), 1.01);
  const RevolutionPatch pinched({{0.5, 0}, {0.05, 0.4}, {0.0, 0.5}, {0.05, 0.6}, {0.5, 1.0}});
  for (int k = 0; k <= 10000; ++k) EXPECT_GE(pinched.profile(k / 10000.0).x, 0.0);
  // A repeated point is a corner: the tangent turns there, and the merged point is listed once.
  const RevolutionPatch cup({{0, 0}, {1, 0}, {1, 0}, {1, 1}});
  EXPECT_EQ(cup.points().size(), 3u);
  EXPECT_TRUE(cup.corners()[1]);
  // With the corner the base stays flat: z = 0 along the whole first segment.
  for (int k = 0; k <= 100; ++k) {
    const glm::dvec2 q = cup.profile(0.5 * k / 100.0);
    if (q.x < 1.0 - 1e-9) {
      EXPECT_NEAR(q.y, 0.0, 1e-12);
    }
  }
}

// Loft: passes through its first and last centres; a closed end is one point; a circular
// section keeps its radius around the spine at the ends. B-spline / Bezier: the clamped corners
// are the corner control points.
TEST(SurfacePatches, LoftAndSplinePatchesInterpolateTheirEnds) {
  const auto secs = bodySections();
  const LoftPatch loft(secs);
  EXPECT_LT(glm::length(loft.spine(0.0) - secs.front().centre), 1e-12);
  EXPECT_LT(glm::length(loft.spine(1.0) - secs.back().centre), 1e-12);
  const LoftPatch tube({{{0, 0, 0}, 0.5, 0.5, {}}, {{1, 0, 0.2}, 0.5, 0.5, {}}, {{2, 0.3, 0}, 0.5, 0.5, {}}});
  for (double u : {0.0, 0.3, 0.6}) EXPECT_NEAR(glm::length(tube.evaluate(u, 0.0).P - glm::dvec3(0.0)), 0.5, 1e-12);
  const BezierPatch b(bezierNet());
  EXPECT_LT(glm::length(b.evaluate(0, 0).P - bezierNet()[0]), 1e-14);
  EXPECT_LT(glm::length(b.evaluate(1, 1).P - bezierNet()[15]), 1e-14);
  const auto net = bsplineNet(6, 5, false);
  const BSplinePatch bs(net, 6, 5);
  EXPECT_LT(glm::length(bs.evaluate(1, 0).P - net[5]), 1e-12);
  EXPECT_LT(glm::length(bs.evaluate(0, 1).P - net[24]), 1e-12);
}

TEST(SurfacePatches, ProblemsAreReported) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(SpherePatch::problem(-1).empty());
  EXPECT_FALSE(SpherePatch::problem(nan).empty());
  EXPECT_TRUE(SpherePatch::problem(1).empty());
  EXPECT_FALSE(TorusPatch::problem(1, 0).empty());
  EXPECT_FALSE(PlanePatch::problem(1, -2).empty());
  EXPECT_FALSE(RevolutionPatch::problem({{1, 0}}).empty());
  EXPECT_FALSE(RevolutionPatch::problem({{-1, 0}, {1, 1}}).empty());
  EXPECT_FALSE(RevolutionPatch::problem({{0, 0}, {0, 1}}).empty());
  EXPECT_FALSE(RevolutionPatch::problem({{1, 0}, {1, 1}}, {true}).empty());
  EXPECT_TRUE(RevolutionPatch::problem(kJugProfile).empty());
  EXPECT_FALSE(LoftPatch::problem({{}}).empty());
  EXPECT_FALSE(LoftPatch::problem({{{0, 0, 0}, -1, 1, {}}, {{1, 0, 0}, 1, 1, {}}}).empty());
  EXPECT_FALSE(LoftPatch::problem({{{0, 0, 0}, 1, 1, {}}, {{0, 0, 0}, 1, 1, {}}}).empty());  // no spine length
  EXPECT_FALSE(LoftPatch::problem({{{0, 0, 0}, 1, 1, {}}, {{0, 0, 1}, 1, 1, {}}}, {0, 0, 1}).empty());  // t || up
  EXPECT_TRUE(LoftPatch::problem({{{0, 0, 0}, 1, 1, {}}, {{0, 0, 1}, 1, 1, {}}}).empty());  // auto up
  EXPECT_FALSE(LoftPatch::problem({{{0, 0, 0}, 1, 1, {{1, 0}, {0, 1}, {-1, 0}}}, {{1, 0, 0}, 1, 1, {}}}).empty());
  EXPECT_TRUE(LoftPatch::problem(bodySections()).empty());
  EXPECT_TRUE(LoftPatch::problem(legSections()).empty());
  auto bad = bezierNet();
  bad[5].y = nan;
  EXPECT_FALSE(BezierPatch::problem(bad).empty());
  EXPECT_FALSE(BSplinePatch::problem(bsplineNet(2, 3, false), 2, 3, true, false).empty());
  EXPECT_FALSE(BSplinePatch::problem(bsplineNet(4, 3, false), 4, 4).empty());
  EXPECT_TRUE(BSplinePatch::problem(bsplineNet(4, 3, false), 4, 3).empty());
  for (const Named& n : everyPatch()) EXPECT_FALSE(n.surface->describe().empty());
}

}  // namespace
}  // namespace wf
