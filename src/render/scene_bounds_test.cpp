// Scene bounds (scene_bounds.cpp): the parallel reduction against a plain serial pass over the
// same points, to the bit, for any thread count.
#include "render/scene.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

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

// Points across several of the reduction's runs (2^15 points each), with NaN and Inf among
// them, zeros of both signs on the box's faces, a triangle index past the positions and a
// vertex no triangle uses (both far outside: neither may count).
Scene testScene() {
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SceneSurface surf;
  for (int i = 0; i < 3000; ++i) surf.mesh.positions.push_back({u(rng), u(rng), 0.1 + 0.4 * std::abs(u(rng))});
  surf.mesh.positions.push_back({1e9, 1e9, 1e9});  // used by no triangle
  for (std::uint32_t i = 0; i + 2 < 3000; i += 3) surf.mesh.triangles.push_back({i, i + 1, i + 2});
  surf.mesh.triangles.push_back({0, 1, 5000000});  // an index past the positions
  s.surfaces.push_back(surf);
  for (int w = 0; w < 2; ++w) {
    SceneWire wire;
    wire.lines.starts.push_back(0);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 70000; ++i) {
      glm::dvec3 p(u(rng) * 3.0, u(rng) * 2.0 + 0.5, std::abs(u(rng)));
      if (i % 9973 == 5) p.x = nan;
      if (i % 12007 == 11) p.y = inf;
      if (i % 31 == 3) p.z = (i / 31) % 2 ? 0.0 : -0.0;  // the smallest z: zeros of both signs
      wire.lines.points.push_back(p);
      if (i % 2 == 1) wire.lines.starts.push_back(std::uint32_t(wire.lines.points.size()));
    }
    s.wires.push_back(std::move(wire));
  }
  return s;
}

TEST(SceneBounds, EqualTheSerialPassToTheBitForAnyThreadCount) {
  const Scene s = testScene();
  glm::dvec3 lo(1e300), hi(-1e300);
  size_t finite = 0;
  eachPoint(s, [&](const glm::dvec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    lo = glm::min(lo, p), hi = glm::max(hi, p);
    ++finite;
  });
  ASSERT_GT(finite, 100000u);
  lo += glm::dvec3(0.0), hi += glm::dvec3(0.0);  // zeros as +0, whatever order kept which
  EXPECT_EQ(lo.z, 0.0);
  EXPECT_FALSE(std::signbit(lo.z));
  EXPECT_LT(hi.x, 1e9);  // the unused vertex and the bad index left out
  const glm::dvec3 centre = 0.5 * lo + 0.5 * hi;
  double r2 = 0;
  eachPoint(s, [&](const glm::dvec3& p) {
    const glm::dvec3 d = p - centre;
    const double q = glm::dot(d, d);
    if (std::isfinite(q)) r2 = std::max(r2, q);
  });
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
      EXPECT_EQ(r, std::sqrt(r2)) << threads << " threads";
    });
  }
}

TEST(SceneBounds, NoFiniteGeometryHasNone) {
  Scene s;
  SceneWire w;
  w.lines.points = {{NAN, 0, 0}, {0, INFINITY, 0}};
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
