/**
 * @class   vtkWireFurMapSource
 * @brief   the pseudo-reflectance maps and the reflectance sphere of a Phong material as images
 *
 * Outputs, as 2-D vtkImageData with a float RGB point array "Radiance", one of the shading
 * tables of WireFur's core (Miller 1988, section 2): the pseudo-reflectance map of the (x, z)
 * or the (y, z) plane (the cylinder-averaged shading of a thin wire looked up by its eye-space
 * tangent), or the reflectance sphere (Phong by the eye-space normal, Williams 1983). The lights
 * are the studio rig of LightCount lights (1 ... 7) fixed to the viewer, plus Ambient.
 *
 * Defaults: Table = XZMap, Resolution = 128, Samples = 64, Diffuse = (0.55, 0.1, 0.06),
 * Specular = (1, 1, 1), Exponent = 20, LightCount = 3.
 */
#ifndef vtkWireFurMapSource_h
#define vtkWireFurMapSource_h

#include "WireFurFiltersModule.h"
#include "vtkImageAlgorithm.h"

class WIREFURFILTERS_EXPORT vtkWireFurMapSource : public vtkImageAlgorithm
{
public:
  static vtkWireFurMapSource* New();
  vtkTypeMacro(vtkWireFurMapSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Tables
  {
    XZMap = 0,
    YZMap = 1,
    ReflectanceSphere = 2
  };

  ///@{
  /// Which table to output (XZMap, YZMap or ReflectanceSphere). Default XZMap.
  vtkSetClampMacro(Table, int, XZMap, ReflectanceSphere);
  vtkGetMacro(Table, int);
  ///@}

  ///@{
  /// Texels per side (8 ... 4096). Default 128.
  vtkSetClampMacro(Resolution, int, 8, 4096);
  vtkGetMacro(Resolution, int);
  ///@}

  ///@{
  /// Normals averaged across the cylinder for a map texel (1 ... 65536). Default 64.
  vtkSetClampMacro(Samples, int, 1, 65536);
  vtkGetMacro(Samples, int);
  ///@}

  ///@{
  /// The Phong material. Defaults: diffuse (0.55, 0.1, 0.06), specular (1, 1, 1), exponent 20.
  vtkSetVector3Macro(Diffuse, double);
  vtkGetVector3Macro(Diffuse, double);
  vtkSetVector3Macro(Specular, double);
  vtkGetVector3Macro(Specular, double);
  vtkSetClampMacro(Exponent, double, 0.0, 1e6);
  vtkGetMacro(Exponent, double);
  ///@}

  ///@{
  /// Lights of the studio rig fixed to the viewer (1 ... 7; 7 is the paper's image 16). Default 3.
  vtkSetClampMacro(LightCount, int, 1, 7);
  vtkGetMacro(LightCount, int);
  ///@}

protected:
  vtkWireFurMapSource();
  ~vtkWireFurMapSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Table = XZMap;
  int Resolution = 128;
  int Samples = 64;
  double Diffuse[3] = { 0.55, 0.1, 0.06 };
  double Specular[3] = { 1.0, 1.0, 1.0 };
  double Exponent = 20.0;
  int LightCount = 3;

private:
  vtkWireFurMapSource(const vtkWireFurMapSource&) = delete;
  void operator=(const vtkWireFurMapSource&) = delete;
};

#endif
