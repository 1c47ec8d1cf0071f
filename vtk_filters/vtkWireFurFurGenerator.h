/**
 * @class   vtkWireFurFurGenerator
 * @brief   grows fur (one polyline per hair) on a parametric surface or a mesh with texture coordinates
 *
 * The fur of WireFur's core (wf::growFur; Miller 1988, section 4.2, and the paper's future work:
 * area-correct placement, curved hairs, clumping, wind) as a VTK filter. The surface is either
 * SetParametricFunction (exact derivatives; takes precedence) or the optional vtkPolyData on input
 * port 0 with texture coordinates, whose (u, v) are the texture coordinates (polygons are fanned;
 * a root whose (u, v) lies in no triangle of the uv layout grows no hair).
 *
 * Output (vtkPolyData): one polyline of Segments + 1 points per hair (root first, double precision
 * points), ordered by root, never by thread timing; point array "Colors" (unsigned char RGB, the
 * active scalars: the core's linear colour, root colour blending to tip colour, clamped to [0, 1]
 * and sRGB-encoded, as VTK displays 8-bit colours and vtkWireFurRenderPass decodes them); cell arrays "HairId" (vtkTypeUInt64Array: (PatchIndex << 32) | root index, stable:
 * in AreaCorrect placement a higher Density only adds hairs, every old id keeps its points) and
 * "RootUV" (double, the root's (u, v)); field data "Thickness" (one double: the hair diameter).
 *
 * Defaults (the core's FurParams): Placement = Grid, GridU = 100, GridV = 70, Jitter = 1,
 * Density = 2e4, CellsU = CellsV = 64, Orientation = (0, 0, 1), UnitTangents = off,
 * LengthMode = Fixed, Length = 0.1, LengthPerSu = 0.05, LengthVariation = 0.2,
 * IntensityVariation = 0.1, Segments = 1, Gravity = 0, GravityDirection = (0, 0, -1),
 * CurlAmplitude = 0, CurlFrequency = 2, Clumping = 0, ClumpCellsU = ClumpCellsV = 16,
 * WindDirection = (1, 0, 0), WindStrength = 0, WindSway = 0.5, WindFrequency = 1, Time = 0,
 * RootColor = (0.30, 0.20, 0.12), TipColor = (0.55, 0.42, 0.30), Thickness = 0.003, Seed = 1,
 * PatchIndex = 0. Ranges are those of wf::FurParams (docs/growth.md); a value out of range, NaN or
 * infinite is not clamped: RequestData reports it (vtkErrorMacro, naming the field) and outputs an
 * empty vtkPolyData. So do a missing surface, a mesh without texture coordinates and a mesh with a
 * NaN point. An empty mesh (a rank's empty piece in a parallel pipeline) grows nothing, no error.
 *
 * Growth runs in parallel (oneTBB, inside the core) and is bit-identical for any thread count.
 * Progress is reported and the abort flag checked around the growth and while filling the output.
 */
#ifndef vtkWireFurFurGenerator_h
#define vtkWireFurFurGenerator_h

#include "WireFurFiltersModule.h"
#include "vtkSmartPointer.h"

#include <array>
#include <vector>
#include "vtkWireFurGrowthAlgorithm.h"

class vtkImageData;

