/**
 * @class   vtkWireFurEdgeClasses
 * @brief   a mesh's or a CAD model's edges by class (boundary, sharp, smooth, seam, ...), and a choice of them
 *
 * Input: vtkPolyData. Output: polylines with cell arrays "EdgeClass" (int: 0 boundary, 1 sharp,
 * 2 smooth, 3 seam, 4 free, 5 non-manifold; docs/cad.md "Edge classes and visibility") and
 * "EdgeAngle" (float: the largest angle between the two faces' normals along the edge, degrees;
 * NaN where it is not between two faces), only the edges Mode and Seams keep.
 * - Polygons (and triangle strips' triangles): every polygon edge, classified from the polygons
 *   around it (points within 1e-9 of the mesh's size joined first; one polygon, boundary; two,
 *   sharp or smooth by the angle between their Newell normals against FeatureAngle; more,
 *   non-manifold), the kept ones chained into polylines where two of one class meet.
 * - No polygons, and lines with an "EdgeClass" array (vtkWireFurCADReader's edges output): those
 *   lines, with the ones of class sharp or smooth classified again by "EdgeAngle" against
 *   FeatureAngle; cells with EdgeClass < 0 (iso lines) are left out. Other cell arrays are
 *   passed on.
 * Mode: 0 all (every edge but seams; default), 1 sharp (boundary, sharp, free and non-manifold
 * edges: "hard edges only"), 2 boundary (boundary and free edges). Seams: seam edges too (default
 * off). FeatureAngle: degrees, 0 ... 180, default 10.
 *
 * Bad input: a cell naming a missing point or a NaN / Inf point is an error and an empty output.
 */
#ifndef vtkWireFurEdgeClasses_h
#define vtkWireFurEdgeClasses_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class WIREFURFILTERS_EXPORT vtkWireFurEdgeClasses : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurEdgeClasses* New();
  vtkTypeMacro(vtkWireFurEdgeClasses, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Which edges: 0 all, 1 sharp, 2 boundary.
  vtkSetClampMacro(Mode, int, 0, 2);
  vtkGetMacro(Mode, int);
  void SetModeToAll() { this->SetMode(0); }
  void SetModeToSharp() { this->SetMode(1); }
  void SetModeToBoundary() { this->SetMode(2); }
  ///@}

  ///@{
  vtkSetMacro(Seams, vtkTypeBool);
  vtkGetMacro(Seams, vtkTypeBool);
  vtkBooleanMacro(Seams, vtkTypeBool);
  ///@}

  ///@{
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  ///@}

  /// Edges of each class (0-5) found by the last update, before the choice.
  vtkIdType GetNumberOfEdgesOfClass(int edgeClass) const;

protected:
  vtkWireFurEdgeClasses() = default;
  ~vtkWireFurEdgeClasses() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode = 0;
  vtkTypeBool Seams = false;
  double FeatureAngle = 10.0;
  vtkIdType Counts[6] = {};

private:
  vtkWireFurEdgeClasses(const vtkWireFurEdgeClasses&) = delete;
  void operator=(const vtkWireFurEdgeClasses&) = delete;
};

#endif
