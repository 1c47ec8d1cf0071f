/**
 * @class   vtkWireFurScalesGenerator
 * @brief   grows scales (two triangles each) on a parametric surface or a mesh with texture coordinates
 *
 * The scales of WireFur's core (wf::growScales; Miller 1988, section 4.2, images 17 and 21) as a
 * VTK filter: the parameter domain is cut into CellsU x CellsV rectangles, each holding a scale at
 * its corner and one at its centre, each scale a kite of two triangles tilted up by Lift with its
 * vertex normals deflected outwards. The surface is SetParametricFunction (exact derivatives; takes
 * precedence) or the optional vtkPolyData on input port 0 with texture coordinates (its (u, v)).
 *
 * Output (vtkPolyData, double precision points): 4 points and 2 triangles per scale, so
 * 4 * CellsU * CellsV triangles when every root is regular (a root at a pole, a non-finite point or
 * outside the mesh's uv layout grows no scale); point normals (active, float), point tangents Tu
 * (active, float, "Tangents"), texture coordinates "TCoords" (active, the root's (u, v) on all four
 * vertices), "Colors" (unsigned char RGB, active scalars: the linear Color * the scale's
 * intensity, clamped to [0, 1] and sRGB-encoded — keep Color below 1 / (1 + IntensityVariation) to
 * keep the whole variation);
 * cell array "ScaleId" (vtkTypeUInt64Array: (PatchIndex << 32) | scale index, the scale index being
 * 2 c for the corner scale and 2 c + 1 for the centre scale of cell c = j CellsU + i; both triangles
 * of a scale carry it).
 *
 * Defaults (the core's ScaleParams): CellsU = CellsV = 16, Size = 1.5, Lift = 0.25,
 * Deflection = 0.6, IntensityVariation = 0.25, Shoulder = 0.4, Color = (1, 1, 1), Seed = 1,
 * PatchIndex = 0. Out-of-range, NaN or infinite values are not clamped: RequestData reports them
 * (vtkErrorMacro, the core's message) and outputs an empty vtkPolyData, as for a missing surface,
 * a mesh without texture coordinates or with a NaN point. An empty mesh (a rank's empty piece)
 * grows nothing, no error.
 */
#ifndef vtkWireFurScalesGenerator_h
#define vtkWireFurScalesGenerator_h

#include "WireFurFiltersModule.h"
#include "vtkWireFurGrowthAlgorithm.h"


class WIREFURFILTERS_EXPORT vtkWireFurScalesGenerator : public vtkWireFurGrowthAlgorithm
{
public:
  static vtkWireFurScalesGenerator* New();
  vtkTypeMacro(vtkWireFurScalesGenerator, vtkWireFurGrowthAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The most triangles one execution may make (4 per cell; checked before anything is
  /// allocated: an error and an empty output past it). Default 16,777,216 (about 2.5 GB).
  vtkSetClampMacro(MaximumTriangles, double, 0.0, 1e12);
  vtkGetMacro(MaximumTriangles, double);
  ///@}

  ///@{
  /// Parametric cells along u and v, 1 ... 16384 each, at most 2^24 in all. Defaults 16, 16.
  vtkSetMacro(CellsU, int);
  vtkGetMacro(CellsU, int);
  vtkSetMacro(CellsV, int);
  vtkGetMacro(CellsV, int);
  ///@}

  ///@{
  /// Scale length and width as a fraction of the cell, (0, 16]. Default 1.5.
  vtkSetMacro(Size, double);
  vtkGetMacro(Size, double);
  ///@}

  ///@{
  /// Tip height above the surface as a fraction of the length, [0, 16]. Default 0.25.
  vtkSetMacro(Lift, double);
  vtkGetMacro(Lift, double);
  ///@}

  ///@{
  /// Outward bend of the vertex normals, [0, 16] (0: flat). Default 0.6.
  vtkSetMacro(Deflection, double);
  vtkGetMacro(Deflection, double);
  ///@}

  ///@{
  /// Per-scale intensity within +-IntensityVariation of 1, [0, 1]. Default 0.25.
  vtkSetMacro(IntensityVariation, double);
  vtkGetMacro(IntensityVariation, double);
  ///@}

  ///@{
  /// Position of the side vertices along the scale, (0, 1). Default 0.4.
  vtkSetMacro(Shoulder, double);
  vtkGetMacro(Shoulder, double);
  ///@}

  ///@{
  /// Linear base colour (>= 0). Default (1, 1, 1).
  vtkSetVector3Macro(Color, double);
  vtkGetVector3Macro(Color, double);
  ///@}



protected:
  vtkWireFurScalesGenerator();
  ~vtkWireFurScalesGenerator() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MaximumTriangles = 16777216.0;
  int CellsU = 16;
  int CellsV = 16;
  double Size = 1.5;
  double Lift = 0.25;
  double Deflection = 0.6;
  double IntensityVariation = 0.25;
  double Shoulder = 0.4;
  double Color[3] = { 1.0, 1.0, 1.0 };

private:
  vtkWireFurScalesGenerator(const vtkWireFurScalesGenerator&) = delete;
  void operator=(const vtkWireFurScalesGenerator&) = delete;
};

#endif
