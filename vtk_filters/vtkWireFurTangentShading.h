/**
 * @class   vtkWireFurTangentShading
 * @brief   eye-space tangents and cylinder-shaded colours of polylines, for plain VTK mappers
 *
 * Input: vtkPolyData whose lines (VTK_LINE and VTK_POLY_LINE cells) are wires, fur or grain in
 * world space. Output: a shallow copy of the input with these point arrays added:
 *   - "Tangents" (float, 3): the unit world-space tangent, set as the active tangents;
 *   - "EyeTangents" (float, 3): the same tangent in the eye space of the camera (camera at the
 *     origin looking down -z, viewer on +z: the space the maps are built in);
 *   - "ShadedRadiance" (float, 3): linear RGB radiance of the wire drawn as a thin cylinder of
 *     that axis (Miller 1988, section 2.2), unclamped;
 *   - "ShadedColor" (unsigned char, 3): ShadedRadiance clamped to [0, 1] and sRGB-encoded, set as
 *     the active scalars, so a vtkPolyDataMapper shows it as it is (or select it with
 *     ScalarModeToUsePointFieldData + SelectColorArray("ShadedColor")).
 *
 * Input colours: a point array "Colors" (unsigned char, 3 or 4 components, sRGB-encoded, as
 * vtkWireFurFurGenerator writes its root-to-tip colours) replaces the diffuse colour (its largest
 * component stays the diffuse coefficient) and multiplies the radiance, as point colours do in
 * VTK's mappers and in the core's renders: the strands keep their own colours.
 *
 * Tangent at a point: the normalised sum of the unit directions of its incoming and outgoing
 * segments (one-sided at the ends of an open line; a closed polyline, first point id = last, wraps
 * around). Zero-length segments are skipped (a repeated point takes the tangent of the points
 * around it); segments touching a NaN / Inf point are not used. A point shared by several cells
 * sums the cells' tangents, each with the sign that agrees with the first cell's (T and -T are the
 * same cylinder). Where incoming and outgoing cancel (a hairpin) the incoming direction is used.
 * A point with no usable segment gets (0, 0, 0) and is counted in DegeneratePoints; it shades as
 * a cylinder seen end-on (the core's convention). Bad input is an error and an empty output: no
 * input, or one with a NaN or Inf coordinate (counted in NonFinitePoints). With
 * SkipNonFinitePoints on, such points get the tangent (0, 0, 0) and black instead, the others are
 * shaded, and one warning gives the count.
 *
 * Eye space is given by Camera's view transform (eye-from-world = its rotation part; Camera's
 * model transform is not used). Without a Camera the Renderer's active camera is used, and
 * without either a default vtkCamera (at (0, 0, 1) looking at the origin, +y up).
 *
 * Lights (converted to directional lights in eye space, direction towards the light):
 *   - without a Renderer: the studio rig of LightCount lights fixed to the viewer (the rig of
 *     vtkWireFurMapSource and the core's pictures), plus Ambient;
 *   - with a Renderer: its vtkLights that are switched on, intensity = Intensity * DiffuseColor,
 *     plus Ambient. A Headlight shines along the view axis (eye direction (0, 0, 1)); a CameraLight's
 *     Position - FocalPoint is already an eye-space direction (VTK's light coordinates: camera at
 *     (0, 0, 1) looking at the origin); a SceneLight's transformed Position - FocalPoint is a world
 *     direction, rotated into eye space. Positional lights and spot lights are taken as directional
 *     lights along their axis (the map assumes lights at infinity); attenuation, cone and specular
 *     colour are ignored. A renderer with no lights at all and AutomaticLightCreation on gets the
 *     white headlight of intensity 1 that VTK would create when it renders.
 *
 * Shading (SetShading): by default (closed) every point is shaded at its own view vector by the
 * cylinder integral in closed form (shading/cylinder_lobe.h), exact in perspective but for a
 * table of one variable per exponent (a member, rebuilt only when the exponent changes);
 * ErrorEstimate is that table's measured error times the largest specular colour and the
 * lights' summed intensity (~1e-9). SetShadingToMaps(): one lookup per point in a
 * PseudoReflectanceMap (the paper's orthographic
 * assumption: view vector (0, 0, 1) in eye space). The map is a member, rebuilt only when the
 * material, the eye-space lights or the map options change (paper: "recomputed if the camera
 * rotates or moves relative to the lights"): a camera moving with its lights (studio rig, headlight,
 * camera lights) or a camera only translated among scene lights reuses it. MapBuilds counts the
 * builds. At each build ErrorEstimate is set to the largest difference (any RGB component) between
 * the map and the exact cylinder integral (view (0, 0, 1)) over 192 tangents spread evenly over
 * the sphere. SetShadingToExact() (or ExactShading on): every point is shaded by the closed form
 * with its factor computed exactly (the reference, to ~1e-15) at its true view vector, no table
 * is built, and ErrorEstimate is 0. Empty input gives an empty output and no error.
 *
 * Defaults: Camera = none, Renderer = none, Diffuse = (0.55, 0.1, 0.06), Specular = (1, 1, 1),
 * Exponent = 20, Ambient = (0.05, 0.05, 0.05), LightCount = 3, Shading = closed, ExactShading = off,
 * ExactTolerance = 1e-8, MapResolution = 128, MapSamples = 64.
 *
 * The Renderer is held by a weak reference (it usually owns the actor that shows this output).
 */
#ifndef vtkWireFurTangentShading_h
#define vtkWireFurTangentShading_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

class vtkCamera;
class vtkRenderer;

