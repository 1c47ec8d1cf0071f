// Assemblies: a STEP file written from an XCAF document (names, colours, two located instances of
// one part), and a mirrored instance.
//
// About the mirror: OpenCASCADE 7.6 cannot carry a mirrored instance through STEP. An XCAF
// component whose location is gp_Trsf::SetMirror(gp_Ax2) is accepted by XCAFDoc_ShapeTool, but
// STEPCAFControl_Writer::Transfer then throws Standard_DomainError "Moving with scaling
// transformation is forbidden" (TopoDS_Shape::Moved refuses negative transformations since 7.6);
// STEPControl_Writer on a compound holding a mirrored instance writes it without error but as a
// right-handed AXIS2_PLACEMENT_3D, i.e. silently as a rotation (the solid comes back turned, not
// mirrored). STEP's placements are right-handed by definition. So the mirror is tested through
// BREP, which stores the location matrix as is: a compound with one instance translated and one
// mirrored (TopoDS_Shape::Moved(loc, theRaiseExc = false)).
#include "cad_fixtures.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <Quantity_Color.hxx>
#include <IGESCAFControl_Writer.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopoDS_Compound.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>

using namespace cadtest;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The part: a 10 x 10 x 10 box with a hole of radius 2 along z through (3, 4) (off centre, so the
// part has no mirror symmetry across x = const or y = const).
TopoDS_Shape bracket() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 10, 10).Shape();
  const TopoDS_Shape tool = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(3, 4, -1), gp_Dir(0, 0, 1)), 2, 12).Shape();
  return BRepAlgoAPI_Cut(box, tool).Shape();
}

// The outward normals of the bracket placed by `t` (a rigid motion, mirror allowed) at a world
// point p on it: the normals of every face of the part p lies on (one inside a face, two on an
// edge, three at a corner). In the part's frame (t^-1 p) the hole's normal is -radial (into the
// hole, out of the material) and the planes' the outward axes; they are mapped to the world by
// t's linear part (a normal maps like a vector under an orthogonal map, mirror or not). Empty when
// p is not on the part. The reader's normal at a point must be one of these (1e-6: float
// normals): a flipped normal matches none, since no two faces of the part share a point with
// opposite normals.
std::vector<Vec3> bracketNormals(const gp_Trsf& t, const Vec3& p) {
  const gp_Pnt q = toPnt(p).Transformed(t.Inverted());
  const double x = q.X(), y = q.Y(), z = q.Z(), e = 1e-9;
  const bool inX = x > -e && x < 10 + e, inY = y > -e && y < 10 + e, inZ = z > -e && z < 10 + e;
  const double rho = std::hypot(x - 3, y - 4);
  std::vector<gp_Vec> ns;
  if (!(inX && inY && inZ) || rho < 2 - e) return {};
  if (std::abs(rho - 2) < e) ns.emplace_back(-(x - 3) / rho, -(y - 4) / rho, 0);
  if (std::abs(x) < e) ns.emplace_back(-1, 0, 0);
  if (std::abs(x - 10) < e) ns.emplace_back(1, 0, 0);
  if (std::abs(y) < e) ns.emplace_back(0, -1, 0);
  if (std::abs(y - 10) < e) ns.emplace_back(0, 1, 0);
  if (std::abs(z) < e) ns.emplace_back(0, 0, -1);
  if (std::abs(z - 10) < e) ns.emplace_back(0, 0, 1);
  std::vector<Vec3> out;
  for (const gp_Vec& n : ns) out.push_back(fromGp(n.Transformed(t).XYZ()));
  return out;
}

bool matchesOne(const Vec3& n, const std::vector<Vec3>& candidates) {
  for (const Vec3& c : candidates)
    if (norm(sub(n, c)) < 1e-6) return true;
  return false;
}

// Points of part `part` (cell "PartId") whose normal is none of bracketNormals(t, p); at most 5
// are reported.
int badNormals(const Read& r, int part, const gp_Trsf& t) {
  vtkDataArray* pid = r.faces->GetCellData()->GetArray("PartId");
  std::vector<int> pointPart(size_t(r.nPoints()), -1);
  vtkIdType n = 0;
  const vtkIdType* pts = nullptr;
  vtkIdType c = 0;
  vtkCellArray* polys = r.faces->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, pts); ++c)
    for (vtkIdType k = 0; k < n; ++k) pointPart[size_t(pts[k])] = int(pid->GetTuple1(c));
  int bad = 0, checked = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    if (pointPart[size_t(i)] != part) continue;
    const Vec3 p = r.point(i), nn = r.normal(i);
    ++checked;
    if (!matchesOne(nn, bracketNormals(t, p)) && ++bad <= 5)
      ADD_FAILURE() << "part " << part << " point (" << p[0] << ", " << p[1] << ", " << p[2] << ") normal (" << nn[0] << ", "
                    << nn[1] << ", " << nn[2] << ") is not the outward normal of a face there";
  }
  EXPECT_GT(checked, 50);
  return bad;
}

