// Review tests of Surface::frame, tessellation and TransformedSurface on degenerate and extreme
// input.
#include "surface/patches.h"
#include "surface/tessellate.h"
#include "surface/transformed_surface.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace wf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void expectFiniteFrame(const SurfaceFrame& f, const std::string& what) {
  EXPECT_TRUE(finite3(f.P) && finite3(f.Su) && finite3(f.Sv) && finite3(f.N) && finite3(f.Tu) && finite3(f.Tv)) << what;
  EXPECT_NEAR(glm::length(f.N), 1.0, 1e-12) << what;
  EXPECT_NEAR(glm::length(f.Tu), 1.0, 1e-12) << what;
  EXPECT_NEAR(glm::length(f.Tv), 1.0, 1e-12) << what;
  EXPECT_NEAR(glm::dot(f.N, f.Tu), 0.0, 1e-9) << what;
  EXPECT_NEAR(glm::dot(f.N, f.Tv), 0.0, 1e-9) << what;
}

// A loft along z whose radius is 0 in the middle (three zero sections: the blended radius is
// (1 - 2v)^3 near v = 1/2, a pinch to a point on the spine).
std::shared_ptr<LoftPatch> pinchedLoft() {
  std::vector<LoftSection> sections;
  const double radii[5] = {1, 0, 0, 0, 1};
  for (int k = 0; k < 5; ++k) {
    LoftSection s;
    s.centre = {0, 0, double(k)};
    s.a = s.b = radii[k];
    sections.push_back(s);
  }
  return std::make_shared<LoftPatch>(sections);
}

TEST(SurfaceReview, FrameAtNonFiniteParametersIsDefined) {
  auto sphere = std::make_shared<SpherePatch>(1.0);
  std::vector<std::shared_ptr<const Surface>> surfaces = {
      sphere, pinchedLoft(), std::make_shared<TorusPatch>(1.0, 0.3),
      std::make_shared<TransformedSurface>(sphere, glm::scale(glm::dmat4(1.0), glm::dvec3(-2, 1, 0))),
      std::make_shared<TransformedSurface>(sphere, glm::scale(glm::dmat4(1.0), glm::dvec3(1e-6))),
      std::make_shared<TransformedSurface>(sphere, glm::scale(glm::dmat4(1.0), glm::dvec3(1e6)))};
  const double odd[] = {kNaN, kInf, -kInf, 1e308, -1e308, 0.0, 1.0, 0.5};
  for (const auto& s : surfaces)
    for (double u : odd)
      for (double v : odd) expectFiniteFrame(s->frame(u, v), s->describe() + " at " + std::to_string(u) + "," + std::to_string(v));
}

// The pinch of the loft: frames finite; at the pinch the limit normal is perpendicular to the
// spine (the radius has zero slope there); the tessellation is finite, its kept triangles have
// area, and they wind about the vertex normals (counter-clockwise about N).
TEST(SurfaceReview, LoftPinchedToAPointInTheMiddle) {
  auto loft = pinchedLoft();
  ASSERT_EQ(loft->problem(), "");
  for (double u : {0.0, 0.125, 0.3, 0.5}) {
    const SurfaceFrame f = loft->frame(u, 0.5);
    expectFiniteFrame(f, "pinch");
    EXPECT_TRUE(f.degenerate);
    EXPECT_NEAR(f.N.z, 0.0, 1e-3) << u;
    // Outward: along the direction of S(u, v) from the spine just beside the pinch.
    const glm::dvec3 beside = loft->evaluate(u, 0.55).P - loft->spine(0.55);
    EXPECT_GT(glm::dot(f.N, beside), 0.0) << u;
  }
  const TriangleMesh m = tessellate(*loft, 32, 40);  // row 20 is the pinch
  for (size_t k = 0; k < m.positions.size(); ++k) {
    ASSERT_TRUE(finite3(m.positions[k]) && finite3(m.normals[k]) && finite3(m.tangents[k]));
    ASSERT_NEAR(glm::length(m.normals[k]), 1.0, 1e-12);
  }
  for (const glm::uvec3& t : m.triangles) {
    const glm::dvec3 c = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    ASSERT_GT(glm::length(c), 0.0);
    const glm::dvec3 n = m.normals[t.x] + m.normals[t.y] + m.normals[t.z];
    EXPECT_GT(glm::dot(c, n), 0.0) << t.x << " " << t.y << " " << t.z;
    if (HasFailure()) break;
  }
}

