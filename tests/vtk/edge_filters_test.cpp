// The CAD engineer's filters (docs/cad.md "Edge classes and visibility", docs/vtk.md):
// vtkWireFurEdgeClasses, vtkWireFurSilhouette (mesh path; the exact path is tested with the CAD
// reader in tests/cad) and vtkWireFurEdgeVisibility, against closed forms.
#include "vtkWireFurEdgeClasses.h"
#include "vtkWireFurEdgeVisibility.h"
#include "vtkWireFurSilhouette.h"

#include "vtkAppendPolyData.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCubeSource.h"
#include "vtkCylinderSource.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkStripper.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

namespace
{

int cellValue(vtkPolyData* pd, const char* name, vtkIdType c)
{
  return int(pd->GetCellData()->GetArray(name)->GetTuple1(c));
}

// One line from a to b.
vtkSmartPointer<vtkPolyData> segment(const double a[3], const double b[3])
{
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(a);
  pts->InsertNextPoint(b);
  vtkNew<vtkCellArray> cells;
  const vtkIdType ids[2] = { 0, 1 };
  cells->InsertNextCell(2, ids);
  auto line = vtkSmartPointer<vtkPolyData>::New();
  line->SetPoints(pts);
  line->SetLines(cells);
  return line;
}

} // namespace

// A cube of six quads (24 points, split): 12 sharp edges at 90 degrees, none smooth (a quad has no
// diagonal), none boundary. Sharp and all both give the 12; boundary gives none. A 4 x 4 plane:
// its 16 border edges chained into one closed loop of 17 points; its inner edges smooth at 0.
TEST(EdgeClassesFilter, CubeAndPlane)
{
  vtkNew<vtkCubeSource> cube;
  vtkNew<vtkWireFurEdgeClasses> f;
  f->SetInputConnection(cube->GetOutputPort());
  f->SetModeToSharp();
  f->Update();
  vtkPolyData* out = f->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 12);
  EXPECT_EQ(f->GetNumberOfEdgesOfClass(1), 12);
  EXPECT_EQ(f->GetNumberOfEdgesOfClass(2), 0);
  for (vtkIdType c = 0; c < 12; ++c)
  {
    EXPECT_EQ(cellValue(out, "EdgeClass", c), 1);
    EXPECT_NEAR(out->GetCellData()->GetArray("EdgeAngle")->GetTuple1(c), 90.0, 1e-4);
  }
  f->SetModeToAll();
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfLines(), 12);
  f->SetModeToBoundary();
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfLines(), 0);

  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(4, 4);
  f->SetInputConnection(plane->GetOutputPort());
  f->Update();
  ASSERT_EQ(f->GetOutput()->GetNumberOfLines(), 1);
  vtkNew<vtkIdList> ids;
  f->GetOutput()->GetLines()->InitTraversal();
  f->GetOutput()->GetLines()->GetNextCell(ids);
  EXPECT_EQ(ids->GetNumberOfIds(), 17);
  EXPECT_EQ(f->GetNumberOfEdgesOfClass(0), 16);
  EXPECT_EQ(f->GetNumberOfEdgesOfClass(2), 24);
}

// Lines already classified (as the CAD reader gives them): chosen by class, sharp and smooth
// judged again by EdgeAngle against FeatureAngle; iso lines (-1) left out; cell data passed on.
TEST(EdgeClassesFilter, ChoosesAmongClassifiedLines)
{
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> cls, tag;
  vtkNew<vtkDoubleArray> angle;
  cls->SetName("EdgeClass");
  angle->SetName("EdgeAngle");
  tag->SetName("Tag");
  const int classes[] = { 1, 2, 3, 0, -1, 1 };
  const double angles[] = { 90, 0.5, NAN, NAN, NAN, 15 };
  for (int i = 0; i < 6; ++i)
  {
    const vtkIdType a = pts->InsertNextPoint(i, 0, 0), b = pts->InsertNextPoint(i, 1, 0);
    const vtkIdType ids[2] = { a, b };
    lines->InsertNextCell(2, ids);
    cls->InsertNextValue(classes[i]);
    angle->InsertNextValue(angles[i]);
    tag->InsertNextValue(100 + i);
  }
  pd->SetPoints(pts);
  pd->SetLines(lines);
  pd->GetCellData()->AddArray(cls);
  pd->GetCellData()->AddArray(angle);
  pd->GetCellData()->AddArray(tag);
  vtkNew<vtkWireFurEdgeClasses> f;
  f->SetInputData(pd);
  f->SetModeToSharp();
  f->Update();
  // Sharp at 10: cells 0 (90), 3 (boundary), 5 (15).
  vtkPolyData* out = f->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 3);
  EXPECT_EQ(cellValue(out, "Tag", 0), 100);
  EXPECT_EQ(cellValue(out, "Tag", 1), 103);
  EXPECT_EQ(cellValue(out, "Tag", 2), 105);
  f->SetFeatureAngle(20);  // 15 becomes smooth
  f->SeamsOn();            // the seam joins
  f->Update();
  ASSERT_EQ(f->GetOutput()->GetNumberOfLines(), 3);
  EXPECT_EQ(cellValue(f->GetOutput(), "Tag", 1), 102);
  EXPECT_EQ(cellValue(f->GetOutput(), "EdgeClass", 1), 3);
}

