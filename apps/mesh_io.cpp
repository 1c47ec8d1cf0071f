#include "mesh_io.h"

#include "cli.h"

#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkAlgorithm.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkAbstractArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <string>

namespace wfapp {

namespace {

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

// Collects the first error VTK reports instead of letting it print a multi-line message.
class ErrorCatcher : public vtkCommand {
 public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (message.empty() && data) {
      message = static_cast<const char*>(data);
      // Keep the last line, which is the reader's own words.
      while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
      const size_t nl = message.rfind('\n');
      if (nl != std::string::npos) message = message.substr(nl + 1);
      // Drop VTK's "vtkSomeReader (0x...): " prefix: the reader's words are what matter.
      const size_t tag = message.find("): ");
      if (message.rfind("vtk", 0) == 0 && tag != std::string::npos && tag < 64) message = message.substr(tag + 3);
    }
  }
  std::string message;
};

// VTK's PLY reader trusts the header: a short vertex line or a body shorter than the header
// declares makes it read past its buffers. Before handing a file to it, check that the body can
// hold what the header promises: for binary files, at least the declared counts times the fixed
// sizes (a list counts its length field only); for ASCII, enough lines with enough numbers.
void checkPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw UsageError(path + ": not a PLY file (no 'ply' magic)");
  struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::uint64_t fixedBytes = 0;  // scalars, and each list's length field
    int scalars = 0, lists = 0;
  };
  std::vector<Element> elements;
  auto typeSize = [&](const std::string& t) -> int {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    throw UsageError(path + ": PLY header: unknown property type '" + t + "'");
  };
  int lineNo = 1;
  bool ended = false;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream w(line);
    std::string key;
    w >> key;
    if (key == "format") w >> format;
    else if (key == "element") {
      Element e;
      long long n = -1;
      if (!(w >> e.name >> n) || n < 0 || n > 2000000000LL)
        throw UsageError(path + ":" + std::to_string(lineNo) + ": PLY header: bad element line");
      e.count = std::uint64_t(n);
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) throw UsageError(path + ":" + std::to_string(lineNo) + ": PLY header: property before any element");
      std::string t;
      w >> t;
      if (t == "list") {
        std::string countType, itemType;
        w >> countType >> itemType;
        elements.back().fixedBytes += std::uint64_t(typeSize(countType));
        typeSize(itemType);
        ++elements.back().lists;
      } else {
        elements.back().fixedBytes += std::uint64_t(typeSize(t));
        ++elements.back().scalars;
      }
    } else if (key == "end_header") {
      ended = true;
      break;
    }
  }
  if (!ended) throw UsageError(path + ": PLY header has no end_header");
  if (format == "binary_little_endian" || format == "binary_big_endian") {
    const std::uint64_t header = std::uint64_t(in.tellg());
    std::uint64_t need = 0;
    for (const Element& e : elements) need += e.count * e.fixedBytes;
    const std::uint64_t size = std::filesystem::file_size(path);
    if (size < header + need)
      throw UsageError(path + ": PLY body is " + std::to_string(size - header) + " bytes, the header declares at least " +
                       std::to_string(need));
  } else if (format == "ascii") {
    for (const Element& e : elements)
      for (std::uint64_t i = 0; i < e.count; ++i) {
        ++lineNo;
        if (!std::getline(in, line))
          throw UsageError(path + ": PLY body ends before " + std::to_string(e.count) + " " + e.name + " lines");
        std::istringstream w(line);
        int tokens = 0;
        std::string tok;
        long long listLength = 0;
        for (int k = 0; k < e.scalars + e.lists && w >> tok; ++k) ++tokens;
        if (e.lists > 0) listLength = std::atoll(tok.c_str());  // the last list's length (one list per element in practice)
        int rest = 0;
        while (w >> tok) ++rest;
        if (tokens < e.scalars + e.lists || (e.lists > 0 && rest < listLength))
          throw UsageError(path + ":" + std::to_string(lineNo) + ": PLY " + e.name + " line has too few values");
      }
  } else {
    throw UsageError(path + ": PLY header: unknown format '" + format + "'");
  }
}

