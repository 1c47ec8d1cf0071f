// Deflection (how finely faces are meshed) and determinism across thread counts.
#include "cad_fixtures.h"

#include <BRepBuilderAPI_Transform.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>

#include <cstring>

using namespace cadtest;

namespace {

TopoDS_Shape filletedBox() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) fillet.Add(2, TopoDS::Edge(edges(i)));
  return fillet.Shape();
}

struct SphereMesh {
  int triangles = 0;
  double maxCentroidDepth = 0;  // max over triangles of R - |centroid|
  double applied = 0, size = 0, relative = 0;
};

SphereMesh meshSphere(const std::string& path, double R, double linear) {
  const Read r = readOk(path, [&](vtkWireFurCADReader* x) {
    x->SetRelativeDeflection(true);
    x->SetLinearDeflection(linear);
  });
  SphereMesh m;
  m.applied = r.reader->GetAppliedLinearDeflection();
  m.size = r.reader->GetModelSize();
  m.relative = r.reader->GetLinearDeflection();
  for (const auto& t : r.triangles()) {
    ++m.triangles;
    const Vec3 c = scale(add(add(r.point(t[0]), r.point(t[1])), r.point(t[2])), 1.0 / 3.0);
    m.maxCentroidDepth = std::max(m.maxCentroidDepth, R - norm(c));
  }
  return m;
}

// The largest distance of a triangle's centroid from the sphere (R - |centroid|) in OpenCASCADE's
// own mesh of the sphere at deflection d (BRepMesh_IncrementalMesh, as the reader calls it:
// absolute deflection, angular 0.35, sequential): the reference for what BRepMesh achieves.
double occtCentroidDepth(double R, double d) {
  const TopoDS_Shape s = BRepPrimAPI_MakeSphere(R).Shape();
  BRepMesh_IncrementalMesh mesher(s, d, Standard_False, 0.35, Standard_False);
  TopLoc_Location loc;
  const Handle(Poly_Triangulation) t = BRep_Tool::Triangulation(facesOf(s).front(), loc);
  double worst = 0;
  for (int i = 1; i <= t->NbTriangles(); ++i) {
    int a = 0, b = 0, c = 0;
    t->Triangle(i).Get(a, b, c);
    worst = std::max(worst, R - ((t->Node(a).XYZ() + t->Node(b).XYZ() + t->Node(c).XYZ()) / 3).Modulus());
  }
  return worst;
}

}  // namespace

// A sphere (R = 5) meshed at relative deflection 1e-3 and at half of it:
// - GetModelSize() is the bounding-box diagonal 2 R sqrt(3), to 1e-7 relative (OpenCASCADE's
//   bounding box is widened by the shape's tolerance, 1e-7 absolute);
// - GetAppliedLinearDeflection() == LinearDeflection * GetModelSize() (the same product: exact);
// - halving the deflection gives more triangles: for a sphere the count goes as 1/d (the chord
//   angle theta with sagitta d = R theta^2 / 8, triangles ~ 4 pi / theta^2); the ratio must be in
//   [1.5, 2.5] (BRepMesh's subdivision is discrete);
// - the triangles' centroids stay close to the sphere. NOT within the applied deflection d as
//   asked: BRepMesh itself does not guarantee that. At 5e-4 (d = 0.00866) OpenCASCADE's own mesh,
//   made directly with BRepMesh_IncrementalMesh, has centroids up to 0.0147 = 1.7 d inside the
//   sphere (triangles along the seam u = 0 near the equator; also 1.6 d at 2e-3, 1.7 d at 1e-4),
//   while at 1e-3 it stays within d. So the test asserts what holds: the reader's worst centroid
//   depth equals BRepMesh's own at the same deflection (1e-12 R: the reader adds no error of its
//   own) and is at most 2 d. The excess is reported as a finding (docs promise a deflection).
TEST(CadDeflection, SphereHalvingAndCentroids) {
  const double R = 5;
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(R).Shape(), "deflection_sphere.brep");
  const SphereMesh a = meshSphere(path, R, 1e-3), b = meshSphere(path, R, 5e-4);
  const double diag = 2 * R * std::sqrt(3.0);
  EXPECT_NEAR(a.size, diag, 1e-7 * diag);
  EXPECT_EQ(a.applied, a.relative * a.size);
  EXPECT_EQ(b.applied, b.relative * b.size);
  EXPECT_DOUBLE_EQ(b.applied, 0.5 * a.applied);
  EXPECT_GT(b.triangles, a.triangles);
  const double ratio = double(b.triangles) / double(a.triangles);
  EXPECT_GE(ratio, 1.5);
  EXPECT_LE(ratio, 2.5);
  for (const SphereMesh* m : {&a, &b}) {
    EXPECT_NEAR(m->maxCentroidDepth, occtCentroidDepth(R, m->applied), 1e-12 * R) << "deflection " << m->applied;
    EXPECT_LE(m->maxCentroidDepth, 2 * m->applied);
    EXPECT_GT(m->maxCentroidDepth, 0.1 * m->applied) << "the mesh is much finer than asked for";
  }
  EXPECT_LE(a.maxCentroidDepth, a.applied) << "at 1e-3 BRepMesh keeps within d";
}

