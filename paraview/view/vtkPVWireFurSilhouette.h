/**
 * @class   vtkPVWireFurSilhouette
 * @brief   vtkWireFurSilhouette with its camera as properties, for ParaView
 *
 * The plugin's proxy for the silhouettes of the CAD reader's faces (exact) or of a mesh. A filter on a pvserver cannot see the client's view, so the
 * camera is given as properties named as the render view's (CameraPosition, CameraFocalPoint,
 * CameraViewUp, CameraViewAngle, CameraParallelProjection, CameraParallelScale): in Python,
 * copying them from the view is one loop (docs/paraview.md). The camera's clipping range is
 * fitted to the inputs' bounds (wf_pv_camera.h); it is not a property. Changing a camera
 * property re-executes the filter, nothing else about the camera does.
 */
#ifndef vtkPVWireFurSilhouette_h
#define vtkPVWireFurSilhouette_h

#include "WireFurParaViewViewModule.h"
#include "vtkNew.h"
#include "vtkWireFurSilhouette.h"

class vtkCamera;

class WIREFURPARAVIEWVIEW_EXPORT vtkPVWireFurSilhouette : public vtkWireFurSilhouette
{
public:
  static vtkPVWireFurSilhouette* New();
  vtkTypeMacro(vtkPVWireFurSilhouette, vtkWireFurSilhouette);
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
  vtkPVWireFurSilhouette();
  ~vtkPVWireFurSilhouette() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkNew<vtkCamera> ViewCamera;

private:
  vtkPVWireFurSilhouette(const vtkPVWireFurSilhouette&) = delete;
  void operator=(const vtkPVWireFurSilhouette&) = delete;
};

#endif