class WIREFURFILTERS_EXPORT vtkWireFurTangentShading : public vtkPolyDataAlgorithm
{
public:
  static vtkWireFurTangentShading* New();
  vtkTypeMacro(vtkWireFurTangentShading, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The camera whose eye space the tangents and shading are computed in. Default none (the
  /// Renderer's active camera, else a default vtkCamera).
  void SetCamera(vtkCamera* camera);
  vtkCamera* GetCamera();
  ///@}

  ///@{
  /// The renderer whose lights shade the wires (held weakly). Default none: the studio rig.
  void SetRenderer(vtkRenderer* renderer);
  vtkRenderer* GetRenderer();
  ///@}

  ///@{
  /// The Phong material. Defaults: diffuse (0.55, 0.1, 0.06), specular (1, 1, 1), exponent 20
  /// (0 ... 1e6).
  vtkSetVector3Macro(Diffuse, double);
  vtkGetVector3Macro(Diffuse, double);
  vtkSetVector3Macro(Specular, double);
  vtkGetVector3Macro(Specular, double);
  vtkSetClampMacro(Exponent, double, 0.0, 1e6);
  vtkGetMacro(Exponent, double);
  ///@}

  ///@{
  /// Ambient light (linear RGB), added to either kind of lights. Default (0.05, 0.05, 0.05).
  vtkSetVector3Macro(Ambient, double);
  vtkGetVector3Macro(Ambient, double);
  ///@}

  ///@{
  /// Lights of the studio rig fixed to the viewer, used without a Renderer (1 ... 7). Default 3.
  vtkSetClampMacro(LightCount, int, 1, 7);
  vtkGetMacro(LightCount, int);
  ///@}

  ///@{
  /// 0, closed (default): the closed form with a lobe table at every point's own view vector;
  /// 1, maps: the paper's pseudo-reflectance map (orthographic view); 2, exact.
  vtkSetClampMacro(Shading, int, 0, 2);
  vtkGetMacro(Shading, int);
  void SetShadingToClosed() { this->SetShading(0); }
  void SetShadingToMaps() { this->SetShading(1); }
  void SetShadingToExact() { this->SetShading(2); }
  ///@}

  ///@{
  /// On: shade every point by the exact path whatever Shading says (kept from before Shading).
  /// Default off.
  vtkSetMacro(ExactShading, vtkTypeBool);
  vtkGetMacro(ExactShading, vtkTypeBool);
  vtkBooleanMacro(ExactShading, vtkTypeBool);
  ///@}

  ///@{
  /// Relative tolerance of the quadrature the exact path used before it became the closed form
  /// (1e-14 ... 1e-2, default 1e-8). Kept for existing pipelines; no longer used.
  vtkSetClampMacro(ExactTolerance, double, 1e-14, 1e-2);
  vtkGetMacro(ExactTolerance, double);
  ///@}

  ///@{
  /// Texel nodes per side of each pseudo-reflectance map (8 ... 4096). Default 128.
  vtkSetClampMacro(MapResolution, int, 8, 4096);
  vtkGetMacro(MapResolution, int);
  ///@}

  ///@{
  /// Normals averaged across the cylinder for a map texel (1 ... 65536). Default 64.
  vtkSetClampMacro(MapSamples, int, 1, 65536);
  vtkGetMacro(MapSamples, int);
  ///@}

  /// How many times the map has been built by this filter.
  int GetMapBuilds();
  /// Seconds the last map build took (0 before the first).
  double GetMapSeconds();
  /// The shading error bound: closed, the lobe table's (see above); maps, the largest
  /// map-versus-exact difference measured at the last map build; exact, 0.
  vtkGetMacro(ErrorEstimate, double);
  /// The last output's own error: at up to 256 evenly spaced points, its radiance against the
  /// exact cylinder model at the point's true view vector (for the map, that includes the
  /// perspective it leaves out). 0 on the exact path.
  vtkGetMacro(MeasuredError, double);
  /// Points of the last execution with a NaN or Inf coordinate.
  vtkGetMacro(NonFinitePoints, vtkIdType);
  ///@{
  /// Shade the finite points of an input that has NaN / Inf points (those get black and a zero
  /// tangent, with a warning) instead of an error and an empty output. Default off.
  vtkSetMacro(SkipNonFinitePoints, vtkTypeBool);
  vtkGetMacro(SkipNonFinitePoints, vtkTypeBool);
  vtkBooleanMacro(SkipNonFinitePoints, vtkTypeBool);
  ///@}
  /// Finite points of the last execution with no usable segment (tangent (0, 0, 0)).
  vtkGetMacro(DegeneratePoints, vtkIdType);

  /// Includes the camera's and the renderer's lights' modification times.
  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurTangentShading();
  ~vtkWireFurTangentShading() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkSmartPointer<vtkCamera> Camera;
  vtkWeakPointer<vtkRenderer> Renderer;
  double Diffuse[3] = { 0.55, 0.1, 0.06 };
  double Specular[3] = { 1.0, 1.0, 1.0 };
  double Exponent = 20.0;
  double Ambient[3] = { 0.05, 0.05, 0.05 };
  int LightCount = 3;
  vtkTypeBool ExactShading = 0;
  double ExactTolerance = 1e-8;
  int MapResolution = 128;
  int MapSamples = 64;
  double ErrorEstimate = 0.0;
  int Shading = 0;
  vtkIdType NonFinitePoints = 0;
  vtkTypeBool SkipNonFinitePoints = 0;
  double MeasuredError = 0.0;
  vtkIdType DegeneratePoints = 0;

private:
  vtkWireFurTangentShading(const vtkWireFurTangentShading&) = delete;
  void operator=(const vtkWireFurTangentShading&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
