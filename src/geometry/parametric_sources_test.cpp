// Parametric sources: the surfaces scenes name, against their closed forms.
#include "geometry/parametric_sources.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>
#include <numbers>

namespace wf {
namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Every vertex of a sphere lies on it, its normal is the unit radial direction (outward),
// poles included (no NaN), and no triangle is degenerate (the collapsed ones at the poles are left out).
TEST(ParametricSources, SphereVerticesAndNormalsAreExact) {
  ParametricSource s;
  s.type = ParametricSource::Type::Sphere;
  s.radius = 2.5;
  s.resolutionU = 24;
  s.resolutionV = 12;
  const TriangleMesh m = tessellate(s);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    ASSERT_TRUE(finite(m.positions[i]) && finite(m.normals[i]) && finite(m.tangents[i]));
    EXPECT_NEAR(glm::length(m.positions[i]), 2.5, 1e-12);
    EXPECT_NEAR(glm::length(m.normals[i] - m.positions[i] / 2.5), 0.0, 1e-12);  // outward unit radial
    EXPECT_NEAR(glm::length(m.tangents[i]), 1.0, 1e-9);
  }
  for (const glm::uvec3& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    EXPECT_GT(glm::length(n), 0.0);
    // Wound counter-clockwise seen from outside: the face normal agrees with the vertex normals.
    EXPECT_GT(glm::dot(n, m.normals[t.x] + m.normals[t.y] + m.normals[t.z]), 0.0);
  }
  // A u x v grid with the two pole rows collapsed: 2 * 24 * 12 - 2 * 24 triangles.
  EXPECT_EQ(m.triangles.size(), size_t(2 * 24 * 12 - 2 * 24));
}

// Torus: distance to the tube's centre circle is the minor radius; the normal points from that
// circle to the vertex.
TEST(ParametricSources, TorusVerticesAndNormalsAreExact) {
  ParametricSource s;
  s.type = ParametricSource::Type::Torus;
  s.major = 1.0;
  s.minor = 0.3;
  const TriangleMesh m = tessellate(s);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 p = m.positions[i];
    const glm::dvec3 c = glm::normalize(glm::dvec3(p.x, p.y, 0.0)) * s.major;
    EXPECT_NEAR(glm::length(p - c), 0.3, 1e-12);
    EXPECT_NEAR(glm::length(m.normals[i] - (p - c) / 0.3), 0.0, 1e-12);
  }
  EXPECT_EQ(m.triangles.size(), size_t(2 * s.resolutionU * s.resolutionV));
}

// Lathe of a vertical profile at radius 1 (a cylinder): normals are horizontal and outward.
TEST(ParametricSources, LatheNormalsPointOutward) {
  ParametricSource s;
  s.type = ParametricSource::Type::Lathe;
  s.profile = {{1.0, -1.0}, {1.0, 0.0}, {1.0, 1.0}};
  const TriangleMesh m = tessellate(s);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 radial = glm::normalize(glm::dvec3(m.positions[i].x, m.positions[i].y, 0.0));
    EXPECT_NEAR(glm::length(m.normals[i] - radial), 0.0, 1e-9);
  }
}

// A profile that starts and ends on the axis (a closed vase): no NaN anywhere.
TEST(ParametricSources, LatheWithPointsOnTheAxisHasNoNaN) {
  ParametricSource s;
  s.type = ParametricSource::Type::Lathe;
  s.profile = {{0.0, -1.0}, {0.6, -0.8}, {0.4, 0.9}, {0.0, 1.0}};
  const TriangleMesh m = tessellate(s);
  for (size_t i = 0; i < m.positions.size(); ++i) ASSERT_TRUE(finite(m.normals[i]) && finite(m.tangents[i]));
}

