#include "vtkWireFurScalesGenerator.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkParametricFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTypeUInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include "growth/scales.h"
#include "wf_vtk_pieces.h"
#include "wf_vtk_surfaces.h"

#include <algorithm>
#include <cmath>
#include <exception>

vtkStandardNewMacro(vtkWireFurScalesGenerator);

namespace
{
// The scale index of a scale whose root is `uv`: growScales puts the corner scale of cell (i, j) at
// fromUnit(i / nu, j / nv) and the centre scale at fromUnit((i + 1/2) / nu, (j + 1/2) / nv), and
// leaves out degenerate scales, so the triangle order alone does not give the index. The nearest
// of the two candidate roots (half a cell apart) names it.
std::uint64_t scaleIndex(const wf::ParameterDomain& d, int nu, int nv, const glm::dvec2& uv)
{
  const glm::dvec2 st = d.toUnit(uv.x, uv.y) * glm::dvec2(nu, nv);
  const int ci = std::clamp(int(std::lround(st.x)), 0, nu - 1);
  const int cj = std::clamp(int(std::lround(st.y)), 0, nv - 1);
  const int mi = std::clamp(int(std::floor(st.x)), 0, nu - 1);
  const int mj = std::clamp(int(std::floor(st.y)), 0, nv - 1);
  const glm::dvec2 corner = d.fromUnit(double(ci) / nu, double(cj) / nv);
  const glm::dvec2 centre = d.fromUnit((mi + 0.5) / nu, (mj + 0.5) / nv);
  const glm::dvec2 scale(d.du(), d.dv());
  const double dc = glm::length((uv - corner) / scale), dm = glm::length((uv - centre) / scale);
  if (dc <= dm)
  {
    return 2 * (std::uint64_t(cj) * std::uint64_t(nu) + std::uint64_t(ci));
  }
  return 2 * (std::uint64_t(mj) * std::uint64_t(nu) + std::uint64_t(mi)) + 1;
}
} // namespace

vtkWireFurScalesGenerator::vtkWireFurScalesGenerator() = default;

