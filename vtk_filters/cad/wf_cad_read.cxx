// STEP and IGES through XCAF (names, colours, assemblies, locations), BREP, and the capture of
// OpenCASCADE's messages.
#include "wf_cad_model.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BinTools.hxx>
#include <Bnd_Box.hxx>
#include <NCollection_DataMap.hxx>
#include <TopTools_ShapeMapHasher.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Gravity.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_Label.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

namespace wfcad {

// ---------------------------------------------------------------------------------------------
// Messages: one printer, installed once in place of OpenCASCADE's console printer, hands each
// message to the capture active on this thread (and drops it when there is none).

namespace {

struct CaptureState {
  std::string firstFail, firstAlarm;
};
thread_local CaptureState* activeCapture = nullptr;

class CapturePrinter : public Message_Printer {
 protected:
  void send(const TCollection_AsciiString& text, const Message_Gravity gravity) const override {
    CaptureState* c = activeCapture;
    if (!c) return;
    std::string line = text.ToCString();
    for (char& ch : line)
      if (ch == '\n' || ch == '\r' || ch == '\t') ch = ' ';
    // OpenCASCADE frames some messages in asterisks ("**** ERR StepFile : ... ****").
    while (!line.empty() && (line.back() == ' ' || line.back() == '*')) line.pop_back();
    while (!line.empty() && (line.front() == ' ' || line.front() == '*')) line.erase(line.begin());
    if (line.empty()) return;
    if (gravity >= Message_Fail && c->firstFail.empty()) c->firstFail = line;
    else if (gravity == Message_Alarm && c->firstAlarm.empty()) c->firstAlarm = line;
  }
};

void installPrinter() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    m->ChangePrinters().Clear();
    Handle(CapturePrinter) p = new CapturePrinter();
    p->SetTraceLevel(Message_Trace);
    m->AddPrinter(p);
  });
}

}  // namespace

struct MessageCaptureImpl {};

MessageCapture::MessageCapture() {
  installPrinter();
  activeCapture = new CaptureState();
}
MessageCapture::~MessageCapture() {
  delete activeCapture;
  activeCapture = nullptr;
}
std::string MessageCapture::firstFailure() const {
  if (!activeCapture) return {};
  return !activeCapture->firstFail.empty() ? activeCapture->firstFail : activeCapture->firstAlarm;
}

// ---------------------------------------------------------------------------------------------

