#include "vtkPVWireFurEdgeVisibility.h"

#include "wf_pv_camera.h"

#include "vtkCamera.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkPVWireFurEdgeVisibility);

vtkPVWireFurEdgeVisibility::vtkPVWireFurEdgeVisibility()
{
  this->ViewCamera->SetPosition(0, 0, 6.69);
  this->SetCamera(this->ViewCamera);
}

vtkPVWireFurEdgeVisibility::~vtkPVWireFurEdgeVisibility() = default;

WFPV_CAMERA_FILTER_MEMBERS(vtkPVWireFurEdgeVisibility)
