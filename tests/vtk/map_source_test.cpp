// vtkWireFurMapSource against the core's own tables: the image is the map / sphere, texel for
// texel, with the documented extent and spacing.
#include "vtkWireFurMapSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

#include <gtest/gtest.h>

TEST(VtkMapSource, ImageIsTheCoresMapTexelForTexel)
{
  vtkNew<vtkWireFurMapSource> source;
  source->SetResolution(32);
  source->SetSamples(16);
  source->SetTable(vtkWireFurMapSource::YZMap);
  source->Update();
  vtkImageData* img = source->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  ASSERT_EQ(dims[0], 32);
  ASSERT_EQ(dims[1], 32);
  auto* a = vtkFloatArray::SafeDownCast(img->GetPointData()->GetArray("Radiance"));
  ASSERT_NE(a, nullptr);
  wf::PhongMaterial m;
  m.diffuse = glm::dvec3(0.55, 0.1, 0.06);
  m.specular = glm::dvec3(1.0);
  m.exponent = 20;
  wf::PseudoReflectanceMapOptions o;
  o.resolution = 32;
  o.samples = 16;
  wf::PseudoReflectanceMap map;
  map.build(m, wf::LightRig::studioRig(3).canonical(), o);
  double worst = 0;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i)
    {
      const glm::vec3 c = map.lookupPlane(wf::PseudoReflectanceMap::Plane::YZ, -1.0 + 2.0 * i / 31, -1.0 + 2.0 * j / 31);
      float t[3];
      a->GetTypedTuple(j * 32 + i, t);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(t[k] - c[k])));
    }
  EXPECT_EQ(worst, 0.0);
  double spacing[3];
  img->GetSpacing(spacing);
  EXPECT_NEAR(spacing[0], 2.0 / 31, 1e-15);
}