// Isolines: the counts asked for; torus lines are closed; a sphere's parallels stay off the poles.
TEST(ParametricSources, IsolinesHaveTheRequestedCountsAndClose) {
  ParametricSource torus;
  torus.type = ParametricSource::Type::Torus;
  const PolylineSet t = isolines(torus, 12, 5, 32);
  ASSERT_EQ(t.polylineCount(), 17u);
  for (size_t i = 0; i < t.polylineCount(); ++i) {
    EXPECT_EQ(t.points[t.starts[i]], t.points[t.starts[i + 1] - 1]) << "line " << i << " is closed";
    EXPECT_EQ(t.starts[i + 1] - t.starts[i], 33u);
  }
  ParametricSource sphere;
  sphere.type = ParametricSource::Type::Sphere;
  const PolylineSet p = isolines(sphere, 8, 3, 16);
  ASSERT_EQ(p.polylineCount(), 11u);
  for (size_t i = 8; i < 11; ++i)  // parallels at v = 1/4, 2/4, 3/4: z = -cos(pi v)
    EXPECT_NEAR(p.points[p.starts[i]].z, -std::cos(std::numbers::pi * double(i - 7) / 4.0), 1e-12);
  ParametricSource box;
  box.type = ParametricSource::Type::Box;
  EXPECT_EQ(isolines(box, 0, 0).polylineCount(), 12u);  // a box's wire-frame: its 12 edges
}

// Mesh edges: every distinct edge once (a tetrahedron has 6, two triangles sharing one have 5).
TEST(ParametricSources, MeshEdgesAreTheDistinctEdges) {
  TriangleMesh tet;
  tet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  EXPECT_EQ(meshEdges(tet).polylineCount(), 6u);
  TriangleMesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_EQ(meshEdges(quad).polylineCount(), 5u);
}

// Normals transform by the inverse transpose: under a non-uniform scale a sphere's normals stay
// perpendicular to the (now ellipsoid) surface, i.e. along the gradient (x/a^2, y/b^2, z/c^2).
TEST(ParametricSources, TransformKeepsNormalsPerpendicular) {
  ParametricSource s;
  s.type = ParametricSource::Type::Sphere;
  TriangleMesh m = tessellate(s);
  const glm::dvec3 k(3.0, 1.0, 0.5);
  glm::dmat4 M(1.0);
  M[0][0] = k.x, M[1][1] = k.y, M[2][2] = k.z;
  transformMesh(m, M);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 p = m.positions[i];
    const glm::dvec3 g = glm::normalize(glm::dvec3(p.x / (k.x * k.x), p.y / (k.y * k.y), p.z / (k.z * k.z)));
    EXPECT_NEAR(glm::length(m.normals[i] - g), 0.0, 1e-9);
  }
}

