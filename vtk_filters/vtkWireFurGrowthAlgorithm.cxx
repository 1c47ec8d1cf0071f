#include "vtkWireFurGrowthAlgorithm.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkParametricFunction.h"
#include "vtkPolyData.h"

#include <algorithm>

vtkCxxSetObjectMacro(vtkWireFurGrowthAlgorithm, ParametricFunction, vtkParametricFunction);

vtkWireFurGrowthAlgorithm::vtkWireFurGrowthAlgorithm()
{
  this->SetNumberOfInputPorts(1);
}

vtkWireFurGrowthAlgorithm::~vtkWireFurGrowthAlgorithm()
{
  this->SetParametricFunction(nullptr);
}

vtkMTimeType vtkWireFurGrowthAlgorithm::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->ParametricFunction)
  {
    t = std::max(t, this->ParametricFunction->GetMTime());
  }
  return t;
}

int vtkWireFurGrowthAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

vtkPolyData* vtkWireFurGrowthAlgorithm::GrowthInput(vtkInformationVector** inputVector)
{
  return this->ParametricFunction ? nullptr : vtkPolyData::GetData(inputVector[0], 0);
}

void vtkWireFurGrowthAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ParametricFunction: ";
  if (this->ParametricFunction)
  {
    os << this->ParametricFunction->GetClassName() << " (" << this->ParametricFunction << ")\n";
  }
  else
  {
    os << "(none)\n";
  }
  os << indent << "FlipNormals: " << this->FlipNormals << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "PatchIndex: " << this->PatchIndex << "\n";
}
