// The edges output (port 1): the model's edges as polylines sharing their end points, lying on the
// face mesh; and the faces' iso-parametric lines.
#include "cad_fixtures.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS_Shell.hxx>
#include <gp.hxx>
#include <gp_Ax3.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <gp_Circ.hxx>
#include <BRepFilletAPI_MakeChamfer.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRep_Builder.hxx>
#include <TopExp_Explorer.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Vertex.hxx>

#include <map>
#include <set>

using namespace cadtest;

namespace {

constexpr double kPi = 3.14159265358979323846;

TopoDS_Shape filletedBox() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) fillet.Add(2, TopoDS::Edge(edges(i)));
  return fillet.Shape();
}

double polylineLength(const Read& r, const Line& l) {
  double s = 0;
  for (size_t i = 1; i < l.ids.size(); ++i) s += norm(sub(edgePoint(r, l.ids[i]), edgePoint(r, l.ids[i - 1])));
  return s;
}

// Distance from p to the nearest point of the faces output (brute force: the meshes are small).
double nearestFaceVertex(const Read& r, const Vec3& p) {
  double best = 1e300;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) best = std::min(best, norm(sub(r.point(i), p)));
  return best;
}

}  // namespace

// A box (BREP): 12 Kind-0 polylines whose end points are 8 shared points, each used by exactly 3
// edges (a box's corner meets 3 edges) and each exactly at a corner of the box (1e-12: the nodes
// are the vertices' points); each polyline's length equals its edge's (10, 20 or 30, 1e-12
// relative), so no polyline runs back and forth; EdgeId runs over 0..11.
TEST(CadEdges, BoxSharedEndPoints) {
  const Read r = readOk(writeBrep(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "edges_box.brep"));
  const std::vector<Line> ls = lines(r);
  ASSERT_EQ(ls.size(), 12u);
  std::map<vtkIdType, int> uses;
  std::set<int> ids;
  for (const Line& l : ls) {
    EXPECT_EQ(l.kind, 0);
    ids.insert(l.id);
    ++uses[l.ids.front()];
    ++uses[l.ids.back()];
    const double len = polylineLength(r, l);
    const double expected = std::abs(len - 10) < 1 ? 10 : std::abs(len - 20) < 1 ? 20 : 30;
    EXPECT_NEAR(len, expected, 1e-12 * expected);
  }
  EXPECT_EQ(ids.size(), 12u);
  EXPECT_EQ(*ids.begin(), 0);
  EXPECT_EQ(*ids.rbegin(), 11);
  ASSERT_EQ(uses.size(), 8u);
  for (const auto& [id, n] : uses) {
    EXPECT_EQ(n, 3) << "end point " << id;
    const Vec3 p = edgePoint(r, id);
    for (int k = 0; k < 3; ++k) {
      const double hi = k == 0 ? 10 : k == 1 ? 20 : 30;
      EXPECT_TRUE(std::abs(p[k]) < 1e-12 || std::abs(p[k] - hi) < 1e-12 * hi) << "coordinate " << k << " = " << p[k];
    }
  }
}