// With RelativeDeflection off, LinearDeflection is in world units: applied = LinearDeflection
// exactly, and the centroids stay within it (at 0.01 on R = 5, BRepMesh keeps its centroids
// within d; see above for deflections where it does not).
TEST(CadDeflection, AbsoluteDeflection) {
  const double R = 5;
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(R).Shape(), "deflection_abs.brep");
  const Read r = readOk(path, [](vtkWireFurCADReader* x) {
    x->SetRelativeDeflection(false);
    x->SetLinearDeflection(0.01);
  });
  EXPECT_EQ(r.reader->GetAppliedLinearDeflection(), 0.01);
  double depth = 0;
  for (const auto& t : r.triangles())
    depth = std::max(depth, R - norm(scale(add(add(r.point(t[0]), r.point(t[1])), r.point(t[2])), 1.0 / 3.0)));
  EXPECT_LE(depth, 0.01 + 1e-12 * R);
}

// Relative deflection makes the mesh independent of the model's scale: the filleted box (26
// faces: planes, cylinders, spheres) scaled by 1e-3 and by 1e3 (BRepBuilderAPI_Transform, which
// scales the geometry and the tolerances) gives exactly the same number of triangles as at scale
// 1, and the applied deflection scales with the factor, to 1e-5 relative: the model size is
// OpenCASCADE's bounding box widened by the shapes' tolerances, which do not go below
// Precision::Confusion() = 1e-7 absolute; on the 1e-3 model (diagonal 0.037) that widens the
// diagonal by about 2 sqrt(3) 1e-7 / 0.037 ~ 1e-5.
TEST(CadDeflection, ScaleInvariance) {
  const TopoDS_Shape base = filletedBox();
  std::vector<int> counts;
  std::vector<double> applied;
  for (double s : {1e-3, 1.0, 1e3}) {
    gp_Trsf t;
    t.SetScale(gp_Pnt(0, 0, 0), s);
    const TopoDS_Shape scaled = BRepBuilderAPI_Transform(base, t, Standard_True).Shape();
    const Read r = readOk(writeBrep(scaled, "scaled_" + std::to_string(counts.size()) + ".brep"));
    counts.push_back(int(r.faces->GetNumberOfCells()));
    applied.push_back(r.reader->GetAppliedLinearDeflection() / s);
    EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 26) << "scale " << s;
  }
  EXPECT_EQ(counts[0], counts[1]) << "scale 1e-3";
  EXPECT_EQ(counts[2], counts[1]) << "scale 1e3";
  EXPECT_NEAR(applied[0], applied[1], 1e-5 * applied[1]);
  EXPECT_NEAR(applied[2], applied[1], 1e-5 * applied[1]);
}

