// Writes the seed corpus of the CAD fuzz targets, made with OpenCASCADE at fuzz time (nothing
// binary is committed): OUTDIR/{step,iges,brep,fcstd}/... Small models, so that every execution
// stays cheap: a box, a cylinder, a filleted box, a box with a hole through it, a B-spline face;
// STEP and IGES through XCAF with names, colours and an assembly with a coloured instance;
// BREP in text and binary; FreeCAD documents (Document.xml, GuiDocument.xml, PartShape*.brp,
// a DiffuseColor list, an App::Part container) as stored zips.
//
// Usage: make_cad_seeds OUTDIR
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <BinTools.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Writer.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Writer.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TDF_Label.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <BRep_Builder.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gp_Ax2.hxx>
#include <gp_Trsf.hxx>

#include <zip.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

TopoDS_Shape box() { return BRepPrimAPI_MakeBox(10.0, 20.0, 30.0).Shape(); }
TopoDS_Shape cylinder() { return BRepPrimAPI_MakeCylinder(5.0, 12.0).Shape(); }

TopoDS_Shape filletedBox() {
  const TopoDS_Shape b = BRepPrimAPI_MakeBox(10.0, 10.0, 10.0).Shape();
  BRepFilletAPI_MakeFillet f(b);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(b, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) f.Add(1.5, TopoDS::Edge(edges(i)));
  return f.Shape();
}

TopoDS_Shape boxWithHole() {
  const TopoDS_Shape b = BRepPrimAPI_MakeBox(20.0, 20.0, 5.0).Shape();
  const TopoDS_Shape c = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(10, 10, -1), gp::DZ()), 4.0, 7.0).Shape();
  return BRepAlgoAPI_Cut(b, c).Shape();
}

TopoDS_Shape bsplineFace() {
  TColgp_Array2OfPnt pts(1, 4, 1, 4);
  for (int i = 1; i <= 4; ++i)
    for (int j = 1; j <= 4; ++j) pts(i, j) = gp_Pnt(i, j, std::sin(i * 0.9) * std::cos(j * 0.7));
  Handle(Geom_BSplineSurface) s = GeomAPI_PointsToBSplineSurface(pts).Surface();
  return BRepBuilderAPI_MakeFace(s, 1e-7).Shape();
}

TopoDS_Shape sphere() { return BRepPrimAPI_MakeSphere(3.0).Shape(); }

void writeFile(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f << bytes;
}

std::string brepText(const TopoDS_Shape& s) {
  std::ostringstream o;
  BRepTools::Write(s, o);
  return o.str();
}

std::string brepBinary(const TopoDS_Shape& s) {
  std::ostringstream o(std::ios::binary);
  BinTools::Write(s, o);
  return o.str();
}

bool plainStep(const TopoDS_Shape& s, const fs::path& p) {
  STEPControl_Writer w;
  return w.Transfer(s, STEPControl_AsIs) == IFSelect_RetDone && w.Write(p.c_str()) == IFSelect_RetDone;
}

bool plainIges(const TopoDS_Shape& s, const fs::path& p, int brepMode) {
  IGESControl_Controller::Init();
  Interface_Static::SetIVal("write.iges.brep.mode", brepMode);  // 0: trimmed surfaces, 1: BREP entities
  IGESControl_Writer w("MM", brepMode);
  w.AddShape(s);
  w.ComputeModel();
  return w.Write(p.c_str());
}