// Tangents and dS/du, dS/dv are directions along the surface: they transform by the linear part
// A of M (dS'/du = A dS/du, exactly, 1e-12), not by the inverse transpose; tangents stay unit and
// perpendicular to the transformed normals.
TEST(ParametricSources, TransformMovesDerivativesByTheLinearPart) {
  ParametricSource s;
  s.type = ParametricSource::Type::Torus;
  const TriangleMesh before = tessellate(s);
  TriangleMesh m = before;
  glm::dmat4 M(1.0);
  M[0] = glm::dvec4(2.0, 0.5, 0.0, 0.0);
  M[1] = glm::dvec4(0.0, 3.0, 0.0, 0.0);
  M[2] = glm::dvec4(0.3, 0.0, 0.5, 0.0);
  M[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
  transformMesh(m, M);
  const glm::dmat3 A(M);
  ASSERT_EQ(m.derivU.size(), m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_LT(glm::length(m.derivU[i] - A * before.derivU[i]), 1e-12);
    EXPECT_LT(glm::length(m.derivV[i] - A * before.derivV[i]), 1e-12);
    EXPECT_LT(glm::length(m.tangents[i] - glm::normalize(A * before.tangents[i])), 1e-12);
    EXPECT_NEAR(glm::dot(m.tangents[i], m.normals[i]), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(glm::normalize(m.derivV[i]), m.normals[i]), 0.0, 1e-12);
  }
}

// The scene lathe of the jugs (data/scenes/jug_*.json): a smooth profile with a crisp base rim
// (a 55-degree turn > profileCornerAngle), so the base is flat at z = -1 and never below it.
TEST(ParametricSources, JugLatheHasAFlatBaseAndASmoothBody) {
  ParametricSource s;
  s.type = ParametricSource::Type::Lathe;
  s.profile = {{0.0, -1.0}, {0.55, -1.0}, {0.62, -0.9}, {0.7, -0.6}, {0.72, -0.3}, {0.66, 0.0},
               {0.5, 0.3},  {0.36, 0.55}, {0.32, 0.75}, {0.36, 0.9}, {0.42, 1.0}};
  s.resolutionU = 96;
  s.resolutionV = 64;
  ASSERT_TRUE(s.problem().empty());
  const TriangleMesh m = tessellate(s);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_GE(m.positions[i].z, -1.0 - 1e-12);
    if (m.positions[i].z < -0.999 && glm::length(glm::dvec2(m.positions[i])) < 0.54) {  // the base
      EXPECT_NEAR(m.normals[i].z, -1.0, 1e-12);
    }
  }
  // Along the meridian u = 0 (vertex 0 of every row of 97): the base rim is a crease, a doubled
  // row at one v whose two normals are the two sides' (the profile turns by about 55 degrees
  // there); everywhere else the body is smooth, neighbouring normals turning by less than 12
  // degrees per step (64 steps over the profile).
  const size_t rows = m.positions.size() / 97;
  int creaseRows = 0;
  for (size_t j = 0; j + 1 < rows; ++j) {
    const glm::dvec3 a = m.normals[j * 97], b = m.normals[(j + 1) * 97];
    if (m.uvs[j * 97].y == m.uvs[(j + 1) * 97].y) {  // the crease's pair: crisp
      ++creaseRows;
      EXPECT_LT(glm::dot(a, b), std::cos(40.0 * std::numbers::pi / 180.0)) << "row " << j;
      EXPECT_LT(glm::length(m.positions[j * 97] - m.positions[(j + 1) * 97]), 1e-12);
    } else if (m.positions[j * 97].z > -0.999) {
      EXPECT_GT(glm::dot(a, b), std::cos(12.0 * std::numbers::pi / 180.0)) << "row " << j;
    }
  }
  EXPECT_EQ(creaseRows, 1);  // the base rim (the default 50-degree corner angle)
}

TEST(ParametricSources, ProblemsAreReported) {
  ParametricSource s;
  s.type = ParametricSource::Type::Torus;
  s.minor = -1;
  EXPECT_FALSE(s.problem().empty());
  s = ParametricSource{};
  s.type = ParametricSource::Type::Lathe;
  EXPECT_FALSE(s.problem().empty());  // no profile
  s.profile = {{1, 0}, {std::nan(""), 1}};
  EXPECT_FALSE(s.problem().empty());
  s = ParametricSource{};
  s.resolutionU = 2;
  EXPECT_FALSE(s.problem().empty());
  EXPECT_TRUE(ParametricSource{}.problem().empty());
  s = ParametricSource{};
  s.type = ParametricSource::Type::Loft;
  EXPECT_FALSE(s.problem().empty());  // no sections
  s.sections = {{{0, 0, 0}, 0.0, 0.0, {}}, {{1, 0, 0}, 0.5, 0.4, {}}, {{2, 0, 0.3}, 0.0, 0.0, {}}};
  EXPECT_TRUE(s.problem().empty());
  EXPECT_FALSE(tessellate(s).triangles.empty());
  s = ParametricSource{};
  s.type = ParametricSource::Type::Bezier;
  EXPECT_FALSE(s.problem().empty());  // no control points
  for (int k = 0; k < 16; ++k) s.controlPoints.emplace_back(k % 4, k / 4, 0.0);
  EXPECT_TRUE(s.problem().empty());
  EXPECT_EQ(tessellate(s).triangles.size(), size_t(2 * 48 * 24));
  s.type = ParametricSource::Type::BSpline;
  s.controlCountU = 3;
  EXPECT_FALSE(s.problem().empty());  // 16 points are not a 3 x 4 net
  s.controlCountU = 4;
  s.periodicU = true;
  EXPECT_TRUE(s.problem().empty());
}

}  // namespace
}  // namespace wf