// Determinism: a compound of many faces of all kinds (filleted box, sphere, torus, cylinder)
// read with 1 thread and with 2 threads (and with oneTBB's default) gives bit-identical outputs:
// points, Normals, Su, Sv, TCoords, Colors, the triangles and FaceId, and the edges output.
TEST(CadDeterminism, ThreadCountsBitIdentical) {
  TopoDS_Compound c;
  BRep_Builder b;
  b.MakeCompound(c);
  b.Add(c, filletedBox());
  b.Add(c, BRepPrimAPI_MakeSphere(gp_Pnt(30, 0, 0), 4).Shape());
  b.Add(c, BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(-20, 0, 0), gp_Dir(0, 1, 0)), 5, 1.5).Shape());
  b.Add(c, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, -20, 0), gp_Dir(1, 1, 1)), 3, 8).Shape());
  const std::string path = writeBrep(c, "determinism.brep");
  auto read = [&](int threads) {
    return readOk(path, [&](vtkWireFurCADReader* x) {
      x->SetNumberOfThreads(threads);
      x->SetLinearDeflection(2e-4);
      x->SetNumberOfUIsoLines(2);
      x->SetNumberOfVIsoLines(2);
    });
  };
  const Read one = read(1), two = read(2), any = read(0);
  auto sameArray = [](vtkDataArray* a, vtkDataArray* b) {
    if (!a || !b || a->GetDataType() != b->GetDataType() || a->GetNumberOfTuples() != b->GetNumberOfTuples() ||
        a->GetNumberOfComponents() != b->GetNumberOfComponents())
      return false;
    const size_t bytes = size_t(a->GetNumberOfValues()) * size_t(a->GetDataTypeSize());
    return std::memcmp(a->GetVoidPointer(0), b->GetVoidPointer(0), bytes) == 0;
  };
  for (const Read* other : {&two, &any}) {
    ASSERT_EQ(one.nPoints(), other->nPoints());
    EXPECT_TRUE(sameArray(one.faces->GetPoints()->GetData(), other->faces->GetPoints()->GetData()));
    for (const char* name : {"Normals", "Su", "Sv", "TCoords", "Colors"})
      EXPECT_TRUE(sameArray(one.faces->GetPointData()->GetArray(name), other->faces->GetPointData()->GetArray(name))) << name;
    EXPECT_TRUE(sameArray(one.faces->GetCellData()->GetArray("FaceId"), other->faces->GetCellData()->GetArray("FaceId")));
    EXPECT_TRUE(sameArray(one.faces->GetPolys()->GetConnectivityArray(), other->faces->GetPolys()->GetConnectivityArray()));
    EXPECT_TRUE(sameArray(one.edges->GetPoints()->GetData(), other->edges->GetPoints()->GetData()));
    EXPECT_TRUE(sameArray(one.edges->GetLines()->GetConnectivityArray(), other->edges->GetLines()->GetConnectivityArray()));
    EXPECT_TRUE(sameArray(one.edges->GetCellData()->GetArray("Kind"), other->edges->GetCellData()->GetArray("Kind")));
  }
  EXPECT_GT(one.reader->GetNumberOfFaces(), 26);
}

// The brief's range of coordinates, 1e-6 to 1e6: a torus (R = 3, r = 1) scaled by 1e-6 and by
// 1e6 reads, meshes and gives outward unit normals (away from the tube's centre circle, to 1e-6)
// at both scales. OpenCASCADE's mesher fails below its absolute confusion (1e-7), which the
// relative default asks for at 1e-6: the applied deflection is held at 1e-7 there.
TEST(CadDeflection, CoordinatesFromOneMillionthToOneMillion) {
  for (double s : {1e-6, 1e6}) {
    gp_Trsf t;
    t.SetScale(gp_Pnt(0, 0, 0), s);
    const TopoDS_Shape torus = BRepBuilderAPI_Transform(BRepPrimAPI_MakeTorus(3, 1).Shape(), t, true).Shape();
    const Read r = readOk(writeBrep(torus, s < 1 ? "torus_micro.brep" : "torus_mega.brep"));
    EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 1) << s;
    EXPECT_GE(r.reader->GetAppliedLinearDeflection(), 1e-7) << s;
    EXPECT_GT(r.faces->GetNumberOfCells(), 100) << s;
    double worst = 0;
    for (vtkIdType i = 0; i < r.nPoints(); ++i) {
      const Vec3 p = r.point(i);
      const double rho = std::hypot(p[0], p[1]);
      const Vec3 centre{3 * s * p[0] / rho, 3 * s * p[1] / rho, 0.0};
      worst = std::max(worst, norm(sub(r.normal(i), unit(sub(p, centre)))));
    }
    EXPECT_LT(worst, 1e-6) << s;
  }
}
