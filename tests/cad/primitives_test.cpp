// The CAD reader on OpenCASCADE's primitives: a box through STEP, IGES and BREP, and a cylinder,
// a sphere and a torus checked against the closed forms of their parameterisations (OpenCASCADE's
// ElSLib conventions: cylinder S = r(cos u X + sin u Y) + v Z; sphere S = R(cos v cos u, cos v
// sin u, sin v), v in [-pi/2, pi/2]; torus S = (R + r cos v)(cos u X + sin u Y) + r sin v Z).
#include "cad_fixtures.h"

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <IGESControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopLoc_Location.hxx>
#include <gp_Ax1.hxx>
#include <gp_Dir.hxx>

#include <map>
#include <set>

using namespace cadtest;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The box of every box test: corner (1, 2, 3), sides 10, 20, 30 (off the origin so that a lost
// translation shows).
const Vec3 kLo{1, 2, 3}, kHi{11, 22, 33};

TopoDS_Shape makeBox() { return BRepPrimAPI_MakeBox(gp_Pnt(1, 2, 3), 10, 20, 30).Shape(); }

// Every point normal is the outward axis direction of the box face the point lies on: n = +e_k
// needs P_k = hi_k, n = -e_k needs P_k = lo_k (so the normal is outward by construction, not only
// by dot(n, P - centre) > 0, which is checked too). Normals are floats: 1e-6 is rounding with a
// margin. Positions are exact up to double rounding of corners like 33: 1e-9 absolute.
void checkBoxNormals(const Read& r) {
  const Vec3 c = scale(add(kLo, kHi), 0.5);
  int bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 n = r.normal(i), p = r.point(i);
    int k = 0;
    for (int j = 1; j < 3; ++j)
      if (std::abs(n[j]) > std::abs(n[k])) k = j;
    bool ok = std::abs(std::abs(n[k]) - 1.0) < 1e-6 && std::abs(n[(k + 1) % 3]) < 1e-6 && std::abs(n[(k + 2) % 3]) < 1e-6;
    ok = ok && std::abs(p[k] - (n[k] > 0 ? kHi[k] : kLo[k])) < 1e-9;
    ok = ok && dot(n, sub(p, c)) > 0;
    if (!ok && ++bad <= 5)
      ADD_FAILURE() << "point " << i << " (" << p[0] << ", " << p[1] << ", " << p[2] << ") normal (" << n[0] << ", " << n[1]
                    << ", " << n[2] << ")";
  }
  EXPECT_EQ(bad, 0);
}

// The area of a box's triangles is exactly 2(ab + bc + ca) = 2200 up to rounding: 1e-9 relative.
void checkBoxArea(const Read& r) {
  const double exact = 2.0 * (10 * 20 + 20 * 30 + 30 * 10);
  EXPECT_NEAR(meshArea(r), exact, 1e-9 * exact);
}

// Every triangle winds counter-clockwise about its vertex normals (a box has no degenerate
// triangle: any triangle under 1e-12 of the area counts as one, and none may be).
void checkBoxWinding(const Read& r) {
  const WindingReport w = checkWinding(r, 1e-12 * 2200);
  EXPECT_EQ(w.degenerate, 0);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles;
}

// Distinct values of the cell array FaceId.
std::set<int> faceIdsOf(const Read& r) {
  std::set<int> s;
  vtkDataArray* a = r.faces->GetCellData()->GetArray("FaceId");
  for (vtkIdType c = 0; c < a->GetNumberOfTuples(); ++c) s.insert(int(a->GetTuple1(c)));
  return s;
}

int countKind(const Read& r, int kind) {
  int n = 0;
  for (const Line& l : lines(r)) n += l.kind == kind;
  return n;
}

// A surface in closed form, in world coordinates, with its expected outward normal.
struct ClosedForm {
  std::function<Vec3(double, double)> S;
  std::function<Vec3(double, double, const Vec3&)> outward;  // expected unit outward normal at (u, v), P
  double hu, hv;                              // finite-difference steps (parameter units)
  double scaleU, scaleV;                      // |Su|, |Sv| scales: the errors are relative to them
};

struct ClosedFormErrors {
  int points = 0;
  double position = 0, normal = 0, su = 0, sv = 0;  // max errors, relative (see compareClosedForm)
};

