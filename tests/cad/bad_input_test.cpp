// Bad input: every case must fail the update with ONE line in GetErrorMessage() that starts with
// the file's path and names the problem, leave both outputs empty, and neither crash nor hang.
// Each case is a test of its own, and each first reads its file in a fresh copy of this
// executable under a time limit (runIsolated, cad_fixtures.h): a crash or a hang inside
// OpenCASCADE fails that test, names its input, and leaves the rest of the run going.
//
// The inputs are made here: truncations of valid files written by OpenCASCADE, bytes from a
// seeded std::mt19937 (the same bytes on every run), hand-written STEP and FreeCAD documents.
#include "fcstd_fixtures.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <cctype>
#include <random>

using namespace cadtest;
using namespace cadtest::fc;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The time a read of one small bad file may take in the isolated copy: such reads take well under
// a second (most a few milliseconds) even on a loaded 2-core machine; 10 s means a hang.
constexpr double kIsolationSeconds = 10;

// The contract of a failed update: the read neither crashes nor hangs (checked in an isolated
// copy first), then, in this process: one line (no CR or LF), "PATH: ...", the problem named
// (each of `words` appears, case-insensitively), both outputs empty.
void expectFailure(const std::string& path, const std::vector<std::string>& words,
                   const std::function<void(vtkWireFurCADReader*)>& configure = {}) {
  if (inIsolatedChild()) {
    readBad(path, configure);
    std::exit(0);
  }
  const IsolatedRun run = runIsolated(kIsolationSeconds);
  ASSERT_TRUE(!run.timedOut && run.signal == 0 && run.exitCode == 0)
      << "reading " << path << " " << run.describe() << "; its output:\n" << run.output;
  const Read r = readBad(path, configure);
  const std::string m = r.reader->GetErrorMessage();
  SCOPED_TRACE("message: " + m);
  ::testing::Test::RecordProperty("message", m);
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_EQ(m.find('\r'), std::string::npos);
  EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << "does not start with the path";
  for (const std::string& w : words) EXPECT_NE(lower(m).find(lower(w)), std::string::npos) << "does not name '" << w << "'";
  EXPECT_EQ(r.faces->GetNumberOfPoints(), 0);
  EXPECT_EQ(r.faces->GetNumberOfCells(), 0);
  EXPECT_EQ(r.edges->GetNumberOfPoints(), 0);
  EXPECT_EQ(r.edges->GetNumberOfCells(), 0);
}

std::string randomBytes(size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::string s(n, '\0');
  for (char& c : s) c = char(g() & 0xff);
  return s;
}

// Printable garbage (what a parser reads furthest into): tokens of STEP / IGES / BREP syntax
// shuffled by a seeded generator.
std::string randomTokens(size_t n, unsigned seed, const std::vector<std::string>& tokens) {
  std::mt19937 g(seed);
  std::string s;
  while (s.size() < n) s += tokens[g() % tokens.size()];
  return s;
}

std::string validStepBox() { return readBytes(writeStep(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "valid_box.step")); }

const char* kEmptyStepHeader =
    "ISO-10303-21;\n"
    "HEADER;\n"
    "FILE_DESCRIPTION(('no shapes'),'2;1');\n"
    "FILE_NAME('noshapes.step','2024-01-01T00:00:00',('wirefur'),(''),'tests','tests','');\n"
    "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\n"
    "ENDSEC;\n";

}  // namespace

// A path that does not exist: "no such file".
TEST(CadBadInput, MissingFile) { expectFailure(tempPath("does_not_exist.step"), {"no such file"}); }

// An empty file: "empty file".
TEST(CadBadInput, EmptyFile) {
  const std::string p = tempPath("empty.step");
  writeBytes(p, "");
  expectFailure(p, {"empty"});
}

// A directory named like a STEP file: "not a regular file".
TEST(CadBadInput, Directory) {
  const std::string p = tempPath("folder.step");
  std::filesystem::create_directory(p);
  expectFailure(p, {"not a regular file"});
}

