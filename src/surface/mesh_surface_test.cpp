// wf::MeshSurface (surface/mesh_surface.h): over a mesh's texture coordinates, and over the
// automatic layout of a mesh without them.
#include "surface/mesh_surface.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// The automatic layout is isometric: wherever (u, v) lands on a triangle, Su and Sv are unit and
// perpendicular, and the (u, v) area the triangles cover is their area in space (so area-correct
// roots are exact); Su is the up axis projected onto the triangle (here +z, or +x on the face
// whose normal is along z). The covered area is counted on a 400 x 400 grid of the domain.
TEST(MeshSurface, AutomaticLayoutIsIsometricAndCombed) {
  const TriangleMesh m = tetrahedron();
  const MeshSurface s(m);
  ASSERT_TRUE(s.problem().empty()) << s.problem();
  EXPECT_TRUE(s.automaticLayout());
  const ParameterDomain d = s.domain();
  const int n = 400;
  double covered = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 uv = d.fromUnit((i + 0.5) / n, (j + 0.5) / n);
      const SurfacePoint p = s.evaluate(uv.x, uv.y);
      if (!std::isfinite(p.P.x)) continue;
      covered += d.du() * d.dv() / (double(n) * n);
      ASSERT_NEAR(glm::length(p.Su), 1.0, 1e-9);
      ASSERT_NEAR(glm::length(p.Sv), 1.0, 1e-9);
      ASSERT_NEAR(glm::dot(p.Su, p.Sv), 0.0, 1e-9);
      const glm::dvec3 N = glm::normalize(glm::cross(p.Su, p.Sv));
      const glm::dvec3 up = std::abs(N.z) > 0.999 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
      const glm::dvec3 want = glm::normalize(up - glm::dot(up, N) * N);
      ASSERT_NEAR(glm::dot(p.Su, want), 1.0, 1e-9);
    }
  const double area = 3 * 0.5 + 0.5 * std::sqrt(3.0);  // three right triangles and the slanted face
  EXPECT_NEAR(covered, area, 0.02 * area);
}

// With texture coordinates the mesh's own (u, v) are used: a unit square cut in two, uv = xy.
TEST(MeshSurface, OwnTextureCoordinates) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshSurface s(m);
  ASSERT_TRUE(s.problem().empty());
  EXPECT_FALSE(s.automaticLayout());
  const SurfacePoint p = s.evaluate(0.25, 0.5);
  EXPECT_NEAR(p.P.x, 0.5, 1e-12);
  EXPECT_NEAR(p.P.y, 1.5, 1e-12);
  EXPECT_NEAR(p.Su.x, 2.0, 1e-12);
  EXPECT_NEAR(p.Sv.y, 3.0, 1e-12);
}

// A texture layout that overlaps itself (every quad on the whole texture, as tiled exports do):
// the explicit layout refuses it before building a lookup of N^2 entries, and a mesh falls back
// to the automatic layout (which covers the whole area). So does a mirrored half, whose triangles
// are wound against the majority in uv and would grow nothing.
TEST(MeshSurface, OverlappingOrMirroredLayoutsFallBackToTheAutomaticOne) {
  TriangleMesh m;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const std::uint32_t b = std::uint32_t(m.positions.size());
    const double x = 1.1 * k;
    for (const glm::dvec2& c : {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(1, 1), glm::dvec2(0, 1)}) {
      m.positions.emplace_back(x + c.x, c.y, 0.0);
      m.uvs.push_back(c);
    }
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b, b + 2, b + 3});
  }
  const MeshSurface own(m.positions, m.uvs, m.triangles);
  EXPECT_NE(own.problem().find("overlap"), std::string::npos) << own.problem();
  const MeshSurface fallback(m);
  EXPECT_TRUE(fallback.problem().empty()) << fallback.problem();
  EXPECT_TRUE(fallback.automaticLayout());

  TriangleMesh mirrored;
  mirrored.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {-1, 1, 0}};
  mirrored.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {1, 0}, {1, 1}};  // the left half mirrors the right
  mirrored.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}};
  EXPECT_TRUE(MeshSurface(mirrored).automaticLayout());
}

// A NaN corner leaves its triangle out of a mesh's surface (fur and scales grow on the rest), in
// the mesh's own layout and the automatic one; an unused point at 1e6 does not make the others
// "zero area". The explicit layout (the VTK filters' contract) refuses the NaN instead.
TEST(MeshSurface, NaNCornersAreLeftOutAndFarUnusedPointsIgnored) {
  const double nan = std::nan("");
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1e-3, 0, 0}, {1e-3, 1e-3, 0}, {0, 1e-3, 0}, {nan, 0, 0}, {1e6, 1e6, 1e6}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}};
  const MeshSurface own(m);
  ASSERT_TRUE(own.problem().empty()) << own.problem();
  EXPECT_FALSE(own.automaticLayout());
  EXPECT_EQ(own.triangleCount(), 2u);
  m.uvs.clear();
  const MeshSurface automatic(m);
  ASSERT_TRUE(automatic.problem().empty()) << automatic.problem();
  EXPECT_EQ(automatic.triangleCount(), 2u);
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0, 0}};
  EXPECT_NE(MeshSurface(m.positions, m.uvs, m.triangles).problem().find("not finite"), std::string::npos);
}

TEST(MeshSurface, NoTrianglesIsAProblem) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}};
  EXPECT_FALSE(MeshSurface(m).problem().empty());
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  m.triangles = {{0, 1, 2}};  // zero area
  EXPECT_FALSE(MeshSurface(m).problem().empty());
}

}  // namespace
}  // namespace wf