// For every output point of face `faceId`: the point against S(u, v) at its TCoords (relative to
// `length`), the normal against the closed-form outward normal, Su and Sv against central finite
// differences of S (relative to scaleU, scaleV). The finite differences err by about h^2/6 |S'''|
// + eps |S| / h, ~1e-11 relative for h = 1e-5.
ClosedFormErrors compareClosedForm(const Read& r, int faceId, const ClosedForm& f, double length) {
  ClosedFormErrors e;
  const std::vector<int> pf = r.pointFaces();
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    if (pf[size_t(i)] != faceId) continue;
    ++e.points;
    const auto [u, v] = r.uv(i);
    const Vec3 p = r.point(i);
    e.position = std::max(e.position, norm(sub(p, f.S(u, v))) / length);
    e.normal = std::max(e.normal, norm(sub(r.normal(i), f.outward(u, v, p))));
    const Vec3 su = scale(sub(f.S(u + f.hu, v), f.S(u - f.hu, v)), 0.5 / f.hu);
    const Vec3 sv = scale(sub(f.S(u, v + f.hv), f.S(u, v - f.hv)), 0.5 / f.hv);
    e.su = std::max(e.su, norm(sub(r.su(i), su)) / f.scaleU);
    e.sv = std::max(e.sv, norm(sub(r.sv(i), sv)) / f.scaleV);
  }
  return e;
}

// Su and Sv of every point against central finite differences of the face's own Geom_Surface
// (BRep_Tool::Surface of the face of the shape WE made, with its location), and the point against
// S(u, v): errors relative to `length` (the model's size; derivatives of angular parameters are
// of the size of the model). Faces correspond by index: a BREP round trip keeps the face order.
ClosedFormErrors compareWithGeomSurfaces(const Read& r, const TopoDS_Shape& shape, double length) {
  ClosedFormErrors e;
  const std::vector<TopoDS_Face> faces = facesOf(shape);
  const std::vector<int> pf = r.pointFaces();
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const int f = pf[size_t(i)];
    if (f < 0 || f >= int(faces.size())) {
      ADD_FAILURE() << "point " << i << " has FaceId " << f;
      continue;
    }
    ++e.points;
    TopLoc_Location loc;
    const Handle(Geom_Surface) s = BRep_Tool::Surface(faces[size_t(f)], loc);
    const gp_Trsf t = loc.Transformation();
    auto S = [&](double u, double v) { return fromGp(s->Value(u, v).Transformed(t).XYZ()); };
    const auto [u, v] = r.uv(i);
    const double h = 1e-5;
    e.position = std::max(e.position, norm(sub(r.point(i), S(u, v))) / length);
    e.su = std::max(e.su, norm(sub(r.su(i), scale(sub(S(u + h, v), S(u - h, v)), 0.5 / h))) / length);
    e.sv = std::max(e.sv, norm(sub(r.sv(i), scale(sub(S(u, v + h), S(u, v - h)), 0.5 / h))) / length);
  }
  return e;
}

}  // namespace

// Box as BREP: 6 faces, 12 edges (a box has 12 edges and OpenCASCADE's box shares them between
// faces), outward axis normals, CCW winding, exact area.
TEST(CadBox, Brep) {
  const Read r = readOk(writeBrep(makeBox(), "box.brep"));
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), 12);
  EXPECT_EQ(countKind(r, 0), 12);
  EXPECT_EQ(faceIdsOf(r), (std::set<int>{0, 1, 2, 3, 4, 5}));
  checkBoxNormals(r);
  checkBoxWinding(r);
  checkBoxArea(r);
}

// Box as STEP (AP214 through STEPControl_Writer, read back through XCAF): the same exact counts
// (STEP shares edges between faces of a closed shell), normals, winding and area.
TEST(CadBox, Step) {
  const Read r = readOk(writeStep(makeBox(), "box.step"));
  EXPECT_EQ(r.reader->GetNumberOfParts(), 1);
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), 12);
  EXPECT_EQ(countKind(r, 0), 12);
  checkBoxNormals(r);
  checkBoxWinding(r);
  checkBoxArea(r);
}

