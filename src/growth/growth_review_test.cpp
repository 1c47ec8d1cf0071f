// Review tests of fur and scales on extreme, degenerate and transformed surfaces, and of the
// renderer's thread-count independence on a fur scene.
#include "growth/fur.h"
#include "growth/scales.h"
#include "render/renderer.h"
#include "surface/patches.h"
#include "surface/transformed_surface.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

namespace wf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A plane whose left half (u < 0.5) is not finite: P NaN there; Su NaN on a strip u in [0.5, 0.6).
class HalfBrokenPlane final : public Surface {
 public:
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, false, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
    if (u < 0.5) return {glm::dvec3(kNaN), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)};
    if (u < 0.6) return {glm::dvec3(u, v, 0), glm::dvec3(kNaN, 0, 0), glm::dvec3(0, 1, 0)};
    return {glm::dvec3(u, v, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)};
  }
  std::string describe() const override { return "half broken plane"; }
};

TEST(GrowthReview, FurOnNonFiniteSurfaceSkipsRootsAndStaysFinite) {
  HalfBrokenPlane s;
  for (auto placement : {FurParams::Placement::Grid, FurParams::Placement::AreaCorrect}) {
    FurParams p;
    p.placement = placement;
    p.gridU = 40, p.gridV = 20;
    p.density = 2000;
    p.cellsU = p.cellsV = 16;
    p.segments = 3;
    p.gravity = 0.5;
    p.curlAmplitude = 0.1;
    p.clumping = 0.5;
    const Fur f = growFur(s, p);
    EXPECT_GT(f.counts.hairs, 0u);
    for (const glm::dvec3& q : f.hairs.points) ASSERT_TRUE(finite3(q));
    for (const glm::vec3& c : f.hairs.colours) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z));
    // Hairs on the Su-NaN strip grow along the limit normal (+z).
    for (size_t h = 0; h < f.hairs.polylineCount(); ++h) {
      const glm::dvec3 r = f.hairs.points[f.hairs.starts[h]], t = f.hairs.points[f.hairs.starts[h] + 1];
      EXPECT_GT(t.z - r.z, 0.0);
    }
    if (placement == FurParams::Placement::Grid) {
      EXPECT_GT(f.counts.skippedDegenerate, 0u);
    }
  }
}

// The mirrored surface's hairs grow outward (away from the centre) and its scales face outward.
TEST(GrowthReview, MirroredSphereGrowsOutward) {
  auto base = std::make_shared<SpherePatch>(1.0);
  const glm::dmat4 M = glm::translate(glm::dmat4(1.0), glm::dvec3(3, 0, 0)) *
                       glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 2.0, 0.5));
  TransformedSurface s(base, M);
  const glm::dvec3 centre(3, 0, 0);
  FurParams p;
  p.gridU = 30, p.gridV = 15;
  const Fur f = growFur(s, p);
  ASSERT_GT(f.counts.hairs, 0u);
  for (size_t h = 0; h < f.hairs.polylineCount(); ++h) {
    const glm::dvec3 r = f.hairs.points[f.hairs.starts[h]], t = f.hairs.points[f.hairs.starts[h] + 1];
    // The ellipsoid's outward normal at r: A^-T (r - c) direction, i.e. (x / a^2, y / b^2, z / c^2).
    const glm::dvec3 q = r - centre, n(q.x / 1.0, q.y / 4.0, q.z / 0.25);
    EXPECT_GT(glm::dot(t - r, n), 0.0) << h;
    if (HasFailure()) break;
  }
  ScaleParams sp;
  sp.cellsU = 12, sp.cellsV = 8;
  const TriangleMesh m = growScales(s, sp);
  ASSERT_FALSE(m.triangles.empty());
  for (const glm::uvec3& t : m.triangles) {
    const glm::dvec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
    const glm::dvec3 q = a - centre, n(q.x, q.y / 4.0, q.z / 0.25);
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), n), 0.0);
    EXPECT_GT(glm::dot(m.normals[t.x], n), 0.0);
    if (HasFailure()) break;
  }
}

