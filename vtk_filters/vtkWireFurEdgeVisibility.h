/**
 * @class   vtkWireFurEdgeVisibility
 * @brief   a wire-frame cut where surfaces hide it from a camera, each piece marked seen or hidden
 *
 * Input port 0: vtkPolyData whose lines are the wire-frame (edges, silhouettes). Port 1
 * (optional; without it nothing hides, and only the view clips): the occluding surfaces
 * (vtkPolyData polygons and strips; often the CAD reader's faces). Output: the
 * lines cut into pieces each wholly seen or not, with the input line's cell data copied to each
 * of its pieces and the cell array "Visible" (unsigned char: 1 seen, 0 not seen: hidden, or
 * outside the view: before the near plane, beyond the far one, off the ViewportSize image).
 * As `wirefur export --visibility` (src/scene/edge_visibility.h): each segment clipped to the
 * view, the polygons binned on the screen, a point hidden when the ray from it towards the viewer
 * (as far as the near plane) crosses a polygon more than 1e-7 of its distance in front of it
 * (exact ray tests in double, so an edge on its own face's tessellation is seen), the part in the
 * view sampled every SamplePixels of its screen length and each change bisected to 1e-3 px. The
 * camera's clipping range is used as it is (ResetCameraClippingRange to fit it to the data).
 * Silhouettes get SilhouetteSlack.
 * Camera: SetCamera, else the Renderer's active camera (held weakly; its size, when it has one,
 * replaces ViewportSize). Re-executes when the camera moves.
 */
#ifndef vtkWireFurEdgeVisibility_h
#define vtkWireFurEdgeVisibility_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkCamera;
class vtkRenderer;

class WIREFURFILTERS_EXPORT vtkWireFurEdgeVisibility : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurEdgeVisibility* New();
  vtkTypeMacro(vtkWireFurEdgeVisibility, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The occluding surfaces (input port 1).
  void SetSurfaceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSurfaceData(vtkDataObject* data) { this->SetInputData(1, data); }

  ///@{
  void SetCamera(vtkCamera* camera);
  vtkCamera* GetCamera();
  void SetRenderer(vtkRenderer* renderer);
  vtkRenderer* GetRenderer();
  ///@}

  ///@{
  /// The screen the sampling is measured on, pixels (default 1000 x 1000).
  vtkSetVector2Macro(ViewportSize, int);
  vtkGetVector2Macro(ViewportSize, int);
  ///@}

  ///@{
  /// Sample spacing along each segment on screen, pixels (default 0.5, 0.01 ... 100).
  vtkSetClampMacro(SamplePixels, double, 0.01, 100.0);
  vtkGetMacro(SamplePixels, double);
  ///@}

  ///@{
  /// Hits nearer than this to a point of a silhouette (a line whose "EdgeClass" is 6) do not
  /// hide it, world units. Negative or NaN (default -1): the larger of sqrt(2 deflection r) (the
  /// deflection from the surfaces' "LinearDeflection" field, which the CAD reader writes; r half
  /// their bounding box's diagonal) and the width of the surface's triangles at the point
  /// (wf::VisibilityOptions in src/scene/edge_visibility.h). A silhouette, exact (on the true
  /// surface) or from a mesh's normals (inside a triangle), has a grazing ray that the
  /// tessellation's chords can cross near the point: with no slack about half a sphere mesh's
  /// silhouette is taken as hidden.
  vtkSetMacro(SilhouetteSlack, double);
  vtkGetMacro(SilhouetteSlack, double);
  ///@}

  /// World length of the seen and hidden pieces, and the cuts made, in the last update.
  double GetVisibleLength() const { return this->VisibleLength; }
  double GetHiddenLength() const { return this->HiddenLength; }
  vtkIdType GetNumberOfSplits() const { return this->Splits; }

  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurEdgeVisibility();
  ~vtkWireFurEdgeVisibility() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  class vtkInternals;  // the camera and renderer (wfvtk::FilterView)
  vtkInternals* Internals;
  int ViewportSize[2] = { 1000, 1000 };
  double SamplePixels = 0.5;
  double SilhouetteSlack = -1.0;
  double VisibleLength = 0, HiddenLength = 0;
  vtkIdType Splits = 0;

private:
  vtkWireFurEdgeVisibility(const vtkWireFurEdgeVisibility&) = delete;
  void operator=(const vtkWireFurEdgeVisibility&) = delete;
};

#endif
