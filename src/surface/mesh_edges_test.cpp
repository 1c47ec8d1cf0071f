// wf::classifyMeshEdges (surface/mesh_edges.h): classes against what each mesh is made of, the
// angles against their closed forms, and the chaining of kept edges into polylines.
#include "surface/mesh_edges.h"

#include "geometry/parametric_sources.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wf {
namespace {

std::size_t count(const ClassifiedEdges& e, EdgeClass c) { return e.counts[std::size_t(c)]; }

EdgeSelection select(EdgeSelection::Mode mode, double featureAngle = kDefaultFeatureAngle) {
  EdgeSelection s;
  s.mode = mode;
  s.featureAngle = featureAngle;
  return s;
}

}  // namespace

// A box of six faces with four vertices each (split, as a renderer's mesh has them): welded, it has
// 12 sharp edges at exactly 90 degrees (1e-12) and 6 smooth face diagonals at 0; no boundary. In
// sharp mode the 12 edges stay apart (three meet at each corner): 12 two-point polylines.
TEST(MeshEdges, BoxFromSplitFaces) {
  ParametricSource box;
  box.type = ParametricSource::Type::Box;
  const TriangleMesh m = tessellate(box);
  ASSERT_EQ(m.positions.size(), 24u);
  const ClassifiedEdges e = classifyMeshEdges(m, select(EdgeSelection::Mode::Sharp));
  EXPECT_EQ(count(e, EdgeClass::Sharp), 12u);
  EXPECT_EQ(count(e, EdgeClass::Smooth), 6u);
  EXPECT_EQ(count(e, EdgeClass::Boundary), 0u);
  ASSERT_EQ(e.lines.polylineCount(), 12u);
  for (std::size_t k = 0; k < 12; ++k) {
    EXPECT_EQ(e.lines.starts[k + 1] - e.lines.starts[k], 2u);
    EXPECT_EQ(e.classes[k], EdgeClass::Sharp);
    EXPECT_NEAR(e.angles[k], 90.0, 1e-4);  // (float)
  }
  // All: every edge, 18 (the diagonals too).
  EXPECT_EQ(classifyMeshEdges(m, select(EdgeSelection::Mode::All)).lines.polylineCount(), 18u);
  // Boundary: none on a closed box.
  EXPECT_EQ(classifyMeshEdges(m, select(EdgeSelection::Mode::Boundary)).lines.polylineCount(), 0u);
}

// A square of two triangles: 4 boundary edges chained into one closed loop of 5 points (first =
// last), and the diagonal smooth. Flipping one triangle (inconsistent winding) keeps the diagonal
// at 0 degrees, not 180. A third triangle on the diagonal makes it non-manifold.
TEST(MeshEdges, SquareLoopWindingAndNonManifold) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  ClassifiedEdges e = classifyMeshEdges(m, select(EdgeSelection::Mode::Boundary));
  ASSERT_EQ(e.lines.polylineCount(), 1u);
  ASSERT_EQ(e.lines.points.size(), 5u);
  EXPECT_EQ(e.lines.points.front(), e.lines.points.back());
  EXPECT_EQ(count(e, EdgeClass::Boundary), 4u);
  EXPECT_EQ(count(e, EdgeClass::Smooth), 1u);

  m.triangles[1] = {0, 3, 2};
  e = classifyMeshEdges(m, select(EdgeSelection::Mode::All));
  EXPECT_EQ(count(e, EdgeClass::Smooth), 1u);
  for (std::size_t k = 0; k < e.classes.size(); ++k)
    if (e.classes[k] == EdgeClass::Smooth) {
      EXPECT_EQ(e.angles[k], 0.0f);
    }

  m.positions.push_back({0.5, 0.5, 1});
  m.triangles.push_back({0, 2, 4});
  e = classifyMeshEdges(m, select(EdgeSelection::Mode::Sharp));
  EXPECT_EQ(count(e, EdgeClass::NonManifold), 1u);
}

