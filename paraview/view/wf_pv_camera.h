// The camera of the plugin's view-dependent filters (vtkPVWireFurSilhouette,
// vtkPVWireFurEdgeVisibility): a filter on a pvserver cannot see the client's view, so the
// camera comes as properties named as the render view's own (CameraPosition, ...), and its
// clipping range is fitted to the data each time the filter runs.
#pragma once

#include "vtkPolyDataAlgorithm.h"

class vtkCamera;
class vtkInformationVector;

namespace wfpv {

/// Sets camera's clipping range to hold the bounds of every input on ports [0, ports): nearest
/// and farthest corner along the view direction, with 1% to spare (near at least 1e-3 of far,
/// as VTK's renderer keeps it).
/// Does not touch the camera when nothing is in front of it.
void fitClippingRange(vtkCamera* camera, vtkInformationVector** inputs, int ports);

}  // namespace wfpv

/// The camera setters, GetMTime and RequestData of a view-dependent filter `Class` with a member
/// vtkNew<vtkCamera> ViewCamera (the same in both filters). Each setter marks the filter, and
/// GetMTime leaves the camera out: the clipping range set in RequestData re-executes nothing.
#define WFPV_CAMERA_FILTER_MEMBERS(Class)                                                                  \
  void Class::SetCameraPosition(double x, double y, double z)                                              \
  {                                                                                                        \
    this->ViewCamera->SetPosition(x, y, z), this->Modified();                                              \
  }                                                                                                        \
  void Class::SetCameraFocalPoint(double x, double y, double z)                                            \
  {                                                                                                        \
    this->ViewCamera->SetFocalPoint(x, y, z), this->Modified();                                            \
  }                                                                                                        \
  void Class::SetCameraViewUp(double x, double y, double z)                                                \
  {                                                                                                        \
    this->ViewCamera->SetViewUp(x, y, z), this->Modified();                                                \
  }                                                                                                        \
  void Class::SetCameraViewAngle(double degrees) { this->ViewCamera->SetViewAngle(degrees), this->Modified(); } \
  void Class::SetCameraParallelProjection(int on)                                                          \
  {                                                                                                        \
    this->ViewCamera->SetParallelProjection(on), this->Modified();                                         \
  }                                                                                                        \
  void Class::SetCameraParallelScale(double scale)                                                         \
  {                                                                                                        \
    this->ViewCamera->SetParallelScale(scale), this->Modified();                                           \
  }                                                                                                        \
  vtkMTimeType Class::GetMTime() { return this->vtkPolyDataAlgorithm::GetMTime(); }                        \
  int Class::RequestData(vtkInformation* request, vtkInformationVector** inputs, vtkInformationVector* outputs) \
  {                                                                                                        \
    wfpv::fitClippingRange(this->ViewCamera, inputs, this->GetNumberOfInputPorts());                       \
    return this->Superclass::RequestData(request, inputs, outputs);                                        \
  }                                                                                                        \
  void Class::PrintSelf(ostream& os, vtkIndent indent)                                                     \
  {                                                                                                        \
    this->Superclass::PrintSelf(os, indent);                                                               \
    os << indent << "ViewCamera:\n";                                                                       \
    this->ViewCamera->PrintSelf(os, indent.GetNextIndent());                                               \
  }
