#include "vtkPVWireFurSilhouette.h"

#include "wf_pv_camera.h"

#include "vtkCamera.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkPVWireFurSilhouette);

vtkPVWireFurSilhouette::vtkPVWireFurSilhouette()
{
  this->ViewCamera->SetPosition(0, 0, 6.69);
  this->SetCamera(this->ViewCamera);
}

vtkPVWireFurSilhouette::~vtkPVWireFurSilhouette() = default;

WFPV_CAMERA_FILTER_MEMBERS(vtkPVWireFurSilhouette)
