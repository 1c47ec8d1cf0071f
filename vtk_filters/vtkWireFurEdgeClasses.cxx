#include "vtkWireFurEdgeClasses.h"

#include "render/edge_classes.h"
#include "surface/mesh_edges.h"
#include "wf_vtk_surfaces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkWireFurEdgeClasses);

vtkIdType vtkWireFurEdgeClasses::GetNumberOfEdgesOfClass(int c) const
{
  return c >= 0 && c < 6 ? this->Counts[c] : 0;
}

int vtkWireFurEdgeClasses::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  for (vtkIdType& c : this->Counts)
    c = 0;
  if (!input || input->GetNumberOfPoints() == 0)
    return 1;
  if (const std::string problem = wf::vtkio::inputProblem(input); !problem.empty())
  {
    vtkErrorMacro(<< problem);
    return 1;
  }
  wf::EdgeSelection selection;
  selection.mode = wf::EdgeSelection::Mode(this->Mode);
  selection.seams = this->Seams;
  selection.featureAngle = this->FeatureAngle;

  vtkNew<vtkIntArray> classes;
  classes->SetName("EdgeClass");
  vtkNew<vtkFloatArray> angles;
  angles->SetName("EdgeAngle");

  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() > 0)
  {
    std::vector<glm::dvec3> positions(size_t(input->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
      input->GetPoint(i, &positions[size_t(i)].x);
    std::vector<std::uint32_t> starts{ 0 }, ids;
    vtkNew<vtkIdList> cell;
    vtkCellArray* polys = input->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(cell);)
    {
      for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
        ids.push_back(std::uint32_t(cell->GetId(k)));
      starts.push_back(std::uint32_t(ids.size()));
    }
    vtkCellArray* strips = input->GetStrips();
    for (strips->InitTraversal(); strips->GetNextCell(cell);)
      for (vtkIdType k = 0; k + 2 < cell->GetNumberOfIds(); ++k)
      {
        // Every other triangle of a strip turns the other way.
        const vtkIdType a = cell->GetId(k), b = cell->GetId(k + 1), c = cell->GetId(k + 2);
        const vtkIdType tri[3] = { k % 2 == 0 ? a : b, k % 2 == 0 ? b : a, c };
        for (vtkIdType id : tri)
          ids.push_back(std::uint32_t(id));
        starts.push_back(std::uint32_t(ids.size()));
      }
    const wf::ClassifiedEdges e = wf::classifyPolygonEdges(positions, starts, ids, selection);
    for (int c = 0; c < 6; ++c)
      this->Counts[c] = vtkIdType(e.counts[c]);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> lines;
    for (size_t k = 0; k < e.lines.polylineCount(); ++k)
    {
      lines->InsertNextCell(vtkIdType(e.lines.starts[k + 1] - e.lines.starts[k]));
      for (std::uint32_t i = e.lines.starts[k]; i < e.lines.starts[k + 1]; ++i)
        lines->InsertCellPoint(points->InsertNextPoint(&e.lines.points[i].x));
      classes->InsertNextValue(int(e.classes[k]));
      angles->InsertNextValue(e.angles[k]);
    }
    output->SetPoints(points);
    output->SetLines(lines);
    output->GetCellData()->AddArray(classes);
    output->GetCellData()->AddArray(angles);
    return 1;
  }

  // Lines already classified (the CAD reader's edges): choose among them.
  vtkDataArray* inClass = input->GetCellData()->GetArray("EdgeClass");
  vtkDataArray* inAngle = input->GetCellData()->GetArray("EdgeAngle");
  if (!inClass)
  {
    vtkErrorMacro(<< "the input has no polygons to classify and its lines no EdgeClass array");
    return 1;
  }
  output->SetPoints(input->GetPoints());
  vtkNew<vtkCellArray> lines;
  vtkCellData* inCd = input->GetCellData();
  vtkCellData* outCd = output->GetCellData();
  outCd->CopyAllocate(inCd);
  const vtkIdType firstLine = input->GetNumberOfVerts();  // cell ids run over verts, then lines
  vtkNew<vtkIdList> cell;
  vtkCellArray* in = input->GetLines();
  vtkIdType c = 0;
  for (in->InitTraversal(); in->GetNextCell(cell); ++c)
  {
    const double cls = inClass->GetTuple1(firstLine + c);
    if (!(cls >= 0 && cls <= 7))
      continue;
    wf::EdgeClass k = wf::EdgeClass(int(cls));
    const double angle = inAngle ? inAngle->GetTuple1(firstLine + c) : std::nan("");
    // (Without an EdgeAngle array, as after appending other lines, the given class stands.)
    if (inAngle && (k == wf::EdgeClass::Sharp || k == wf::EdgeClass::Smooth))
      k = wf::EdgeSelection::byAngle(angle, this->FeatureAngle);
    if (int(k) < 6)
      ++this->Counts[int(k)];
    if (!selection.keeps(k, angle))
      continue;
    const vtkIdType out = lines->InsertNextCell(cell);
    outCd->CopyData(inCd, firstLine + c, out);
    outCd->GetArray("EdgeClass")->SetTuple1(out, int(k));
  }
  output->SetLines(lines);
  outCd->Squeeze();
  return 1;
}

void vtkWireFurEdgeClasses::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->Mode << "\n";
  os << indent << "Seams: " << this->Seams << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
}
