// The CAD reader on solids made by OpenCASCADE's modelling algorithms: a box with all 12 edges
// filleted (planes, cylinders and sphere corners) and a box with a cylindrical hole cut through it
// (a REVERSED face).
#include "cad_fixtures.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Ax2.hxx>

#include <map>

using namespace cadtest;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kA = 10, kB = 20, kC = 30, kR = 2;  // the filleted box [0,a]x[0,b]x[0,c], radius r

TopoDS_Shape filletedBox() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(kA, kB, kC).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) fillet.Add(kR, TopoDS::Edge(edges(i)));
  fillet.Build();
  EXPECT_TRUE(fillet.IsDone());
  return fillet.Shape();
}

// The nearest point of the inner box [r, a-r] x [r, b-r] x [r, c-r]: every point of the filleted
// box's surface is at distance r from it, along the outward normal.
Vec3 innerClamp(const Vec3& p) {
  return {std::clamp(p[0], kR, kA - kR), std::clamp(p[1], kR, kB - kR), std::clamp(p[2], kR, kC - kR)};
}

// A box 10 x 10 x 10 with a hole of radius 2 along z through (5, 5).
constexpr double kHoleR = 2;
TopoDS_Shape boxWithHole() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 10, 10).Shape();
  const TopoDS_Shape tool = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(5, 5, -1), gp_Dir(0, 0, 1)), kHoleR, 12).Shape();
  BRepAlgoAPI_Cut cut(box, tool);
  EXPECT_TRUE(cut.IsDone());
  return cut.Shape();
}

// The hole's points: on the hole (radius 2 from the axis x = y = 5, 1e-9 relative: mesh nodes are
// surface points), normals toward the axis (into the hole, out of the material): equal to
// -(P - axis point)/r to 1e-6 (float normals); planar faces outward along +-x, +-y, +-z at the
// box's bounds (exact); every triangle CCW about its normals.
void checkHole(const Read& r, int holeFace) {
  const std::vector<int> pf = r.pointFaces();
  int holePoints = 0, bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i), n = r.normal(i);
    if (pf[size_t(i)] == holeFace) {
      ++holePoints;
      const Vec3 radial = Vec3{p[0] - 5, p[1] - 5, 0};
      EXPECT_NEAR(norm(radial), kHoleR, 1e-9 * kHoleR);
      const Vec3 expected = scale(unit(radial), -1.0);
      if (!(norm(sub(n, expected)) < 1e-6) && ++bad <= 5)
        ADD_FAILURE() << "hole point (" << p[0] << ", " << p[1] << ", " << p[2] << ") normal (" << n[0] << ", " << n[1] << ", "
                      << n[2] << ")";
    } else {
      int k = 0;
      for (int j = 1; j < 3; ++j)
        if (std::abs(n[j]) > std::abs(n[k])) k = j;
      const bool ok = std::abs(std::abs(n[k]) - 1) < 1e-6 && std::abs(p[k] - (n[k] > 0 ? 10.0 : 0.0)) < 1e-9;
      if (!ok && ++bad <= 5)
        ADD_FAILURE() << "plane point (" << p[0] << ", " << p[1] << ", " << p[2] << ") normal (" << n[0] << ", " << n[1] << ", "
                      << n[2] << ")";
    }
  }
  EXPECT_GT(holePoints, 20);
  EXPECT_EQ(bad, 0);
  const WindingReport w = checkWinding(r, 1e-14);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles;
  EXPECT_EQ(w.degenerate, 0);
}

int cylinderFace(const TopoDS_Shape& s) {
  const std::vector<GeomAbs_SurfaceType> t = surfaceTypes(s);
  int found = -1;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] == GeomAbs_Cylinder) {
      EXPECT_EQ(found, -1) << "more than one cylindrical face";
      found = int(i);
    }
  return found;
}

}  // namespace

// The fixture itself: filleting all 12 edges of a box with one radius gives 26 faces: the 6
// planes (shrunk), 12 cylinders (a quarter each, along the edges) and 8 sphere octants (the
// corners, where three fillets of one radius meet at right angles). Checked on the shape we made,
// then the reader must find and mesh the same 26.
TEST(CadFillet, FaceCountAndTypes) {
  const TopoDS_Shape s = filletedBox();
  std::map<GeomAbs_SurfaceType, int> count;
  for (GeomAbs_SurfaceType t : surfaceTypes(s)) ++count[t];
  EXPECT_EQ(count[GeomAbs_Plane], 6);
  EXPECT_EQ(count[GeomAbs_Cylinder], 12);
  EXPECT_EQ(count[GeomAbs_Sphere], 8);
  EXPECT_EQ(int(surfaceTypes(s).size()), 26);
  const Read r = readOk(writeBrep(s, "fillet_count.brep"));
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 26);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 26);
  EXPECT_EQ(r.reader->GetNumberOfSkippedFaces(), 0);
}

