/**
 * @class   vtkWireFurSilhouette
 * @brief   the silhouettes of a surface for a camera: exact for the CAD reader's faces, from normals for meshes
 *
 * Input: vtkPolyData with polygons. Output: polylines in world space where the surface turns away
 * from the viewer (N . V = 0 for the true, perspective view vector V), cell array "EdgeClass" = 6
 * (silhouette; docs/cad.md). Re-executes when the camera moves (its MTime is part of this
 * filter's).
 * - Exact path: when the input is vtkWireFurCADReader's faces output (port 0) and UseExactSurfaces
 *   is on (default), each face's silhouette is traced on its own (u, v) domain from
 *   OpenCASCADE's surface and trimmed by the face (src/surface/silhouette.h: marching squares on
 *   32 x 32 cells, roots to 1e-13, chords refined until within TolerancePixels of the curve on a
 *   ViewportSize screen), as `wirefur render` draws CAD silhouettes. The reader's module is
 *   found through the reader object itself: nothing here links OpenCASCADE.
 * - Mesh path (any other input, or UseExactSurfaces off): g = N . V at each point from the point
 *   normals ("Normals", else computed by vtkPolyDataNormals without splitting), its zero set
 *   traced linearly across each triangle (polygons fanned, strips split) and joined into polylines
 *   (vtkStripper). Its error is the tessellation's: O(h^2) across a face of curvature 1/R for
 *   triangles of size h.
 * Camera: SetCamera, else the Renderer's active camera (the Renderer, held weakly, also gives
 * ViewportSize when it has a size); without either, an error and an empty output.
 * UsedExactSurfaces() says which path the last update took.
 */
#ifndef vtkWireFurSilhouette_h
#define vtkWireFurSilhouette_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkCamera;
class vtkRenderer;

class WIREFURFILTERS_EXPORT vtkWireFurSilhouette : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurSilhouette* New();
  vtkTypeMacro(vtkWireFurSilhouette, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  void SetCamera(vtkCamera* camera);
  vtkCamera* GetCamera();
  void SetRenderer(vtkRenderer* renderer);
  vtkRenderer* GetRenderer();
  ///@}

  ///@{
  /// The screen the tolerance is measured on, pixels (default 1000 x 1000; a Renderer with a
  /// size gives its own).
  vtkSetVector2Macro(ViewportSize, int);
  vtkGetVector2Macro(ViewportSize, int);
  ///@}

  ///@{
  /// Exact path: the largest distance on screen between a chord and the curve, pixels (default
  /// 0.1, 0.001 ... 100).
  vtkSetClampMacro(TolerancePixels, double, 0.001, 100.0);
  vtkGetMacro(TolerancePixels, double);
  ///@}

  ///@{
  vtkSetMacro(UseExactSurfaces, vtkTypeBool);
  vtkGetMacro(UseExactSurfaces, vtkTypeBool);
  vtkBooleanMacro(UseExactSurfaces, vtkTypeBool);
  ///@}

  bool UsedExactSurfaces() const { return this->Exact; }

  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurSilhouette();
  ~vtkWireFurSilhouette() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  class vtkInternals;  // the camera and renderer (wfvtk::FilterView)
  vtkInternals* Internals;
  int ViewportSize[2] = { 1000, 1000 };
  double TolerancePixels = 0.1;
  vtkTypeBool UseExactSurfaces = true;
  bool Exact = false;

private:
  vtkWireFurSilhouette(const vtkWireFurSilhouette&) = delete;
  void operator=(const vtkWireFurSilhouette&) = delete;
};

#endif