// Box as IGES in OpenCASCADE's default "Faces" mode: each face is written as an independent
// trimmed surface (IGES type 144) with its own boundary curves. The FILE therefore holds 24 edges
// (4 per face, each box edge twice): checked independently by reading it with a plain
// IGESControl_Reader and counting edges with TopExp. The reader sews IGES parts
// (BRepBuilderAPI_Sewing, docs/cad.md), so what it must output is the box's 12 edges, with 8
// shared corners; normals, winding and area as for BREP.
TEST(CadBox, IgesFacesMode) {
  const std::string path = writeIges(makeBox(), "box_faces.igs", 0);
  {
    IGESControl_Reader plain;
    ASSERT_EQ(plain.ReadFile(path.c_str()), IFSelect_RetDone);
    plain.TransferRoots();
    TopTools_IndexedMapOfShape edges;
    TopExp::MapShapes(plain.OneShape(), TopAbs_EDGE, edges);
    EXPECT_EQ(edges.Extent(), 24) << "the fixture is not written face by face";
  }
  const Read r = readOk(path);
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), 12);
  EXPECT_EQ(countKind(r, 0), 12);
  std::set<vtkIdType> ends;
  for (const Line& l : lines(r)) ends.insert(l.ids.front()), ends.insert(l.ids.back());
  EXPECT_EQ(ends.size(), 8u);
  checkBoxNormals(r);
  checkBoxWinding(r);
  checkBoxArea(r);
}

// Box as IGES in "BRep" mode (a manifold solid B-rep object, type 186): edges are shared, so 12.
TEST(CadBox, IgesBrepMode) {
  const Read r = readOk(writeIges(makeBox(), "box_brep.igs", 1));
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), 12);
  checkBoxNormals(r);
  checkBoxWinding(r);
  checkBoxArea(r);
}

// A cylinder (r = 2, h = 5): lateral-face points lie on S(u, v) at their TCoords (1e-9 of r:
// mesh nodes are surface points up to rounding), normals equal the closed-form outward normal
// (x, y, 0)/r to 1e-6 (float normals), Su = (-r sin u, r cos u, 0) and Sv = (0, 0, 1) match central
// differences to 1e-6 relative; the caps' normals are -z / +z at z = 0 / 5 exactly. Every face's
// Su and Sv also match finite differences of its own Geom_Surface (1e-6 of the size).
TEST(CadPrimitives, CylinderClosedForm) {
  const double rad = 2, h = 5;
  const TopoDS_Shape cyl = BRepPrimAPI_MakeCylinder(rad, h).Shape();
  const Read r = readOk(writeBrep(cyl, "cylinder.brep"));
  const std::vector<GeomAbs_SurfaceType> types = surfaceTypes(cyl);
  ASSERT_EQ(r.reader->GetNumberOfFaces(), int(types.size()));
  int lateral = -1;
  for (size_t i = 0; i < types.size(); ++i)
    if (types[i] == GeomAbs_Cylinder) lateral = int(i);
  ASSERT_GE(lateral, 0);
  ClosedForm f;
  f.S = [&](double u, double v) { return Vec3{rad * std::cos(u), rad * std::sin(u), v}; };
  f.outward = [&](double, double, const Vec3& p) { return unit(Vec3{p[0], p[1], 0}); };
  f.hu = f.hv = 1e-5;
  f.scaleU = rad, f.scaleV = 1;
  const ClosedFormErrors e = compareClosedForm(r, lateral, f, rad);
  EXPECT_GT(e.points, 20);
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.normal, 1e-6);
  EXPECT_LT(e.su, 1e-6);
  EXPECT_LT(e.sv, 1e-6);
  // Caps: outward along the axis, exactly on their planes.
  const std::vector<int> pf = r.pointFaces();
  int capPoints = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    if (pf[size_t(i)] == lateral) continue;
    ++capPoints;
    const Vec3 p = r.point(i), n = r.normal(i);
    const bool top = p[2] > h / 2;
    EXPECT_NEAR(p[2], top ? h : 0.0, 1e-12);
    EXPECT_LT(norm(sub(n, Vec3{0, 0, top ? 1.0 : -1.0})), 1e-6);
  }
  EXPECT_GT(capPoints, 0);
  const ClosedFormErrors g = compareWithGeomSurfaces(r, cyl, rad);
  EXPECT_LT(g.position, 1e-9);
  EXPECT_LT(g.su, 1e-6);
  EXPECT_LT(g.sv, 1e-6);
  const WindingReport w = checkWinding(r, 1e-14);
  EXPECT_EQ(w.wrong, 0);
  EXPECT_EQ(w.degenerate, 0);
}