// The filleted box (BREP; 26 faces, curved edges): one Kind-0 polyline per non-degenerate edge of
// the shape (counted with TopExp and BRep_Tool::Degenerated on the shape we made: OpenCASCADE's
// corner patches are sphere faces with a degenerate edge at a pole, which is skipped); the
// polylines' end points are exactly as many shared points as the shape has vertices, each at its vertex's
// position (BRep_Tool::Pnt, 1e-9 of the size: vertex tolerances are 1e-7); every point of every
// polyline is a point of the face mesh (distance to the nearest face vertex <= 1e-12 of the
// size, in practice 0: both are the same triangulation node, so wire and surface meet without
// cracks); each polyline's length is at most its edge's length (chords) and at least
// (1 - d/r) of it (a chord of sagitta <= d on radius r = 2 loses d/(3r) of the arc; the
// deflection d applied), so none runs back and forth.
TEST(CadEdges, FilletedBoxEdgesOnFaceMesh) {
  const TopoDS_Shape s = filletedBox();
  TopTools_IndexedMapOfShape edges, vertices;
  TopExp::MapShapes(s, TopAbs_EDGE, edges);
  TopExp::MapShapes(s, TopAbs_VERTEX, vertices);
  int degenerate = 0;
  for (int i = 1; i <= edges.Extent(); ++i) degenerate += BRep_Tool::Degenerated(TopoDS::Edge(edges(i)));
  const Read r = readOk(writeBrep(s, "edges_fillet.brep"));
  const std::vector<Line> ls = lines(r);
  ASSERT_EQ(int(ls.size()), edges.Extent() - degenerate);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), edges.Extent() - degenerate);
  const double size = r.reader->GetModelSize(), d = r.reader->GetAppliedLinearDeflection();
  std::set<vtkIdType> ends;
  double worstOnMesh = 0;
  int badLength = 0;
  for (const Line& l : ls) {
    ASSERT_EQ(l.kind, 0);
    ASSERT_GE(l.id, 0);
    ASSERT_LT(l.id, edges.Extent());
    ends.insert(l.ids.front());
    ends.insert(l.ids.back());
    for (vtkIdType id : l.ids) worstOnMesh = std::max(worstOnMesh, nearestFaceVertex(r, edgePoint(r, id)));
    // The edge with this EdgeId: edges are numbered in TopExp::MapShapes order, degenerate ones
    // included (their numbers are not used).
    const TopoDS_Edge e = TopoDS::Edge(edges(l.id + 1));
    EXPECT_FALSE(BRep_Tool::Degenerated(e));
    const double len = GCPnts_AbscissaPoint::Length(BRepAdaptor_Curve(e));
    const double poly = polylineLength(r, l);
    if (!(poly <= len * (1 + 1e-9) && poly >= len * (1 - d / 2.0)) && ++badLength <= 5)
      ADD_FAILURE() << "edge " << l.id << ": polyline " << poly << ", edge " << len;
    // The end points are the edge's vertices.
    TopoDS_Vertex v1, v2;
    TopExp::Vertices(e, v1, v2);
    const Vec3 a = fromGp(BRep_Tool::Pnt(v1).XYZ()), b = fromGp(BRep_Tool::Pnt(v2).XYZ());
    const Vec3 f = edgePoint(r, l.ids.front()), g = edgePoint(r, l.ids.back());
    const bool forward = norm(sub(f, a)) < 1e-9 * size && norm(sub(g, b)) < 1e-9 * size;
    const bool backward = norm(sub(f, b)) < 1e-9 * size && norm(sub(g, a)) < 1e-9 * size;
    EXPECT_TRUE(forward || backward) << "edge " << l.id;
  }
  EXPECT_EQ(badLength, 0);
  EXPECT_EQ(int(ends.size()), vertices.Extent());
  EXPECT_LE(worstOnMesh, 1e-12 * size);
}

