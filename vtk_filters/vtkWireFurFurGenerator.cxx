#include "vtkWireFurFurGenerator.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkParametricFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTypeUInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include "core/srgb.h"
#include "growth/fur.h"
#include "texture/textures.h"
#include "wf_vtk_pieces.h"
#include "wf_vtk_surfaces.h"

#include <algorithm>
#include <cmath>
#include <exception>

vtkStandardNewMacro(vtkWireFurFurGenerator);


vtkWireFurFurGenerator::vtkWireFurFurGenerator() = default;

vtkMTimeType vtkWireFurFurGenerator::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();  // with the parametric function's
  for (vtkImageData* m : { this->DensityMap.Get(), this->LengthMap.Get(), this->OrientationMap.Get(),
         this->RootColorMap.Get() })
  {
    if (m)
    {
      t = std::max(t, m->GetMTime());
    }
  }
  return t;
}

#define WIREFUR_MAP_ACCESSORS(Name)                                                                \
  void vtkWireFurFurGenerator::Set##Name(vtkImageData* map)                                        \
  {                                                                                                \
    if (this->Name.Get() != map)                                                                   \
    {                                                                                              \
      this->Name = map;                                                                            \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  vtkImageData* vtkWireFurFurGenerator::Get##Name() { return this->Name.Get(); }
WIREFUR_MAP_ACCESSORS(DensityMap)
WIREFUR_MAP_ACCESSORS(LengthMap)
WIREFUR_MAP_ACCESSORS(OrientationMap)
WIREFUR_MAP_ACCESSORS(RootColorMap)
#undef WIREFUR_MAP_ACCESSORS

void vtkWireFurFurGenerator::AddColorRegion(
  double s, double t, double radius, double r, double g, double b, double falloff)
{
  this->ColorRegions.push_back({ s, t, radius, r, g, b, falloff });
  this->Modified();
}

void vtkWireFurFurGenerator::RemoveAllColorRegions()
{
  if (!this->ColorRegions.empty())
  {
    this->ColorRegions.clear();
    this->Modified();
  }
}

int vtkWireFurFurGenerator::GetNumberOfColorRegions()
{
  return int(this->ColorRegions.size());
}

namespace
{
// One component of a 2-D image as a linear-light RGBA image (the core's texture input), row 0 at
// the top (VTK's row 0 is at the bottom: t = 0). `component` < 0: RGB (unsigned char decoded from
// sRGB, other types as they are). Empty when the image has no scalars or is not 2-D.
wf::ImageRGBA toCoreImage(vtkImageData* img, int component)
{
  wf::ImageRGBA out;
  vtkDataArray* a = img ? img->GetPointData()->GetScalars() : nullptr;
  int dims[3] = { 0, 0, 0 };
  if (img)
  {
    img->GetDimensions(dims);
  }
  if (!a || dims[0] < 1 || dims[1] < 1 || dims[2] != 1 || a->GetNumberOfTuples() != vtkIdType(dims[0]) * dims[1])
  {
    return out;
  }
  const bool bytes = a->GetDataType() == VTK_UNSIGNED_CHAR;
  const int nc = a->GetNumberOfComponents();
  out = wf::ImageRGBA(dims[0], dims[1]);
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const vtkIdType id = vtkIdType(j) * dims[0] + i;
      glm::vec4 p(1.0f);
      for (int c = 0; c < 3; ++c)
      {
        const int k = component >= 0 ? std::min(component, nc - 1) : std::min(c, nc - 1);
        double v = a->GetComponent(id, k);
        if (bytes && component < 0)
        {
          v = wf::srgbToLinear(float(v / 255.0));
        }
        p[c] = float(std::isfinite(v) ? v : 0.0);
      }
      out.at(i, dims[1] - 1 - j) = p;
    }
  }
  return out;
}
}

