// wf::layoutGrain (surface/grain_layout.h): the groove coordinate across the grain becomes a world
// length, per face, whatever the parametrisation and however finely the face is meshed.
#include "surface/grain_layout.h"

#include "geometry/parametric_sources.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The vertex of a tessellation at exact (u, v), or -1.
long vertexAt(const TriangleMesh& m, glm::dvec2 uv) {
  for (std::size_t i = 0; i < m.uvs.size(); ++i)
    if (glm::length(m.uvs[i] - uv) < 1e-12) return long(i);
  return -1;
}

}  // namespace

// A torus (major 1, minor 0.35) over [0, 1]^2: |Sv| = 2 pi 0.35 everywhere, |Su| = 2 pi (1 + 0.35
// cos 2 pi v). Longer: the grain runs along u (the torus is longer around), so v, the groove
// coordinate, becomes v 2 pi 0.35, the arc length across the grain, exactly (1e-12) at any
// resolution; u becomes u times the area-weighted mean of |Su|, 2 pi (1 + 0.35^2 / 2) in the
// limit: within 2e-3 of it at 128 x 64, and the two meshings agree to 1e-2.
TEST(GrainLayout, TorusGrooveCoordinateIsAWorldLength) {
  double uAt[2];
  int k = 0;
  for (int res : {32, 128}) {
    ParametricSource s;
    s.type = ParametricSource::Type::Torus;
    s.major = 1, s.minor = 0.35;
    s.resolutionU = res, s.resolutionV = res / 2;
    TriangleMesh m = tessellate(s);
    const long i = vertexAt(m, {0.5, 0.5});
    ASSERT_GE(i, 0);
    const GrainLayoutStats st = layoutGrain(m, {}, GrainLayout::Longer);
    EXPECT_EQ(st.faces, 1u);
    EXPECT_EQ(st.alongU, 1u);
    EXPECT_NEAR(m.uvs[std::size_t(i)].y, 0.5 * 2 * kPi * 0.35, 1e-12);
    EXPECT_NEAR(glm::length(m.derivV[std::size_t(i)]), 1.0, 1e-12);  // dS/dv' is unit across the grain
    uAt[k++] = m.uvs[std::size_t(i)].x;
  }
  const double limit = 0.5 * 2 * kPi * (1 + 0.35 * 0.35 / 2);
  EXPECT_NEAR(uAt[1], limit, 2e-3 * limit);
  EXPECT_NEAR(uAt[0], uAt[1], 1e-2 * limit);
}

// Two faces in one mesh: a plane 2 x 10 (u along x, v along y) and a copy 10 x 2. Longer puts the
// first's grain along v (swapping u and v, and dS/du with dS/dv: the grain, dS/du, now runs along
// y) and the second's along u; U and V force one side. Without texture coordinates nothing changes.
TEST(GrainLayout, LongerPicksPerFace) {
  auto plane = [](double x, double y) {
    ParametricSource s;
    s.type = ParametricSource::Type::Plane;
    s.size = {x, y, 0};
    s.resolutionU = 4, s.resolutionV = 4;
    return tessellate(s);
  };
  const TriangleMesh a = plane(2, 10), b = plane(10, 2);
  TriangleMesh both = a;
  std::vector<int> face(a.triangles.size(), 7);
  const auto base = std::uint32_t(both.positions.size());
  for (auto* v : {&both.positions, &both.normals, &both.derivU, &both.derivV}) (void)v;
  both.positions.insert(both.positions.end(), b.positions.begin(), b.positions.end());
  both.normals.insert(both.normals.end(), b.normals.begin(), b.normals.end());
  both.derivU.insert(both.derivU.end(), b.derivU.begin(), b.derivU.end());
  both.derivV.insert(both.derivV.end(), b.derivV.begin(), b.derivV.end());
  both.uvs.insert(both.uvs.end(), b.uvs.begin(), b.uvs.end());
  for (const glm::uvec3& t : b.triangles) both.triangles.push_back(t + glm::uvec3(base)), face.push_back(3);
  ASSERT_EQ(both.derivU.size(), both.positions.size());
  TriangleMesh m = both;
  GrainLayoutStats st = layoutGrain(m, face, GrainLayout::Longer);
  EXPECT_EQ(st.faces, 2u);
  EXPECT_EQ(st.alongU, 1u);
  EXPECT_EQ(st.alongV, 1u);
  // The first face's grain (derivU) along y, unit; the second's along x.
  EXPECT_NEAR(std::abs(glm::normalize(m.derivU[0]).y), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(glm::normalize(m.derivU[base]).x), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(m.derivV[0]), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(m.derivV[base]), 1.0, 1e-12);
  m = both;
  st = layoutGrain(m, face, GrainLayout::U);
  EXPECT_EQ(st.alongU, 2u);
  m = both;
  m.uvs.clear();
  st = layoutGrain(m, face, GrainLayout::Longer);
  EXPECT_EQ(st.faces, 0u);
  EXPECT_EQ(m.derivU, both.derivU);
}

}  // namespace wf