// An XCAF document: a coloured box part, a cylinder part with one red face, and an assembly
// holding the box twice (one instance rotated and coloured) and the cylinder once.
Handle(TDocStd_Document) xcafDocument() {
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  Handle(TDocStd_Document) doc;
  app->NewDocument("MDTV-XCAF", doc);
  Handle(XCAFDoc_ShapeTool) st = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  Handle(XCAFDoc_ColorTool) ct = XCAFDoc_DocumentTool::ColorTool(doc->Main());
  const TopoDS_Shape b = box(), c = cylinder();
  const TDF_Label boxL = st->AddShape(b, false);
  TDataStd_Name::Set(boxL, "Box part");
  ct->SetColor(boxL, Quantity_Color(0.2, 0.4, 0.8, Quantity_TOC_RGB), XCAFDoc_ColorSurf);
  const TDF_Label cylL = st->AddShape(c, false);
  TDataStd_Name::Set(cylL, "Cylinder part");
  TopExp_Explorer e(c, TopAbs_FACE);
  const TDF_Label faceL = st->AddSubShape(cylL, e.Current());
  if (!faceL.IsNull()) ct->SetColor(faceL, Quantity_Color(0.9, 0.1, 0.1, Quantity_TOC_RGB), XCAFDoc_ColorSurf);
  const TDF_Label asmL = st->NewShape();
  TDataStd_Name::Set(asmL, "Assembly");
  gp_Trsf t1, t2, t3;
  t1.SetTranslation(gp_Vec(30, 0, 0));
  // (OpenCASCADE 7.6 refuses mirroring and scaling locations: Standard_DomainError.)
  t2.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp::DZ()), 0.7);
  t3.SetTranslation(gp_Vec(0, 40, 0));
  st->AddComponent(asmL, boxL, TopLoc_Location(t1));
  const TDF_Label rotated = st->AddComponent(asmL, boxL, TopLoc_Location(t2));
  if (!rotated.IsNull()) ct->SetColor(rotated, Quantity_Color(0.1, 0.8, 0.1, Quantity_TOC_RGB), XCAFDoc_ColorGen);
  st->AddComponent(asmL, cylL, TopLoc_Location(t3));
  st->UpdateAssemblies();
  return doc;
}

bool xcafStep(const fs::path& p) {
  Handle(TDocStd_Document) doc = xcafDocument();
  STEPCAFControl_Writer w;
  w.SetColorMode(true);
  w.SetNameMode(true);
  const bool ok = w.Transfer(doc, STEPControl_AsIs) && w.Write(p.c_str()) == IFSelect_RetDone;
  XCAFApp_Application::GetApplication()->Close(doc);
  return ok;
}

bool xcafIges(const fs::path& p) {
  Handle(TDocStd_Document) doc = xcafDocument();
  IGESCAFControl_Writer w;
  w.SetColorMode(true);
  w.SetNameMode(true);
  const bool ok = w.Transfer(doc) && w.Write(p.c_str());
  XCAFApp_Application::GetApplication()->Close(doc);
  return ok;
}

// ---------------------------------------------------------------------------------------------
// FreeCAD documents.

std::string packedColour(double r, double g, double b) {
  auto q = [](double x) { return std::uint32_t(std::lround(x * 255.0)); };
  return std::to_string((q(r) << 24) | (q(g) << 16) | (q(b) << 8));
}

std::string colourList(const std::vector<std::uint32_t>& cs) {
  std::string s(4 + 4 * cs.size(), '\0');
  const std::uint32_t n = std::uint32_t(cs.size());
  std::memcpy(s.data(), &n, 4);
  for (size_t i = 0; i < cs.size(); ++i) std::memcpy(s.data() + 4 + 4 * i, &cs[i], 4);
  return s;
}

std::string property(const std::string& name, const std::string& type, const std::string& body) {
  return "        <Property name=\"" + name + "\" type=\"" + type + "\">\n          " + body + "\n        </Property>\n";
}

struct FcObject {
  std::string name, type, label, shapeFile, placement;  // placement: the PropertyPlacement attributes
  std::vector<std::string> group;
  bool visible = true;
};