// Iso lines on a cylinder (r = 2, h = 5; faces: lateral, top, bottom). NumberOfUIsoLines 3 and
// NumberOfVIsoLines 2:
// - Kind 1 (u constant) on the lateral face (EdgeId = its face index): 3 vertical lines, every
//   point at radius r (1e-6 relative, as asked), all points of a line at one angle u (1e-9), from
//   z = 0 to z = 5 (1e-9); the 3 angles evenly spaced over the period (u = k 2 pi / 4, k = 1..3:
//   OpenCASCADE's StdPrs_Isolines puts N lines at the interior points of N + 1 equal steps);
// - Kind 2 (v constant) on the lateral face: 2 horizontal circles at one height each, radius r;
// - iso lines of the planar caps lie in their planes (z = 0 or 5, 1e-12) inside the disc.
TEST(CadEdges, CylinderIsoLines) {
  const double rad = 2, h = 5;
  const TopoDS_Shape cyl = BRepPrimAPI_MakeCylinder(rad, h).Shape();
  const std::vector<GeomAbs_SurfaceType> types = surfaceTypes(cyl);
  int lateral = -1;
  for (size_t i = 0; i < types.size(); ++i)
    if (types[i] == GeomAbs_Cylinder) lateral = int(i);
  ASSERT_GE(lateral, 0);
  const Read r = readOk(writeBrep(cyl, "iso_cylinder.brep"), [](vtkWireFurCADReader* x) {
    x->SetNumberOfUIsoLines(3);
    x->SetNumberOfVIsoLines(2);
  });
  std::vector<double> angles;
  int vLines = 0, capLines = 0;
  for (const Line& l : lines(r)) {
    if (l.kind == 0) continue;
    ASSERT_TRUE(l.kind == 1 || l.kind == 2);
    ASSERT_GE(l.ids.size(), 2u);
    if (l.id != lateral) {
      ++capLines;
      for (vtkIdType id : l.ids) {
        const Vec3 p = edgePoint(r, id);
        EXPECT_TRUE(std::abs(p[2]) < 1e-12 || std::abs(p[2] - h) < 1e-12) << p[2];
        EXPECT_LE(std::hypot(p[0], p[1]), rad * (1 + 1e-9));
      }
      continue;
    }
    const Vec3 first = edgePoint(r, l.ids.front());
    for (vtkIdType id : l.ids) {
      const Vec3 p = edgePoint(r, id);
      EXPECT_NEAR(std::hypot(p[0], p[1]), rad, 1e-6 * rad);
      if (l.kind == 1) EXPECT_LT(norm(sub(unit(Vec3{p[0], p[1], 0}), unit(Vec3{first[0], first[1], 0}))), 1e-9);
      else EXPECT_NEAR(p[2], first[2], 1e-9);
    }
    if (l.kind == 1) {
      const Vec3 last = edgePoint(r, l.ids.back());
      EXPECT_NEAR(std::min(first[2], last[2]), 0.0, 1e-9);
      EXPECT_NEAR(std::max(first[2], last[2]), h, 1e-9);
      double a = std::atan2(first[1], first[0]);
      if (a < 0) a += 2 * kPi;
      angles.push_back(a);
    } else {
      ++vLines;
      EXPECT_GT(first[2], 0.0);
      EXPECT_LT(first[2], h);
    }
  }
  ASSERT_EQ(angles.size(), 3u);
  std::sort(angles.begin(), angles.end());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(angles[size_t(k)], (k + 1) * 2 * kPi / 4, 1e-9);
  EXPECT_EQ(vLines, 2);
  EXPECT_GT(capLines, 0);
}

// A model of edges only (a BREP wire: a circle of radius 5 in the plane z = 1 and a segment
// through its centre): no faces, so port 0 is empty, and the update still succeeds (only "no
// faces and no edges" fails). The free edges are sampled to the deflection: the circle's points
// lie on it (radius 5 and z = 1, 1e-12 relative), its chords' midpoints stay within the applied
// deflection d of it (sagitta <= d), and the segment is its two end points.
TEST(CadEdges, EdgesOnlyModel) {
  const gp_Circ circle(gp_Ax2(gp_Pnt(0, 0, 1), gp_Dir(0, 0, 1)), 5);
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  b.Add(c, BRepBuilderAPI_MakeEdge(circle).Edge());
  b.Add(c, BRepBuilderAPI_MakeEdge(gp_Pnt(-5, 0, 1), gp_Pnt(5, 0, 1)).Edge());
  const Read r = readCad(writeBrep(c, "wire.brep"));
  ASSERT_EQ(r.reader->GetErrorMessage(), "");
  EXPECT_EQ(r.faces->GetNumberOfCells(), 0);
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 0);
  EXPECT_EQ(r.reader->GetNumberOfEdges(), 2);
  const double d = r.reader->GetAppliedLinearDeflection();
  const std::vector<Line> ls = lines(r);
  ASSERT_EQ(ls.size(), 2u);
  int circles = 0;
  for (const Line& l : ls) {
    if (l.ids.size() == 2) {
      const Vec3 a = edgePoint(r, l.ids[0]), e = edgePoint(r, l.ids[1]);
      EXPECT_NEAR(norm(sub(a, e)), 10.0, 1e-12 * 10);
      continue;
    }
    ++circles;
    EXPECT_GT(l.ids.size(), 8u);
    EXPECT_EQ(l.ids.front(), l.ids.back()) << "a closed edge starts and ends at its one vertex";
    for (size_t i = 0; i < l.ids.size(); ++i) {
      const Vec3 p = edgePoint(r, l.ids[i]);
      EXPECT_NEAR(std::hypot(p[0], p[1]), 5.0, 1e-12 * 5);
      EXPECT_NEAR(p[2], 1.0, 1e-12);
      if (i > 0) {
        const Vec3 m = scale(add(p, edgePoint(r, l.ids[i - 1])), 0.5);
        EXPECT_LE(5.0 - std::hypot(m[0], m[1]), d * (1 + 1e-9));
      }
    }
  }
  EXPECT_EQ(circles, 1);
}