// An extension the reader does not read: named in the message.
TEST(CadBadInput, UnsupportedExtension) {
  const std::string p = tempPath("model.obj");
  writeBytes(p, "v 0 0 0\n");
  expectFailure(p, {"unsupported extension", ".obj"});
}

// A valid STEP box cut in half (the DATA section ends mid-entity, no ENDSEC, no END-ISO-10303-21):
// the update must fail naming STEP, not output a partial model.
TEST(CadBadInput, TruncatedStep) {
  const std::string full = validStepBox();
  const std::string p = tempPath("truncated.step");
  writeBytes(p, full.substr(0, full.size() / 2));
  expectFailure(p, {"STEP"});
}

// A valid IGES box (BRep mode) cut in half.
TEST(CadBadInput, TruncatedIges) {
  const std::string full = readBytes(writeIges(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "valid_box.igs", 1));
  const std::string p = tempPath("truncated.igs");
  writeBytes(p, full.substr(0, full.size() / 2));
  expectFailure(p, {"IGES"});
}

// The same IGES box (BRep mode, IGESControl_Writer("MM", 1), 13365 bytes of 165 lines) cut at
// 70% of its bytes: the Directory section is whole, the Parameter section is cut, so entities
// point at parameter records that are not there.
// FOUND: SIGSEGV inside OpenCASCADE, IGESSolid_Face::NbLoops() called from
// IGESToBRep_BRepEntity::TransferFace, under IGESCAFControl_Reader::Transfer (wf_cad_read.cxx).
// Cutting after any of the lines 110..158 (except 121) crashes the same way.
TEST(CadBadInput, TruncatedIgesBrepModeAt70Percent) {
  const std::string full = readBytes(writeIges(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "valid_box70.igs", 1));
  const std::string p = tempPath("truncated70.igs");
  writeBytes(p, full.substr(0, full.size() * 70 / 100));
  expectFailure(p, {"IGES"});
}

// An IGES box in Faces mode (IGESControl_Writer("MM", 0), 153 lines) cut after 3/4 of its lines:
// no Terminate record, Parameter section cut. The documented contract is that a truncated file
// fails the update.
// FOUND: it does not: the reader outputs the faces that survived (1 of 6 faces, 2 triangles,
// without error or warning). IGES's Terminate ('T') record gives the number of records of each
// section, so the truncation is detectable.
TEST(CadBadInput, TruncatedIgesFacesModeIsNotAPartialModel) {
  const std::string full = readBytes(writeIges(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "valid_box_faces.igs", 0));
  std::vector<std::string> lines;
  std::istringstream in(full);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::string cut;
  for (size_t i = 0; i < lines.size() * 3 / 4; ++i) cut += lines[i] + "\n";
  const std::string p = tempPath("truncated_faces.igs");
  writeBytes(p, cut);
  expectFailure(p, {"IGES"});
}

// A valid BREP sphere cut in half.
TEST(CadBadInput, TruncatedBrep) {
  const std::string full = brepText(BRepPrimAPI_MakeSphere(3).Shape());
  const std::string p = tempPath("truncated.brep");
  writeBytes(p, full.substr(0, full.size() / 2));
  expectFailure(p, {"BREP"});
}

// A BREP whose TShapes section announces one shape and ends after the shape's type ("Ve"): the
// smallest truncated BREP text (12 lines).
// FOUND: the update never returns: OpenCASCADE's BRepTools::Read loops forever at the end of the
// stream (BRepTools_ShapeSet::ReadGeometry; 100% CPU, constant memory, > 120 s observed). A valid
// BREP of a sphere cut after line 18, 19, 20, 25, ... of its 71 lines does the same.
const char* kTruncatedBrep =
    "\nCASCADE Topology V3, (c) Open Cascade\nLocations 0\nCurve2ds 0\nCurves 0\nPolygon3D 0\n"
    "PolygonOnTriangulations 0\nSurfaces 0\nTriangulations 0\n\nTShapes 1\nVe\n";
TEST(CadBadInput, TruncatedBrepInTShapes) {
  const std::string p = tempPath("truncated_tshapes.brep");
  writeBytes(p, kTruncatedBrep);
  expectFailure(p, {"BREP"});
}