// A fold of two triangles at a known dihedral angle: the crease's class flips at the feature
// angle, and the angle is exact near 0 and 180 (atan2, not acos: 1e-6 degrees resolves).
TEST(MeshEdges, FoldAngleAgainstTheFeatureAngle) {
  for (double fold : {1e-6, 5.0, 10.5, 90.0, 179.9}) {
    const double r = fold * 3.14159265358979323846 / 180.0;
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0.5, 0}, {-std::cos(r), 0.5, std::sin(r)}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}};
    const ClassifiedEdges e = classifyMeshEdges(m, select(EdgeSelection::Mode::All, 10.0));
    bool found = false;
    for (std::size_t k = 0; k < e.classes.size(); ++k)
      if (e.classes[k] != EdgeClass::Boundary) {
        found = true;
        EXPECT_NEAR(e.angles[k], fold, 1e-4 * std::max(1.0, fold)) << fold;
        EXPECT_EQ(e.classes[k], fold > 10.0 ? EdgeClass::Sharp : EdgeClass::Smooth) << fold;
      }
    EXPECT_TRUE(found);
  }
}

// A tessellated sphere computes its seam's points twice (u = 0 and 2 pi; here they come out
// equal): welded, it has no boundary at all, and at 64 x 32 no facet turns by more than 10
// degrees, so sharp mode keeps nothing.
TEST(MeshEdges, SphereSeamIsWelded) {
  ParametricSource s;
  s.type = ParametricSource::Type::Sphere;
  s.resolutionU = 64, s.resolutionV = 32;
  const TriangleMesh m = tessellate(s);
  const ClassifiedEdges e = classifyMeshEdges(m, select(EdgeSelection::Mode::Sharp));
  EXPECT_EQ(count(e, EdgeClass::Boundary), 0u);
  EXPECT_EQ(count(e, EdgeClass::Sharp), 0u);
  EXPECT_EQ(e.lines.polylineCount(), 0u);
  EXPECT_GT(count(e, EdgeClass::Smooth), 64u * 30u);
}

// The weld tolerance and slivers (from a review): the square's corner 2 given twice, the copy
// moved by 1e-12 (within 1e-9 of the mesh's size) so that the two triangles meet only once
// welded; a sliver triangle (1, 4, 2) whose corners 4 and 2 weld together adds nothing (it left
// the border non-manifold before); an unused vertex at 1e10 does not widen the tolerance (it
// welded the whole square into one point); the same square scaled by 1e+-120 gives the same
// classes (the cross products underflowed or overflowed to no edges at all).
TEST(MeshEdges, WeldToleranceSliversStrayVerticesAndScale) {
  for (double scale : {1.0, 1e-120, 1e120}) {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1 + 1e-12, 0}, {1e10, 0, 0}};
    for (glm::dvec3& p : m.positions) p *= scale;
    m.triangles = {{0, 1, 2}, {0, 4, 3}, {1, 4, 2}};
    const ClassifiedEdges e = classifyMeshEdges(m, select(EdgeSelection::Mode::All));
    EXPECT_EQ(count(e, EdgeClass::Boundary), 4u) << scale;
    EXPECT_EQ(count(e, EdgeClass::Smooth), 1u) << scale;
    EXPECT_EQ(count(e, EdgeClass::NonManifold), 0u) << scale;
  }
}

// From a review: a quad with a collapsed edge (two corners at one point, as a quad mesh has at a
// pole) is a triangle, not left out: two such quads and a triangle closing a tetrahedron-like cap
// leave no false border.
TEST(MeshEdges, QuadWithACollapsedEdgeIsATriangle) {
  const std::vector<glm::dvec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  // Faces of a tetrahedron, two of them as quads with a repeated corner.
  const std::vector<std::uint32_t> ids = {0, 2, 1, 1, 0, 1, 3, 3, 0, 3, 2, 1, 2, 3};
  const std::vector<std::uint32_t> starts = {0, 4, 8, 11, 14};
  const ClassifiedEdges e = classifyPolygonEdges(p, starts, ids, select(EdgeSelection::Mode::All));
  EXPECT_EQ(e.counts[std::size_t(EdgeClass::Boundary)], 0u);
  EXPECT_EQ(e.counts[std::size_t(EdgeClass::Sharp)], 6u);
}

}  // namespace wf