// A mirrored object should be the mirror image of the unmirrored one. TransformedSurface
// reverses u to keep the normal outward, so a hair leaning along +Su (orientation a != 0) leans
// along -A Su: the mirror image of combed fur is combed the other way, and the scales (which
// run along +Tu) point the other way too.
TEST(GrowthReview, MirroredPlaneFurAndScalesAreTheMirrorImage) {
  auto base = std::make_shared<PlanePatch>(2.0, 2.0);
  const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
  TransformedSurface mirrored(base, mirror);
  FurParams p;
  p.gridU = 8, p.gridV = 8;
  p.jitter = 0.0;  // roots at the cell centres: a set symmetric under u -> 1 - u
  p.lengthVariation = 0.0;
  p.orientation = {0.5, 0.0, 1.0};
  p.lengthMode = FurParams::LengthMode::Fixed;
  const Fur a = growFur(*base, p), b = growFur(mirrored, p);
  ASSERT_EQ(a.hairs.polylineCount(), b.hairs.polylineCount());
  // For every hair of a, b has one at the mirrored root with the mirrored tip.
  int unmatched = 0;
  for (size_t h = 0; h < a.hairs.polylineCount(); ++h) {
    const glm::dvec3 r = a.hairs.points[a.hairs.starts[h]], t = a.hairs.points[a.hairs.starts[h] + 1];
    const glm::dvec3 mr(-r.x, r.y, r.z), mt(-t.x, t.y, t.z);
    bool found = false;
    for (size_t k = 0; k < b.hairs.polylineCount() && !found; ++k)
      found = glm::length(b.hairs.points[b.hairs.starts[k]] - mr) < 1e-9 &&
              glm::length(b.hairs.points[b.hairs.starts[k] + 1] - mt) < 1e-9;
    unmatched += !found;
  }
  EXPECT_EQ(unmatched, 0) << "hairs of the mirrored plane that are not the mirror image";
  ScaleParams sp;
  sp.cellsU = 4, sp.cellsV = 4;
  const TriangleMesh sa = growScales(*base, sp), sb = growScales(mirrored, sp);
  ASSERT_EQ(sa.positions.size(), sb.positions.size());
  // Vertex 2 of each scale is its tip: on the unmirrored plane it lies at +x of the root.
  double meanTipA = 0, meanTipB = 0;
  for (size_t k = 0; k < sa.positions.size(); k += 4) {
    meanTipA += sa.positions[k + 2].x - sa.positions[k].x;
    meanTipB += sb.positions[k + 2].x - sb.positions[k].x;
  }
  EXPECT_LT(meanTipB, 0.0) << "mirror image of tips along +x (" << meanTipA << ") should point along -x";
}

// Singular transforms (scale 0 on one axis: a sphere flattened to a disc; everything 0: a point).
TEST(GrowthReview, SingularTransformGivesFiniteFurAndScales) {
  auto base = std::make_shared<SpherePatch>(1.0);
  for (glm::dvec3 scale : {glm::dvec3(1, 1, 0), glm::dvec3(0, 1, 1), glm::dvec3(0, 0, 0), glm::dvec3(1e-12, 1e12, 1)}) {
    TransformedSurface s(base, glm::scale(glm::dmat4(1.0), scale));
    FurParams p;
    p.gridU = 20, p.gridV = 10;
    p.segments = 2;
    p.curlAmplitude = 0.2;
    for (auto mode : {FurParams::LengthMode::Fixed, FurParams::LengthMode::ProportionalToSu, FurParams::LengthMode::Paper}) {
      p.lengthMode = mode;
      Fur f;
      ASSERT_NO_THROW(f = growFur(s, p));
      for (const glm::dvec3& q : f.hairs.points) ASSERT_TRUE(finite3(q));
    }
    p.placement = FurParams::Placement::AreaCorrect;
    p.density = scale.y > 10 ? 1e-10 : 100;  // the 1e12-wide disc has ~6e12 units of area
    Fur f;
    ASSERT_NO_THROW(f = growFur(s, p)) << scale.x << " " << scale.y << " " << scale.z;
    for (const glm::dvec3& q : f.hairs.points) ASSERT_TRUE(finite3(q));
    ScaleParams sp;
    const TriangleMesh m = growScales(s, sp);
    for (size_t k = 0; k < m.positions.size(); ++k) {
      ASSERT_TRUE(finite3(m.positions[k]));
      ASSERT_TRUE(finite3(m.normals[k]));
      ASSERT_NEAR(glm::length(m.normals[k]), 1.0, 1e-9);
    }
  }
}