struct Rgb {
  int r, g, b;
};
Quantity_Color srgb(Rgb c) { return Quantity_Color(c.r / 255.0, c.g / 255.0, c.b / 255.0, Quantity_TOC_sRGB); }

}  // namespace

// A STEP assembly written from XCAF: part "Bracket" (colour sRGB (200, 30, 90) on the part) added
// once with AddShape and placed twice with AddComponent: instance 1 translated by (20, 0, 0),
// instance 2 turned 90 degrees about z and translated by (-20, 5, 0), with a colour of its own on
// the component, sRGB (10, 120, 250). Read back: 2 parts, both named "Bracket"; every point's
// "Colors" is its instance's colour: the part's for the first, the instance's (which overrides
// the part's) for the second (sRGB 8-bit, +-1 for the round trip through OpenCASCADE's linear RGB
// and STEP's real numbers); each instance's normals are the
// closed-form outward normals of the bracket under its own placement (1e-6), so the placements
// were applied; all triangles CCW.
TEST(CadAssembly, StepXcafNamesColoursPlacements) {
  gp_Trsf t1, rot, move2;
  t1.SetTranslation(gp_Vec(20, 0, 0));
  rot.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), kPi / 2);
  move2.SetTranslation(gp_Vec(-20, 5, 0));
  const gp_Trsf t2 = move2 * rot;
  const Rgb colour{200, 30, 90}, instanceColour{10, 120, 250};

  const std::string path = tempPath("assembly.step");
  quietOcct();
  {
    Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
    Handle(TDocStd_Document) doc;
    app->NewDocument("MDTV-XCAF", doc);
    Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    Handle(XCAFDoc_ColorTool) colours = XCAFDoc_DocumentTool::ColorTool(doc->Main());
    const TDF_Label part = shapes->AddShape(bracket(), Standard_False);
    TDataStd_Name::Set(part, "Bracket");
    colours->SetColor(part, srgb(colour), XCAFDoc_ColorSurf);
    const TDF_Label assembly = shapes->NewShape();
    TDataStd_Name::Set(assembly, "Assembly");
    TDataStd_Name::Set(shapes->AddComponent(assembly, part, TopLoc_Location(t1)), "first");
    const TDF_Label second = shapes->AddComponent(assembly, part, TopLoc_Location(t2));
    TDataStd_Name::Set(second, "second");
    colours->SetColor(second, srgb(instanceColour), XCAFDoc_ColorSurf);
    shapes->UpdateAssemblies();
    STEPCAFControl_Writer w;
    w.SetColorMode(Standard_True);
    w.SetNameMode(Standard_True);
    ASSERT_TRUE(w.Transfer(doc, STEPControl_AsIs));
    ASSERT_EQ(w.Write(path.c_str()), IFSelect_RetDone);
    app->Close(doc);
  }
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfParts(), 2);
  EXPECT_EQ(r.reader->GetPartName(0), "Bracket");
  EXPECT_EQ(r.reader->GetPartName(1), "Bracket");
  vtkStringArray* names = vtkStringArray::SafeDownCast(r.faces->GetFieldData()->GetAbstractArray("PartNames"));
  ASSERT_NE(names, nullptr);
  ASSERT_EQ(names->GetNumberOfValues(), 2);
  EXPECT_EQ(names->GetValue(0), "Bracket");
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 2 * int(facesOf(bracket()).size()));
  vtkDataArray* colors = r.faces->GetPointData()->GetArray("Colors");
  ASSERT_NE(colors, nullptr);
  vtkDataArray* partIds = r.faces->GetCellData()->GetArray("PartId");
  int wrongColour = 0, counted[2] = {0, 0};
  vtkIdType np = 0;
  const vtkIdType* pts = nullptr;
  vtkIdType cell = 0;
  vtkCellArray* polys = r.faces->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(np, pts); ++cell) {
    const int part = int(partIds->GetTuple1(cell));
    ASSERT_TRUE(part == 0 || part == 1);
    const Rgb want = part == 0 ? colour : instanceColour;
    for (vtkIdType k = 0; k < np; ++k) {
      const vtkIdType i = pts[k];
      const int c[3] = {int(colors->GetComponent(i, 0)), int(colors->GetComponent(i, 1)), int(colors->GetComponent(i, 2))};
      ++counted[part];
      if ((std::abs(c[0] - want.r) > 1 || std::abs(c[1] - want.g) > 1 || std::abs(c[2] - want.b) > 1) && ++wrongColour <= 3)
        ADD_FAILURE() << "part " << part << " colour (" << c[0] << ", " << c[1] << ", " << c[2] << ")";
    }
  }
  EXPECT_EQ(wrongColour, 0);
  EXPECT_GT(counted[0], 0);
  EXPECT_GT(counted[1], 0);
  // PartId follows the order of the components (first, second).
  const int a = badNormals(r, 0, t1) + badNormals(r, 1, t2);
  EXPECT_EQ(a, 0);
  const WindingReport w = checkWinding(r, 1e-12);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles;
}