// Edge classes (render/edge_classes.h) against what each solid is made of. A box: 12 sharp edges,
// each at exactly 90 degrees between its faces' outward normals (1e-9). The box with 2-mm fillets
// on every edge: the 24 edges where a fillet meets a face are smooth at 0 degrees (1e-6: the
// fillets are exactly tangent); the fillets' corner patches meet each other along smooth edges
// too; nothing is sharp. A cylinder: its seam (class 3, the same face on both sides) and its two
// circles, sharp at 90. A lone planar face: 4 boundary edges. A wire alone: free edges.
// The reader's count per class equals what its array says.
TEST(CadEdges, ClassesOfBoxFilletsCylinderFaceAndWire) {
  auto classes = [](const Read& r) {
    std::map<int, int> n;
    for (const Line& l : lines(r))
      if (l.kind == 0) ++n[l.edgeClass];
    for (const auto& [c, k] : n) EXPECT_EQ(r.reader->GetNumberOfEdgesOfClass(c), k) << "class " << c;
    return n;
  };
  {
    const Read r = readOk(writeBrep(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "classes_box.brep"));
    EXPECT_EQ(classes(r), (std::map<int, int>{{1, 12}}));
    for (const Line& l : lines(r)) EXPECT_NEAR(l.angle, 90.0, 1e-9);
  }
  {
    const Read r = readOk(writeBrep(filletedBox(), "classes_fillet.brep"));
    const std::map<int, int> n = classes(r);
    EXPECT_EQ(n.count(1), 0u) << "a fully filleted box has no sharp edge";
    EXPECT_GE(n.at(2), 24);
    for (const Line& l : lines(r)) {
      if (l.edgeClass == 2) {
        EXPECT_LT(l.angle, 1e-6);
      }
    }
  }
  {
    const Read r = readOk(writeBrep(BRepPrimAPI_MakeCylinder(5, 10).Shape(), "classes_cyl.brep"));
    EXPECT_EQ(classes(r), (std::map<int, int>{{1, 2}, {3, 1}}));
    for (const Line& l : lines(r)) {
      if (l.edgeClass == 1) {
        EXPECT_NEAR(l.angle, 90.0, 1e-9);
      } else {
        EXPECT_TRUE(std::isnan(l.angle));
      }
    }
  }
  {
    const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
    TopExp_Explorer faces(box, TopAbs_FACE);
    const Read r = readOk(writeBrep(faces.Current(), "classes_face.brep"));
    EXPECT_EQ(classes(r), (std::map<int, int>{{0, 4}}));
  }
  {
    TopoDS_Compound c;
    BRep_Builder b;
    b.MakeCompound(c);
    b.Add(c, BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(10, 0, 0)).Edge());
    const Read r = readCad(writeBrep(c, "classes_wire.brep"));
    ASSERT_EQ(r.reader->GetErrorMessage(), "");
    EXPECT_EQ(classes(r), (std::map<int, int>{{4, 1}}));
  }
}

// The feature angle splits a chamfer's edges: a box with a 1-mm chamfer at 45 degrees on one
// edge gives two edges at 45 degrees (sharp at the default 10, smooth at 50).
TEST(CadEdges, FeatureAngleSplitsAChamfer) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
  BRepFilletAPI_MakeChamfer chamfer(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  chamfer.Add(1.0, TopoDS::Edge(edges(1)));
  const std::string path = writeBrep(chamfer.Shape(), "classes_chamfer.brep");
  int at45 = 0;
  for (const Line& l : lines(readOk(path)))
    if (std::abs(l.angle - 45.0) < 1e-9) {
      ++at45;
      EXPECT_EQ(l.edgeClass, 1);
    }
  EXPECT_EQ(at45, 2);
  const Read wide = readOk(path, [](vtkWireFurCADReader* r) { r->SetFeatureAngle(50); });
  int smooth = 0;
  for (const Line& l : lines(wide)) smooth += l.edgeClass == 2;
  EXPECT_EQ(smooth, 2);
}