// The same truncated BREP text as the shape file of a FreeCAD document: the same hang.
TEST(CadBadInput, FcstdTruncatedShapeFile) {
  const std::string p = writeFcstd("truncated_shape.FCStd", {Object::feature("Box", "Box", Placement(), "PartShape.brp")},
                                   std::vector<View>{View{"Box", true, std::nullopt}}, {{"PartShape.brp", kTruncatedBrep}});
  expectFailure(p, {"PartShape.brp"});
}

// Random bytes under each extension: refused by the format checks, naming the format.
TEST(CadBadInput, RandomBytesStep) {
  const std::string p = tempPath("random.step");
  writeBytes(p, randomBytes(8192, 1));
  expectFailure(p, {"not a STEP file"});
}
TEST(CadBadInput, RandomBytesIges) {
  const std::string p = tempPath("random.igs");
  writeBytes(p, randomBytes(8192, 2));
  expectFailure(p, {"not an IGES file"});
}
TEST(CadBadInput, RandomBytesBrep) {
  const std::string p = tempPath("random.brep");
  writeBytes(p, randomBytes(8192, 3));
  expectFailure(p, {"not a BREP file"});
}
TEST(CadBadInput, RandomBytesFcstd) {
  const std::string p = tempPath("random.FCStd");
  writeBytes(p, randomBytes(8192, 4));
  expectFailure(p, {"zip"});
}

// A PNG (signature, IHDR chunk, then bytes) named .step.
TEST(CadBadInput, PngNamedStep) {
  const char header[] = "\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x10\0\0\0\x10\x08\x02\0\0\0";
  std::string png(header, sizeof header - 1);  // 29 bytes: the literal, without its terminator
  png += randomBytes(1000, 5);
  const std::string p = tempPath("picture.step");
  writeBytes(p, png);
  expectFailure(p, {"not a STEP file"});
}

// A well-formed STEP file whose DATA section holds no shape (one CARTESIAN_POINT): "no shapes"
// or OpenCASCADE's "no entities" to transfer; either way the message names STEP.
TEST(CadBadInput, StepWithoutShapes) {
  const std::string p = tempPath("noshapes.step");
  writeBytes(p, std::string(kEmptyStepHeader) + "DATA;\n#1 = CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\nEND-ISO-10303-21;\n");
  expectFailure(p, {"STEP"});
}

// The same with an empty DATA section.
TEST(CadBadInput, StepWithEmptyData) {
  const std::string p = tempPath("emptydata.step");
  writeBytes(p, std::string(kEmptyStepHeader) + "DATA;\nENDSEC;\nEND-ISO-10303-21;\n");
  expectFailure(p, {"STEP"});
}

// A STEP header followed by shuffled STEP tokens: OpenCASCADE's STEP parser must reject it
// without crashing.
TEST(CadBadInput, StepHeaderThenGarbage) {
  const std::string p = tempPath("garbage_body.step");
  writeBytes(p, std::string(kEmptyStepHeader) + "DATA;\n" +
                    randomTokens(6000, 6, {"#1", "#2", "=", "(", ")", ",", ";", "'x'", "CARTESIAN_POINT", "ADVANCED_FACE",
                                           "1.5E3", ".T.", "$", "*", "\n", "PRODUCT", "#99999999999"}));
  expectFailure(p, {"STEP"});
}

// A valid IGES file's Start and Global sections followed by shuffled IGES records: the parser
// must reject it (or find nothing) without crashing.
TEST(CadBadInput, IgesHeaderThenGarbage) {
  const std::string full = readBytes(writeIges(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), "valid_head.igs", 1));
  // Keep the lines up to the end of the Global section (column 73 = 'G').
  std::string head;
  std::istringstream in(full);
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() >= 73 && line[72] != 'S' && line[72] != 'G') break;
    head += line + "\n";
  }
  ASSERT_FALSE(head.empty());
  std::mt19937 g(7);
  std::string body;
  for (int i = 0; i < 120; ++i) {
    std::string rec = randomTokens(72, unsigned(g()), {"      ", "128", "144", "186", "1,", "0.5,", "-3", ";", "D", "P"});
    rec.resize(72, ' ');
    body += rec + (i % 2 ? "P" : "D") + std::string(7 - std::to_string(i + 1).size(), ' ') + std::to_string(i + 1) + "\n";
  }
  const std::string p = tempPath("garbage_body.igs");
  writeBytes(p, head + body);
  expectFailure(p, {"IGES"});
}