// A mirrored instance, through BREP (see the top of this file for why not STEP): a compound of
// the bracket translated by (20, 0, 0) and the same bracket (the same TShape, so meshed once and
// shared) placed by mirror(x = 0) * translation: x -> -x. Checks, per point i of the first
// instance's N points and point N + i of the mirrored one (same faces in the same order, the same
// triangulation):
// - the mirrored points are the mirror images of the first's: (-x, y, z), to 1e-12 of the size
//   (both are the same node through two transformations);
// - normals: the mirrored instance's normals are the closed-form outward normals of the mirrored
//   solid (1e-6), i.e. (-nx, ny, nz): still outward although the location has det -1;
// - Su, Sv: derivatives of the mirrored parameterisation, M Su (1e-12 relative);
// - every triangle of both instances winds CCW about its normals (the mirror turns the winding,
//   the reader must turn it back).
TEST(CadAssembly, MirroredInstanceBrep) {
  const TopoDS_Shape part = bracket();
  gp_Trsf t1, mirror;
  t1.SetTranslation(gp_Vec(20, 0, 0));
  mirror.SetMirror(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)));
  const gp_Trsf t2 = mirror * t1;
  ASSERT_TRUE(t2.IsNegative());
  TopoDS_Compound c;
  BRep_Builder b;
  b.MakeCompound(c);
  b.Add(c, part.Moved(TopLoc_Location(t1)));
  b.Add(c, part.Moved(TopLoc_Location(t2), Standard_False));
  const Read r = readOk(writeBrep(c, "mirrored.brep"));
  const int nf = int(facesOf(part).size());
  ASSERT_EQ(r.reader->GetNumberOfFaces(), 2 * nf);
  ASSERT_EQ(r.reader->GetNumberOfMeshedFaces(), 2 * nf);
  ASSERT_EQ(r.nPoints() % 2, 0);
  const vtkIdType n = r.nPoints() / 2;
  const std::vector<int> pf = r.pointFaces();
  double pos = 0, nrm = 0, su = 0, sv = 0;
  int badPos = 0;
  for (vtkIdType i = 0; i < n; ++i) {
    ASSERT_LT(pf[size_t(i)], nf);
    ASSERT_EQ(pf[size_t(n + i)], pf[size_t(i)] + nf);
    const Vec3 p = r.point(i), q = r.point(n + i);
    pos = std::max(pos, norm(sub(q, Vec3{-p[0], p[1], p[2]})) / 30.0);
    badPos += !(pos < 1e-12);
    const Vec3 np = r.normal(i), nq = r.normal(n + i);
    nrm = std::max(nrm, norm(sub(nq, Vec3{-np[0], np[1], np[2]})));
    const Vec3 sp = r.su(i), sq = r.su(n + i), tp = r.sv(i), tq = r.sv(n + i);
    su = std::max(su, norm(sub(sq, Vec3{-sp[0], sp[1], sp[2]})) / std::max(1.0, norm(sp)));
    sv = std::max(sv, norm(sub(tq, Vec3{-tp[0], tp[1], tp[2]})) / std::max(1.0, norm(tp)));
  }
  EXPECT_EQ(badPos, 0);
  EXPECT_LT(pos, 1e-12);
  EXPECT_LT(nrm, 1e-6);
  EXPECT_LT(su, 1e-12);
  EXPECT_LT(sv, 1e-12);
  // Both instances outward in closed form. The BREP reader gives one part (the compound): the
  // instances are told apart by x (first at x >= 20, mirrored at x <= -20).
  auto partOfX = [&](bool positive, const gp_Trsf& t) {
    int bad = 0;
    for (vtkIdType i = 0; i < r.nPoints(); ++i)
      if ((r.point(i)[0] > 0) == positive) bad += !matchesOne(r.normal(i), bracketNormals(t, r.point(i)));
    return bad;
  };
  EXPECT_EQ(partOfX(true, t1), 0);
  EXPECT_EQ(partOfX(false, t2), 0);
  const WindingReport w = checkWinding(r, 1e-12);
  EXPECT_EQ(w.wrong, 0) << "of " << w.triangles;
  EXPECT_EQ(w.degenerate, 0);
}

