// FreeCAD documents (.FCStd), written by the tests with libzip in the layout of FreeCAD 0.19 -
// 0.21: Document.xml (objects, their Label, Placement, Shape file, App::Part Group), GuiDocument.xml
// (view providers: Visibility, ShapeColor) and one BREP text per shape (BRepTools::Write), the
// shape stored with its location equal to the object's own Placement, as FreeCAD saves it.
#include "fcstd_fixtures.h"

#include <BRepPrimAPI_MakeBox.hxx>

#include <cstring>

using namespace cadtest;
using namespace cadtest::fc;

namespace {

// Expects every point's colour to be `rgb` (+-1: the sRGB 8-bit value goes through
// OpenCASCADE's linear RGB and back).
void expectColour(const Read& r, int red, int green, int blue) {
  vtkDataArray* c = r.faces->GetPointData()->GetArray("Colors");
  ASSERT_NE(c, nullptr);
  int bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i)
    bad += std::abs(c->GetComponent(i, 0) - red) > 1 || std::abs(c->GetComponent(i, 1) - green) > 1 ||
           std::abs(c->GetComponent(i, 2) - blue) > 1;
  EXPECT_EQ(bad, 0) << "first point (" << c->GetComponent(0, 0) << ", " << c->GetComponent(0, 1) << ", " << c->GetComponent(0, 2)
                    << ")";
}

// The faces' bounds against the expected box, exactly up to rounding (1e-9 absolute: the box's
// corners are moved by a rotation whose matrix entries are 0 and 1 up to 1e-16).
void expectBounds(const Read& r, const std::array<double, 6>& want) {
  double b[6];
  r.faces->GetBounds(b);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(b[k], want[size_t(k)], 1e-9) << "bound " << k;
}

}  // namespace

// Two objects: "Box" (label "Visible box", a 1 x 2 x 3 box at Placement: 90 degrees about z,
// quaternion (0, 0, sin 45, cos 45) as Q0..Q3 = x, y, z, w, then translated by (10, 20, 30);
// ShapeColor sRGB (204, 51, 17)) and "Hidden" (a 5 x 5 x 5 box; Visibility false in
// GuiDocument.xml). Expected: one part, named by its Label; the rotation takes (x, y, z) to
// (-y, x, z), so the box spans [-2, 0] x [0, 1] x [0, 3] before the translation: bounds
// [8, 10] x [20, 21] x [30, 33]; colour (204, 51, 17) at every point; the box's normals are the
// outward axes of its faces at those bounds.
TEST(CadFreeCad, VisiblePlacementColour) {
  const Placement boxAt = Placement::rotation(0, 0, 1, 90).translated(10, 20, 30);
  std::vector<Object> objects = {
      Object::feature("Box", "Visible box", boxAt, "PartShape.brp"),
      Object::feature("Hidden", "Hidden box", Placement(), "PartShape1.brp"),
  };
  std::vector<View> views = {View{"Box", true, packColour(204, 51, 17)}, View{"Hidden", false, packColour(0, 0, 255)}};
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(1, 2, 3).Shape();
  const std::string path = writeFcstd("visible.FCStd", objects, views,
                                      {{"PartShape.brp", brepText(box.Moved(boxAt.location()))},
                                       {"PartShape1.brp", brepText(BRepPrimAPI_MakeBox(5, 5, 5).Shape())}});
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfParts(), 1);
  EXPECT_EQ(r.reader->GetPartName(0), "Visible box");
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 6);
  expectBounds(r, {8, 10, 20, 21, 30, 33});
  expectColour(r, 204, 51, 17);
  double b[6];
  r.faces->GetBounds(b);
  int bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 p = r.point(i), n = r.normal(i);
    int k = 0;
    for (int j = 1; j < 3; ++j)
      if (std::abs(n[j]) > std::abs(n[k])) k = j;
    bad += !(std::abs(std::abs(n[k]) - 1) < 1e-6 && std::abs(p[k] - (n[k] > 0 ? b[2 * k + 1] : b[2 * k])) < 1e-9);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(checkWinding(r, 1e-12).wrong, 0);
}