// A zip archive (valid) without Document.xml: "Document.xml" named.
TEST(CadBadInput, ZipWithoutDocumentXml) {
  const std::string p = writeZip("nodocument.FCStd", {{"readme.txt", "not a FreeCAD document"}});
  expectFailure(p, {"Document.xml"});
}

// Document.xml that is not well-formed XML: the entry and a line number named.
TEST(CadBadInput, MalformedDocumentXml) {
  const std::string p = writeZip("badxml.FCStd", {{"Document.xml", "<?xml version='1.0'?>\n<Document>\n<Objects>\n</Document>\n"}});
  expectFailure(p, {"Document.xml:"});
}

// A FreeCAD document whose only object names a shape file that is not in the archive.
TEST(CadBadInput, FcstdShapeFileMissing) {
  const std::string p = writeFcstd("noshapefile.FCStd", {Object::feature("Box", "Box", Placement(), "PartShape.brp")},
                                   std::vector<View>{View{"Box", true, std::nullopt}}, {});
  expectFailure(p, {"PartShape.brp", "not in the archive"});
}

// A FreeCAD document whose only object's shape file is garbage after a BREP header.
TEST(CadBadInput, FcstdShapeFileCorrupt) {
  const std::string p = writeFcstd("badshapefile.FCStd", {Object::feature("Box", "Box", Placement(), "PartShape.brp")},
                                   std::vector<View>{View{"Box", true, std::nullopt}},
                                   {{"PartShape.brp", "DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\n" +
                                                          randomBytes(3000, 8)}});
  expectFailure(p, {"PartShape.brp"});
}

// A FreeCAD document with every object hidden: "hidden".
TEST(CadBadInput, FcstdAllHidden) {
  const std::string p = writeFcstd("allhidden.FCStd",
                                   {Object::feature("A", "A", Placement(), "PartShape.brp"),
                                    Object::feature("B", "B", Placement(), "PartShape1.brp")},
                                   std::vector<View>{View{"A", false, std::nullopt}, View{"B", false, std::nullopt}},
                                   {{"PartShape.brp", brepText(BRepPrimAPI_MakeBox(1, 1, 1).Shape())},
                                    {"PartShape1.brp", brepText(BRepPrimAPI_MakeBox(1, 1, 1).Shape())}});
  expectFailure(p, {"hidden"});
}

// A FreeCAD document whose only object is visible and has an EMPTY shape file (FreeCAD writes an
// empty file for an empty shape). The update fails (nothing to draw), and the message must give
// the right reason: the object is not hidden.
// FOUND: the message says "every object with a shape is hidden (1 of them)": wf_cad_fcstd.cxx
// skips empty shape files (`if (bytes.empty()) continue;`) and then reports any empty model as
// "hidden".
TEST(CadBadInput, FcstdOnlyEmptyShapeIsNotCalledHidden) {
  const std::string p = writeFcstd("emptyshape.FCStd", {Object::feature("Box", "Box", Placement(), "PartShape.brp")},
                                   std::vector<View>{View{"Box", true, std::nullopt}}, {{"PartShape.brp", ""}});
  expectFailure(p, {"empty"});
  EXPECT_EQ(lower(readBad(p).reader->GetErrorMessage()).find("hidden"), std::string::npos);
}

// A FreeCAD document with no object that has a shape.
TEST(CadBadInput, FcstdNoShapes) {
  const std::string p = writeFcstd("noshapes.FCStd", {Object::container("Part", "Part", Placement(), {})},
                                   std::vector<View>{View{"Part", true, std::nullopt}}, {});
  expectFailure(p, {"no object with a shape"});
}