// Face colours through XCAF: a box [0,10]x[0,20]x[0,30] whose part colour is sRGB (40, 90, 160)
// and whose top face (z = 30) has its own colour (230, 20, 20), written as STEP
// (STEPCAFControl_Writer) and as IGES in Faces mode (IGESCAFControl_Writer; the reader sews IGES
// parts, and face colours must follow their faces through the sewing). Every point of the top
// face (z = 30, normal +z) has the face's colour, every other point the part's (+-1).
// FOUND (reader bug, IGES only): every colour is lost, all 24 points come out grey (200, 200, 200).
// OpenCASCADE's IGES reader puts the colours on the faces (the part colour on each face entity);
// wf_cad_read.cxx sew() maps them with `sewing.IsModified(face) ? sewing.Modified(face) : face`,
// but BRepBuilderAPI_Sewing::IsModified/Modified answer only for the shapes given to Add (here
// the whole compound), so no sewn face is found in the map; ModifiedSubShape(face) is the call that
// maps a face to its sewn face. STEP keeps both colours.
TEST(CadAssembly, FaceColoursStepAndIges) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
  TopoDS_Face top;
  for (const TopoDS_Face& f : facesOf(box)) {
    BRepAdaptor_Surface s(f);
    if (s.GetType() == GeomAbs_Plane && std::abs(s.Value(0.5 * (s.FirstUParameter() + s.LastUParameter()),
                                                          0.5 * (s.FirstVParameter() + s.LastVParameter())).Z() - 30) < 1e-12)
      top = f;
  }
  ASSERT_FALSE(top.IsNull());
  const Rgb partColour{40, 90, 160}, faceColour{230, 20, 20};
  quietOcct();
  for (const bool iges : {false, true}) {
    SCOPED_TRACE(iges ? "IGES" : "STEP");
    const std::string path = tempPath(iges ? "face_colours.igs" : "face_colours.step");
    {
      Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
      Handle(TDocStd_Document) doc;
      app->NewDocument("MDTV-XCAF", doc);
      Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
      Handle(XCAFDoc_ColorTool) colours = XCAFDoc_DocumentTool::ColorTool(doc->Main());
      const TDF_Label part = shapes->AddShape(box, Standard_False);
      TDataStd_Name::Set(part, "Block");
      colours->SetColor(part, srgb(partColour), XCAFDoc_ColorSurf);
      const TDF_Label face = shapes->AddSubShape(part, top);
      ASSERT_FALSE(face.IsNull());
      colours->SetColor(face, srgb(faceColour), XCAFDoc_ColorSurf);
      if (iges) {
        IGESCAFControl_Writer w;
        w.SetColorMode(Standard_True);
        w.SetNameMode(Standard_True);
        ASSERT_TRUE(w.Transfer(doc));
        ASSERT_TRUE(w.Write(path.c_str()));
      } else {
        STEPCAFControl_Writer w;
        w.SetColorMode(Standard_True);
        ASSERT_TRUE(w.Transfer(doc, STEPControl_AsIs));
        ASSERT_EQ(w.Write(path.c_str()), IFSelect_RetDone);
      }
      app->Close(doc);
    }
    const Read r = readOk(path);
    EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
    vtkDataArray* c = r.faces->GetPointData()->GetArray("Colors");
    int topPoints = 0, bad = 0;
    for (vtkIdType i = 0; i < r.nPoints(); ++i) {
      const Vec3 p = r.point(i), n = r.normal(i);
      const bool onTop = std::abs(p[2] - 30) < 1e-9 && n[2] > 0.5;
      topPoints += onTop;
      const Rgb want = onTop ? faceColour : partColour;
      const int got[3] = {int(c->GetComponent(i, 0)), int(c->GetComponent(i, 1)), int(c->GetComponent(i, 2))};
      if ((std::abs(got[0] - want.r) > 1 || std::abs(got[1] - want.g) > 1 || std::abs(got[2] - want.b) > 1) && ++bad <= 3)
        ADD_FAILURE() << (onTop ? "top" : "other") << " point colour (" << got[0] << ", " << got[1] << ", " << got[2] << ")";
    }
    EXPECT_GT(topPoints, 0);
    EXPECT_EQ(bad, 0);
  }
}