int vtkWireFurScalesGenerator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  vtkPolyData* input = this->GrowthInput(inputVector);

  // A parallel pipeline's piece: the whole surface and this process's share of it (wf_vtk_pieces.h).
  const wf::vtkio::GrowthShare share =
    wf::vtkio::growthShare(this->ParametricFunction, input, this->FlipNormals != 0, outputVector);
  const std::shared_ptr<const wf::Surface>& surface = share.surface;
  if (!surface)
  {
    if (!share.problem.empty())
      vtkErrorMacro(<< share.problem);
    else if (wf::vtkio::wholeDataRequested(outputVector))
      vtkWarningMacro(<< wf::vtkio::wholeEmptyWarning);  // (a rank's empty piece: silent)
    return 1;
  }

  wf::ScaleParams p;
  p.cellsU = this->CellsU;
  p.cellsV = this->CellsV;
  p.size = this->Size;
  p.lift = this->Lift;
  p.deflection = this->Deflection;
  p.intensityVariation = this->IntensityVariation;
  p.shoulder = this->Shoulder;
  p.colour = glm::vec3(glm::dvec3(this->Color[0], this->Color[1], this->Color[2]));
  p.seed = this->Seed;
  p.maxTriangles = this->MaximumTriangles;  // checked by the core before it allocates
  p.rootFilter = share.keep;                 // this process's scales (all when not distributed)
  if (const std::string why = p.problem(); !why.empty())
  {
    vtkErrorMacro(<< "invalid scale parameters: " << why);
    return 1;
  }

  wf::TriangleMesh mesh;
  if (!wf::vtkio::runGrowth(this, "scales", *surface, [&] { mesh = wf::growScales(*surface, p, this->PatchIndex); }))
  {
    return 1;
  }
  if (mesh.triangles.empty() && !share.keep)  // (a share may hold no scale)
  {
    vtkErrorMacro(<< "scales on " << surface->describe()
                  << ": no scale lies on a finite surface (NaN or Inf parameters or points?)");
    return 1;
  }

  const vtkIdType nPoints = vtkIdType(mesh.positions.size());
  const vtkIdType nTriangles = vtkIdType(mesh.triangles.size());
  const bool haveNormals = mesh.normals.size() == mesh.positions.size();
  const bool haveTangents = mesh.tangents.size() == mesh.positions.size();
  const bool haveUvs = mesh.uvs.size() == mesh.positions.size();
  const bool haveColours = mesh.colours.size() == mesh.positions.size();

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nPoints);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nPoints);
  vtkNew<vtkFloatArray> tangents;
  tangents->SetName("Tangents");
  tangents->SetNumberOfComponents(3);
  tangents->SetNumberOfTuples(nPoints);
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(nPoints);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(nPoints);
  double* xyz = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  float* nrm = normals->GetPointer(0);
  float* tan = tangents->GetPointer(0);
  float* tc = tcoords->GetPointer(0);
  unsigned char* rgb = colors->GetPointer(0);
  wf::vtkio::parallelFor(0, nPoints, [&](std::int64_t begin, std::int64_t end) {
    for (vtkIdType i = vtkIdType(begin); i < vtkIdType(end); ++i)
    {
      const size_t k = size_t(i);
      for (int a = 0; a < 3; ++a)
      {
        xyz[3 * i + a] = mesh.positions[k][a];
        nrm[3 * i + a] = haveNormals ? float(mesh.normals[k][a]) : 0.0f;
        tan[3 * i + a] = haveTangents ? float(mesh.tangents[k][a]) : 0.0f;
        rgb[3 * i + a] = wf::vtkio::srgb8(haveColours ? mesh.colours[k][a] : 1.0f);
      }
      tc[2 * i] = haveUvs ? float(mesh.uvs[k].x) : 0.0f;
      tc[2 * i + 1] = haveUvs ? float(mesh.uvs[k].y) : 0.0f;
    }
  });
  this->UpdateProgress(0.9);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nTriangles + 1);
  connectivity->SetNumberOfTuples(3 * nTriangles);
  vtkNew<vtkTypeUInt64Array> ids;
  ids->SetName("ScaleId");
  ids->SetNumberOfTuples(nTriangles);
  const wf::ParameterDomain domain = surface->domain();
  const std::uint64_t patchBits = std::uint64_t(this->PatchIndex) << 32;
  offsets->SetValue(0, 0);
  wf::vtkio::parallelFor(0, nTriangles, [&](std::int64_t begin, std::int64_t end) {
    for (vtkIdType t = vtkIdType(begin); t < vtkIdType(end); ++t)
    {
      const glm::uvec3& tri = mesh.triangles[size_t(t)];
      offsets->SetValue(t + 1, 3 * (t + 1));
      connectivity->SetValue(3 * t, tri.x);
      connectivity->SetValue(3 * t + 1, tri.y);
      connectivity->SetValue(3 * t + 2, tri.z);
      const glm::dvec2 uv = haveUvs ? mesh.uvs[tri.x] : glm::dvec2(0.0);
      ids->SetValue(t, patchBits | scaleIndex(domain, this->CellsU, this->CellsV, uv));
    }
  });
  vtkNew<vtkCellArray> polys;
  if (nTriangles > 0)
  {
    polys->SetData(offsets, connectivity);
  }

  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetPointData()->SetNormals(normals);
  output->GetPointData()->SetTangents(tangents);
  output->GetPointData()->SetTCoords(tcoords);
  output->GetPointData()->SetScalars(colors);
  output->GetCellData()->AddArray(ids);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWireFurScalesGenerator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumTriangles: " << this->MaximumTriangles << "\n";
  os << indent << "CellsU: " << this->CellsU << "\n";
  os << indent << "CellsV: " << this->CellsV << "\n";
  os << indent << "Size: " << this->Size << "\n";
  os << indent << "Lift: " << this->Lift << "\n";
  os << indent << "Deflection: " << this->Deflection << "\n";
  os << indent << "IntensityVariation: " << this->IntensityVariation << "\n";
  os << indent << "Shoulder: " << this->Shoulder << "\n";
  os << indent << "Color: " << this->Color[0] << " " << this->Color[1] << " " << this->Color[2]
     << "\n";
}