// The same cylinder MOVED by a location (rotation of 30 degrees about (1, 1, 0) through the origin,
// then a translation): the location is stored in the BREP. World S = T(S_local): points, normals
// (T applied to the local outward normal) and Su, Sv (finite differences of T(S_local)) must all
// follow the location; tolerances as for the unmoved cylinder.
TEST(CadPrimitives, CylinderWithLocation) {
  const double rad = 2, h = 5;
  gp_Trsf rot, move;
  rot.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 1, 0)), kPi / 6);
  move.SetTranslation(gp_Vec(5, -3, 2));
  const gp_Trsf T = move * rot;
  const TopoDS_Shape cyl = BRepPrimAPI_MakeCylinder(rad, h).Shape().Moved(TopLoc_Location(T));
  const Read r = readOk(writeBrep(cyl, "cylinder_located.brep"));
  const std::vector<GeomAbs_SurfaceType> types = surfaceTypes(cyl);
  int lateral = -1;
  for (size_t i = 0; i < types.size(); ++i)
    if (types[i] == GeomAbs_Cylinder) lateral = int(i);
  ASSERT_GE(lateral, 0);
  const gp_Trsf Tinv = T.Inverted();
  ClosedForm f;
  f.S = [&](double u, double v) { return fromGp(gp_Pnt(rad * std::cos(u), rad * std::sin(u), v).Transformed(T).XYZ()); };
  f.outward = [&](double, double, const Vec3& p) {
    const gp_Pnt local = toPnt(p).Transformed(Tinv);
    return fromGp(gp_Vec(local.X(), local.Y(), 0).Normalized().Transformed(T).XYZ());
  };
  f.hu = f.hv = 1e-5;
  f.scaleU = rad, f.scaleV = 1;
  const ClosedFormErrors e = compareClosedForm(r, lateral, f, rad);
  EXPECT_GT(e.points, 20);
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.normal, 1e-6);
  EXPECT_LT(e.su, 1e-6);
  EXPECT_LT(e.sv, 1e-6);
  EXPECT_EQ(checkWinding(r, 1e-14).wrong, 0);
}

// A sphere (R = 3): points on S(u, v) (1e-9 of R), normals = P/R (outward, closed form) to 1e-6,
// Su and Sv against central differences (1e-6 of R), |P| = R to 1e-12 relative.
TEST(CadPrimitives, SphereClosedForm) {
  const double R = 3;
  const TopoDS_Shape sph = BRepPrimAPI_MakeSphere(R).Shape();
  const Read r = readOk(writeBrep(sph, "sphere.brep"));
  ASSERT_EQ(r.reader->GetNumberOfFaces(), 1);
  ClosedForm f;
  f.S = [&](double u, double v) { return Vec3{R * std::cos(v) * std::cos(u), R * std::cos(v) * std::sin(u), R * std::sin(v)}; };
  f.outward = [&](double, double, const Vec3& p) { return unit(p); };
  f.hu = f.hv = 1e-5;
  f.scaleU = f.scaleV = R;
  const ClosedFormErrors e = compareClosedForm(r, 0, f, R);
  EXPECT_EQ(e.points, r.nPoints());
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.normal, 1e-6);
  EXPECT_LT(e.su, 1e-6);
  EXPECT_LT(e.sv, 1e-6);
  for (vtkIdType i = 0; i < r.nPoints(); ++i) ASSERT_NEAR(norm(r.point(i)), R, 1e-12 * R);
  EXPECT_LT(maxNormalLengthError(r), 1e-6);
}

