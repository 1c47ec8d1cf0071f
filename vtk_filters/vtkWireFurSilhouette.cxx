#include "vtkWireFurSilhouette.h"

#include "surface/silhouette.h"
#include "wf_cad_plugin.h"  // vtk_filters/cad: the exact faces' type (no OpenCASCADE in it)
#include "wf_render_pass_scene.h"
#include "wf_vtk_surfaces.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkRenderer.h"
#include "vtkStripper.h"

#include <dlfcn.h>

#include <cmath>
#include <cstring>
#include <map>
#include <vector>

vtkStandardNewMacro(vtkWireFurSilhouette);

class vtkWireFurSilhouette::vtkInternals : public wfvtk::FilterView
{
};

vtkWireFurSilhouette::vtkWireFurSilhouette()
  : Internals(new vtkInternals)
{
}
vtkWireFurSilhouette::~vtkWireFurSilhouette() { delete this->Internals; }

void vtkWireFurSilhouette::SetCamera(vtkCamera* camera)
{
  if (this->Internals->camera != camera)
  {
    this->Internals->camera = camera;
    this->Modified();
  }
}
vtkCamera* vtkWireFurSilhouette::GetCamera() { return this->Internals->camera; }
void vtkWireFurSilhouette::SetRenderer(vtkRenderer* renderer)
{
  if (this->Internals->renderer != renderer)
  {
    this->Internals->renderer = renderer;
    this->Modified();
  }
}
vtkRenderer* vtkWireFurSilhouette::GetRenderer() { return this->Internals->renderer; }

vtkMTimeType vtkWireFurSilhouette::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->Internals->mtime(this->ViewportSize));
}

namespace
{

// wirefur_cad_face_surfaces from the library that holds the reader's class (found by the
// object's vtable), or null: the CAD module may be loaded privately (RTLD_LOCAL, as Python
// loads extension modules), where a global lookup would not see it.
WireFurCadFacesFunction cadFacesFunction(vtkAlgorithm* reader)
{
  Dl_info info{};
  if (!dladdr(*reinterpret_cast<void**>(reader), &info) || !info.dli_fname)
    return nullptr;
  void* h = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD);
  if (!h)
    return nullptr;
  void* f = dlsym(h, "wirefur_cad_face_surfaces");
  dlclose(h);  // (still loaded: the reader's library)
  return reinterpret_cast<WireFurCadFacesFunction>(f);
}

} // namespace

