// vtkWireFurSilhouette's exact path (docs/cad.md): downstream of the CAD reader it traces each
// face's silhouette from OpenCASCADE's surface, found through the reader object (the Filters
// module does not link the CAD module).
#include "cad_fixtures.h"

#include "vtkWireFurSilhouette.h"

#include <BRepPrimAPI_MakeSphere.hxx>
#include <vtkCamera.h>
#include <vtkCellData.h>

#include <cmath>

using namespace cadtest;

// A sphere of radius 10 seen from distance 40: the true silhouette is the circle at 10^2 / 40 =
// 2.5 from the centre towards the eye, of radius sqrt(100 - 6.25). The exact path's points are
// roots on the exact surface: on that circle to 1e-9 (the mesh path is only as good as the
// tessellation, 1e-3 here). With UseExactSurfaces off, the same filter takes the mesh path.
TEST(CadSilhouetteFilter, SphereExactlyOnTheTrueCircle) {
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(10.0).Shape(), "sil_sphere.brep");
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkCamera> camera;
  camera->SetPosition(0, -40, 0);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 0, 1);
  vtkNew<vtkWireFurSilhouette> f;
  f->SetInputConnection(reader->GetOutputPort(0));
  f->SetCamera(camera);
  f->SetViewportSize(800, 600);
  f->Update();
  ASSERT_TRUE(f->UsedExactSurfaces());
  vtkPolyData* out = f->GetOutput();
  ASSERT_GT(out->GetNumberOfPoints(), 20);
  const double y = -2.5, r = std::sqrt(100.0 - 6.25);
  double worst = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    double p[3];
    out->GetPoint(i, p);
    worst = std::max({worst, std::abs(p[1] - y), std::abs(std::hypot(p[0], p[2]) - r)});
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(int(out->GetCellData()->GetArray("EdgeClass")->GetTuple1(0)), 6);
  f->UseExactSurfacesOff();
  f->Update();
  EXPECT_FALSE(f->UsedExactSurfaces());
  EXPECT_GT(f->GetOutput()->GetNumberOfPoints(), 20);
}