// The sphere's poles (points with |z| = R): the normal is finite, unit (1e-6, float) and equal to
// the outward limit (0, 0, +-1) to 1e-6, although Su = R cos v (-sin u, cos u, 0) vanishes there
// (|Su| <= 1e-12 R: cos(pi/2) in doubles is 6e-17). Triangles at the poles wind CCW about the
// normal; triangles collapsed to zero area (two corners at the pole) are reported and skipped.
TEST(CadPrimitives, SpherePoles) {
  const double R = 3;
  const Read r = readOk(writeBrep(BRepPrimAPI_MakeSphere(R).Shape(), "sphere_poles.brep"));
  int poles[2] = {0, 0};
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i);
    if (std::abs(std::abs(p[2]) - R) > 1e-12 * R) continue;
    const Vec3 n = r.normal(i);
    ++poles[p[2] > 0];
    ASSERT_TRUE(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]));
    EXPECT_NEAR(norm(n), 1.0, 1e-6);
    EXPECT_LT(norm(sub(n, Vec3{0, 0, p[2] > 0 ? 1.0 : -1.0})), 1e-6) << "pole point " << i;
    EXPECT_LT(norm(r.su(i)), 1e-12 * R);
  }
  EXPECT_GT(poles[0], 0);
  EXPECT_GT(poles[1], 0);
  const WindingReport w = checkWinding(r, 1e-12 * R * R);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles << " (" << w.degenerate << " degenerate)";
  EXPECT_LT(w.degenerate, w.triangles);
}

// A torus (R = 3, r = 1): points on S(u, v), normals away from the tube's centre circle
// ((P - R (x, y, 0)/rho) / r, closed form) to 1e-6, Su and Sv against central differences (1e-6
// of R + r). The "grain runs along u": OpenCASCADE's torus u goes round the main axis Z
// (gp_Torus), so Su at every vertex is tangent to the circle about Z through the point:
// Su . (Z x radial) / |Su| = +1 (counter-clockwise about +Z) to 1e-6.
TEST(CadPrimitives, TorusClosedFormAndGrain) {
  const double R = 3, rr = 1;
  const Read r = readOk(writeBrep(BRepPrimAPI_MakeTorus(R, rr).Shape(), "torus.brep"));
  ASSERT_EQ(r.reader->GetNumberOfFaces(), 1);
  ClosedForm f;
  f.S = [&](double u, double v) {
    const double q = R + rr * std::cos(v);
    return Vec3{q * std::cos(u), q * std::sin(u), rr * std::sin(v)};
  };
  f.outward = [&](double, double, const Vec3& p) {
    const double rho = std::hypot(p[0], p[1]);
    return unit(sub(p, Vec3{R * p[0] / rho, R * p[1] / rho, 0}));
  };
  f.hu = f.hv = 1e-5;
  f.scaleU = R + rr, f.scaleV = rr;
  const ClosedFormErrors e = compareClosedForm(r, 0, f, R + rr);
  EXPECT_EQ(e.points, r.nPoints());
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.normal, 1e-6);
  EXPECT_LT(e.su, 1e-6);
  EXPECT_LT(e.sv, 1e-6);
  double worst = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i), su = r.su(i);
    const Vec3 radial = unit(Vec3{p[0], p[1], 0});
    const Vec3 tangent = cross(Vec3{0, 0, 1}, radial);
    worst = std::max(worst, std::abs(dot(su, tangent) / norm(su) - 1.0));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(checkWinding(r, 1e-14).wrong, 0);
}