// A sphere of radius R = 1 seen from distance D = 4 in perspective: its true silhouette is the
// circle of the points P with (P - C) . (E - P) = 0, at distance R^2 / D = 0.25 from the centre
// towards the eye and of radius sqrt(1 - 1/16). From the point normals of a 128 x 64 tessellation,
// every silhouette point lies within 2e-3 of that circle (the tessellation's O(h^2)), and it is one
// closed curve. Moving the camera re-executes the filter (its MTime).
TEST(SilhouetteFilter, SphereMeshAgainstTheTrueCircle)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(128);
  sphere->SetPhiResolution(64);
  vtkNew<vtkCamera> camera;
  camera->SetPosition(0, 0, 4);
  camera->SetFocalPoint(0, 0, 0);
  sphere->SetRadius(1.0);
  vtkNew<vtkWireFurSilhouette> f;
  f->SetInputConnection(sphere->GetOutputPort());
  f->SetCamera(camera);
  f->Update();
  EXPECT_FALSE(f->UsedExactSurfaces());
  vtkPolyData* out = f->GetOutput();
  ASSERT_GE(out->GetNumberOfLines(), 1);
  EXPECT_LE(out->GetNumberOfLines(), 2);  // (the stripper may cut a closed loop once)
  ASSERT_GT(out->GetNumberOfPoints(), 100);
  const double z = 0.25, r = std::sqrt(1.0 - 1.0 / 16.0);
  double worst = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    worst = std::max({ worst, std::abs(p[2] - z), std::abs(std::hypot(p[0], p[1]) - r) });
  }
  EXPECT_LT(worst, 2e-3);
  EXPECT_EQ(cellValue(out, "EdgeClass", 0), 6);
  camera->SetPosition(0, 0, 2);  // now at 0.5, radius sqrt(3)/2
  f->Update();
  double p[3];
  f->GetOutput()->GetPoint(0, p);
  EXPECT_NEAR(p[2], 0.5, 5e-3);
}

// A line from x = -2 to 2 at z = -1, y = 0.1 behind a unit square at z = 0, eye at z = 5: hidden
// for |x| <= 0.6 (x * 5/6 inside the square), so three pieces seen, hidden, seen, with the line's
// cell data on each; lengths 2.8 seen, 1.2 hidden (1e-4).
TEST(EdgeVisibilityFilter, LineBehindASquare)
{
  vtkNew<vtkPlaneSource> square;  // [-0.5, 0.5]^2 at z = 0
  const double from[3] = { -2, 0.1, -1 }, to[3] = { 2, 0.1, -1 };
  vtkSmartPointer<vtkPolyData> line = segment(from, to);
  vtkNew<vtkIntArray> tag;
  tag->SetName("Tag");
  tag->InsertNextValue(7);
  line->GetCellData()->AddArray(tag);
  vtkNew<vtkCamera> camera;
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  vtkNew<vtkWireFurEdgeVisibility> f;
  f->SetInputData(line);
  f->SetSurfaceConnection(square->GetOutputPort());
  f->SetCamera(camera);
  f->SetViewportSize(640, 480);
  f->Update();
  vtkPolyData* out = f->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 3);
  EXPECT_EQ(cellValue(out, "Visible", 0), 1);
  EXPECT_EQ(cellValue(out, "Visible", 1), 0);
  EXPECT_EQ(cellValue(out, "Visible", 2), 1);
  for (vtkIdType c = 0; c < 3; ++c)
    EXPECT_EQ(cellValue(out, "Tag", c), 7);
  EXPECT_NEAR(f->GetVisibleLength(), 2.8, 1e-4);
  EXPECT_NEAR(f->GetHiddenLength(), 1.2, 1e-4);
  EXPECT_EQ(f->GetNumberOfSplits(), 2);
}

