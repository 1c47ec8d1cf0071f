/**
 * @class   vtkPVWireFurEdgeVisibility
 * @brief   vtkWireFurEdgeVisibility with its camera as properties, for ParaView
 *
 * The plugin's proxy for the edges cut where the surfaces (port 1) hide them, marked Visible. A filter on a pvserver cannot see the client's view, so the
 * camera is given as properties named as the render view's (CameraPosition, CameraFocalPoint,
 * CameraViewUp, CameraViewAngle, CameraParallelProjection, CameraParallelScale): in Python,
 * copying them from the view is one loop (docs/paraview.md). The camera's clipping range is
 * fitted to the inputs' bounds (wf_pv_camera.h); it is not a property. Changing a camera
 * property re-executes the filter, nothing else about the camera does.
 */
#ifndef vtkPVWireFurEdgeVisibility_h
#define vtkPVWireFurEdgeVisibility_h

#include "WireFurParaViewViewModule.h"
#include "vtkNew.h"
#include "vtkWireFurEdgeVisibility.h"

class vtkCamera;

class WIREFURPARAVIEWVIEW_EXPORT vtkPVWireFurEdgeVisibility : public vtkWireFurEdgeVisibility
{
public:
  static vtkPVWireFurEdgeVisibility* New();
  vtkTypeMacro(vtkPVWireFurEdgeVisibility, vtkWireFurEdgeVisibility);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The camera, as vtkCamera's setters (defaults: ParaView's first view, from (0, 0, 6.69)).
  void SetCameraPosition(double x, double y, double z);
  void SetCameraFocalPoint(double x, double y, double z);
  void SetCameraViewUp(double x, double y, double z);
  void SetCameraViewAngle(double degrees);
  void SetCameraParallelProjection(int on);
  void SetCameraParallelScale(double scale);
  ///@}

  /// This filter's own time and its properties', not the camera's (whose clipping range each
  /// update sets).
  vtkMTimeType GetMTime() override;

protected:
  vtkPVWireFurEdgeVisibility();
  ~vtkPVWireFurEdgeVisibility() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkNew<vtkCamera> ViewCamera;

private:
  vtkPVWireFurEdgeVisibility(const vtkPVWireFurEdgeVisibility&) = delete;
  void operator=(const vtkPVWireFurEdgeVisibility&) = delete;
};

#endif
