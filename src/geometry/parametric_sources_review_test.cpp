// Review tests of the parametric sources at extreme parameters. The tests named *Bug* fail on
// the code as reviewed; each says what it shows.
#include "geometry/parametric_sources.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>

namespace wf {
namespace {

bool allFinite(const TriangleMesh& m) {
  for (const auto& p : m.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  for (const auto& n : m.normals)
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) || std::abs(glm::length(n) - 1) > 1e-9) return false;
  for (const auto& t : m.tangents)
    if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) || std::abs(glm::length(t) - 1) > 1e-9) return false;
  return true;
}

// A lathe profile that is one point repeated, or that lies entirely on the axis, passes
// problem() but tessellates to no triangles at all: `wirefur render` then draws an empty
// picture with exit status 0 and no warning. problem() should reject it (zero-length profile /
// profile on the axis), like it rejects a zero radius.
TEST(ParametricSourcesReview, DegenerateLatheProfileIsRejected) {
  for (const std::vector<glm::dvec2>& profile :
       {std::vector<glm::dvec2>{{1, 0}, {1, 0}}, std::vector<glm::dvec2>{{0, 0}, {0, 1}}}) {
    ParametricSource s;
    s.type = ParametricSource::Type::Lathe;
    s.profile = profile;
    const TriangleMesh m = tessellate(s);
    EXPECT_TRUE(!s.problem().empty() || !m.triangles.empty())
        << "profile (" << profile[0].x << "," << profile[0].y << ")-(" << profile[1].x << "," << profile[1].y
        << "): problem() is empty but the surface has " << m.triangles.size() << " triangles";
  }
}

// evaluate() recomputes the profile's arc lengths (a heap vector of P entries) for every
// vertex, twice per vertex (the tangent), so tessellate is O(U * V * P). The scene format
// bounds neither P nor (beyond 4096) U and V: a 5000-point profile at [512, 256] takes
// ~3.5 s (20000 points: 14 s), at [4096, 4096] about 15 minutes. Precomputing the cumulative lengths once makes it O(U V log P).
TEST(ParametricSourcesReview, LatheTessellationIsLinearInProfileLength) {
  ParametricSource s;
  s.type = ParametricSource::Type::Lathe;
  for (int i = 0; i < 5000; ++i) s.profile.emplace_back(1.0 + 0.2 * std::sin(i * 4e-3), i * 4e-4);
  s.resolutionU = 512;
  s.resolutionV = 256;
  ASSERT_TRUE(s.problem().empty());
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh m = tessellate(s);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(m.positions.size(), size_t(513) * 257);  // the seam column is duplicated (continuous u)
  EXPECT_LT(seconds, 1.0) << "131k vertices took " << seconds << " s";
}

// The normal matrix is glm::inverse(M)^T: when det(M) leaves the double range (an anisotropic
// scale the scene reader accepts, e.g. [1e-160, 1e-160, 1]) it is inf / NaN and safeNormalize
// falls back to the untransformed normal, which is wrong (here 45 degrees off). The cofactor
// matrix (inverse times det, no division) gives the right direction for any scale.
TEST(ParametricSourcesReview, NormalsKeepTheirDirectionWhenTheDeterminantUnderflows) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {glm::normalize(glm::dvec3(1, 0, 1)), {0, 0, 1}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}};
  // The same transform with moderate factors gives the reference direction (~ +x).
  TriangleMesh ok = m;
  transformMesh(ok, glm::scale(glm::dmat4(1.0), glm::dvec3(1e-100, 1e-100, 1)));
  ASSERT_GT(ok.normals[0].x, 0.999);
  transformMesh(m, glm::scale(glm::dmat4(1.0), glm::dvec3(1e-160, 1e-160, 1)));
  EXPECT_GT(m.normals[0].x, 0.999) << "normal " << m.normals[0].x << " " << m.normals[0].y << " " << m.normals[0].z;
}

// What was fine: finite unit normals and tangents for the extremes the scene reader allows.
TEST(ParametricSourcesReview, ExtremeParametersStayFinite) {
  std::vector<ParametricSource> cases;
  for (double r : {1e-12, 1e12}) {
    ParametricSource s;
    s.radius = r;
    cases.push_back(s);
  }
  {
    ParametricSource t;  // self-intersecting torus, passing through the axis
    t.type = ParametricSource::Type::Torus;
    t.major = 0.2;
    t.minor = 1.0;
    cases.push_back(t);
    t.major = t.minor = 1.0;
    cases.push_back(t);
  }
  {
    ParametricSource l;  // closed lathe with both ends on the axis, and a repeated point
    l.type = ParametricSource::Type::Lathe;
    l.profile = {{0, 0}, {1, 0.5}, {1, 0.5}, {0, 1}};
    cases.push_back(l);
  }
  for (auto type : {ParametricSource::Type::Sphere, ParametricSource::Type::Torus, ParametricSource::Type::Plane}) {
    ParametricSource s;
    s.type = type;
    s.resolutionU = 3;
    s.resolutionV = 2;
    cases.push_back(s);
  }
  for (const ParametricSource& s : cases) {
    ASSERT_TRUE(s.problem().empty()) << s.problem();
    const TriangleMesh m = tessellate(s);
    EXPECT_FALSE(m.triangles.empty());
    EXPECT_TRUE(allFinite(m));
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) EXPECT_LT(t[k], m.positions.size());
    const PolylineSet l = isolines(s, 3, 2);
    for (const auto& p : l.points) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
  }
}

}  // namespace
}  // namespace wf