// The mesh path reads triangle strips as it reads polygons: the same sphere as strips gives the
// same circle (strips were once ignored: no output). On a cylinder seen square-on, N . V is exactly
// 0 on two generators: the silhouette runs along those mesh edges, with no piece of zero length
// (two crossings at one vertex were once two points), nor where vtkStripper joins long curves.
TEST(SilhouetteFilter, StripsAndZerosAtVertices)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(128);
  sphere->SetPhiResolution(64);
  sphere->SetRadius(1.0);
  vtkNew<vtkStripper> strips;
  strips->SetInputConnection(sphere->GetOutputPort());
  strips->Update();
  ASSERT_GT(strips->GetOutput()->GetNumberOfStrips(), 0);
  ASSERT_EQ(strips->GetOutput()->GetNumberOfPolys(), 0);
  vtkNew<vtkCamera> camera;
  camera->SetPosition(0, 0, 4);
  camera->SetFocalPoint(0, 0, 0);
  vtkNew<vtkWireFurSilhouette> f;
  f->SetInputConnection(strips->GetOutputPort());
  f->SetCamera(camera);
  f->Update();
  vtkPolyData* out = f->GetOutput();
  ASSERT_GT(out->GetNumberOfPoints(), 100);
  double worst = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    worst = std::max({ worst, std::abs(p[2] - 0.25), std::abs(std::hypot(p[0], p[1]) - std::sqrt(1.0 - 1.0 / 16.0)) });
  }
  EXPECT_LT(worst, 2e-3);

  vtkNew<vtkCylinderSource> cylinder;  // axis y, radius 0.5; generator i at angle 2 pi i / 8
  cylinder->SetResolution(8);
  cylinder->CappingOff();
  vtkNew<vtkCamera> ortho;
  ortho->ParallelProjectionOn();
  ortho->SetPosition(0, 0, 10);
  ortho->SetFocalPoint(0, 0, 0);
  f->SetInputConnection(cylinder->GetOutputPort());
  f->SetCamera(ortho);
  f->Update();
  out = f->GetOutput();
  ASSERT_GE(out->GetNumberOfLines(), 2);
  vtkNew<vtkIdList> cell;
  double shortest = 1e300;
  for (out->GetLines()->InitTraversal(); out->GetLines()->GetNextCell(cell);)
    for (vtkIdType k = 0; k + 1 < cell->GetNumberOfIds(); ++k)
    {
      double a[3], b[3];
      out->GetPoint(cell->GetId(k), a);
      out->GetPoint(cell->GetId(k + 1), b);
      shortest = std::min(shortest, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
      EXPECT_NEAR(std::abs(a[0]), 0.5, 1e-12);
      EXPECT_NEAR(a[2], 0.0, 1e-12);
    }
  EXPECT_GT(shortest, 0.5);  // the generators' length is 1

  // A silhouette of more than 1000 segments (vtkStripper's default maximum): one closed curve,
  // no repeated point.
  vtkNew<vtkSphereSource> fine;
  fine->SetThetaResolution(3000);
  fine->SetPhiResolution(20);
  f->SetInputConnection(fine->GetOutputPort());
  f->SetCamera(camera);
  f->Update();
  out = f->GetOutput();
  EXPECT_LE(out->GetNumberOfLines(), 2);
  vtkIdType segments = 0;
  for (out->GetLines()->InitTraversal(); out->GetLines()->GetNextCell(cell);)
    for (vtkIdType k = 0; k + 1 < cell->GetNumberOfIds(); ++k, ++segments)
    {
      double a[3], b[3];
      out->GetPoint(cell->GetId(k), a);
      out->GetPoint(cell->GetId(k + 1), b);
      EXPECT_GT(vtkMath::Distance2BetweenPoints(a, b), 0.0);
    }
  EXPECT_GT(segments, 1000);
}

// Without a surface (port 1 is optional) nothing hides the line: one piece, seen.
TEST(EdgeVisibilityFilter, NoSurfaceHidesNothing)
{
  const double from[3] = { -1, 0, 0 }, to[3] = { 1, 0, 0 };
  vtkSmartPointer<vtkPolyData> line = segment(from, to);
  vtkNew<vtkCamera> camera;
  camera->SetPosition(0, 0, 5);
  vtkNew<vtkWireFurEdgeVisibility> f;
  f->SetInputData(line);
  f->SetCamera(camera);
  f->Update();
  ASSERT_EQ(f->GetOutput()->GetNumberOfLines(), 1);
  EXPECT_EQ(cellValue(f->GetOutput(), "Visible", 0), 1);
  EXPECT_NEAR(f->GetVisibleLength(), 2.0, 1e-9);
}

