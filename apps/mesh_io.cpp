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
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
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
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".obj") {
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".ply") {
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