// Control for the test above: the same document with "Hidden" visible gives both parts (so the
// hidden object was left out because of its Visibility, not because its shape was unreadable).
TEST(CadFreeCad, HiddenObjectIsReadWhenVisible) {
  std::vector<Object> objects = {
      Object::feature("Box", "Visible box", Placement(), "PartShape.brp"),
      Object::feature("Hidden", "Hidden box", Placement(), "PartShape1.brp"),
  };
  std::vector<View> views = {View{"Box", true, packColour(204, 51, 17)}, View{"Hidden", true, packColour(0, 0, 255)}};
  const std::string path = writeFcstd("both_visible.FCStd", objects, views,
                                      {{"PartShape.brp", brepText(BRepPrimAPI_MakeBox(1, 2, 3).Shape())},
                                       {"PartShape1.brp", brepText(BRepPrimAPI_MakeBox(5, 5, 5).Shape())}});
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfParts(), 2);
  EXPECT_EQ(r.reader->GetPartName(0), "Visible box");
  EXPECT_EQ(r.reader->GetPartName(1), "Hidden box");
  EXPECT_EQ(r.reader->GetNumberOfFaces(), 12);
  expectBounds(r, {0, 5, 0, 5, 0, 5});
}

// Without GuiDocument.xml (a document saved without the GUI) the object's own Visibility property
// in Document.xml decides: "Hidden" has Visibility false there and is left out.
TEST(CadFreeCad, DocumentVisibilityWithoutGui) {
  Object hidden = Object::feature("Hidden", "Hidden box", Placement(), "PartShape1.brp");
  hidden.visibility = false;
  Object shown = Object::feature("Box", "Box", Placement(), "PartShape.brp");
  shown.visibility = true;
  const std::string path = writeFcstd("nogui.FCStd", {shown, hidden}, std::nullopt,
                                      {{"PartShape.brp", brepText(BRepPrimAPI_MakeBox(1, 2, 3).Shape())},
                                       {"PartShape1.brp", brepText(BRepPrimAPI_MakeBox(5, 5, 5).Shape())}});
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfParts(), 1);
  EXPECT_EQ(r.reader->GetPartName(0), "Box");
  expectBounds(r, {0, 1, 0, 2, 0, 3});
}

// An App::Part container "Part" (Placement: 90 degrees about x, quaternion (sin 45, 0, 0, cos 45),
// then translated by (100, 0, 0)) holding "Box" (a 1 x 2 x 3 box at Placement translation
// (0, 5, 0); its PartShape.brp carries that location only, as FreeCAD stores a child). The world
// placement is Part * Box: the box spans [0, 1] x [5, 7] x [0, 3] in the container, the rotation
// takes (x, y, z) to (x, -z, y): [0, 1] x [-3, 0] x [5, 7], then + (100, 0, 0). The other order
// (Box * Part) would give [100, 101] x [2, 5] x [0, 2]. Exact to 1e-9.
TEST(CadFreeCad, AppPartComposesPlacements) {
  const Placement partAt = Placement::rotation(1, 0, 0, 90).translated(100, 0, 0);
  const Placement boxAt = Placement().translated(0, 5, 0);
  Object part = Object::container("Part", "Container", partAt, {"Box"});
  Object box = Object::feature("Box", "Child box", boxAt, "PartShape.brp");
  const std::string path =
      writeFcstd("apppart.FCStd", {part, box}, std::vector<View>{View{"Part", true, std::nullopt}, View{"Box", true, packColour(10, 200, 30)}},
                 {{"PartShape.brp", brepText(BRepPrimAPI_MakeBox(1, 2, 3).Shape().Moved(boxAt.location()))}});
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfParts(), 1);
  EXPECT_EQ(r.reader->GetPartName(0), "Child box");
  expectBounds(r, {100, 101, -3, 0, 5, 7});
  expectColour(r, 10, 200, 30);
  EXPECT_EQ(checkWinding(r, 1e-12).wrong, 0);
}