// The renderer's view, followed: the line x in [-2, 2] at z = -1, eye at z = 5 (distance 6, 30
// degree vertical angle: half-height 6 tan 15 = 1.608). At 640 x 480 the image is 2.144 wide on
// each side and the whole line is in it (2.8 seen, 1.2 behind the square). Resized to 240 x 480
// (half-width 0.804) the parts beyond |x| = 0.804 are outside the view: not seen. Then the active
// camera is replaced by an older camera looking from the other side at distance 2.5 ... the
// re-executions come from the filter's MTime (the window's size, the camera object), not from
// a call to Modified.
TEST(EdgeVisibilityFilter, FollowsTheRenderersCameraAndSize)
{
  vtkNew<vtkCamera> older;  // created first: its MTime is older than the filter's last update
  older->SetPosition(0, 0, -7);
  older->SetFocalPoint(0, 0, 0);
  vtkNew<vtkPlaneSource> square;
  const double from[3] = { -2, 0.1, -1 }, to[3] = { 2, 0.1, -1 };
  vtkSmartPointer<vtkPolyData> line = segment(from, to);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(640, 480);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  renderer->GetActiveCamera()->SetPosition(0, 0, 5);
  renderer->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  vtkNew<vtkWireFurEdgeVisibility> f;
  f->SetInputData(line);
  f->SetSurfaceConnection(square->GetOutputPort());
  f->SetRenderer(renderer);
  f->Update();
  EXPECT_NEAR(f->GetVisibleLength(), 2.8, 1e-4);
  EXPECT_NEAR(f->GetHiddenLength(), 1.2, 1e-4);
  window->SetSize(240, 480);
  f->Update();
  const double half = 6.0 * std::tan(vtkMath::RadiansFromDegrees(15.0)) * 0.5;  // at z = -1
  EXPECT_NEAR(f->GetVisibleLength(), 2 * (half - 0.6), 1e-3);
  renderer->SetActiveCamera(older);
  f->Update();
  // From z = -7, 6 away from the line again, nothing in front of it: 2 * half seen.
  EXPECT_NEAR(f->GetVisibleLength(), 2 * half, 1e-3);
  EXPECT_NEAR(f->GetHiddenLength(), 4.0 - 2 * half, 1e-3);
}

// The mesh path's silhouette over its own sphere (radius 1, eye at distance 4): all of it is seen
// (it lies inside triangles whose neighbours cross its grazing rays: the slack is the width of the
// triangles at each point; with none, about half was taken as hidden). A 0.1 x 0.1 square put 0.5
// in front of one silhouette point, towards the eye, hides a piece of about its size there: the
// slack is local (it was once sqrt(2 deflection r) of the whole scene, which grows with an
// assembly's size and let nearby occluders through).
TEST(EdgeVisibilityFilter, MeshSilhouettesSeenWholeAndHiddenByANearSquare)
{
  for (const int res : { 32, 128 })
  {
    SCOPED_TRACE(res);
    vtkNew<vtkSphereSource> sphere;
    sphere->SetRadius(1.0);
    sphere->SetThetaResolution(res);
    sphere->SetPhiResolution(res / 2);
    vtkNew<vtkCamera> camera;
    camera->SetPosition(0, 0, 4);
    camera->SetFocalPoint(0, 0, 0);
    camera->SetClippingRange(0.5, 10);
    vtkNew<vtkWireFurSilhouette> outline;
    outline->SetInputConnection(sphere->GetOutputPort());
    outline->SetCamera(camera);
    vtkNew<vtkWireFurEdgeVisibility> f;
    f->SetInputConnection(outline->GetOutputPort());
    f->SetSurfaceConnection(sphere->GetOutputPort());
    f->SetCamera(camera);
    f->Update();
    const double total = f->GetVisibleLength() + f->GetHiddenLength();
    EXPECT_NEAR(total, 2 * vtkMath::Pi() * std::sqrt(1.0 - 1.0 / 16.0), 0.05);  // (chords of the circle)
    EXPECT_LT(f->GetHiddenLength(), 1e-6 * total);

    // A square in front of the silhouette point (r, 0, 1/4), 0.5 towards the eye.
    const double r = std::sqrt(1.0 - 1.0 / 16.0);
    const glm::dvec3 p(r, 0, 0.25), eye(0, 0, 4);
    const glm::dvec3 c = p + 0.5 * glm::normalize(eye - p);
    vtkNew<vtkPlaneSource> square;
    square->SetOrigin(c.x - 0.05, c.y - 0.05, c.z);
    square->SetPoint1(c.x + 0.05, c.y - 0.05, c.z);
    square->SetPoint2(c.x - 0.05, c.y + 0.05, c.z);
    vtkNew<vtkAppendPolyData> both;
    both->AddInputConnection(sphere->GetOutputPort());
    both->AddInputConnection(square->GetOutputPort());
    f->SetSurfaceConnection(both->GetOutputPort());
    f->Update();
    // The square's shadow on the silhouette, seen from the eye: 0.1 x (distance to p) / (distance to c).
    const double shadow = 0.1 * glm::length(eye - p) / glm::length(eye - c);
    EXPECT_NEAR(f->GetHiddenLength(), shadow, 0.25 * shadow);
  }
}
