// vtkWireFurSilhouette's exact path (docs/cad.md): downstream of the CAD reader it traces each
// face's silhouette from OpenCASCADE's surface, found through the reader object (the Filters
// module does not link the CAD module).
#include "cad_fixtures.h"

#include "vtkWireFurEdgeVisibility.h"
#include "vtkWireFurSilhouette.h"

#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <glm/glm.hpp>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkPolyData.h>
#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
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

// vtkWireFurEdgeVisibility on the exact silhouettes of a tilted torus (R = 10, r = 3, eye at
// (0, -40, 25)) over the reader's faces: a silhouette point is seen when the ray from it to the
// eye stays out of the solid torus, (sqrt(x^2 + y^2) - R)^2 + z^2 >= r^2, marched in steps of 1e-3
// from 1e-2 on. The tessellation's chords pass in front of grazing rays (far along the saddle inside
// the ring), so the filter gives silhouettes a slack of sqrt(2 deflection r) from the reader's
// "LinearDeflection" field: every exact silhouette point then agrees with the march; with no
// slack some are taken as hidden.
TEST(CadSilhouetteFilter, EdgeVisibilityOfExactSilhouettesAgreesWithTheTrueTorus) {
  const std::string path = writeBrep(BRepPrimAPI_MakeTorus(10.0, 3.0).Shape(), "sil_torus.brep");
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkCamera> camera;
  const glm::dvec3 eye(0, -40, 25);
  camera->SetPosition(eye.x, eye.y, eye.z);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 0, 1);
  camera->SetClippingRange(1, 200);
  vtkNew<vtkWireFurSilhouette> silhouettes;
  silhouettes->SetInputConnection(reader->GetOutputPort(0));
  silhouettes->SetCamera(camera);
  silhouettes->SetViewportSize(800, 600);
  vtkNew<vtkWireFurEdgeVisibility> f;
  f->SetInputConnection(silhouettes->GetOutputPort());
  f->SetSurfaceConnection(reader->GetOutputPort(0));
  f->SetCamera(camera);
  f->SetViewportSize(800, 600);
  f->Update();
  ASSERT_TRUE(silhouettes->UsedExactSurfaces());
  const double deflection = reader->GetOutput(0)->GetFieldData()->GetArray("LinearDeflection")->GetTuple1(0);
  EXPECT_NEAR(deflection, reader->GetAppliedLinearDeflection(), 1e-15);
  auto seenByMarch = [&](const glm::dvec3& p) {
    const glm::dvec3 d = eye - p;
    const double L = glm::length(d);
    for (double t = 1e-2; t < L; t += 1e-3) {
      const glm::dvec3 q = p + d * (t / L);
      const double a = std::hypot(q.x, q.y) - 10.0;
      if (a * a + q.z * q.z < 9.0) return false;
    }
    return true;
  };
  // Interior points of each piece are exact silhouette points (its ends may be cuts).
  auto disagreements = [&](vtkPolyData* out, long& checked) {
    long wrong = 0;
    checked = 0;
    vtkDataArray* visible = out->GetCellData()->GetArray("Visible");
    vtkNew<vtkIdList> cell;
    vtkIdType c = 0;
    for (out->GetLines()->InitTraversal(); out->GetLines()->GetNextCell(cell); ++c)
      for (vtkIdType k = 1; k + 1 < cell->GetNumberOfIds(); k += 3) {
        glm::dvec3 p;
        out->GetPoint(cell->GetId(k), &p.x);
        ++checked;
        wrong += seenByMarch(p) != (visible->GetTuple1(c) != 0);
      }
    return wrong;
  };
  long checked = 0;
  EXPECT_EQ(disagreements(f->GetOutput(), checked), 0);
  EXPECT_GT(checked, 50);
  f->SetSilhouetteSlack(0);
  f->Update();
  EXPECT_GT(disagreements(f->GetOutput(), checked), 0);
}