// Scale-free: the frame of a sphere scaled by 1e-6 and by 1e6 (and a mirrored one) equals the
// unit sphere's, at the poles and elsewhere, and tessellation keeps the same triangles.
TEST(SurfaceReview, FrameAndTessellationAreScaleFree) {
  auto sphere = std::make_shared<SpherePatch>(1.0);
  for (double k : {1e-6, 1e6}) {
    TransformedSurface s(sphere, glm::translate(glm::dmat4(1.0), glm::dvec3(k * 3)) * glm::scale(glm::dmat4(1.0), glm::dvec3(k)));
    for (double v : {0.0, 1e-9, 0.25, 0.5, 1.0 - 1e-9, 1.0})
      for (double u : {0.0, 0.3, 0.99}) {
        const SurfaceFrame a = sphere->frame(u, v), b = s.frame(u, v);
        EXPECT_LT(glm::length(a.N - b.N), 1e-9) << k << " " << u << " " << v;
        EXPECT_EQ(a.degenerate, b.degenerate);
      }
    EXPECT_EQ(tessellate(*sphere, 24, 12).triangles.size(), tessellate(s, 24, 12).triangles.size()) << k;
  }
}

// A mirror: normals outward (for the closed sphere), triangles wound about them.
TEST(SurfaceReview, MirroredSurfaceKeepsOutwardNormalsAndWinding) {
  auto sphere = std::make_shared<SpherePatch>(1.0);
  for (glm::dvec3 sc : {glm::dvec3(-1, 1, 1), glm::dvec3(1, -3, 1), glm::dvec3(-1, -1, -1), glm::dvec3(1, 1, -1e-6)}) {
    TransformedSurface s(sphere, glm::scale(glm::dmat4(1.0), sc));
    const TriangleMesh m = tessellate(s, 24, 12);
    for (size_t k = 0; k < m.positions.size(); ++k) {
      // outward normal of the ellipsoid at P: (x / a^2, y / b^2, z / c^2)
      const glm::dvec3 p = m.positions[k], o(p.x / (sc.x * sc.x), p.y / (sc.y * sc.y), p.z / (sc.z * sc.z));
      EXPECT_GT(glm::dot(m.normals[k], o), 0.0) << k;
      if (HasFailure()) return;
    }
    for (const glm::uvec3& t : m.triangles) {
      const glm::dvec3 c = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      EXPECT_GT(glm::dot(c, m.normals[t.x] + m.normals[t.y] + m.normals[t.z]), 0.0);
      if (HasFailure()) return;
    }
  }
}

// A singular transform (a sphere flattened to a disc, or to a segment): frames finite,
// tessellation finite.
TEST(SurfaceReview, SingularTransformGivesDefinedFrames) {
  auto sphere = std::make_shared<SpherePatch>(1.0);
  for (glm::dvec3 sc : {glm::dvec3(1, 1, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 0)}) {
    TransformedSurface s(sphere, glm::scale(glm::dmat4(1.0), sc));
    for (double u : {0.0, 0.25, 0.7})
      for (double v : {0.0, 0.3, 0.5, 0.8, 1.0}) expectFiniteFrame(s.frame(u, v), "singular");
    const TriangleMesh m = tessellate(s, 16, 8);
    for (size_t k = 0; k < m.positions.size(); ++k) ASSERT_TRUE(finite3(m.positions[k]) && finite3(m.normals[k]));
  }
}

}  // namespace
}  // namespace wf