std::string documentXml(const std::vector<FcObject>& objects) {
  std::string s = "<?xml version='1.0' encoding='utf-8'?>\n<Document SchemaVersion=\"4\" ProgramVersion=\"0.21\" FileVersion=\"1\">\n";
  s += "  <Objects Count=\"" + std::to_string(objects.size()) + "\">\n";
  for (size_t i = 0; i < objects.size(); ++i)
    s += "    <Object type=\"" + objects[i].type + "\" name=\"" + objects[i].name + "\" id=\"" + std::to_string(i + 1) + "\"/>\n";
  s += "  </Objects>\n  <ObjectData Count=\"" + std::to_string(objects.size()) + "\">\n";
  for (const FcObject& o : objects) {
    s += "    <Object name=\"" + o.name + "\">\n      <Properties Count=\"5\">\n";
    s += property("Label", "App::PropertyString", "<String value=\"" + o.label + "\"/>");
    if (!o.placement.empty()) s += property("Placement", "App::PropertyPlacement", "<PropertyPlacement " + o.placement + "/>");
    if (!o.shapeFile.empty()) s += property("Shape", "Part::PropertyPartShape", "<Part file=\"" + o.shapeFile + "\"/>");
    s += property("Visibility", "App::PropertyBool", std::string("<Bool value=\"") + (o.visible ? "true" : "false") + "\"/>");
    if (!o.group.empty()) {
      std::string links = "<LinkList count=\"" + std::to_string(o.group.size()) + "\">";
      for (const std::string& g : o.group) links += "<Link value=\"" + g + "\"/>";
      s += property("Group", "App::PropertyLinkList", links + "</LinkList>");
    }
    s += "      </Properties>\n    </Object>\n";
  }
  return s + "  </ObjectData>\n</Document>\n";
}

struct FcView {
  std::string name, shapeColour, diffuseFile;
  bool visible = true;
};

std::string guiDocumentXml(const std::vector<FcView>& views) {
  std::string s = "<?xml version='1.0' encoding='utf-8'?>\n<Document SchemaVersion=\"1\" HasExpansion=\"1\">\n";
  s += "  <ViewProviderData Count=\"" + std::to_string(views.size()) + "\">\n";
  for (const FcView& v : views) {
    s += "    <ViewProvider name=\"" + v.name + "\" expanded=\"0\">\n      <Properties Count=\"3\">\n";
    if (!v.diffuseFile.empty()) s += property("DiffuseColor", "App::PropertyColorList", "<ColorList file=\"" + v.diffuseFile + "\"/>");
    if (!v.shapeColour.empty()) s += property("ShapeColor", "App::PropertyColor", "<PropertyColor value=\"" + v.shapeColour + "\"/>");
    s += property("Visibility", "App::PropertyBool", std::string("<Bool value=\"") + (v.visible ? "true" : "false") + "\"/>");
    s += "      </Properties>\n    </ViewProvider>\n";
  }
  return s + "  </ViewProviderData>\n</Document>\n";
}