namespace {

std::string failureText(const Standard_Failure& f) {
  const char* m = f.GetMessageString();
  std::string s = (m && *m) ? m : f.DynamicType()->Name();
  for (char& ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

std::string headOf(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(s.data(), std::streamsize(n));
  s.resize(size_t(in.gcount()));
  return s;
}

std::string nameOf(const TDF_Label& label) {
  Handle(TDataStd_Name) n;
  if (label.IsNull() || !label.FindAttribute(TDataStd_Name::GetID(), n)) return {};
  return TCollection_AsciiString(n->Get()).ToCString();  // UTF-8
}

std::optional<Quantity_Color> colourOf(const Handle(XCAFDoc_ColorTool)& ct, const TDF_Label& label) {
  Quantity_Color c;
  if (label.IsNull()) return std::nullopt;
  if (ct->GetColor(label, XCAFDoc_ColorSurf, c) || ct->GetColor(label, XCAFDoc_ColorGen, c)) return c;
  return std::nullopt;
}

struct XcafWalker {
  Handle(XCAFDoc_ShapeTool) shapes;
  Handle(XCAFDoc_ColorTool) colours;
  Model* model = nullptr;

  void walk(const TDF_Label& label, const TopLoc_Location& parent, std::optional<Quantity_Color> inherited, int depth) {
    if (depth > 64) throw CadError("assembly nested deeper than 64 levels (a cycle?)");
    TDF_Label ref = label;
    TopLoc_Location here = parent;
    std::optional<Quantity_Color> colour = inherited;
    if (XCAFDoc_ShapeTool::IsReference(label)) {
      if (!XCAFDoc_ShapeTool::GetReferredShape(label, ref)) return;
      here = parent * XCAFDoc_ShapeTool::GetLocation(label);
      if (auto c = colourOf(colours, ref)) colour = c;
      if (auto c = colourOf(colours, label)) colour = c;  // the instance's colour wins
    } else if (auto c = colourOf(colours, ref)) {
      colour = c;
    }
    if (XCAFDoc_ShapeTool::IsAssembly(ref)) {
      TDF_LabelSequence components;
      XCAFDoc_ShapeTool::GetComponents(ref, components);
      for (Standard_Integer i = 1; i <= components.Length(); ++i) walk(components.Value(i), here, colour, depth + 1);
      return;
    }
    TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(ref);
    if (shape.IsNull()) return;
    Part p;
    p.name = nameOf(ref);
    if (p.name.empty()) p.name = nameOf(label);
    p.shape = shape;
    p.placement = here;
    p.colour = colour;
    bool anyFace = false;
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
      TDF_Label sub;
      std::optional<Quantity_Color> c;
      if (shapes->FindSubShape(ref, e.Current(), sub)) c = colourOf(colours, sub);
      anyFace = anyFace || c.has_value();
      p.faceColours.push_back(c);
    }
    if (!anyFace) p.faceColours.clear();
    model->parts.push_back(std::move(p));
  }
};

// IGES files are often written face by face, without shared topology: every face has its own
// edges, so an edge between two faces would be drawn twice and shared points would not be
// shared. Sewing (tolerance 1e-5 of the part's size) joins coincident edges; face colours follow
// their faces through it.
void sew(Part& p) {
  int faces = 0;
  for (TopExp_Explorer e(p.shape, TopAbs_FACE); e.More(); e.Next()) ++faces;
  if (faces < 2) return;
  Bnd_Box box;
  BRepBndLib::Add(p.shape, box, Standard_False);
  if (box.IsVoid()) return;
  const double size = std::sqrt(box.SquareExtent());
  if (!(size > 0) || !std::isfinite(size)) return;
  try {
    BRepBuilderAPI_Sewing sewing(1e-5 * size);
    sewing.Add(p.shape);
    sewing.Perform();
    const TopoDS_Shape sewn = sewing.SewedShape();
    if (sewn.IsNull()) return;
    std::vector<std::optional<Quantity_Color>> colours;
    if (!p.faceColours.empty()) {
      NCollection_DataMap<TopoDS_Shape, Quantity_Color, TopTools_ShapeMapHasher> byFace;
      int k = 0;
      for (TopExp_Explorer e(p.shape, TopAbs_FACE); e.More(); e.Next(), ++k)
        if (size_t(k) < p.faceColours.size() && p.faceColours[size_t(k)]) {
          // Modified() answers only for the shape given to Add; a face's sewn face is its
          // modified sub-shape.
          const TopoDS_Shape f = sewing.IsModifiedSubShape(e.Current()) ? sewing.ModifiedSubShape(e.Current()) : e.Current();
          byFace.Bind(f, *p.faceColours[size_t(k)]);
        }
      for (TopExp_Explorer e(sewn, TopAbs_FACE); e.More(); e.Next()) {
        const Quantity_Color* c = byFace.Seek(e.Current());
        colours.push_back(c ? std::optional<Quantity_Color>(*c) : std::nullopt);
      }
    }
    p.shape = sewn;
    p.faceColours = colours;
  } catch (const Standard_Failure&) {
    // Left unsewn: drawn all the same, with doubled edges.
  }
}

}  // namespace

Model readStepOrIges(const std::string& path, bool iges) {
  const char* format = iges ? "IGES" : "STEP";
  const std::string head = headOf(path, 4096);
  if (!iges) {
    // ISO 10303-21 (a STEP file) opens with its magic, after optional white space.
    size_t i = 0;
    while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
    if (head.compare(i, 12, "ISO-10303-21") != 0) throw CadError("not a STEP file (no ISO-10303-21 header)");
  } else {
    // IGES: fixed 80-column records; the first is a Start (S) or flag (F) record.
    const size_t eol = head.find_first_of("\r\n");
    const std::string first = head.substr(0, eol);
    if (first.size() < 73 || (first[72] != 'S' && first[72] != 'F' && first[72] != 'G'))
      throw CadError("not an IGES file (no Start record in column 73 of the first line)");
    // The last record is the Terminate record (T in column 73). Without it the file was cut
    // short, and OpenCASCADE would read a part of the model without a word (or crash).
    std::ifstream in(path, std::ios::binary);
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    const std::streamoff from = std::max<std::streamoff>(0, size - 400);
    std::string tail(size_t(size - from), '\0');
    in.seekg(from);
    in.read(tail.data(), std::streamsize(tail.size()));
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r' || tail.back() == ' ' || tail.back() == '\0')) tail.pop_back();
    const size_t lineStart = tail.find_last_of("\r\n");
    const std::string last = lineStart == std::string::npos ? tail : tail.substr(lineStart + 1);
    if (last.size() < 73 || last[72] != 'T')
      throw CadError("IGES file is truncated (its last line is not a Terminate record, T in column 73)");
  }
  MessageCapture capture;
  Model model;
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  Handle(TDocStd_Document) doc;
  app->NewDocument("MDTV-XCAF", doc);
  try {
    bool transferred = false;
    IFSelect_ReturnStatus status = IFSelect_RetVoid;
    if (iges) {
      IGESCAFControl_Reader r;
      r.SetColorMode(true);
      r.SetNameMode(true);
      r.SetLayerMode(false);
      status = r.ReadFile(path.c_str());
      if (status == IFSelect_RetDone) transferred = r.Transfer(doc);
    } else {
      STEPCAFControl_Reader r;
      r.SetColorMode(true);
      r.SetNameMode(true);
      r.SetLayerMode(false);
      r.SetPropsMode(false);
      r.SetGDTMode(false);
      r.SetMatMode(false);
      r.SetViewMode(false);
      status = r.ReadFile(path.c_str());
      if (status == IFSelect_RetDone) transferred = r.Transfer(doc);
    }
    const std::string why = capture.firstFailure();
    if (status != IFSelect_RetDone) {
      std::string what = status == IFSelect_RetVoid ? "no entities" : status == IFSelect_RetError ? "unreadable" : "parse failed";
      throw CadError(std::string(format) + " " + what + (why.empty() ? std::string() : ": " + why));
    }
    if (!transferred) throw CadError(std::string(format) + " entities could not be turned into shapes" + (why.empty() ? std::string() : ": " + why));
    XcafWalker w;
    w.shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    w.colours = XCAFDoc_DocumentTool::ColorTool(doc->Main());
    w.model = &model;
    TDF_LabelSequence roots;
    w.shapes->GetFreeShapes(roots);
    for (Standard_Integer i = 1; i <= roots.Length(); ++i) w.walk(roots.Value(i), TopLoc_Location(), std::nullopt, 0);
  } catch (const Standard_Failure& f) {
    app->Close(doc);
    throw CadError(std::string(format) + " reader failed: " + failureText(f));
  } catch (...) {
    app->Close(doc);
    throw;
  }
  app->Close(doc);
  if (model.parts.empty()) throw CadError(std::string(format) + " file has no shapes");
  if (iges)
    for (Part& p : model.parts) sew(p);
  return model;
}

TopoDS_Shape brepFromMemory(const std::string& bytes, bool binary, const std::string& entity) {
  MessageCapture capture;
  TopoDS_Shape shape;
  try {
    std::istringstream in(bytes, std::ios::binary);
    // OpenCASCADE's BREP parsers do not check the stream: a token that is not a number leaves it
    // failed, and a loop bound read from it runs on for billions of turns (a hang found by
    // fuzzing). A failed extraction throws instead.
    in.exceptions(std::ios::failbit | std::ios::badbit);
    if (binary) {
      BinTools::Read(shape, in);
    } else {
      BRep_Builder b;
      BRepTools::Read(shape, in, b);
    }
  } catch (const Standard_Failure& f) {
    throw CadError(entity + ": corrupt BREP: " + failureText(f));
  } catch (const std::ios_base::failure&) {
    throw CadError(entity + ": corrupt BREP: a value is missing or not a number");
  }
  if (shape.IsNull()) {
    const std::string why = capture.firstFailure();
    throw CadError(entity + ": BREP holds no shape" + (why.empty() ? std::string() : " (" + why + ")"));
  }
  return shape;
}

bool looksLikeBrep(const std::string& head, bool& binary) {
  // BinTools writes "\nOpen CASCADE Topology V<n>, (c) ..." first; BRepTools a text header
  // "CASCADE Topology V<n>, (c) ..." (after an optional "DBRep_DrawableShape" line).
  size_t i = 0;
  while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
  binary = head.compare(i, 23, "Open CASCADE Topology V") == 0;
  return binary || head.find("CASCADE Topology V") != std::string::npos;
}

Model readBrep(const std::string& path) {
  const std::string head = headOf(path, 256);
  bool binary = false;
  if (!looksLikeBrep(head, binary)) throw CadError("not a BREP file (no 'CASCADE Topology' header)");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  Part p;
  p.name = std::filesystem::path(path).stem().string();
  p.shape = brepFromMemory(all.str(), binary, "shape");
  Model m;
  m.parts.push_back(std::move(p));
  return m;
}

}  // namespace wfcad