// A binary STL is 84 bytes and 50 per triangle; VTK reads a truncated one without a word.
void checkStl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, 84);
  const std::uint64_t size = std::filesystem::file_size(path);
  if (in.gcount() == 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, 4);
    if (84 + 50 * std::uint64_t(n) == size) return;  // a well-formed binary STL (even if it says "solid")
  }
  if (std::string(head, std::min<std::streamsize>(in.gcount(), 5)) == "solid") return;  // ASCII: VTK parses it
  if (in.gcount() < 84) throw UsageError(path + ": too short for an STL file");
  std::uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  throw UsageError(path + ": binary STL declares " + std::to_string(n) + " triangles (" + std::to_string(84 + 50 * std::uint64_t(n)) +
                   " bytes) but the file has " + std::to_string(size));
}

// Every cell must name points that exist: VTK's filters index without checking.
void checkCells(const std::string& path, vtkPolyData* pd) {
  const vtkIdType np = pd->GetNumberOfPoints();
  vtkCellArray* arrays[4] = {pd->GetVerts(), pd->GetLines(), pd->GetPolys(), pd->GetStrips()};
  vtkNew<vtkIdList> ids;
  vtkIdType cell = 0;
  for (vtkCellArray* a : arrays) {
    if (!a) continue;
    for (a->InitTraversal(); a->GetNextCell(ids); ++cell)
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        if (ids->GetId(k) < 0 || ids->GetId(k) >= np)
          throw UsageError(path + ": cell " + std::to_string(cell) + " refers to point " + std::to_string(ids->GetId(k)) +
                           " of " + std::to_string(np));
  }
}

// Point and cell data arrays of the wrong length are dropped: VTK's filters copy attributes by
// index without checking (vtkOBJReader, for one, leaves a file's lines' points without normals
// and texture coordinates in arrays shorter than the points; vtkTriangleFilter then reads past
// their end). The geometry is kept; only the arrays that do not fit go.
void dropMisfitArrays(vtkPolyData* pd) {
  const vtkIdType np = pd->GetNumberOfPoints(), nc = pd->GetNumberOfCells();
  for (auto [data, n] : {std::pair<vtkDataSetAttributes*, vtkIdType>{pd->GetPointData(), np}, {pd->GetCellData(), nc}})
    for (int i = data->GetNumberOfArrays() - 1; i >= 0; --i)
      if (vtkAbstractArray* a = data->GetAbstractArray(i); a && a->GetNumberOfTuples() != n) data->RemoveArray(i);
}

}  // namespace

bool isGeometryFile(const std::string& path) {
  const std::string e = extension(path);
  return e == ".vtp" || e == ".vtk" || e == ".stl" || e == ".obj" || e == ".ply";
}

