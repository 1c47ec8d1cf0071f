// Scene bounds (scene_bounds.cpp): the parallel reduction against a plain serial pass over the
// same points, to the bit, for any thread count.
#include "render/scene.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <utility>

namespace wf {
namespace {

// Every vertex a triangle uses (indices past the positions skipped) and every polyline point:
// what the bounds enclose, visited one by one.
template <class F>
void eachPoint(const Scene& s, F&& f) {
  for (const SceneSurface& surf : s.surfaces)
    for (const glm::uvec3& t : surf.mesh.triangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] < surf.mesh.positions.size()) f(surf.mesh.positions[t[k]]);
  for (const SceneWire& w : s.wires)
    for (const glm::dvec3& p : w.lines.points) f(p);
}

bool sameBits(const glm::dvec3& a, const glm::dvec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A surface of 40,000 triangles (two of the reduction's runs of 2^15) and two wires of 70,000
// points (three runs each, the last short), with NaN and Inf among the points, zeros of both
// signs (-0 first) on the box's lowest z, a vertex no triangle uses and a triangle index past
// the positions (neither may count). Each face of the box is held by one point alone, each in
// a different run (the surface's second, the wires' first and last), so that a run left out
// changes the box.
Scene testScene(bool surfaces, bool wires) {
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&](double sx, double sy, double z0) {
    const double x = u(rng) * sx;  // one draw per statement: the same scene with any compiler
    const double y = u(rng) * sy;
    const double z = z0 + 0.4 * std::abs(u(rng));
    return glm::dvec3(x, y, z);
  };
  if (surfaces) {
    SceneSurface surf;
    for (int i = 0; i < 30000; ++i) surf.mesh.positions.push_back(point(1.0, 1.0, 0.1));
    surf.mesh.positions.push_back({1e9, 1e9, 1e9});      // 30000: used by no triangle
    surf.mesh.positions.push_back({4.0, 0.0, 0.2});      // 30001: the largest x, in the second run
    for (std::uint32_t t = 0; t < 40000; ++t) {
      const std::uint32_t a = (t * 3) % 30000, b = (t * 3 + 1) % 30000;
      surf.mesh.triangles.push_back({a, b, t == 35000 ? 30001u : (t * 3 + 2) % 30000});
    }
    surf.mesh.triangles.push_back({0, 1, 5000000});  // an index past the positions
    s.surfaces.push_back(surf);
  }
  if (wires) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (int w = 0; w < 2; ++w) {
      SceneWire wire;
      wire.lines.starts.push_back(0);
      for (int i = 0; i < 70000; ++i) {
        glm::dvec3 p = point(3.0, 2.0, 0.0);
        if (i % 9973 == 5) p.x = nan;
        if (i % 12007 == 11) p.y = inf;
        if (i % 31 == 3) p.z = (i / 31) % 2 ? 0.0 : -0.0;  // the smallest z: -0 first, then +0 and -0 in turn
        if (w == 0 && i == 100) p.y = 5.0;                  // the largest y: wire 0's first run
        if (w == 1 && i == 69990) p.y = -5.0;               // the smallest y: wire 1's last, short run
        if (w == 1 && i == 40000) p.x = -6.0;               // the smallest x: wire 1's second run
        if (w == 0 && i == 68000) p.z = 3.0;                // the largest z: wire 0's last run
        wire.lines.points.push_back(p);
        if (i % 2 == 1) wire.lines.starts.push_back(std::uint32_t(wire.lines.points.size()));
      }
      s.wires.push_back(std::move(wire));
    }
  }
  return s;
}

// The old serial pass, point by point in scene order.
bool serialSphere(const Scene& s, glm::dvec3& lo, glm::dvec3& hi, glm::dvec3& centre, double& radius) {
  lo = glm::dvec3(1e300), hi = glm::dvec3(-1e300);
  bool any = false;
  eachPoint(s, [&](const glm::dvec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    lo = glm::min(lo, p), hi = glm::max(hi, p);
    any = true;
  });
  centre = 0.5 * lo + 0.5 * hi;
  double r2 = 0;
  eachPoint(s, [&](const glm::dvec3& p) {
    const glm::dvec3 d = p - centre;
    const double q = glm::dot(d, d);
    if (std::isfinite(q)) r2 = std::max(r2, q);
  });
  radius = std::sqrt(r2);
  return any;
}

TEST(SceneBounds, EqualTheSerialPassToTheBitForAnyThreadCount) {
  for (const auto& [surfaces, wires] : {std::pair{true, true}, std::pair{true, false}, std::pair{false, true}}) {
    const Scene s = testScene(surfaces, wires);
    glm::dvec3 lo, hi, centre;
    double radius = 0;
    ASSERT_TRUE(serialSphere(s, lo, hi, centre, radius));
    if (surfaces) {
      EXPECT_EQ(hi.x, 4.0);  // the unused vertex and the bad index left out
    }
    if (wires) {
      EXPECT_EQ(lo.x, -6.0);
      EXPECT_EQ(lo.y, -5.0);
      EXPECT_EQ(hi.y, 5.0);
      EXPECT_EQ(hi.z, 3.0);
      EXPECT_EQ(lo.z, 0.0);
      EXPECT_TRUE(std::signbit(lo.z));  // the first zero met
    }
    for (int threads : {1, 2, 7}) {
      tbb::task_arena arena(threads);
      arena.execute([&] {
        glm::dvec3 blo, bhi, c;
        double r = 0;
        ASSERT_TRUE(s.bounds(blo, bhi));
        EXPECT_TRUE(sameBits(blo, lo)) << threads << " threads";
        EXPECT_TRUE(sameBits(bhi, hi)) << threads << " threads";
        ASSERT_TRUE(s.boundingSphere(c, r));
        EXPECT_TRUE(sameBits(c, centre)) << threads << " threads";
        EXPECT_EQ(r, radius) << threads << " threads";
      });
    }
  }
}

TEST(SceneBounds, NoFiniteGeometryHasNone) {
  Scene s;
  SceneWire w;
  w.lines.points = {{std::numeric_limits<double>::quiet_NaN(), 0, 0}, {0, std::numeric_limits<double>::infinity(), 0}};
  w.lines.starts = {0, 2};
  s.wires.push_back(w);
  glm::dvec3 lo, hi, c;
  double r = 0;
  EXPECT_FALSE(s.bounds(lo, hi));
  EXPECT_FALSE(s.boundingSphere(c, r));
  EXPECT_FALSE(Scene{}.boundingSphere(c, r));
}

}  // namespace
}  // namespace wf