int vtkWireFurFurGenerator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  vtkPolyData* input = this->GrowthInput(inputVector);

  // Problems are reported and give an empty output; the pipeline goes on (return 1).
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

  wf::FurParams p;
  p.seed = this->Seed;
  p.placement = this->Placement == AreaCorrect ? wf::FurParams::Placement::AreaCorrect
                                               : wf::FurParams::Placement::Grid;
  p.gridU = this->GridU;
  p.gridV = this->GridV;
  p.jitter = this->Jitter;
  p.density = this->Density;
  p.cellsU = this->CellsU;
  p.cellsV = this->CellsV;
  p.orientation = glm::dvec3(this->Orientation[0], this->Orientation[1], this->Orientation[2]);
  p.unitTangents = this->UnitTangents != 0;
  p.lengthMode = this->LengthMode == Paper ? wf::FurParams::LengthMode::Paper
    : this->LengthMode == ProportionalToSu ? wf::FurParams::LengthMode::ProportionalToSu
                                           : wf::FurParams::LengthMode::Fixed;
  p.length = this->Length;
  p.lengthPerSu = this->LengthPerSu;
  p.lengthVariation = this->LengthVariation;
  p.intensityVariation = this->IntensityVariation;
  p.segments = this->Segments;
  p.gravity = this->Gravity;
  p.gravityDirection =
    glm::dvec3(this->GravityDirection[0], this->GravityDirection[1], this->GravityDirection[2]);
  p.curlAmplitude = this->CurlAmplitude;
  p.curlFrequency = this->CurlFrequency;
  p.clumping = this->Clumping;
  p.clumpCellsU = this->ClumpCellsU;
  p.clumpCellsV = this->ClumpCellsV;
  p.windDirection =
    glm::dvec3(this->WindDirection[0], this->WindDirection[1], this->WindDirection[2]);
  p.windStrength = this->WindStrength;
  p.windSway = this->WindSway;
  p.windFrequency = this->WindFrequency;
  p.time = this->Time;
  p.rootColour = glm::vec3(glm::dvec3(this->RootColor[0], this->RootColor[1], this->RootColor[2]));
  p.tipColour = glm::vec3(glm::dvec3(this->TipColor[0], this->TipColor[1], this->TipColor[2]));
  p.thickness = this->Thickness;
  p.maxPoints = this->MaximumPoints;  // counted exactly by the core before it allocates
  p.rootFilter = share.keep;           // this process's roots (every root when not distributed)
  // Maps (the core looks them up at the unit coordinates (s, t), wrapping along periodic axes).
  const wf::ParameterDomain domain = surface->domain();
  auto scalarMap = [&](vtkImageData* img, int component) -> std::shared_ptr<const wf::ScalarTexture> {
    if (!img)
    {
      return nullptr;
    }
    wf::ImageRGBA core = toCoreImage(img, component);
    if (core.width == 0)
    {
      vtkWarningMacro("a map without 2-D point scalars is ignored");
      return nullptr;
    }
    // One component copied into R, G and B: its luminance is the component itself.
    return std::make_shared<wf::ImageHeight>(core, domain.periodicU, domain.periodicV);
  };
  p.densityMap = scalarMap(this->DensityMap, 0);
  p.lengthMap = scalarMap(this->LengthMap, 0);
  if (this->OrientationMap)
  {
    p.orientationMapA = scalarMap(this->OrientationMap, 0);
    p.orientationMapB = scalarMap(this->OrientationMap, 1);
    p.orientationMapC = scalarMap(this->OrientationMap, 2);
  }
  if (this->RootColorMap)
  {
    wf::ImageRGBA core = toCoreImage(this->RootColorMap, -1);
    if (core.width > 0)
    {
      p.rootColourMap = std::make_shared<wf::ImageTexture>(core, domain.periodicU, domain.periodicV);
    }
  }
  for (const auto& r : this->ColorRegions)
  {
    wf::FurColourRegion region;
    region.centre = glm::dvec2(r[0], r[1]);
    region.radius = r[2];
    region.colour = glm::vec3(float(r[3]), float(r[4]), float(r[5]));
    region.falloff = r[6];
    p.colourRegions.push_back(region);
  }
  if (const std::string why = p.problem(); !why.empty())
  {
    vtkErrorMacro(<< "invalid fur parameters: " << why);
    return 1;
  }

  wf::Fur fur;
  if (!wf::vtkio::runGrowth(this, "fur", *surface, [&] { fur = wf::growFur(*surface, p, this->PatchIndex); }))
  {
    return 1;
  }
  if (fur.counts.hairs == 0 && fur.counts.elsewhere == 0 && fur.counts.skippedDegenerate > 0)
  {
    vtkErrorMacro(<< "fur on " << surface->describe() << ": none of the " << fur.counts.rootsTried
                  << " roots lies on a finite surface (NaN or Inf parameters or points?)");
    return 1;
  }
  vtkDebugMacro(<< "fur on " << surface->describe() << ": " << fur.counts.hairs << " hairs of "
                << fur.counts.rootsTried << " roots (" << fur.counts.skippedDegenerate
                << " not on the surface, " << fur.counts.skippedZeroLength << " zero length)");

  const vtkIdType nPoints = vtkIdType(fur.hairs.points.size());
  const vtkIdType nHairs = vtkIdType(fur.hairs.polylineCount());

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nPoints);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(nPoints);
  const bool haveColours = fur.hairs.colours.size() == fur.hairs.points.size();
  auto* xyz = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  unsigned char* rgb = colors->GetPointer(0);
  wf::vtkio::parallelFor(0, nPoints, [&](std::int64_t begin, std::int64_t end) {
    for (vtkIdType i = vtkIdType(begin); i < vtkIdType(end); ++i)
    {
      const glm::dvec3& q = fur.hairs.points[size_t(i)];
      xyz[3 * i] = q.x;
      xyz[3 * i + 1] = q.y;
      xyz[3 * i + 2] = q.z;
      const glm::vec3 c = haveColours ? fur.hairs.colours[size_t(i)] : glm::vec3(1.0f);
      rgb[3 * i] = wf::vtkio::srgb8(c.x);
      rgb[3 * i + 1] = wf::vtkio::srgb8(c.y);
      rgb[3 * i + 2] = wf::vtkio::srgb8(c.z);
    }
  });
  this->UpdateProgress(0.9);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nHairs + 1);
  connectivity->SetNumberOfTuples(nPoints);
  vtkNew<vtkTypeUInt64Array> ids;
  ids->SetName("HairId");
  ids->SetNumberOfTuples(nHairs);
  vtkNew<vtkDoubleArray> rootUv;
  rootUv->SetName("RootUV");
  rootUv->SetNumberOfComponents(2);
  rootUv->SetNumberOfTuples(nHairs);
  for (vtkIdType h = 0; h <= nHairs; ++h)
  {
    offsets->SetValue(h, nHairs > 0 ? vtkIdType(fur.hairs.starts[size_t(h)]) : 0);
  }
  wf::vtkio::parallelFor(0, nPoints, [&](std::int64_t begin, std::int64_t end) {
    for (vtkIdType i = vtkIdType(begin); i < vtkIdType(end); ++i)
    {
      connectivity->SetValue(i, i);
    }
  });
  for (vtkIdType h = 0; h < nHairs; ++h)
  {
    ids->SetValue(h, fur.ids[size_t(h)]);
    rootUv->SetTypedTuple(h, &fur.rootUvs[size_t(h)].x);
  }
  vtkNew<vtkCellArray> lines;
  if (nHairs > 0)
  {
    lines->SetData(offsets, connectivity);
  }

  vtkNew<vtkDoubleArray> thickness;
  thickness->SetName("Thickness");
  thickness->SetNumberOfTuples(1);
  thickness->SetValue(0, fur.thickness);

  output->SetPoints(points);
  output->SetLines(lines);
  output->GetPointData()->SetScalars(colors);
  output->GetCellData()->AddArray(ids);
  output->GetCellData()->AddArray(rootUv);
  output->GetFieldData()->AddArray(thickness);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWireFurFurGenerator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumPoints: " << this->MaximumPoints << "\n";
  os << indent << "DensityMap: " << static_cast<void*>(this->DensityMap.Get()) << "\n";
  os << indent << "LengthMap: " << static_cast<void*>(this->LengthMap.Get()) << "\n";
  os << indent << "OrientationMap: " << static_cast<void*>(this->OrientationMap.Get()) << "\n";
  os << indent << "RootColorMap: " << static_cast<void*>(this->RootColorMap.Get()) << "\n";
  os << indent << "ColorRegions: " << this->ColorRegions.size() << "\n";
  auto v3 = [&](const char* name, const double* v) {
    os << indent << name << ": " << v[0] << " " << v[1] << " " << v[2] << "\n";
  };
  os << indent << "Placement: " << (this->Placement == AreaCorrect ? "AreaCorrect" : "Grid") << "\n";
  os << indent << "GridU: " << this->GridU << "\n";
  os << indent << "GridV: " << this->GridV << "\n";
  os << indent << "Jitter: " << this->Jitter << "\n";
  os << indent << "Density: " << this->Density << "\n";
  os << indent << "CellsU: " << this->CellsU << "\n";
  os << indent << "CellsV: " << this->CellsV << "\n";
  v3("Orientation", this->Orientation);
  os << indent << "UnitTangents: " << (this->UnitTangents ? "On" : "Off") << "\n";
  os << indent << "LengthMode: "
     << (this->LengthMode == Paper ? "Paper"
           : this->LengthMode == ProportionalToSu ? "ProportionalToSu"
                                                  : "Fixed")
     << "\n";
  os << indent << "Length: " << this->Length << "\n";
  os << indent << "LengthPerSu: " << this->LengthPerSu << "\n";
  os << indent << "LengthVariation: " << this->LengthVariation << "\n";
  os << indent << "IntensityVariation: " << this->IntensityVariation << "\n";
  os << indent << "Segments: " << this->Segments << "\n";
  os << indent << "Gravity: " << this->Gravity << "\n";
  v3("GravityDirection", this->GravityDirection);
  os << indent << "CurlAmplitude: " << this->CurlAmplitude << "\n";
  os << indent << "CurlFrequency: " << this->CurlFrequency << "\n";
  os << indent << "Clumping: " << this->Clumping << "\n";
  os << indent << "ClumpCellsU: " << this->ClumpCellsU << "\n";
  os << indent << "ClumpCellsV: " << this->ClumpCellsV << "\n";
  v3("WindDirection", this->WindDirection);
  os << indent << "WindStrength: " << this->WindStrength << "\n";
  os << indent << "WindSway: " << this->WindSway << "\n";
  os << indent << "WindFrequency: " << this->WindFrequency << "\n";
  os << indent << "Time: " << this->Time << "\n";
  v3("RootColor", this->RootColor);
  v3("TipColor", this->TipColor);
  os << indent << "Thickness: " << this->Thickness << "\n";
}