int vtkWireFurSilhouette::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  this->Exact = false;
  vtkCamera* camera = this->Internals->active();
  if (!camera)
  {
    vtkErrorMacro(<< "no camera (SetCamera or SetRenderer)");
    return 1;
  }
  int w, h;
  this->Internals->size(this->ViewportSize, w, h);
  if (!input || input->GetNumberOfPoints() == 0)
    return 1;
  if (const std::string problem = wf::vtkio::inputProblem(input); !problem.empty())
  {
    vtkErrorMacro(<< problem);
    return 1;
  }
  const wf::Camera cam = wfvtk::convertCamera(camera, w, h);
  const wf::ViewTransform view = wf::ViewTransform::make(cam, w, h);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;

  // Exact path: the CAD reader upstream.
  // ParaView puts a vtkPVPostFilter (it passes the data through, adding derived arrays) after
  // every source: looked through, by name (nothing here links ParaView).
  vtkAlgorithm* producer = this->GetNumberOfInputConnections(0) > 0 ? this->GetInputAlgorithm(0, 0) : nullptr;
  vtkAlgorithmOutput* port = producer ? this->GetInputConnection(0, 0) : nullptr;
  while (producer && producer->IsA("vtkPVPostFilter") && producer->GetNumberOfInputConnections(0) == 1)
  {
    port = producer->GetInputConnection(0, 0);
    producer = producer->GetInputAlgorithm(0, 0);
  }
  if (this->UseExactSurfaces && producer && producer->IsA("vtkWireFurCADReader") && port->GetIndex() == 0)
    if (WireFurCadFacesFunction faces = cadFacesFunction(producer))
    {
      std::vector<WireFurCadFace> list;
      faces(reinterpret_cast<vtkWireFurCADReader*>(producer), &list);
      wf::SilhouetteOptions options;
      options.tolerancePx = this->TolerancePixels;
      wf::SilhouetteStats stats;
      for (const WireFurCadFace& f : list)
      {
        if (!f.surface)
          continue;
        wf::PolylineSet curves;
        wf::traceSilhouette(*f.surface, f.inside.get(), view, options, curves, stats);
        for (size_t k = 0; k < curves.polylineCount(); ++k)
        {
          lines->InsertNextCell(vtkIdType(curves.starts[k + 1] - curves.starts[k]));
          for (std::uint32_t i = curves.starts[k]; i < curves.starts[k + 1]; ++i)
            lines->InsertCellPoint(points->InsertNextPoint(&curves.points[i].x));
        }
      }
      // No faces (the file changed since it was read, or none could be evaluated): the mesh.
      this->Exact = !list.empty();
    }

  if (!this->Exact)
  {
    // Mesh path: g = N . V at the points, its zero set across each triangle.
    vtkSmartPointer<vtkPolyData> mesh = input;
    if (!input->GetPointData()->GetNormals())
    {
      vtkNew<vtkPolyDataNormals> normals;
      normals->SetInputData(input);
      normals->SplittingOff();
      normals->ComputePointNormalsOn();
      normals->Update();
      mesh = normals->GetOutput();
    }
    vtkDataArray* n = mesh->GetPointData()->GetNormals();
    std::vector<double> g(size_t(mesh->GetNumberOfPoints()), 0.0);
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    {
      double p[3], nn[3];
      mesh->GetPoint(i, p);
      n->GetTuple(i, nn);
      const glm::dvec3 V = view.perspective ? glm::normalize(view.eye - glm::dvec3(p[0], p[1], p[2]))
                                            : glm::transpose(view.eyeFromWorld) * glm::dvec3(0, 0, 1);
      g[size_t(i)] = nn[0] * V.x + nn[1] * V.y + nn[2] * V.z;
    }
    // One point per crossed mesh edge, shared by the triangles on both sides.
    std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> crossing;
    // A crossing within 1e-9 of an edge's end is that vertex, one point for every edge through
    // it (no pieces of zero length where N . V vanishes at a vertex).
    auto cross = [&](vtkIdType a, vtkIdType b) -> vtkIdType {
      if (a > b)  // first, so that both triangles of an edge decide its snap alike
        std::swap(a, b);
      const double t = g[size_t(a)] / (g[size_t(a)] - g[size_t(b)]);
      if (!(t > 1e-9))
        b = a;
      else if (!(t < 1.0 - 1e-9))
        a = b;
      const auto it = crossing.find({ a, b });
      if (it != crossing.end())
        return it->second;
      double pa[3], pb[3];
      mesh->GetPoint(a, pa);
      mesh->GetPoint(b, pb);
      const double s = a == b ? 0.0 : g[size_t(a)] / (g[size_t(a)] - g[size_t(b)]);
      const vtkIdType id =
        points->InsertNextPoint(pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1]), pa[2] + s * (pb[2] - pa[2]));
      crossing.emplace(std::make_pair(a, b), id);
      return id;
    };
    auto positive = [&](vtkIdType i) { return g[size_t(i)] > 0.0; };
    vtkNew<vtkCellArray> segments;
    vtkNew<vtkIdList> cell;
    auto triangle = [&](vtkIdType a, vtkIdType b, vtkIdType c) {
      const vtkIdType t[3] = { a, b, c };
      vtkIdType ends[2], m = 0;
      for (int e = 0; e < 3; ++e)
        if (positive(t[e]) != positive(t[(e + 1) % 3]))
          ends[m < 2 ? m++ : 1] = cross(t[e], t[(e + 1) % 3]);
      if (m == 2 && ends[0] != ends[1])
        segments->InsertNextCell(2, ends);
    };
    vtkCellArray* polys = mesh->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(cell);)
      for (vtkIdType k = 1; k + 1 < cell->GetNumberOfIds(); ++k)
        triangle(cell->GetId(0), cell->GetId(k), cell->GetId(k + 1));
    vtkCellArray* strips = mesh->GetStrips();
    for (strips->InitTraversal(); strips->GetNextCell(cell);)
      for (vtkIdType k = 0; k + 2 < cell->GetNumberOfIds(); ++k)
        triangle(cell->GetId(k), cell->GetId(k + 1), cell->GetId(k + 2));
    vtkNew<vtkPolyData> raw;
    raw->SetPoints(points);
    raw->SetLines(segments);
    vtkNew<vtkStripper> join;
    join->SetInputData(raw);
    join->JoinContiguousSegmentsOn();
    join->SetMaximumLength(100000);
    join->Update();
    // The stripper can repeat a point where it joins pieces (zero-length segments): left out.
    vtkNew<vtkCellArray> joined;
    vtkCellArray* pieces = join->GetOutput()->GetLines();
    std::vector<vtkIdType> ids;
    for (pieces->InitTraversal(); pieces->GetNextCell(cell);)
    {
      ids.clear();
      for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
        if (ids.empty() || ids.back() != cell->GetId(k))
          ids.push_back(cell->GetId(k));
      if (ids.size() >= 2)
        joined->InsertNextCell(vtkIdType(ids.size()), ids.data());
    }
    output->SetPoints(join->GetOutput()->GetPoints());
    output->SetLines(joined);
    output->GetCellData()->Initialize();
    output->GetPointData()->Initialize();
  }
  else
  {
    output->SetPoints(points);
    output->SetLines(lines);
  }
  vtkNew<vtkIntArray> cls;
  cls->SetName("EdgeClass");
  cls->SetNumberOfTuples(output->GetNumberOfCells());
  cls->Fill(6);
  output->GetCellData()->AddArray(cls);
  return 1;
}

void vtkWireFurSilhouette::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ViewportSize: " << this->ViewportSize[0] << " x " << this->ViewportSize[1] << "\n";
  os << indent << "TolerancePixels: " << this->TolerancePixels << "\n";
  os << indent << "UseExactSurfaces: " << this->UseExactSurfaces << "\n";
}
