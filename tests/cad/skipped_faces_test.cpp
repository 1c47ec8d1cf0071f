// A model with a face that does not mesh: the rest is output and the face is counted as skipped,
// with a warning naming it (the issue: "a model with some bad faces renders the rest and says
// how many were skipped"). The bad face is a plane face bounded by an open wire (two edges that
// do not close), which OpenCASCADE's mesher cannot triangulate, next to a good box.
#include "cad_fixtures.h"

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <Geom_Plane.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pln.hxx>

using namespace cadtest;

TEST(CadSkippedFaces, TheRestIsOutputAndTheSkippedCounted) {
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  b.Add(c, BRepPrimAPI_MakeBox(10, 10, 10).Shape());
  // The open wire: (20,0,0) -> (30,0,0) -> (30,10,0), not closed.
  BRepBuilderAPI_MakeWire w;
  w.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(20, 0, 0), gp_Pnt(30, 0, 0)).Edge());
  w.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(30, 0, 0), gp_Pnt(30, 10, 0)).Edge());
  TopoDS_Face bad;
  b.MakeFace(bad, new Geom_Plane(gp_Pln()), 1e-7);
  b.Add(bad, w.Wire());
  b.Add(c, bad);
  const Read r = readCad(writeBrep(c, "box_and_open_face.brep"));
  EXPECT_EQ(r.reader->GetErrorMessage(), "");
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 7);
  EXPECT_EQ(r.reader->GetNumberOfMeshedFaces(), 6);
  EXPECT_EQ(r.reader->GetNumberOfSkippedFaces(), 1);
  EXPECT_NE(r.reader->GetWarningMessage().find("skipped 1 of 7 faces"), std::string::npos) << r.reader->GetWarningMessage();
  EXPECT_NE(r.reader->GetWarningMessage().find("face 6"), std::string::npos) << r.reader->GetWarningMessage();
  // The box is all there: area 600 exactly (its six planes).
  EXPECT_NEAR(meshArea(r), 600.0, 1e-9);
}