// A cone (base radius 2 at z = 0, apex at z = 4): OpenCASCADE's gp_Cone S(u, v) = (R + v sin A)
// (cos u, sin u, 0) + v cos A (0, 0, 1), semi-angle A = atan(-1/2) (the radius shrinks), v from 0
// to 4 / cos A at the apex. The outward normal is (cos A cos u, cos A sin u, -sin A) everywhere,
// the apex included: there Su = 0 and the normal is the LIMIT along the meridian of the vertex's
// own u (the apex is a true singularity: each of its mesh vertices, one per u, gets its own
// meridian's normal, not the axis). Points on S (1e-9), normals (1e-6, float), Su and Sv against
// central differences (1e-6 of R); at least two apex vertices; the base is -z. And, as on every
// surface, each non-degenerate triangle winds CCW about its vertices' normals.
// FOUND (reader bug): BRepMesh leaves only 2 apex vertices (u = 0 and u = 2 pi), both with the
// limit normal of the meridian u = 0, (0.894, 0, 0.447); the fan of 38 apex triangles around the
// axis shares them, and the 16 on the far side (azimuth ~100..260 degrees) wind clockwise about
// that normal (it differs from their own normal by up to ~127 degrees): the apex shades wrongly.
// A degenerate vertex needs one copy per triangle, with the limit along that triangle's meridian.
TEST(CadPrimitives, ConeApexLimitNormals) {
  const double R = 2, H = 4, A = std::atan2(-R, H);
  const TopoDS_Shape cone = BRepPrimAPI_MakeCone(R, 0, H).Shape();
  const Read r = readOk(writeBrep(cone, "cone.brep"));
  const std::vector<GeomAbs_SurfaceType> types = surfaceTypes(cone);
  int lateral = -1;
  for (size_t i = 0; i < types.size(); ++i)
    if (types[i] == GeomAbs_Cone) lateral = int(i);
  ASSERT_GE(lateral, 0);
  ClosedForm f;
  f.S = [&](double u, double v) {
    const double q = R + v * std::sin(A);
    return Vec3{q * std::cos(u), q * std::sin(u), v * std::cos(A)};
  };
  f.outward = [&](double u, double, const Vec3&) { return Vec3{std::cos(A) * std::cos(u), std::cos(A) * std::sin(u), -std::sin(A)}; };
  f.hu = f.hv = 1e-5;
  f.scaleU = R, f.scaleV = 1;
  const ClosedFormErrors e = compareClosedForm(r, lateral, f, R);
  EXPECT_GT(e.points, 10);
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.normal, 1e-6);
  EXPECT_LT(e.su, 1e-6);
  EXPECT_LT(e.sv, 1e-6);
  const std::vector<int> pf = r.pointFaces();
  int apex = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i);
    if (pf[size_t(i)] == lateral) {
      apex += norm(sub(p, Vec3{0, 0, H})) < 1e-9;
      continue;
    }
    EXPECT_NEAR(p[2], 0.0, 1e-12);
    EXPECT_LT(norm(sub(r.normal(i), Vec3{0, 0, -1})), 1e-6);
  }
  EXPECT_GE(apex, 2);
  const WindingReport w = checkWinding(r, 1e-12);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles << " triangles wind clockwise about a vertex normal";
}

// CanReadFile: by extension, any case; not by content.
TEST(CadReader, CanReadFile) {
  for (const char* yes : {"a.step", "a.STEP", "b.stp", "c.Stp", "d.iges", "e.IGS", "f.brep", "g.BRep", "h.FCStd", "i.fcstd",
                          "/dir.with.dots/j.step"})
    EXPECT_TRUE(vtkWireFurCADReader::CanReadFile(yes)) << yes;
  for (const char* no : {"a.stl", "a.step.bak", "step", "", "a.", "a.brp", "a.FCStd1"})
    EXPECT_FALSE(vtkWireFurCADReader::CanReadFile(no)) << no;
  EXPECT_FALSE(vtkWireFurCADReader::CanReadFile(nullptr));
}

// A path with spaces and non-ASCII (UTF-8) characters and an upper-case extension, through
// STEP, IGES and BREP: read as the same box (6 faces, area 2200 exactly up to rounding), and the
// BREP part is named after the file's stem.
TEST(CadReader, Utf8PathAndUpperCaseExtension) {
  const std::filesystem::path dir = std::filesystem::path(tempPath("Bäume und Sträucher"));
  std::filesystem::create_directories(dir);
  const TopoDS_Shape box = makeBox();
  for (const std::string name : {"Kästchen 1.STEP", "Kästchen 2.IGS", "Kästchen 3.BREP"}) {
    const std::string p = (dir / name).string();
    const std::string ext = std::filesystem::path(name).extension().string();
    const std::string tmp = ext == ".STEP" ? writeStep(box, "utf8_tmp.step") : ext == ".IGS" ? writeIges(box, "utf8_tmp.igs", 1)
                                                                                             : writeBrep(box, "utf8_tmp.brep");
    std::filesystem::copy_file(tmp, p, std::filesystem::copy_options::overwrite_existing);
    const Read r = readOk(p);
    EXPECT_EQ(r.reader->GetNumberOfFaces(), 6) << name;
    EXPECT_NEAR(meshArea(r), 2200.0, 1e-9 * 2200) << name;
    if (ext == ".BREP") {
      EXPECT_EQ(r.reader->GetPartName(0), "Kästchen 3");
    }
  }
}
