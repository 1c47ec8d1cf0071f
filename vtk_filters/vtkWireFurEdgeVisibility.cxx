#include "vtkWireFurEdgeVisibility.h"

#include "scene/edge_visibility.h"
#include "wf_render_pass_scene.h"
#include "wf_vtk_surfaces.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkWireFurEdgeVisibility);

class vtkWireFurEdgeVisibility::vtkInternals : public wfvtk::FilterView
{
};

vtkWireFurEdgeVisibility::vtkWireFurEdgeVisibility()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
}
vtkWireFurEdgeVisibility::~vtkWireFurEdgeVisibility() { delete this->Internals; }

void vtkWireFurEdgeVisibility::SetCamera(vtkCamera* camera)
{
  if (this->Internals->camera != camera)
  {
    this->Internals->camera = camera;
    this->Modified();
  }
}
vtkCamera* vtkWireFurEdgeVisibility::GetCamera() { return this->Internals->camera; }
void vtkWireFurEdgeVisibility::SetRenderer(vtkRenderer* renderer)
{
  if (this->Internals->renderer != renderer)
  {
    this->Internals->renderer = renderer;
    this->Modified();
  }
}
vtkRenderer* vtkWireFurEdgeVisibility::GetRenderer() { return this->Internals->renderer; }

vtkMTimeType vtkWireFurEdgeVisibility::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->Internals->mtime(this->ViewportSize));
}

int vtkWireFurEdgeVisibility::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 1)
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkWireFurEdgeVisibility::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* surfaces = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  this->VisibleLength = this->HiddenLength = 0;
  this->Splits = 0;
  vtkCamera* camera = this->Internals->active();
  if (!camera)
  {
    vtkErrorMacro(<< "no camera (SetCamera or SetRenderer)");
    return 1;
  }
  int w, h;
  this->Internals->size(this->ViewportSize, w, h);
  if (!input || input->GetNumberOfLines() == 0)
    return 1;
  for (vtkPolyData* pd : { input, surfaces })
  {
    if (!pd)
      continue;
    if (const std::string problem = wf::vtkio::inputProblem(pd, pd == input ? "input" : "surface"); !problem.empty())
    {
      vtkErrorMacro(<< problem);
      return 1;
    }
  }

  // The occluders as one surface (polygons fanned, strips split).
  wf::Scene scene;
  if (surfaces && surfaces->GetNumberOfPoints() > 0)
  {
    wf::SceneSurface s;
    s.mesh.positions.resize(size_t(surfaces->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < surfaces->GetNumberOfPoints(); ++i)
      surfaces->GetPoint(i, &s.mesh.positions[size_t(i)].x);
    vtkNew<vtkIdList> cell;
    vtkCellArray* polys = surfaces->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(cell);)
      for (vtkIdType k = 1; k + 1 < cell->GetNumberOfIds(); ++k)
        s.mesh.triangles.emplace_back(cell->GetId(0), cell->GetId(k), cell->GetId(k + 1));
    vtkCellArray* strips = surfaces->GetStrips();
    for (strips->InitTraversal(); strips->GetNextCell(cell);)
      for (vtkIdType k = 0; k + 2 < cell->GetNumberOfIds(); ++k)
        s.mesh.triangles.emplace_back(cell->GetId(k), cell->GetId(k + 1), cell->GetId(k + 2));
    scene.surfaces.push_back(std::move(s));
  }
  const wf::Camera cam = wfvtk::convertCamera(camera, w, h);
  const wf::OcclusionGrid grid(scene, cam, w, h);
  wf::VisibilityOptions options;
  options.samplePx = this->SamplePixels;

  // Silhouettes (EdgeClass 6): the tessellation's chords can pass in front of their grazing rays
  // (wf::VisibilityOptions::slack, localSlack), unless a fixed slack is given.
  const bool fixedSlack = this->SilhouetteSlack >= 0 && std::isfinite(this->SilhouetteSlack);
  double deflectionSlack = 0.0;
  if (!fixedSlack && surfaces && surfaces->GetNumberOfPoints() > 0)
    if (vtkDataArray* d = vtkDataArray::SafeDownCast(surfaces->GetFieldData()->GetAbstractArray("LinearDeflection")))
      if (d->GetNumberOfTuples() > 0 && std::isfinite(d->GetTuple1(0)) && d->GetTuple1(0) > 0)
        deflectionSlack = std::sqrt(2.0 * d->GetTuple1(0) * 0.5 * surfaces->GetLength());
  vtkDataArray* classes = input->GetCellData()->GetArray("EdgeClass");
  wf::VisibilityStats stats;

  // Each input line on its own (its cell data goes to its pieces).
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkCellData* inCd = input->GetCellData();
  vtkCellData* outCd = output->GetCellData();
  outCd->CopyAllocate(inCd);
  vtkNew<vtkUnsignedCharArray> visible;
  visible->SetName("Visible");
  const vtkIdType firstLine = input->GetNumberOfVerts();
  vtkNew<vtkIdList> cell;
  vtkCellArray* in = input->GetLines();
  vtkIdType c = 0;
  for (in->InitTraversal(); in->GetNextCell(cell); ++c)
  {
    wf::PolylineSet one;
    std::vector<glm::dvec3> pts(size_t(cell->GetNumberOfIds()));
    for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
      input->GetPoint(cell->GetId(k), &pts[size_t(k)].x);
    one.add(pts);
    const bool silhouette = classes && int(classes->GetTuple1(firstLine + c)) == int(wf::EdgeClass::Silhouette);
    options.slack = !silhouette ? 0.0 : fixedSlack ? this->SilhouetteSlack : deflectionSlack;
    options.localSlack = silhouette && !fixedSlack;
    const wf::VisibleLines v = wf::splitByVisibility(one, grid, options, stats);
    for (size_t k = 0; k < v.lines.polylineCount(); ++k)
    {
      const vtkIdType out = lines->InsertNextCell(vtkIdType(v.lines.starts[k + 1] - v.lines.starts[k]));
      for (std::uint32_t i = v.lines.starts[k]; i < v.lines.starts[k + 1]; ++i)
        lines->InsertCellPoint(points->InsertNextPoint(&v.lines.points[i].x));
      outCd->CopyData(inCd, firstLine + c, out);
      visible->InsertNextValue(v.visible[k]);
    }
  }
  output->SetPoints(points);
  output->SetLines(lines);
  outCd->AddArray(visible);
  outCd->Squeeze();
  this->VisibleLength = stats.visibleLength;
  this->HiddenLength = stats.hiddenLength;
  this->Splits = vtkIdType(stats.splits);
  return 1;
}

void vtkWireFurEdgeVisibility::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ViewportSize: " << this->ViewportSize[0] << " x " << this->ViewportSize[1] << "\n";
  os << indent << "SamplePixels: " << this->SamplePixels << "\n";
  os << indent << "SilhouetteSlack: " << this->SilhouetteSlack << "\n";
}