// product.step (a tray whose vertical and bottom fillets meet at its corners in blend faces with
// a degenerate edge, a pole): seen obliquely from above, the exact path's curves lie within 1% of
// the model's size of the mesh path's (a different algorithm; the mesh path's own error is the
// tessellation's), and none is a run of one point. The blends' traces along their degenerate
// edges came out as four polylines of 33 copies of a corner point each, 16.5 units (0.37 of the
// model) from any mesh silhouette, drawn as a dot at each corner.
TEST(CadSilhouetteFilter, ProductTrayExactAgreesWithTheMeshAndHasNoPointRuns) {
  vtkNew<vtkWireFurCADReader> reader;
  const std::string path = std::string(WIREFUR_SOURCE_DIR) + "/data/cad/product.step";
  reader->SetFileName(path.c_str());
  reader->Update();
  double b[6];
  reader->GetOutput(0)->GetBounds(b);
  const double c[3] = {(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2};
  const double size = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  vtkNew<vtkCamera> camera;
  camera->SetPosition(c[0] + 1.1 * size, c[1] - 1.4 * size, c[2] + 1.0 * size);
  camera->SetFocalPoint(c);
  camera->SetViewUp(0, 0, 1);
  vtkNew<vtkWireFurSilhouette> exact, mesh;
  for (vtkWireFurSilhouette* f : {exact.Get(), mesh.Get()}) {
    f->SetInputConnection(reader->GetOutputPort(0));
    f->SetCamera(camera);
    f->SetViewportSize(800, 600);
  }
  mesh->UseExactSurfacesOff();
  exact->Update();
  mesh->Update();
  ASSERT_TRUE(exact->UsedExactSurfaces());
  vtkPolyData* e = exact->GetOutput();
  vtkPolyData* m = mesh->GetOutput();
  ASSERT_GT(e->GetNumberOfLines(), 4);
  ASSERT_GT(m->GetNumberOfLines(), 4);
  // Pixels on the 800 x 600 screen, from the camera's own projection.
  vtkMatrix4x4* m4 = camera->GetCompositeProjectionTransformMatrix(800.0 / 600.0, -1, 1);
  auto pixel = [&](const glm::dvec3& p) {
    double in[4] = {p.x, p.y, p.z, 1.0}, out[4];
    m4->MultiplyPoint(in, out);
    return glm::dvec2(400.0 * (out[0] / out[3] + 1.0), 300.0 * (out[1] / out[3] + 1.0));
  };
  // Chords of one output's polylines, and the farthest point of the other from them.
  auto chordsOf = [](vtkPolyData* d) {
    std::vector<std::pair<glm::dvec3, glm::dvec3>> chords;
    vtkNew<vtkIdList> ids;
    d->GetLines()->InitTraversal();
    while (d->GetLines()->GetNextCell(ids))
      for (vtkIdType k = 1; k < ids->GetNumberOfIds(); ++k) {
        glm::dvec3 p, q;
        d->GetPoint(ids->GetId(k - 1), &p.x);
        d->GetPoint(ids->GetId(k), &q.x);
        chords.emplace_back(p, q);
      }
    return chords;
  };
  auto farthest = [](vtkPolyData* from, const std::vector<std::pair<glm::dvec3, glm::dvec3>>& chords) {
    double far = 0;
    for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i) {
      glm::dvec3 p;
      from->GetPoint(i, &p.x);
      double best = HUGE_VAL;
      for (const auto& [a, bb] : chords) {
        const glm::dvec3 d = bb - a;
        const double t = glm::dot(d, d) > 0 ? std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(a + t * d - p));
      }
      far = std::max(far, best);
    }
    return far;
  };
  // Every exact curve is one on the screen: more than the tracer's tolerance (0.1 px) across.
  int runs = 0, repeats = 0;
  vtkNew<vtkIdList> ids;
  e->GetLines()->InitTraversal();
  while (e->GetLines()->GetNextCell(ids)) {
    glm::dvec2 lo(HUGE_VAL), hi(-HUGE_VAL);
    glm::dvec3 prev;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      glm::dvec3 p;
      e->GetPoint(ids->GetId(k), &p.x);
      if (k > 0) repeats += p == prev;
      prev = p;
      lo = glm::min(lo, pixel(p));
      hi = glm::max(hi, pixel(p));
    }
    runs += !(std::max(hi.x - lo.x, hi.y - lo.y) > 0.1);
  }
  EXPECT_EQ(runs, 0);
  EXPECT_EQ(repeats, 0);
  const double far = farthest(e, chordsOf(m));
  // And the other way: no mesh silhouette without an exact one near it (2%: the mesh path's
  // curves cut corners of the tessellation).
  const double back = farthest(m, chordsOf(e));
  EXPECT_LT(back, 0.02 * size) << "a mesh silhouette point far from every exact silhouette";
  EXPECT_LT(far, 0.01 * size) << "an exact silhouette point far from every mesh silhouette";
}