// The filleted box's surface area against its closed form
//   A = 2[(a-2r)(b-2r) + (b-2r)(c-2r) + (c-2r)(a-2r)] + 2 pi r (a+b+c-6r) + 4 pi r^2
// (planes, 12 quarter cylinders = 4 full ones along each direction, 8 octants = one sphere).
// The planar part is meshed exactly up to the rounded boundary; the curved part's triangles are
// chords at most the deflection d below the surface: a chord of sagitta s on radius r loses
// s/(3r) of the arc length, a flat triangle under a spherical cap s/(2r) of its area. The tolerance
// is A_curved * d / r (twice the worst case; the planes' boundaries follow the same chords).
// Also: every normal is (P - nearest point of the inner box)/r (the closed-form outward normal of
// the rounded box; 1e-6, float normals; |P - inner| = r to 1e-9 relative shows the fillets are
// exact cylinders and spheres), outward (dot(n, P - centre) > 0), triangles CCW.
TEST(CadFillet, AreaNormalsWinding) {
  const Read r = readOk(writeBrep(filletedBox(), "fillet.brep"), [](vtkWireFurCADReader* x) { x->SetLinearDeflection(2e-4); });
  const double a = kA - 2 * kR, b = kB - 2 * kR, c = kC - 2 * kR;
  const double curved = 2 * kPi * kR * (a + b + c) + 4 * kPi * kR * kR;
  const double exact = 2 * (a * b + b * c + c * a) + curved;
  const double d = r.reader->GetAppliedLinearDeflection();
  const double area = meshArea(r);
  EXPECT_NEAR(area, exact, curved * d / kR) << "deflection " << d;
  const Vec3 centre{kA / 2, kB / 2, kC / 2};
  int bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i), n = r.normal(i);
    const Vec3 off = sub(p, innerClamp(p));
    const bool ok = std::abs(norm(off) - kR) < 1e-9 * kR && norm(sub(n, scale(off, 1 / kR))) < 1e-6 && dot(n, sub(p, centre)) > 0;
    if (!ok && ++bad <= 5)
      ADD_FAILURE() << "point (" << p[0] << ", " << p[1] << ", " << p[2] << ") normal (" << n[0] << ", " << n[1] << ", " << n[2]
                    << ") |P - inner| = " << norm(off);
  }
  EXPECT_EQ(bad, 0);
  const WindingReport w = checkWinding(r, 1e-12);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles << " (" << w.degenerate << " degenerate)";
}

// The fixture: the hole is ONE cylindrical face, and it is REVERSED in the solid (material
// outside the cylinder), which is what this test is about.
TEST(CadReversed, FixtureHasReversedHole) {
  const TopoDS_Shape s = boxWithHole();
  const int hole = cylinderFace(s);
  ASSERT_GE(hole, 0);
  EXPECT_EQ(facesOf(s)[size_t(hole)].Orientation(), TopAbs_REVERSED);
}

// The hole's normals point into the hole (toward the axis), through BREP (the face order is kept,
// so the hole is the same face index). Su and Sv are the surface's own derivatives, whatever the
// face's orientation: against central differences of the cylinder S = (5,5,z0) + 2(cos u, sin u, 0)
// + v(0, 0, 1) taken from the face's Geom_Surface (1e-6 of r).
TEST(CadReversed, HoleNormalsBrep) {
  const TopoDS_Shape s = boxWithHole();
  const int hole = cylinderFace(s);
  ASSERT_GE(hole, 0);
  const Read r = readOk(writeBrep(s, "hole.brep"));
  checkHole(r, hole);
  // Su, Sv of the hole against finite differences of the face's surface.
  TopLoc_Location loc;
  const Handle(Geom_Surface) g = BRep_Tool::Surface(facesOf(s)[size_t(hole)], loc);
  const std::vector<int> pf = r.pointFaces();
  double su = 0, sv = 0;
  const double h = 1e-5;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    if (pf[size_t(i)] != hole) continue;
    const auto [u, v] = r.uv(i);
    auto S = [&](double uu, double vv) { return fromGp(g->Value(uu, vv).Transformed(loc.Transformation()).XYZ()); };
    su = std::max(su, norm(sub(r.su(i), scale(sub(S(u + h, v), S(u - h, v)), 0.5 / h))) / kHoleR);
    sv = std::max(sv, norm(sub(r.sv(i), scale(sub(S(u, v + h), S(u, v - h)), 0.5 / h))));
  }
  EXPECT_LT(su, 1e-6);
  EXPECT_LT(sv, 1e-6);
}

// The same through STEP (the orientation travels as ADVANCED_FACE's same_sense flag): the face
// order may change, so the hole is found as the faces whose points are all at radius 2 from the
// axis; same checks.
TEST(CadReversed, HoleNormalsStep) {
  const Read r = readOk(writeStep(boxWithHole(), "hole.step"));
  const std::vector<int> pf = r.pointFaces();
  std::map<int, bool> onHole;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i);
    const bool at = std::abs(std::hypot(p[0] - 5, p[1] - 5) - kHoleR) < 1e-6;
    auto it = onHole.find(pf[size_t(i)]);
    onHole[pf[size_t(i)]] = (it == onHole.end() ? true : it->second) && at;
  }
  int hole = -1, n = 0;
  for (auto [f, at] : onHole)
    if (at) hole = f, ++n;
  ASSERT_EQ(n, 1);
  checkHole(r, hole);
}
