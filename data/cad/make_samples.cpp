// Writes the CAD samples of data/cad with OpenCASCADE (the gallery's mould scene, paper image 11):
//   mould.step    the two mould halves opened side by side: the cavity plate (a pocket in the
//                 product's outer shape) and the core plate (a boss in its inner shape), named
//                 and coloured (XCAF)
//   product.step  the moulded product: a tray with rounded corners, shelled, open at the top
// Regenerate (from this folder, with Debian's libocct-*-dev):
//   g++ -std=c++17 -O1 make_samples.cpp -I/usr/include/opencascade -lTKernel -lTKMath -lTKG3d -lTKBRep \
//       -lTKPrim -lTKTopAlgo -lTKBO -lTKFillet -lTKOffset -lTKSTEP -lTKXSBase -lTKXDESTEP -lTKXCAF \
//       -lTKLCAF -lTKCAF -lTKG2d -lTKGeomBase -o /tmp/make_samples && /tmp/make_samples
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepOffsetAPI_MakeThickSolid.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gp_Pln.hxx>

#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Quantity_Color.hxx>

#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

namespace {

// A box with its vertical edges (and, when `all`, its bottom edges too) rounded.
TopoDS_Shape roundedBox(double x, double y, double z, double dx, double dy, double dz, double r, bool bottom) {
  TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(x, y, z), dx, dy, dz).Shape();
  BRepFilletAPI_MakeFillet f(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    TopoDS_Vertex a, b;
    TopExp::Vertices(edge, a, b);
    const gp_Pnt pa = BRep_Tool::Pnt(a), pb = BRep_Tool::Pnt(b);
    const bool vertical = std::abs(pa.Z() - pb.Z()) > 1e-9;
    const bool atBottom = std::abs(pa.Z() - z) < 1e-9 && std::abs(pb.Z() - z) < 1e-9;
    if (vertical || (bottom && atBottom)) f.Add(r, edge);
  }
  return f.Shape();
}

TopoDS_Shape topFace(const TopoDS_Shape& s, double z) {
  for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next()) {
    Bnd_Box b;
    (void)b;
    TopExp_Explorer v(e.Current(), TopAbs_VERTEX);
    bool top = true;
    for (; v.More(); v.Next()) top = top && std::abs(BRep_Tool::Pnt(TopoDS::Vertex(v.Current())).Z() - z) < 1e-9;
    if (top) return e.Current();
  }
  return {};
}

void write(const char* path, const std::vector<std::tuple<const char*, TopoDS_Shape, Quantity_Color>>& parts) {
  Handle(TDocStd_Document) doc;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
  Handle(XCAFDoc_ShapeTool) st = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  Handle(XCAFDoc_ColorTool) ct = XCAFDoc_DocumentTool::ColorTool(doc->Main());
  for (const auto& [name, shape, colour] : parts) {
    const TDF_Label l = st->AddShape(shape, Standard_False);
    TDataStd_Name::Set(l, name);
    ct->SetColor(l, colour, XCAFDoc_ColorSurf);
  }
  STEPCAFControl_Writer w;
  w.SetColorMode(true);
  w.SetNameMode(true);
  if (!w.Transfer(doc, STEPControl_AsIs) || w.Write(path) != IFSelect_RetDone) std::fprintf(stderr, "cannot write %s\n", path);
}

}  // namespace

int main() {
  // The product: a tray 36 x 24 x 10 with corners of radius 5 and a rounded bottom, shelled to 1.5
  // with its top open.
  const TopoDS_Shape outer = roundedBox(-18, -12, 0, 36, 24, 10, 5, true);
  TopTools_ListOfShape open;
  open.Append(topFace(outer, 10));
  BRepOffsetAPI_MakeThickSolid shell;
  shell.MakeThickSolidByJoin(outer, open, -1.5, 1e-4);
  const TopoDS_Shape product = shell.Shape();
  write("product.step", {{"tray", product, Quantity_Color(0.85, 0.55, 0.2, Quantity_TOC_sRGB)}});

  // The mould opened like a book, both halves face up: on the left the cavity plate with the
  // product's outer shape as a pocket, on the right the core plate with its inside as a boss. The
  // product sits upside down over the core (translate it by (35, 0, 10) after turning it over
  // about x), as in the paper's image 11.
  gp_Trsf flip;
  flip.SetMirror(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)));
  gp_Trsf left, right;
  left.SetTranslation(gp_Vec(-35, 0, 0));
  right.SetTranslation(gp_Vec(35, 0, 10));
  gp_Trsf pocketAt = left;
  pocketAt.Multiply(flip);  // z in [-10, 0], x about -35
  const TopoDS_Shape pocket = BRepBuilderAPI_Transform(outer, pocketAt, true).Shape();
  const TopoDS_Shape cavity = BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(gp_Pnt(-62, -20, -16), 54, 40, 16).Shape(), pocket).Shape();
  const TopoDS_Shape inner = roundedBox(-16.5, -10.5, 1.5, 33, 21, 8.5, 3.5, true);
  gp_Trsf bossAt = right;
  bossAt.Multiply(flip);  // z in [0, 8.5], x about +35
  const TopoDS_Shape boss = BRepBuilderAPI_Transform(inner, bossAt, true).Shape();
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(gp_Pnt(8, -20, -16), 54, 40, 16).Shape();
  const TopoDS_Shape core = BRepAlgoAPI_Fuse(plate, boss).Shape();
  write("mould.step", {{"cavity plate", cavity, Quantity_Color(0.55, 0.6, 0.68, Quantity_TOC_sRGB)},
                       {"core plate", core, Quantity_Color(0.66, 0.64, 0.58, Quantity_TOC_sRGB)}});
  return 0;
}