bool writeZip(const fs::path& p, const std::vector<std::pair<std::string, std::string>>& entries) {
  int err = 0;
  zip_t* z = zip_open(p.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  if (!z) return false;
  for (const auto& [name, data] : entries) {
    zip_source_t* s = zip_source_buffer(z, data.data(), data.size(), 0);
    const zip_int64_t i = zip_file_add(z, name.c_str(), s, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8);
    if (i < 0) {
      zip_source_free(s);
      zip_discard(z);
      return false;
    }
    zip_set_file_compression(z, zip_uint64_t(i), ZIP_CM_STORE, 0);  // stored: mutations reach the text
  }
  return zip_close(z) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
    return 2;
  }
  // OpenCASCADE's writers chat on the console: quiet.
  Message::DefaultMessenger()->ChangePrinters().Clear();
  const fs::path out = argv[1];
  for (const char* d : {"step", "iges", "brep", "fcstd"}) fs::create_directories(out / d);
  int failed = 0;
  auto check = [&](bool ok, const char* what) {
    if (!ok) {
      std::fprintf(stderr, "make_cad_seeds: could not write %s\n", what);
      ++failed;
    }
  };

  check(plainStep(box(), out / "step" / "box.step"), "box.step");
  check(plainStep(filletedBox(), out / "step" / "fillet.step"), "fillet.step");
  check(plainStep(bsplineFace(), out / "step" / "bspline.step"), "bspline.step");
  check(xcafStep(out / "step" / "assembly.step"), "assembly.step");

  check(plainIges(box(), out / "iges" / "box_brep.iges", 1), "box_brep.iges");
  check(plainIges(boxWithHole(), out / "iges" / "hole_trimmed.iges", 0), "hole_trimmed.iges");
  check(plainIges(bsplineFace(), out / "iges" / "bspline.iges", 0), "bspline.iges");
  check(xcafIges(out / "iges" / "assembly.iges"), "assembly.iges");

  writeFile(out / "brep" / "box.brep", brepText(box()));
  writeFile(out / "brep" / "fillet.brep", brepText(filletedBox()));
  writeFile(out / "brep" / "hole.brep", brepText(boxWithHole()));
  writeFile(out / "brep" / "bspline.brep", brepText(bsplineFace()));
  writeFile(out / "brep" / "sphere.brep", brepText(sphere()));
  writeFile(out / "brep" / "cylinder_binary.brep", brepBinary(cylinder()));
  {
    TopoDS_Compound c;
    BRep_Builder b;
    b.MakeCompound(c);
    gp_Trsf t;
    t.SetTranslation(gp_Vec(20, 0, 0));
    b.Add(c, cylinder());
    b.Add(c, sphere().Moved(TopLoc_Location(t)));
    writeFile(out / "brep" / "compound.brep", brepText(c));
  }

  // FreeCAD: a box with per-face colours and a placement, and a cylinder inside an App::Part.
  {
    std::vector<FcObject> objects(3);
    objects[0] = {"Box", "Part::Box", "Cube", "PartShape.brp",
                  "Px=\"1\" Py=\"2\" Pz=\"3\" Q0=\"0\" Q1=\"0\" Q2=\"0.3826834\" Q3=\"0.9238795\" A=\"0.785\" Ox=\"0\" Oy=\"0\" Oz=\"1\"", {}, true};
    objects[1] = {"Part", "App::Part", "Part", "",
                  "Px=\"0\" Py=\"30\" Pz=\"0\" Q0=\"0\" Q1=\"0\" Q2=\"0\" Q3=\"1\" A=\"0\" Ox=\"0\" Oy=\"0\" Oz=\"1\"", {"Cylinder"}, true};
    objects[2] = {"Cylinder", "Part::Cylinder", "Cylinder", "PartShape1.brp", "", {}, true};
    std::vector<FcView> views = {{"Box", packedColour(0.8, 0.8, 0.8), "DiffuseColor", true},
                                 {"Part", "", "", true},
                                 {"Cylinder", packedColour(0.2, 0.5, 0.9), "DiffuseColor1", true}};
    std::vector<std::uint32_t> six;
    for (int i = 0; i < 6; ++i) six.push_back(std::uint32_t(0x10203000u * std::uint32_t(i + 1)));
    check(writeZip(out / "fcstd" / "parts.FCStd", {{"Document.xml", documentXml(objects)},
                                                   {"GuiDocument.xml", guiDocumentXml(views)},
                                                   {"PartShape.brp", brepText(box())},
                                                   {"PartShape1.brp", brepText(cylinder())},
                                                   {"DiffuseColor", colourList(six)},
                                                   {"DiffuseColor1", colourList({0xff000000u})}}),
          "parts.FCStd");
  }
  // Without GuiDocument.xml, one hidden object, a binary BREP shape.
  {
    std::vector<FcObject> objects(2);
    objects[0] = {"Fillet", "Part::Fillet", "Fillet", "PartShape.brp", "", {}, true};
    objects[1] = {"Hidden", "Part::Feature", "Hidden", "PartShape1.brp", "", {}, false};
    check(writeZip(out / "fcstd" / "nogui.FCStd", {{"Document.xml", documentXml(objects)},
                                                   {"PartShape.brp", brepText(filletedBox())},
                                                   {"PartShape1.brp", brepBinary(sphere())}}),
          "nogui.FCStd");
  }
  return failed == 0 ? 0 : 1;
}