// From a review: two kinds of B-rep that real files carry, each with one tangent edge that must
// read smooth at 0 degrees, not sharp at 180.
// - A cylinder of radius 5 made of two lateral faces sewn at z = 5, the seam circle's curve on one
//   face re-parametrised (the same points over [pi, 3 pi] instead of [0, 2 pi]): the edge is no
//   longer SameParameter, so the two faces' curves cannot share a parameter (each is projected).
// - A box with one filleted edge as a shell whose fillet face is flipped (an unfixed surface
//   model): both faces run the tangent edges the same way, and one normal is turned back.
TEST(CadEdges, TangentEdgesOfReparametrisedAndFlippedFaces) {
  auto smoothAtZero = [](const TopoDS_Shape& shape, const std::string& name) {
    int smooth = 0;
    for (const Line& l : lines(readOk(writeBrep(shape, name))))
      if (l.edgeClass == 2) {
        ++smooth;
        EXPECT_LT(l.angle, 1e-6) << name;
      }
    return smooth;
  };
  BRepBuilderAPI_Sewing sew;
  for (double z0 : {0.0, 5.0}) {
    Handle(Geom_CylindricalSurface) s = new Geom_CylindricalSurface(gp_Ax3(gp::XOY()), 5.0);
    sew.Add(BRepBuilderAPI_MakeFace(s, 0, 2 * kPi, z0, z0 + 5, 1e-7).Face());
  }
  sew.Perform();
  const TopoDS_Shape cylinder = sew.SewedShape();
  EXPECT_EQ(smoothAtZero(cylinder, "tangent_cyl.brep"), 1);
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(cylinder, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  bool changed = false;
  for (int i = 1; i <= edgeFaces.Extent() && !changed; ++i) {
    const TopoDS_Edge e = TopoDS::Edge(edgeFaces.FindKey(i));
    Standard_Real f, l;
    const Handle(Geom_Curve) c = BRep_Tool::Curve(e, f, l);
    if (c.IsNull() || std::abs(c->Value(0.5 * (f + l)).Z() - 5) > 1e-6 || edgeFaces(i).Extent() < 2) continue;
    const TopoDS_Face face = TopoDS::Face(edgeFaces(i).First());
    Standard_Real pf, pl;
    const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(e, face, pf, pl);
    gp_Pnt2d p0;
    gp_Vec2d d;
    pc->D1(pf, p0, d);
    BRep_Builder b;
    b.UpdateEdge(e, new Geom2d_Line(gp_Pnt2d(p0.X() - d.X() / d.Magnitude() * kPi, p0.Y()), gp_Dir2d(d.X(), d.Y())), face,
                 BRep_Tool::Tolerance(e));
    b.Range(e, face, pf + kPi, pl + kPi);
    b.SameParameter(e, Standard_False);
    b.SameRange(e, Standard_False);
    changed = true;
  }
  ASSERT_TRUE(changed);
  EXPECT_EQ(smoothAtZero(cylinder, "tangent_cyl_reparam.brep"), 1);

  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10, 20, 30).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  fillet.Add(2, TopoDS::Edge(edges(1)));
  const TopoDS_Shape filleted = fillet.Shape();
  EXPECT_EQ(smoothAtZero(filleted, "tangent_fillet.brep"), 2);
  TopoDS_Shell shell;
  BRep_Builder b;
  b.MakeShell(shell);
  bool flipped = false;
  for (TopExp_Explorer x(filleted, TopAbs_FACE); x.More(); x.Next()) {
    TopoDS_Face face = TopoDS::Face(x.Current());
    if (!flipped && BRep_Tool::Surface(face)->DynamicType() != STANDARD_TYPE(Geom_Plane)) {
      face.Reverse();
      flipped = true;
    }
    b.Add(shell, face);
  }
  ASSERT_TRUE(flipped);
  EXPECT_EQ(smoothAtZero(shell, "tangent_fillet_flipped.brep"), 2);
}