// Two levels: an outer App::Part (translation (0, 0, 50)) holding the container of the test above.
// Expected: the same box moved by a further (0, 0, 50): [100, 101] x [-3, 0] x [55, 57]. A hidden
// container hides its children: with the outer container's Visibility false, nothing is left and
// the update fails (every object with a shape is hidden).
TEST(CadFreeCad, NestedAppPartsAndHiddenContainer) {
  const Placement outerAt = Placement().translated(0, 0, 50);
  const Placement partAt = Placement::rotation(1, 0, 0, 90).translated(100, 0, 0);
  const Placement boxAt = Placement().translated(0, 5, 0);
  const std::vector<Object> objects = {Object::container("Outer", "Outer", outerAt, {"Part"}),
                                       Object::container("Part", "Container", partAt, {"Box"}),
                                       Object::feature("Box", "Child box", boxAt, "PartShape.brp")};
  const std::vector<std::pair<std::string, std::string>> files = {
      {"PartShape.brp", brepText(BRepPrimAPI_MakeBox(1, 2, 3).Shape().Moved(boxAt.location()))}};
  {
    const Read r = readOk(writeFcstd("nested.FCStd", objects,
                                     std::vector<View>{View{"Outer", true, std::nullopt}, View{"Part", true, std::nullopt},
                                                       View{"Box", true, std::nullopt}},
                                     files));
    ASSERT_EQ(r.reader->GetNumberOfParts(), 1);
    expectBounds(r, {100, 101, -3, 0, 55, 57});
  }
  {
    const std::string path = writeFcstd("nested_hidden.FCStd", objects,
                                        std::vector<View>{View{"Outer", false, std::nullopt}, View{"Part", true, std::nullopt},
                                                          View{"Box", true, std::nullopt}},
                                        files);
    const Read r = readCad(path);
    EXPECT_NE(r.reader->GetErrorMessage().find("hidden"), std::string::npos) << r.reader->GetErrorMessage();
    EXPECT_EQ(r.faces->GetNumberOfPoints(), 0);
  }
}

// Per-face colours: GuiDocument.xml's DiffuseColor names a ColorList file in the archive (a
// little-endian uint32 count, then that many packed colours, as FreeCAD's PropertyColorList
// writes it). With one colour per face, face k (TopExp_Explorer order of the shape, = FaceId k
// for a single object) gets colour k, overriding ShapeColor; every point of the face has it
// exactly (+-1).
TEST(CadFreeCad, DiffuseColorPerFace) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(1, 2, 3).Shape();
  const unsigned rgb[6][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 0}, {0, 255, 255}, {128, 64, 32}};
  std::string list(4 + 4 * 6, '\0');
  const std::uint32_t count = 6;
  std::memcpy(list.data(), &count, 4);  // little-endian on this (x86-64) machine, as FreeCAD writes
  for (int k = 0; k < 6; ++k) {
    const std::uint32_t c = packColour(rgb[k][0], rgb[k][1], rgb[k][2]);
    std::memcpy(list.data() + 4 + 4 * k, &c, 4);
  }
  std::string gui = guiDocumentXml({View{"Box", true, packColour(9, 9, 9)}});
  const std::string prop = "                <Property name=\"DiffuseColor\" type=\"App::PropertyColorList\" status=\"0\">\n"
                           "                    <ColorList file=\"DiffuseColor\"/>\n"
                           "                </Property>\n";
  gui.insert(gui.find("            </Properties>"), prop);
  const std::string path = writeZip("diffuse.FCStd", {{"Document.xml", documentXml({Object::feature("Box", "Box", Placement(), "PartShape.brp")})},
                                                      {"GuiDocument.xml", gui},
                                                      {"PartShape.brp", brepText(box)},
                                                      {"DiffuseColor", list}});
  const Read r = readOk(path);
  ASSERT_EQ(r.reader->GetNumberOfFaces(), 6);
  const std::vector<int> pf = r.pointFaces();
  vtkDataArray* c = r.faces->GetPointData()->GetArray("Colors");
  int bad = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const int f = pf[size_t(i)];
    ASSERT_TRUE(f >= 0 && f < 6);
    for (int k = 0; k < 3; ++k) bad += std::abs(c->GetComponent(i, k) - double(rgb[f][k])) > 1;
  }
  EXPECT_EQ(bad, 0);
}
