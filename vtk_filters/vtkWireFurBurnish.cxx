#include "vtkWireFurBurnish.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkParametricFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include "texture/grooves.h"
#include "wf_vtk_surfaces.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

vtkStandardNewMacro(vtkWireFurBurnish);
vtkCxxSetObjectMacro(vtkWireFurBurnish, ParametricFunction, vtkParametricFunction);

vtkWireFurBurnish::vtkWireFurBurnish() = default;

vtkWireFurBurnish::~vtkWireFurBurnish()
{
  this->SetParametricFunction(nullptr);
}

vtkMTimeType vtkWireFurBurnish::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->ParametricFunction)
  {
    t = std::max(t, this->ParametricFunction->GetMTime());
  }
  return t;
}

int vtkWireFurBurnish::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  using wf::vtkio::Grain;
  const Grain grain = Grain(this->Grain);
  const bool alongUv = grain == Grain::U || grain == Grain::V;

  // --- checks: every problem is reported and gives an empty output --------------------------------
  if (!input)
  {
    vtkErrorMacro(<< "no input");
    return 1;
  }
  if (wf::vtkio::isEmpty(input))
  {
    // A rank's empty piece in a parallel pipeline: not an error; an empty output with the arrays
    // (so that pieces append with them). A warning when it is the whole data set.
    if (wf::vtkio::wholeDataRequested(outputVector))
      vtkWarningMacro(<< wf::vtkio::wholeEmptyWarning);
    output->ShallowCopy(input);
    vtkNew<vtkFloatArray> tangents;
    tangents->SetName("Tangents");
    tangents->SetNumberOfComponents(3);
    output->GetPointData()->SetTangents(tangents);
    if (this->GrooveCount > 0)
    {
      vtkNew<vtkFloatArray> grooves;
      grooves->SetName("GrooveIntensity");
      output->GetPointData()->AddArray(grooves);
    }
    vtkNew<vtkIntArray> grainFlag;
    grainFlag->SetName("WireFurGrain");
    grainFlag->InsertNextValue(this->Grain);
    output->GetFieldData()->AddArray(grainFlag);
    return 1;
  }
  if (const std::int64_t bad = wf::vtkio::firstCellWithMissingPoints(input); bad >= 0)
  {
    vtkErrorMacro(<< "input cell " << bad << " names a point the input does not have");
    return 1;
  }
  if (const std::int64_t bad = wf::vtkio::firstNonFinitePoint(input); bad >= 0)
  {
    vtkErrorMacro(<< "input point " << bad << " is not finite");
    return 1;
  }
  const glm::dvec3 axisPoint(this->AxisPoint[0], this->AxisPoint[1], this->AxisPoint[2]);
  glm::dvec3 axis(this->AxisDirection[0], this->AxisDirection[1], this->AxisDirection[2]);
  if (!alongUv)
  {
    const double l = glm::length(axis);
    if (!(l > 0) || !std::isfinite(l) || !std::isfinite(axisPoint.x + axisPoint.y + axisPoint.z))
    {
      vtkErrorMacro(<< "radial and circular grain need a finite AxisPoint and a non-zero, finite "
                       "AxisDirection (got "
                    << axis.x << " " << axis.y << " " << axis.z << ")");
      return 1;
    }
    axis /= l;
  }
  if (!(std::isfinite(this->GrooveCount) && this->GrooveCount >= 0))
  {
    vtkErrorMacro(<< "GrooveCount must be finite and >= 0 (got " << this->GrooveCount << ")");
    return 1;
  }
  if (!(this->GrooveDepth >= 0 && this->GrooveDepth <= 1))
  {
    vtkErrorMacro(<< "GrooveDepth must be in [0, 1] (got " << this->GrooveDepth << ")");
    return 1;
  }
  vtkDataArray* tc = wf::vtkio::textureCoordinates(input);
  std::optional<wf::vtkio::ParametricFunctionSurface> function;
  if (this->ParametricFunction)
  {
    function.emplace(this->ParametricFunction);
    if (!function->problem().empty())
    {
      vtkErrorMacro(<< function->problem());
      return 1;
    }
    if (!tc)
    {
      vtkErrorMacro(<< "with a ParametricFunction the input needs the texture coordinates "
                       "vtkParametricFunctionSource writes (GenerateTextureCoordinatesOn)");
      return 1;
    }
  }
  else if (alongUv && !tc)
  {
    vtkErrorMacro(<< "grain along u or v needs texture coordinates (active TCoords, or a "
                     "2-component point array \"TCoords\")");
    return 1;
  }

  const vtkIdType n = input->GetNumberOfPoints();
  std::vector<glm::dvec2> uv(size_t(n), glm::dvec2(0.0));
  if (tc)
  {
    for (vtkIdType i = 0; i < n; ++i)
    {
      uv[size_t(i)] = { tc->GetComponent(i, 0), tc->GetComponent(i, 1) };
    }
  }

  // --- per-point frame: normal and derivatives ------------------------------------------------
  std::vector<glm::dvec3> P(static_cast<size_t>(n));
  std::vector<glm::dvec3> N(P.size(), glm::dvec3(0.0)), Su(P.size(), glm::dvec3(0.0)), Sv(P.size(), glm::dvec3(0.0));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    P[size_t(i)] = { p[0], p[1], p[2] };
  }
  if (!function)
  {
    // Area-weighted means over the triangles around each point.
    vtkDataArray* normals = input->GetPointData()->GetNormals();
    const bool useNormals = normals && normals->GetNumberOfComponents() == 3;
    for (const glm::uvec3& t : wf::vtkio::triangulate(input))
    {
      const glm::dvec3 e1 = P[t.y] - P[t.x], e2 = P[t.z] - P[t.x];
      const glm::dvec3 areaNormal = glm::cross(e1, e2);  // 2 A n
      const double area2 = glm::length(areaNormal);
      if (!useNormals)
      {
        N[t.x] += areaNormal, N[t.y] += areaNormal, N[t.z] += areaNormal;
      }
      if (!tc)
      {
        continue;
      }
      const glm::dvec2 d1 = uv[t.y] - uv[t.x], d2 = uv[t.z] - uv[t.x];
      const double det = d1.x * d2.y - d2.x * d1.y;
      const double scale = std::max({ std::abs(d1.x), std::abs(d1.y), std::abs(d2.x), std::abs(d2.y) });
      if (!(std::abs(det) > 1e-14 * scale * scale))
      {
        continue; // no texture map on this triangle
      }
      const glm::dvec3 su = (e1 * d2.y - e2 * d1.y) / det, sv = (e2 * d1.x - e1 * d2.x) / det;
      for (unsigned v : { t.x, t.y, t.z })
      {
        Su[v] += area2 * su;
        Sv[v] += area2 * sv;
      }
    }
    if (useNormals)
    {
      for (vtkIdType i = 0; i < n; ++i)
      {
        double q[3];
        normals->GetTuple(i, q);
        N[size_t(i)] = { q[0], q[1], q[2] };
      }
    }
  }

  // --- tangents and grooves, in parallel blocks with progress and abort between them ------------
  vtkNew<vtkFloatArray> tangents;
  tangents->SetName("Tangents");
  tangents->SetNumberOfComponents(3);
  tangents->SetNumberOfTuples(n);
  vtkNew<vtkFloatArray> grooves;
  const bool wantGrooves = this->GrooveCount > 0;
  if (wantGrooves)
  {
    grooves->SetName("GrooveIntensity");
    grooves->SetNumberOfTuples(n);
  }
  const wf::GrooveTexture texture(
    wantGrooves ? this->GrooveCount : 1.0, this->GrooveDepth, this->GrooveSeed);
  float* T = tangents->GetPointer(0);
  float* G = wantGrooves ? grooves->GetPointer(0) : nullptr;
  constexpr vtkIdType kBlock = 1 << 16;
  for (vtkIdType first = 0; first < n; first += kBlock)
  {
    this->UpdateProgress(double(first) / double(n));
    if (this->GetAbortExecute())
    {
      output->Initialize();
      return 1;
    }
    wf::vtkio::parallelFor(first, std::min(n, first + kBlock), [&](std::int64_t begin, std::int64_t end) {
      for (vtkIdType i = vtkIdType(begin); i < vtkIdType(end); ++i)
      {
        const size_t k = size_t(i);
        glm::dvec3 normal = N[k], su = Su[k], sv = Sv[k];
        glm::dvec2 coordinate = uv[k];
        if (function)
        {
          // The function's own (u, v), derivatives and (limit) normal.
          coordinate = function->domain().fromUnit(uv[k].x, uv[k].y);
          const wf::SurfaceFrame f = function->frame(coordinate.x, coordinate.y);
          normal = f.N, su = f.Tu, sv = f.Tv;
        }
        const glm::dvec3 t = wf::vtkio::grainTangent(grain, P[k], normal, su, sv, axisPoint, axis);
        T[3 * i] = float(t.x);
        T[3 * i + 1] = float(t.y);
        T[3 * i + 2] = float(t.z);
        if (G)
        {
          G[i] = float(texture.intensity(
            wf::vtkio::grooveCoordinate(grain, P[k], coordinate, axisPoint, axis), 0.0));
        }
      }
    });
  }

  output->ShallowCopy(input);
  output->GetPointData()->SetTangents(tangents);
  if (wantGrooves)
  {
    output->GetPointData()->AddArray(grooves);
  }
  // Says that the active tangents are burnish grain: vtkWireFurRenderPass shades a marked actor
  // of this output as brushed metal (its grain, grooves dimming it) rather than as plastic.
  vtkNew<vtkIntArray> grainFlag;
  grainFlag->SetName("WireFurGrain");
  grainFlag->InsertNextValue(this->Grain);
  output->GetFieldData()->AddArray(grainFlag);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWireFurBurnish::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* names[] = { "U", "V", "Radial", "Circular" };
  os << indent << "Grain: " << names[std::clamp(this->Grain, 0, 3)] << "\n";
  os << indent << "AxisPoint: " << this->AxisPoint[0] << " " << this->AxisPoint[1] << " "
     << this->AxisPoint[2] << "\n";
  os << indent << "AxisDirection: " << this->AxisDirection[0] << " " << this->AxisDirection[1]
     << " " << this->AxisDirection[2] << "\n";
  os << indent << "GrooveCount: " << this->GrooveCount << "\n";
  os << indent << "GrooveDepth: " << this->GrooveDepth << "\n";
  os << indent << "GrooveSeed: " << this->GrooveSeed << "\n";
  os << indent << "ParametricFunction: ";
  if (this->ParametricFunction)
  {
    os << this->ParametricFunction->GetClassName() << " (" << this->ParametricFunction << ")\n";
  }
  else
  {
    os << "(none)\n";
  }
}
