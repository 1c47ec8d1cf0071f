#include "vtkWireFurMapSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "shading/light.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

vtkStandardNewMacro(vtkWireFurMapSource);

vtkWireFurMapSource::vtkWireFurMapSource()
{
  this->SetNumberOfInputPorts(0);
}

int vtkWireFurMapSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* info = outputVector->GetInformationObject(0);
  const int n = this->Resolution;
  int extent[6] = { 0, n - 1, 0, n - 1, 0, 0 };
  info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  // Texel centres over [-1, 1]^2: the table's own coordinates.
  const double spacing[3] = { 2.0 / (n - 1), 2.0 / (n - 1), 1.0 };
  const double origin[3] = { -1.0, -1.0, 0.0 };
  info->Set(vtkDataObject::SPACING(), spacing, 3);
  info->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(info, VTK_FLOAT, 3);
  return 1;
}

int vtkWireFurMapSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* out = vtkImageData::GetData(outputVector);
  const int n = this->Resolution;
  out->SetExtent(0, n - 1, 0, n - 1, 0, 0);
  out->SetSpacing(2.0 / (n - 1), 2.0 / (n - 1), 1.0);
  out->SetOrigin(-1.0, -1.0, 0.0);

  wf::PhongMaterial m;
  m.diffuse = glm::dvec3(this->Diffuse[0], this->Diffuse[1], this->Diffuse[2]);
  m.specular = glm::dvec3(this->Specular[0], this->Specular[1], this->Specular[2]);
  m.exponent = this->Exponent;
  m = m.sanitized();
  const wf::LightRig rig = wf::LightRig::studioRig(this->LightCount).canonical();

  vtkNew<vtkFloatArray> radiance;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  radiance->SetNumberOfTuples(vtkIdType(n) * n);
  if (this->Table == ReflectanceSphere)
  {
    const wf::ReflectanceSphere sphere = wf::ReflectanceSphere::phong(n, m, rig);
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const glm::vec3 c = sphere.lookupTable(-1.0 + 2.0 * i / (n - 1), -1.0 + 2.0 * j / (n - 1));
        radiance->SetTypedTuple(vtkIdType(j) * n + i, &c.x);
      }
    }
  }
  else
  {
    wf::PseudoReflectanceMapOptions options;
    options.resolution = n;
    options.samples = this->Samples;
    wf::PseudoReflectanceMap map;
    map.build(m, rig, options);
    const auto plane = this->Table == XZMap ? wf::PseudoReflectanceMap::Plane::XZ : wf::PseudoReflectanceMap::Plane::YZ;
    for (int j = 0; j < n; ++j)
    {
      this->UpdateProgress(double(j) / n);
      if (this->GetAbortExecute())
      {
        break;
      }
      for (int i = 0; i < n; ++i)
      {
        const glm::vec3 c = map.lookupPlane(plane, -1.0 + 2.0 * i / (n - 1), -1.0 + 2.0 * j / (n - 1));
        radiance->SetTypedTuple(vtkIdType(j) * n + i, &c.x);
      }
    }
  }
  out->GetPointData()->SetScalars(radiance);
  return 1;
}

void vtkWireFurMapSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Table: " << this->Table << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "Samples: " << this->Samples << "\n";
  os << indent << "Diffuse: " << this->Diffuse[0] << " " << this->Diffuse[1] << " " << this->Diffuse[2] << "\n";
  os << indent << "Specular: " << this->Specular[0] << " " << this->Specular[1] << " " << this->Specular[2] << "\n";
  os << indent << "Exponent: " << this->Exponent << "\n";
  os << indent << "LightCount: " << this->LightCount << "\n";
}
