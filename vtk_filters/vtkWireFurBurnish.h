/**
 * @class   vtkWireFurBurnish
 * @brief   burnished-metal grain tangents and groove intensity on a surface
 *
 * Burnished metal after Miller 1988, section 2.2 (images 5-8, 19): the surface is taken to be fine
 * parallel grooves along a grain direction. The output is a shallow copy of the input vtkPolyData
 * with two point arrays added:
 *  - "Tangents" (float, 3 components, unit, set as the active tangents with
 *    vtkPointData::SetTangents): the grain direction in the surface's tangent plane. VTK 9.1's own
 *    PBR anisotropy (vtkProperty::SetInterpolationToPBR, SetAnisotropy) reads the active tangents,
 *    so plain VTK shows brushed metal with it; WireFur's render pass shades it through the
 *    pseudo-reflectance map like a wire.
 *  - "GrooveIntensity" (float, only when GrooveCount > 0): the core's wf::GrooveTexture (count
 *    GrooveCount per unit of the groove coordinate, GrooveDepth, GrooveSeed) at each point (a point
 *    value, no filtering), in (1 - GrooveDepth, 1]. The groove coordinate is the core's
 *    (render/scene.h Burnish): v for grain U, u for grain V, the turn about the axis in [0, 1) for
 *    Radial, the distance from the axis (world units) for Circular.
 *
 * Grain: U (along dS/du), V (along dS/dv), Radial (away from the axis through AxisPoint along
 * AxisDirection) or Circular (around that axis: a record on a turntable). The tangent is projected
 * off the normal; where it vanishes (on the axis, a zero derivative) it is a fixed perpendicular of
 * the normal: never NaN.
 *
 * (u, v) and derivatives. With SetParametricFunction, the input's texture coordinates are the unit
 * coordinates (s, t) in [0, 1]^2 that vtkParametricFunctionSource writes
 * (GenerateTextureCoordinatesOn), (u, v) = (MinimumU + s (MaximumU - MinimumU), ...), and Su, Sv and
 * the normal are the function's own (exact derivatives; the limit normal at a pole). Without it,
 * (u, v) are the input's texture coordinates (active TCoords or an array "TCoords"), Su, Sv at a
 * point are the area-weighted mean of the constant dP/du, dP/dv of the triangles around it, and the
 * normal is the input's point normals or else the area-weighted mean of the triangle normals.
 * Radial and Circular grain need no texture coordinates, grooves included (their groove coordinate
 * is geometric).
 *
 * Defaults: Grain = U, AxisPoint = (0, 0, 0), AxisDirection = (0, 0, 1), GrooveCount = 0 (no groove
 * array), GrooveDepth = 0.5, GrooveSeed = 1, ParametricFunction = nullptr.
 * An input without points (a rank's empty piece in a parallel pipeline) gives an empty output and
 * no error. Errors (vtkErrorMacro, empty output): no input, a NaN or infinite point, grain U or V without
 * texture coordinates, a zero or non-finite AxisDirection or a non-finite AxisPoint for Radial or
 * Circular grain, a negative or non-finite GrooveCount, a GrooveDepth outside [0, 1], an unusable
 * parametric function or one without texture coordinates on the input.
 */
#ifndef vtkWireFurBurnish_h
#define vtkWireFurBurnish_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkParametricFunction;

class WIREFURFILTERS_EXPORT vtkWireFurBurnish : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurBurnish* New();
  vtkTypeMacro(vtkWireFurBurnish, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Grains
  {
    GrainU = 0,
    GrainV = 1,
    Radial = 2,
    Circular = 3
  };

  ///@{
  /// The grain: GrainU, GrainV, Radial or Circular. Default GrainU.
  vtkSetClampMacro(Grain, int, GrainU, Circular);
  vtkGetMacro(Grain, int);
  void SetGrainToU() { this->SetGrain(GrainU); }
  void SetGrainToV() { this->SetGrain(GrainV); }
  void SetGrainToRadial() { this->SetGrain(Radial); }
  void SetGrainToCircular() { this->SetGrain(Circular); }
  ///@}

  ///@{
  /// Radial and Circular grain: the axis (world). Defaults (0, 0, 0) and (0, 0, 1).
  vtkSetVector3Macro(AxisPoint, double);
  vtkGetVector3Macro(AxisPoint, double);
  vtkSetVector3Macro(AxisDirection, double);
  vtkGetVector3Macro(AxisDirection, double);
  ///@}

  ///@{
  /// Grooves per unit of the groove coordinate; 0 = no "GrooveIntensity" array. Default 0.
  vtkSetMacro(GrooveCount, double);
  vtkGetMacro(GrooveCount, double);
  ///@}

  ///@{
  /// Groove depth, [0, 1]: intensities lie in (1 - depth, 1]. Default 0.5.
  vtkSetMacro(GrooveDepth, double);
  vtkGetMacro(GrooveDepth, double);
  ///@}

  ///@{
  /// The groove series. Default 1.
  vtkSetMacro(GrooveSeed, vtkTypeUInt64);
  vtkGetMacro(GrooveSeed, vtkTypeUInt64);
  ///@}

  ///@{
  /// The parametric function the input was tessellated from (exact derivatives; see above).
  /// Default nullptr.
  virtual void SetParametricFunction(vtkParametricFunction*);
  vtkGetObjectMacro(ParametricFunction, vtkParametricFunction);
  ///@}

  /// Includes the parametric function's modification time.
  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurBurnish();
  ~vtkWireFurBurnish() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Grain = GrainU;
  double AxisPoint[3] = { 0.0, 0.0, 0.0 };
  double AxisDirection[3] = { 0.0, 0.0, 1.0 };
  double GrooveCount = 0.0;
  double GrooveDepth = 0.5;
  vtkTypeUInt64 GrooveSeed = 1;
  vtkParametricFunction* ParametricFunction = nullptr;

private:
  vtkWireFurBurnish(const vtkWireFurBurnish&) = delete;
  void operator=(const vtkWireFurBurnish&) = delete;
};

#endif