LoadedGeometry readGeometry(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw UsageError(path + ": no such file");
  const std::string e = extension(path);
  vtkSmartPointer<vtkAlgorithm> reader;
  if (e == ".vtp") {
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".vtk") {
    auto r = vtkSmartPointer<vtkPolyDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".stl") {
    checkStl(path);
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".obj") {
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".ply") {
    checkPly(path);
    auto r = vtkSmartPointer<vtkPLYReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else {
    throw UsageError(path + ": unsupported file type '" + e + "' (expected .vtp .vtk .stl .obj .ply)");
  }
  vtkNew<ErrorCatcher> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->AddObserver(vtkCommand::WarningEvent, catcher);
  reader->Update();
  vtkPolyData* pd = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!catcher->message.empty()) throw UsageError(path + ": " + catcher->message);
  if (!pd || pd->GetNumberOfPoints() == 0)
    throw UsageError(path + ": no points (not a polygonal data file, or empty)");
  checkCells(path, pd);
  dropMisfitArrays(pd);

  LoadedGeometry g;
  // Lines and polylines.
  vtkPoints* pts = pd->GetPoints();
  vtkUnsignedCharArray* rgb = vtkUnsignedCharArray::SafeDownCast(pd->GetPointData()->GetScalars());
  // Point colours (uchar RGB / RGBA, or one grey value) multiply the shading.
  const bool colours = rgb && rgb->GetNumberOfComponents() >= 1;
  auto colourOf = [&](vtkIdType id) {
    if (rgb->GetNumberOfComponents() < 3) return glm::vec3(float(rgb->GetComponent(id, 0)) / 255.0f);
    return glm::vec3(rgb->GetComponent(id, 0), rgb->GetComponent(id, 1), rgb->GetComponent(id, 2)) / 255.0f;
  };
  if (pd->GetNumberOfLines() > 0) {
    vtkCellArray* lines = pd->GetLines();
    vtkNew<vtkIdList> ids;
    g.lines.starts.push_back(0);
    for (lines->InitTraversal(); lines->GetNextCell(ids);) {
      if (ids->GetNumberOfIds() < 2) continue;
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
        double p[3];
        pts->GetPoint(ids->GetId(k), p);
        g.lines.points.emplace_back(p[0], p[1], p[2]);
        if (colours) g.lines.colours.push_back(colourOf(ids->GetId(k)));
      }
      g.lines.starts.push_back(std::uint32_t(g.lines.points.size()));
    }
    if (g.lines.points.empty()) g.lines.starts.clear();
  }
  // Polygons and strips: triangulated, with point normals (VTK's own, feature edges split).
  if (pd->GetNumberOfPolys() > 0 || pd->GetNumberOfStrips() > 0) {
    vtkNew<vtkTriangleFilter> tri;
    tri->SetInputData(pd);
    tri->PassLinesOff();
    tri->PassVertsOff();
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputConnection(tri->GetOutputPort());
    normals->SetFeatureAngle(60.0);
    normals->ConsistencyOn();
    normals->Update();
    vtkPolyData* t = normals->GetOutput();
    vtkDataArray* n = t->GetPointData()->GetNormals();
    vtkUnsignedCharArray* trgb = vtkUnsignedCharArray::SafeDownCast(t->GetPointData()->GetScalars());
    const bool tcol = trgb && trgb->GetNumberOfComponents() >= 3;
    for (vtkIdType i = 0; i < t->GetNumberOfPoints(); ++i) {
      double p[3];
      t->GetPoint(i, p);
      g.mesh.positions.emplace_back(p[0], p[1], p[2]);
      if (n) {
        double v[3];
        n->GetTuple(i, v);
        g.mesh.normals.emplace_back(v[0], v[1], v[2]);
      }
      if (tcol)
        g.mesh.colours.emplace_back(glm::vec3(trgb->GetComponent(i, 0), trgb->GetComponent(i, 1), trgb->GetComponent(i, 2)) / 255.0f);
    }
    vtkCellArray* polys = t->GetPolys();
    vtkNew<vtkIdList> ids;
    for (polys->InitTraversal(); polys->GetNextCell(ids);)
      if (ids->GetNumberOfIds() == 3)
        g.mesh.triangles.emplace_back(std::uint32_t(ids->GetId(0)), std::uint32_t(ids->GetId(1)), std::uint32_t(ids->GetId(2)));
  }
  if (g.mesh.triangles.empty() && g.lines.points.empty())
    throw UsageError(path + ": no polygons or lines to draw");
  return g;
}

void writePolylinesVtp(const wf::PolylineSet& lines, const std::string& path) {
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  for (const glm::dvec3& p : lines.points) pts->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> cells;
  for (size_t i = 0; i < lines.polylineCount(); ++i) {
    cells->InsertNextCell(vtkIdType(lines.starts[i + 1] - lines.starts[i]));
    for (std::uint32_t k = lines.starts[i]; k < lines.starts[i + 1]; ++k) cells->InsertCellPoint(k);
  }
  pd->SetPoints(pts);
  pd->SetLines(cells);
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(pd);
  w->SetDataModeToBinary();
  if (!w->Write()) throw std::runtime_error("cannot write " + path);
}

}  // namespace wfapp