// A BREP holding one vertex: no faces, no edges: "no faces and no edges".
TEST(CadBadInput, BrepVertexOnly) {
  const std::string p = writeBrep(BRepBuilderAPI_MakeVertex(gp_Pnt(1, 2, 3)).Shape(), "vertex.brep");
  expectFailure(p, {"no faces and no edges"});
}

// A BREP holding an empty compound: no geometry at all.
TEST(CadBadInput, BrepEmptyCompound) {
  TopoDS_Compound c;
  BRep_Builder().MakeCompound(c);
  const std::string p = writeBrep(c, "empty_compound.brep");
  expectFailure(p, {"no geometry"});
}

// A BREP holding an unbounded face (a plane without a boundary) next to a box: the model's
// bounds are not finite, which the reader refuses ("not finite") rather than meshing with an
// infinite deflection.
TEST(CadBadInput, BrepInfinitePlane) {
  TopoDS_Compound c;
  BRep_Builder b;
  b.MakeCompound(c);
  b.Add(c, BRepPrimAPI_MakeBox(1, 1, 1).Shape());
  b.Add(c, BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1))).Shape());
  const std::string p = writeBrep(c, "infinite.brep");
  expectFailure(p, {"not finite"});
}

// A BREP text header followed by random bytes.
TEST(CadBadInput, BrepHeaderThenGarbage) {
  const std::string p = tempPath("garbage.brep");
  writeBytes(p, "DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\n" + randomBytes(4000, 9));
  expectFailure(p, {"BREP"});
}

// A BREP text header followed by shuffled BREP tokens (numbers, section names): read further
// into OpenCASCADE's BREP parser than random bytes.
TEST(CadBadInput, BrepHeaderThenTokens) {
  const std::string p = tempPath("tokens.brep");
  writeBytes(p, "DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\n" +
                    randomTokens(4000, 10, {"Locations 1\n", "Curves 2\n", "Surfaces 1\n", "TShapes 3\n", "1 ", "0 ", "-1 ",
                                            "2.5 ", "1e308 ", "Ve\n", "Fa\n", "So\n", "+1 ", "*\n", "99999999 "}));
  expectFailure(p, {"BREP"});
}

// A reader that read a good file and then a bad one: the second update's outputs are empty and
// its counts are reset (nothing of the first file left over).
TEST(CadBadInput, ReuseAfterGoodFile) {
  const std::string good = writeBrep(BRepPrimAPI_MakeBox(1, 2, 3).Shape(), "good.brep");
  const std::string bad = tempPath("bad_after_good.step");
  writeBytes(bad, randomBytes(100, 11));
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(good.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorMessage(), "");
  ASSERT_GT(reader->GetOutput(0)->GetNumberOfCells(), 0);
  ASSERT_EQ(reader->GetNumberOfParts(), 1);
  reader->SetFileName(bad.c_str());
  vtkObject::GlobalWarningDisplayOff();
  reader->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_EQ(reader->GetErrorMessage().rfind(bad + ": ", 0), 0u) << reader->GetErrorMessage();
  EXPECT_EQ(reader->GetOutput(0)->GetNumberOfPoints(), 0);
  EXPECT_EQ(reader->GetOutput(0)->GetNumberOfCells(), 0);
  EXPECT_EQ(reader->GetOutput(1)->GetNumberOfCells(), 0);
  EXPECT_EQ(reader->GetNumberOfParts(), 0);
  EXPECT_EQ(reader->GetNumberOfFaces(), 0);
}

// The triangle budget: a sphere meshed finely with MaximumTriangles 10 fails with a message that
// names the count and the limit, instead of outputting.
TEST(CadBadInput, TriangleBudget) {
  const std::string p = writeBrep(BRepPrimAPI_MakeSphere(3).Shape(), "budget.brep");
  expectFailure(p, {"over the limit of 10"}, [](vtkWireFurCADReader* r) { r->SetMaximumTriangles(10); });
}