class WIREFURFILTERS_EXPORT vtkWireFurFurGenerator : public vtkWireFurGrowthAlgorithm
{
public:
  static vtkWireFurFurGenerator* New();
  vtkTypeMacro(vtkWireFurFurGenerator, vtkWireFurGrowthAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Placements
  {
    Grid = 0,       ///< GridU x GridV dithered (u, v) grid (the paper)
    AreaCorrect = 1 ///< Density roots per unit area
  };
  enum LengthModes
  {
    Paper = 0,           ///< |a Su + b Sv + c N|
    Fixed = 1,           ///< Length world units
    ProportionalToSu = 2 ///< LengthPerSu * |Su|
  };


  ///@{
  /// Root placement, Grid or AreaCorrect. Default Grid.
  vtkSetClampMacro(Placement, int, Grid, AreaCorrect);
  vtkGetMacro(Placement, int);
  void SetPlacementToGrid() { this->SetPlacement(Grid); }
  void SetPlacementToAreaCorrect() { this->SetPlacement(AreaCorrect); }
  ///@}

  ///@{
  /// Grid: roots per row and rows, each 1 ... 2^20. Defaults 100, 70.
  vtkSetMacro(GridU, int);
  vtkGetMacro(GridU, int);
  vtkSetMacro(GridV, int);
  vtkGetMacro(GridV, int);
  ///@}

  ///@{
  /// Grid: dither as a fraction of the grid increment, [0, 1]. Default 1.
  vtkSetMacro(Jitter, double);
  vtkGetMacro(Jitter, double);
  ///@}

  ///@{
  /// AreaCorrect: expected roots per unit area (>= 0), counted on a fixed lattice of CellsU x CellsV
  /// parameter cells (1 ... 4096 each, product <= 2^22). Defaults 2e4, 64, 64.
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  vtkSetMacro(CellsU, int);
  vtkGetMacro(CellsU, int);
  vtkSetMacro(CellsV, int);
  vtkGetMacro(CellsV, int);
  ///@}

  ///@{
  /// The hair's axis along a Su + b Sv + c N. Default (0, 0, 1).
  vtkSetVector3Macro(Orientation, double);
  vtkGetVector3Macro(Orientation, double);
  ///@}

  ///@{
  /// Use unit tangents Tu, Tv instead of Su, Sv in the orientation. Default off.
  vtkSetMacro(UnitTangents, vtkTypeBool);
  vtkGetMacro(UnitTangents, vtkTypeBool);
  vtkBooleanMacro(UnitTangents, vtkTypeBool);
  ///@}

  ///@{
  /// Length mode: Paper, Fixed or ProportionalToSu. Default Fixed.
  vtkSetClampMacro(LengthMode, int, Paper, ProportionalToSu);
  vtkGetMacro(LengthMode, int);
  ///@}

  ///@{
  /// Fixed: length in world units (>= 0), default 0.1. ProportionalToSu: k (>= 0), default 0.05.
  vtkSetMacro(Length, double);
  vtkGetMacro(Length, double);
  vtkSetMacro(LengthPerSu, double);
  vtkGetMacro(LengthPerSu, double);
  ///@}

  ///@{
  /// Random length variation, [0, 1). Default 0.2.
  vtkSetMacro(LengthVariation, double);
  vtkGetMacro(LengthVariation, double);
  ///@}

  ///@{
  /// Random colour intensity variation, [0, 1]. Default 0.1.
  vtkSetMacro(IntensityVariation, double);
  vtkGetMacro(IntensityVariation, double);
  ///@}

  ///@{
  /// Line segments per hair, 1 ... 64. Default 1 (the paper's straight hairs).
  vtkSetMacro(Segments, int);
  vtkGetMacro(Segments, int);
  ///@}

  ///@{
  /// Droop towards GravityDirection (world). Defaults 0 and (0, 0, -1).
  vtkSetMacro(Gravity, double);
  vtkGetMacro(Gravity, double);
  vtkSetVector3Macro(GravityDirection, double);
  vtkGetVector3Macro(GravityDirection, double);
  ///@}

  ///@{
  /// Curl: helix radius about CurlAmplitude * length (>= 0), CurlFrequency turns per hair.
  /// Defaults 0 and 2.
  vtkSetMacro(CurlAmplitude, double);
  vtkGetMacro(CurlAmplitude, double);
  vtkSetMacro(CurlFrequency, double);
  vtkGetMacro(CurlFrequency, double);
  ///@}

  ///@{
  /// Clumping, [0, 1], towards clump centres on a ClumpCellsU x ClumpCellsV lattice (1 ... 4096).
  /// Defaults 0, 16, 16.
  vtkSetMacro(Clumping, double);
  vtkGetMacro(Clumping, double);
  vtkSetMacro(ClumpCellsU, int);
  vtkGetMacro(ClumpCellsU, int);
  vtkSetMacro(ClumpCellsV, int);
  vtkGetMacro(ClumpCellsV, int);
  ///@}

  ///@{
  /// Wind as a function of Time: direction (world), strength (0 = none), sway in [0, 1], frequency.
  /// Defaults (1, 0, 0), 0, 0.5, 1; Time 0.
  vtkSetVector3Macro(WindDirection, double);
  vtkGetVector3Macro(WindDirection, double);
  vtkSetMacro(WindStrength, double);
  vtkGetMacro(WindStrength, double);
  vtkSetMacro(WindSway, double);
  vtkGetMacro(WindSway, double);
  vtkSetMacro(WindFrequency, double);
  vtkGetMacro(WindFrequency, double);
  vtkSetMacro(Time, double);
  vtkGetMacro(Time, double);
  ///@}

  ///@{
  /// Linear colours at the root and the tip. Defaults (0.30, 0.20, 0.12), (0.55, 0.42, 0.30).
  vtkSetVector3Macro(RootColor, double);
  vtkGetVector3Macro(RootColor, double);
  vtkSetVector3Macro(TipColor, double);
  vtkGetVector3Macro(TipColor, double);
  ///@}

  ///@{
  /// Hair diameter in world units (>= 0), written to field data "Thickness". Default 0.003.
  vtkSetMacro(Thickness, double);
  vtkGetMacro(Thickness, double);
  ///@}


  ///@{
  /// Maps over the patch's unit coordinates (s, t) in [0, 1]^2 (s along u, t along v; image row 0
  /// at t = 0, bilinear, wrapping where the surface is periodic), each optional (null: none):
  /// - DensityMap: scales the density (AreaCorrect) by its first component (>= 0);
  /// - LengthMap: scales each hair's length by its first component;
  /// - OrientationMap: 3 components replacing the orientation's (a, b, c);
  /// - RootColorMap: RGB replacing RootColor (unsigned char: sRGB-encoded; float: linear).
  void SetDensityMap(vtkImageData* map);
  vtkImageData* GetDensityMap();
  void SetLengthMap(vtkImageData* map);
  vtkImageData* GetLengthMap();
  void SetOrientationMap(vtkImageData* map);
  vtkImageData* GetOrientationMap();
  void SetRootColorMap(vtkImageData* map);
  vtkImageData* GetRootColorMap();
  ///@}

  ///@{
  /// Regions of (s, t) whose hairs take another colour (the paper's spider, pale near its leg
  /// joints): centre (s, t), radius in (s, t) (wrapping across a periodic seam), linear colour,
  /// falloff (the fraction of the radius over which the colour fades, 0 ... 1). Applied in order.
  void AddColorRegion(double s, double t, double radius, double r, double g, double b, double falloff);
  void RemoveAllColorRegions();
  int GetNumberOfColorRegions();
  ///@}

  ///@{
  /// The most points one execution may make (the core counts them exactly before it allocates
  /// anything: an error and an empty output past it). Default 33,554,432 (about 1.2 GB).
  vtkSetClampMacro(MaximumPoints, double, 0.0, 1e12);
  vtkGetMacro(MaximumPoints, double);
  ///@}

  /// Includes the parametric function's and the maps' modification times.
  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurFurGenerator();
  ~vtkWireFurFurGenerator() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MaximumPoints = 33554432.0;
  int Placement = Grid;
  int GridU = 100;
  int GridV = 70;
  double Jitter = 1.0;
  double Density = 2.0e4;
  int CellsU = 64;
  int CellsV = 64;
  double Orientation[3] = { 0.0, 0.0, 1.0 };
  vtkTypeBool UnitTangents = 0;
  int LengthMode = Fixed;
  double Length = 0.1;
  double LengthPerSu = 0.05;
  double LengthVariation = 0.2;
  double IntensityVariation = 0.1;
  int Segments = 1;
  double Gravity = 0.0;
  double GravityDirection[3] = { 0.0, 0.0, -1.0 };
  double CurlAmplitude = 0.0;
  double CurlFrequency = 2.0;
  double Clumping = 0.0;
  int ClumpCellsU = 16;
  int ClumpCellsV = 16;
  double WindDirection[3] = { 1.0, 0.0, 0.0 };
  double WindStrength = 0.0;
  double WindSway = 0.5;
  double WindFrequency = 1.0;
  double Time = 0.0;
  double RootColor[3] = { 0.30, 0.20, 0.12 };
  double TipColor[3] = { 0.55, 0.42, 0.30 };
  double Thickness = 0.003;
  vtkSmartPointer<vtkImageData> DensityMap, LengthMap, OrientationMap, RootColorMap;
  std::vector<std::array<double, 7>> ColorRegions;  ///< s, t, radius, r, g, b, falloff

private:
  vtkWireFurFurGenerator(const vtkWireFurFurGenerator&) = delete;
  void operator=(const vtkWireFurFurGenerator&) = delete;
};

#endif
