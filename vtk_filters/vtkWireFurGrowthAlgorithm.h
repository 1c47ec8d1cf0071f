/**
 * @class   vtkWireFurGrowthAlgorithm
 * @brief   what the fur and scale generators share: the surface they grow on and their randomness
 *
 * The surface is SetParametricFunction (exact derivatives; takes precedence) or the optional
 * vtkPolyData on input port 0 with texture coordinates. FlipNormals grows from the other side
 * (some VTK functions, vtkParametricTorus among them, have Su x Sv pointing inward). Seed and
 * PatchIndex are all the randomness (PatchIndex is also the top 32 bits of every element id).
 * Defaults: no function, FlipNormals off, Seed 1, PatchIndex 0. Abstract: see
 * vtkWireFurFurGenerator and vtkWireFurScalesGenerator.
 */
#ifndef vtkWireFurGrowthAlgorithm_h
#define vtkWireFurGrowthAlgorithm_h

#include "WireFurFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkParametricFunction;

class WIREFURFILTERS_EXPORT vtkWireFurGrowthAlgorithm : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkWireFurGrowthAlgorithm, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The surface as a vtkParametricFunction (exact derivatives). When set, input port 0 is ignored.
  virtual void SetParametricFunction(vtkParametricFunction*);
  vtkGetObjectMacro(ParametricFunction, vtkParametricFunction);

  ///@{
  /// Grow from the other side: use -(Su x Sv) as the surface's outward normal. Default off.
  vtkSetMacro(FlipNormals, vtkTypeBool);
  vtkGetMacro(FlipNormals, vtkTypeBool);
  vtkBooleanMacro(FlipNormals, vtkTypeBool);
  ///@}

  ///@{
  /// All the randomness: Seed and PatchIndex (also the top 32 bits of every id). Defaults 1, 0.
  vtkSetMacro(Seed, vtkTypeUInt64);
  vtkGetMacro(Seed, vtkTypeUInt64);
  vtkSetMacro(PatchIndex, vtkTypeUInt32);
  vtkGetMacro(PatchIndex, vtkTypeUInt32);
  ///@}

  /// Includes the parametric function's modification time.
  vtkMTimeType GetMTime() override;

protected:
  vtkWireFurGrowthAlgorithm();
  ~vtkWireFurGrowthAlgorithm() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// The mesh on input port 0, or null when a ParametricFunction is set (or nothing is connected).
  vtkPolyData* GrowthInput(vtkInformationVector** inputVector);

  vtkParametricFunction* ParametricFunction = nullptr;
  vtkTypeBool FlipNormals = 0;
  vtkTypeUInt64 Seed = 1;
  vtkTypeUInt32 PatchIndex = 0;

private:
  vtkWireFurGrowthAlgorithm(const vtkWireFurGrowthAlgorithm&) = delete;
  void operator=(const vtkWireFurGrowthAlgorithm&) = delete;
};

#endif