// Scales next to the poles: finite, unit normals facing outward, no scale rooted at the pole.
TEST(GrowthReview, ScalesNearThePolesFaceOutward) {
  SpherePatch s(1.0);
  ScaleParams sp;
  sp.cellsU = 64, sp.cellsV = 256;  // centre scales at v = 1/512 of the poles
  const TriangleMesh m = growScales(s, sp);
  ASSERT_FALSE(m.triangles.empty());
  for (size_t k = 0; k < m.positions.size(); k += 4) {
    const glm::dvec3 r = m.positions[k];
    EXPECT_GT(std::hypot(r.x, r.y), 0.0) << "a scale rooted on the axis (a pole)";
    for (int j = 0; j < 4; ++j) {
      ASSERT_TRUE(finite3(m.positions[k + j]) && finite3(m.normals[k + j]));
      EXPECT_GT(glm::dot(m.normals[k + j], r), 0.0);
    }
    if (HasFailure()) break;
  }
}

// The whole pipeline on a fur scene: bit-identical images for 1, 2 and 7 threads, for the
// A-buffer and for the reference.
TEST(GrowthReview, FurSceneRendersTheSameForAnyThreadCount) {
  auto sphere = std::make_shared<SpherePatch>(1.0);
  FurParams p;
  p.gridU = 120, p.gridV = 60;
  p.length = 0.25;
  p.segments = 4;
  p.gravity = 0.6;
  p.curlAmplitude = 0.05;
  p.clumping = 0.3;
  p.thickness = 0.01;
  Fur fur;
  {
    tbb::task_arena one(1);
    one.execute([&] { fur = growFur(*sphere, p); });
  }
  for (int threads : {2, 7}) {
    tbb::task_arena arena(threads);
    Fur other;
    arena.execute([&] { other = growFur(*sphere, p); });
    ASSERT_EQ(other.hairs.points.size(), fur.hairs.points.size());
    ASSERT_EQ(0, std::memcmp(other.hairs.points.data(), fur.hairs.points.data(),
                             fur.hairs.points.size() * sizeof(glm::dvec3)));
  }
  Scene s;
  s.camera = frameSphere(glm::dvec3(0.0), 1.3, 1.0);
  s.lights = LightRig::studioRig(3);
  SceneWire w;
  w.lines = fur.hairs;
  w.thickness = fur.thickness;
  w.opacity = 0.7f;
  s.wires.push_back(w);
  Material skin;
  skin.burnish.grain = Burnish::Grain::U;
  s.materials.push_back(skin);
  SceneSurface body;
  body.material = 1;
  for (int j = 0; j <= 16; ++j)
    for (int i = 0; i <= 32; ++i) {
      const SurfaceFrame f = sphere->frame(i / 32.0, j / 16.0);
      body.mesh.positions.push_back(f.P);
      body.mesh.normals.push_back(f.N);
      body.mesh.derivU.push_back(f.Su);
      body.mesh.derivV.push_back(f.Sv);
      body.mesh.uvs.push_back({i / 32.0, j / 16.0});
    }
  for (unsigned j = 0; j < 16; ++j)
    for (unsigned i = 0; i < 32; ++i) {
      const unsigned a = j * 33 + i;
      body.mesh.triangles.push_back({a, a + 1, a + 34});
      body.mesh.triangles.push_back({a, a + 34, a + 33});
    }
  s.surfaces.push_back(body);
  RenderOptions o;
  o.width = 96, o.height = 96;
  o.tileSize = 16;
  o.sphereResolution = 32;
  o.map.resolution = 32;
  o.map.samples = 16;
  o.referenceSamples = 4;
  std::vector<ImageRGBA> a, r;
  for (int threads : {1, 2, 7}) {
    o.threads = threads;
    a.push_back(render(s, o).image);
    r.push_back(renderReference(s, o).image);
  }
  for (size_t k = 1; k < a.size(); ++k) {
    EXPECT_EQ(0, std::memcmp(a[k].pixels.data(), a[0].pixels.data(), a[0].pixels.size() * sizeof(glm::vec4))) << k;
    EXPECT_EQ(0, std::memcmp(r[k].pixels.data(), r[0].pixels.data(), r[0].pixels.size() * sizeof(glm::vec4))) << k;
  }
}

}  // namespace
}  // namespace wf
