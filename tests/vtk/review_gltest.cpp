// Review tests of vtkWireFurRenderPass under Xvfb: marked props against OpenGL's own drawing of an
// unmarked copy (transforms, viewports, projections, resizes), caches between frames, degenerate
// inputs. Coverage is compared in linear light: a pixel counts as covered when its linear value is
// at least half the image's brightest (so the A-buffer's antialiased edges and OpenGL's aliased
// ones agree within a pixel).
#include "vtkWireFurRenderPass.h"

#include "core/srgb.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerKey.h>
#include <vtkLight.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

float toLinear(unsigned char v)
{
  return wf::srgbToLinear(v / 255.0f); // core/srgb.h
}

class ErrorCount : public vtkCommand
{
public:
  static ErrorCount* New() { return new ErrorCount; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    ++count;
    last = data ? static_cast<const char*>(data) : "";
  }
  int count = 0;
  std::string last;
};

vtkSmartPointer<vtkPolyData> quadData(double z, double hx, double hy)
{
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(-hx, -hy, z);
  pts->InsertNextPoint(hx, -hy, z);
  pts->InsertNextPoint(hx, hy, z);
  pts->InsertNextPoint(-hx, hy, z);
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, ids);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

struct Image
{
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;  // row 0 at the bottom
  const unsigned char* at(int x, int y) const { return &rgb[(size_t(y) * w + x) * 3]; }
  float lin(int x, int y) const
  {
    const unsigned char* p = at(x, y);
    return std::max({ toLinear(p[0]), toLinear(p[1]), toLinear(p[2]) });
  }
};

struct Coverage
{
  int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
  double area = 0, cx = 0, cy = 0;  // linear-weighted
  int pixels = 0;
};

Coverage coverage(const Image& im, int xa = 0, int xb = -1)
{
  if (xb < 0)
    xb = im.w - 1;
  float peak = 0;
  for (int y = 0; y < im.h; ++y)
    for (int x = xa; x <= xb; ++x)
      peak = std::max(peak, im.lin(x, y));
  Coverage c;
  if (peak <= 0)
    return c;
  for (int y = 0; y < im.h; ++y)
    for (int x = xa; x <= xb; ++x)
    {
      const double v = im.lin(x, y) / peak;
      c.area += v;
      c.cx += v * x;
      c.cy += v * y;
      if (v >= 0.5)
      {
        ++c.pixels;
        c.x0 = std::min(c.x0, x);
        c.x1 = std::max(c.x1, x);
        c.y0 = std::min(c.y0, y);
        c.y1 = std::max(c.y1, y);
      }
    }
  c.cx /= c.area;
  c.cy /= c.area;
  return c;
}

std::string str(const Coverage& c)
{
  char b[200];
  std::snprintf(b, sizeof b, "bbox x %d..%d y %d..%d, %d px, centroid (%.2f, %.2f), area %.1f", c.x0, c.x1, c.y0,
                c.y1, c.pixels, c.cx, c.cy, c.area);
  return b;
}

void expectSameCoverage(const Coverage& pass, const Coverage& gl, const char* what)
{
  SCOPED_TRACE(what);
  std::printf("%s\n  A-buffer: %s\n  OpenGL:   %s\n", what, str(pass).c_str(), str(gl).c_str());
  ASSERT_GT(gl.pixels, 20);
  EXPECT_GT(pass.pixels, 20);
  EXPECT_LE(std::abs(pass.x0 - gl.x0), 1);
  EXPECT_LE(std::abs(pass.x1 - gl.x1), 1);
  EXPECT_LE(std::abs(pass.y0 - gl.y0), 1);
  EXPECT_LE(std::abs(pass.y1 - gl.y1), 1);
  EXPECT_NEAR(pass.cx, gl.cx, 0.75);
  EXPECT_NEAR(pass.cy, gl.cy, 0.75);
}

struct Scene
{
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkWireFurRenderPass> pass;
  vtkNew<ErrorCount> errors;
  int w, h;

  Scene(int width = 200, int height = 150, int samples = 0)
    : w(width)
    , h(height)
  {
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(samples);
    window->SetSize(w, h);
    window->AddRenderer(renderer);
    Setup(renderer);
    renderer->SetPass(pass);
    pass->AddObserver(vtkCommand::ErrorEvent, errors);
  }

  static void Setup(vtkRenderer* r)
  {
    r->SetBackground(0, 0, 0);
    r->AutomaticLightCreationOff();
    vtkNew<vtkLight> light;
    light->SetLightTypeToHeadlight();
    r->AddLight(light);
    vtkCamera* c = r->GetActiveCamera();
    c->SetPosition(0, 0, 5);
    c->SetFocalPoint(0, 0, 0);
    c->SetViewUp(0, 1, 0);
    c->SetViewAngle(30);
    c->SetClippingRange(1, 20);
  }

  static vtkActor* AddQuad(vtkRenderer* r, bool marked, double z, double hx, double hy, const double rgb[3])
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(quadData(z, hx, hy));
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
    actor->GetProperty()->SetDiffuse(1.0);
    actor->GetProperty()->SetSpecular(0.0);
    actor->GetProperty()->SetAmbient(0.0);
    if (marked)
      vtkWireFurRenderPass::Mark(actor);
    r->AddActor(actor);
    return actor;
  }

  vtkActor* AddQuad(bool marked, double z, double hx, double hy, const double rgb[3])
  {
    return AddQuad(renderer, marked, z, hx, hy, rgb);
  }

  Image Render()
  {
    window->Render();
    int* size = window->GetSize();
    Image im;
    im.w = size[0];
    im.h = size[1];
    vtkNew<vtkUnsignedCharArray> a;
    window->GetPixelData(0, 0, im.w - 1, im.h - 1, 1, a);
    im.rgb.assign(a->GetPointer(0), a->GetPointer(0) + size_t(im.w) * im.h * 3);
    return im;
  }
};

const double kWhite[3] = { 1, 1, 1 };

/// The same quad once marked (A-buffer) and once unmarked (OpenGL), with `prepare` applied to the
/// actor (and `camera` to the scene) both times; their coverages.
template <class Prepare, class Cam>
void compareMarkedWithOpenGL(const char* what, Prepare prepare, Cam camera, int width = 200, int height = 150)
{
  Coverage cov[2];
  for (int marked = 0; marked < 2; ++marked)
  {
    Scene s(width, height);
    vtkActor* a = s.AddQuad(marked == 1, 0.0, 0.6, 0.4, kWhite);
    prepare(a);
    camera(s.renderer->GetActiveCamera());
    cov[marked] = coverage(s.Render());
    EXPECT_EQ(s.errors->count, 0) << s.errors->last;
    if (marked)
    {
      EXPECT_EQ(s.pass->GetLastMarkedProps(), 1);
    }
  }
  expectSameCoverage(cov[1], cov[0], what);
}

auto noCamera = [](vtkCamera*) {};

TEST(ReviewRenderPassGL, MarkedSurfaceCoverageMatchesOpenGL)
{
  compareMarkedWithOpenGL("plain quad", [](vtkActor*) {}, noCamera);
}

TEST(ReviewRenderPassGL, UserMatrixIsApplied)
{
  compareMarkedWithOpenGL(
    "SetPosition / SetScale / RotateZ",
    [](vtkActor* a) {
      a->SetPosition(0.4, -0.2, 0.3);
      a->SetScale(0.7, 1.3, 1.0);
      a->RotateZ(20);
    },
    noCamera);
  compareMarkedWithOpenGL(
    "SetUserMatrix",
    [](vtkActor* a) {
      vtkNew<vtkTransform> t;
      t->Translate(-0.5, 0.25, 0.0);
      t->RotateY(30);
      a->SetUserTransform(t);
    },
    noCamera);
}

TEST(ReviewRenderPassGL, ParallelProjection)
{
  compareMarkedWithOpenGL("parallel projection", [](vtkActor*) {},
    [](vtkCamera* c) {
      c->ParallelProjectionOn();
      c->SetParallelScale(1.0);
    });
}

TEST(ReviewRenderPassGL, OffCentreCameraAndHorizontalViewAngle)
{
  compareMarkedWithOpenGL("turned camera, horizontal view angle", [](vtkActor*) {},
    [](vtkCamera* c) {
      c->SetPosition(1.5, 1.0, 4.0);
      c->SetFocalPoint(0.2, 0.1, 0.0);
      c->SetViewUp(0.1, 1, 0);
      c->UseHorizontalViewAngleOn();
      c->SetViewAngle(40);
    });
}

// A renderer covering the right half of the window: the marked quad lands where OpenGL draws the
// unmarked one.
TEST(ReviewRenderPassGL, ViewportThatIsNotTheWholeWindow)
{
  Coverage cov[2];
  for (int marked = 0; marked < 2; ++marked)
  {
    Scene s(300, 150);
    s.renderer->SetViewport(0.5, 0.0, 1.0, 1.0);
    s.AddQuad(marked == 1, 0.0, 0.6, 0.4, kWhite);
    const Image im = s.Render();
    cov[marked] = coverage(im);
    // nothing drawn in the left half
    int leftLit = 0;
    for (int y = 0; y < im.h; ++y)
      for (int x = 0; x < 150; ++x)
        leftLit += im.lin(x, y) > 0.01f;
    EXPECT_EQ(leftLit, 0) << (marked ? "A-buffer" : "OpenGL");
  }
  expectSameCoverage(cov[1], cov[0], "viewport 0.5..1");
}

// Two renderers in one window, each with its own pass and a marked quad (red left, blue right).
TEST(ReviewRenderPassGL, TwoRenderersInOneWindow)
{
  Scene s(300, 150);
  s.renderer->SetViewport(0.0, 0.0, 0.5, 1.0);
  const double red[3] = { 1, 0, 0 }, blue[3] = { 0, 0, 1 };
  s.AddQuad(true, 0.0, 0.6, 0.4, red);
  vtkNew<vtkRenderer> right;
  right->SetViewport(0.5, 0.0, 1.0, 1.0);
  Scene::Setup(right);
  vtkNew<vtkWireFurRenderPass> pass2;
  right->SetPass(pass2);
  Scene::AddQuad(right, true, 0.0, 0.6, 0.4, blue);
  s.window->AddRenderer(right);
  const Image im = s.Render();
  const unsigned char* l = im.at(75, 75);
  const unsigned char* r = im.at(225, 75);
  std::printf("left centre (%d %d %d), right centre (%d %d %d)\n", l[0], l[1], l[2], r[0], r[1], r[2]);
  EXPECT_GT(l[0], 100);
  EXPECT_LT(l[2], 20);
  EXPECT_GT(r[2], 100);
  EXPECT_LT(r[0], 20);
  EXPECT_EQ(s.pass->GetLastMarkedProps(), 1);
  EXPECT_EQ(pass2->GetLastMarkedProps(), 1);
}

// Resizing the window between renders (also multisampled: the resolve framebuffer is resized).
TEST(ReviewRenderPassGL, WindowResizedBetweenRenders)
{
  for (int samples : { 0, 4 })
  {
    Coverage cov[2];
    for (int marked = 0; marked < 2; ++marked)
    {
      Scene s(200, 150, samples);
      s.AddQuad(marked == 1, 0.0, 0.6, 0.4, kWhite);
      s.Render();
      s.window->SetSize(320, 240);
      const Image im = s.Render();
      EXPECT_EQ(im.w, 320);
      cov[marked] = coverage(im);
      EXPECT_EQ(s.errors->count, 0) << s.errors->last;
    }
    expectSameCoverage(cov[1], cov[0], samples ? "resized, 4 samples" : "resized");
  }
}

// Marked and unmarked quads interleaved in depth: red marked at z 0.5 (front), green unmarked at
// z 0, blue marked at z -0.5; all overlap at the centre (half-widths 12, 28 and 46 pixels).
// Expected red at the centre, green 25 px right of it, blue 40 px right of it.
TEST(ReviewRenderPassGL, MarkedAndUnmarkedInterleavedInDepth)
{
  Scene s;
  const double red[3] = { 1, 0, 0 }, green[3] = { 0, 1, 0 }, blue[3] = { 0, 0, 1 };
  s.AddQuad(true, 0.5, 0.2, 0.2, red);
  s.AddQuad(false, 0.0, 0.5, 0.5, green);
  s.AddQuad(true, -0.5, 0.9, 0.9, blue);
  const Image im = s.Render();
  const unsigned char* c = im.at(100, 75);
  const unsigned char* g = im.at(100 + 25, 75);  // inside green (0.5 at ~ 85 px/unit), outside red
  const unsigned char* b = im.at(100 + 40, 75);  // outside green (28 px), inside blue (46 px)
  std::printf("centre (%d %d %d), green ring (%d %d %d), blue ring (%d %d %d)\n", c[0], c[1], c[2], g[0], g[1], g[2],
              b[0], b[1], b[2]);
  EXPECT_GT(c[0], 100);
  EXPECT_LT(c[1], 20);
  EXPECT_GT(g[1], 100);
  EXPECT_LT(g[2], 20);
  EXPECT_GT(b[2], 100);
  EXPECT_LT(b[1], 20);
}

// The material changes between frames (the ShadingCache keeps tables): the image follows.
TEST(ReviewRenderPassGL, PropertyColourChangeBetweenFrames)
{
  Scene s;
  s.pass->SetShadingToMaps();  // the map path's reflectance sphere must follow the property
  const double red[3] = { 1, 0, 0 };
  vtkActor* a = s.AddQuad(true, 0.0, 0.6, 0.4, red);
  Image im = s.Render();
  const unsigned char* p = im.at(100, 75);
  EXPECT_GT(p[0], 100);
  EXPECT_LT(p[2], 20);
  a->GetProperty()->SetColor(0, 0, 1);
  im = s.Render();
  p = im.at(100, 75);
  std::printf("after SetColor(0, 0, 1): (%d %d %d), tables built %d\n", p[0], p[1], p[2], s.pass->GetLastTablesBuilt());
  EXPECT_LT(p[0], 20);
  EXPECT_GT(p[2], 100);
  // Also the specular power alone (same colours).
  a->GetProperty()->SetSpecular(1.0);
  a->GetProperty()->SetSpecularPower(5);
  s.Render();
  EXPECT_GT(s.pass->GetLastTablesBuilt(), 0);
}

// Point colours (unsigned char scalars, direct) on a marked actor: the quad shows them; with
// ScalarVisibilityOff it shows the property's colour. Cell colours likewise (OpenGL shows them).
TEST(ReviewRenderPassGL, MappedColours)
{
  for (int mode = 0; mode < 3; ++mode)
  {
    Scene s;
    vtkSmartPointer<vtkPolyData> pd = quadData(0.0, 0.6, 0.4);
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetNumberOfComponents(3);
    if (mode == 2)
    {
      colours->InsertNextTuple3(255, 0, 0);
      pd->GetCellData()->SetScalars(colours);
    }
    else
    {
      for (int i = 0; i < 4; ++i)
        colours->InsertNextTuple3(255, 0, 0);
      pd->GetPointData()->SetScalars(colours);
    }
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    mapper->SetColorModeToDirectScalars();
    mapper->SetScalarVisibility(mode != 1);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(0, 0, 1);
    actor->GetProperty()->SetSpecular(0);
    s.renderer->AddActor(actor);
    const Image gl = s.Render();  // unmarked first: what OpenGL draws
    const unsigned char* q = gl.at(100, 75);
    vtkWireFurRenderPass::Mark(actor);
    const Image im = s.Render();
    const unsigned char* p = im.at(100, 75);
    std::printf("  OpenGL (unmarked): (%d %d %d)\n", q[0], q[1], q[2]);
    std::printf("mode %d (0 point colours, 1 scalar visibility off, 2 cell colours): (%d %d %d)\n", mode, p[0],
                p[1], p[2]);
    if (mode == 1)
    {
      EXPECT_LT(p[0], 20);
      EXPECT_GT(p[2], 100);
    }
    else
    {
      // OpenGL shows the scalar colours in place of the property's diffuse colour: red. The
      // pass must show what OpenGL shows for the same actor.
      EXPECT_GT(q[0], 100) << "mode " << mode;
      EXPECT_GT(p[0], 100) << "mode " << mode;
      EXPECT_LT(p[2], 20) << "mode " << mode;
    }
  }
}

// The marked actor's input becomes empty after the first render: expected the delegate's picture
// (black), no error, no stale geometry.
TEST(ReviewRenderPassGL, InputBecomesEmpty)
{
  Scene s;
  vtkActor* a = s.AddQuad(true, 0.0, 0.6, 0.4, kWhite);
  Image im = s.Render();
  EXPECT_GT(coverage(im).pixels, 100);
  vtkNew<vtkPolyData> empty;
  vtkPolyDataMapper::SafeDownCast(a->GetMapper())->SetInputData(empty);
  im = s.Render();
  int lit = 0;
  for (unsigned char v : im.rgb)
    lit += v != 0;
  EXPECT_EQ(lit, 0);
  EXPECT_EQ(s.errors->count, 0) << s.errors->last;
  // Points but no cells.
  vtkNew<vtkPolyData> pointsOnly;
  pointsOnly->SetPoints(quadData(0, 1, 1)->GetPoints());
  vtkPolyDataMapper::SafeDownCast(a->GetMapper())->SetInputData(pointsOnly);
  im = s.Render();
  lit = 0;
  for (unsigned char v : im.rgb)
    lit += v != 0;
  EXPECT_EQ(lit, 0);
  EXPECT_EQ(s.errors->count, 0) << s.errors->last;
}

TEST(ReviewRenderPassGL, MaskSizes)
{
  for (int mw : { 4, 8 })
  {
    const int mh = mw == 4 ? 4 : 8;
    Coverage cov[2];
    for (int marked = 0; marked < 2; ++marked)
    {
      Scene s;
      s.pass->SetMaskSize(mw, mh);
      EXPECT_EQ(s.pass->GetMaskWidth(), mw);
      EXPECT_EQ(s.pass->GetMaskHeight(), mh);
      s.AddQuad(marked == 1, 0.0, 0.6, 0.4, kWhite);
      cov[marked] = coverage(s.Render());
      if (marked)
      {
        EXPECT_NEAR(s.pass->GetLastCoverageError(), 1.0 / (mw * mh), 1e-12);
      }
    }
    expectSameCoverage(cov[1], cov[0], mw == 4 ? "mask 4x4" : "mask 8x8");
  }
}

// A wire: a marked polyline moved by the actor's position lands where OpenGL draws the unmarked
// copy (centroid within a pixel).
TEST(ReviewRenderPassGL, MarkedWireWithUserTransform)
{
  Coverage cov[2];
  for (int marked = 0; marked < 2; ++marked)
  {
    Scene s;
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(-0.8, -0.3, 0);
    pts->InsertNextPoint(0.8, 0.3, 0);
    vtkNew<vtkCellArray> lines;
    const vtkIdType ids[2] = { 0, 1 };
    lines->InsertNextCell(2, ids);
    vtkNew<vtkPolyData> pd;
    pd->SetPoints(pts);
    pd->SetLines(lines);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(1, 1, 1);
    actor->GetProperty()->SetLineWidth(3);
    actor->GetProperty()->SetLighting(false);
    actor->SetPosition(0.3, 0.4, 0);
    actor->SetScale(0.5, 1, 1);
    if (marked)
    {
      vtkWireFurRenderPass::Mark(actor);
      actor->GetPropertyKeys()->Set(vtkWireFurRenderPass::WIREFUR_WIRE_STYLE(), 1);  // plain
    }
    s.renderer->AddActor(actor);
    cov[marked] = coverage(s.Render());
  }
  std::printf("wire\n  A-buffer: %s\n  OpenGL:   %s\n", str(cov[1]).c_str(), str(cov[0]).c_str());
  EXPECT_NEAR(cov[1].cx, cov[0].cx, 1.0);
  EXPECT_NEAR(cov[1].cy, cov[0].cy, 1.0);
  EXPECT_LE(std::abs(cov[1].x0 - cov[0].x0), 2);
  EXPECT_LE(std::abs(cov[1].x1 - cov[0].x1), 2);
}

// A camera light is the same light as a scene light placed along its world direction: the pass
// must give the same picture for both (VTK's camera-light frame: camera at (0, 0, 1) looking at
// the origin, +y up). The camera is turned so that the frames differ.
TEST(ReviewRenderPassGL, CameraLightEqualsTheSceneLightItStandsFor)
{
  Image im[2];
  for (int k = 0; k < 2; ++k)
  {
    Scene s;
    s.renderer->RemoveAllLights();
    vtkCamera* c = s.renderer->GetActiveCamera();
    c->Azimuth(25);
    c->OrthogonalizeViewUp();
    vtkNew<vtkLight> light;
    const double eyeDir[3] = { 0.6, 0.5, 0.62 };
    if (k == 0)
    {
      light->SetLightTypeToCameraLight();
      light->SetPosition(eyeDir[0], eyeDir[1], eyeDir[2]);
      light->SetFocalPoint(0, 0, 0);
    }
    else
    {
      // world direction = inverse view rotation x eye direction
      vtkMatrix4x4* v = c->GetViewTransformMatrix();
      double w[3] = { 0, 0, 0 };
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          w[i] += v->GetElement(j, i) * eyeDir[j];
      light->SetLightTypeToSceneLight();
      light->SetPosition(w[0], w[1], w[2]);
      light->SetFocalPoint(0, 0, 0);
      light->SetPositional(false);
    }
    s.renderer->AddLight(light);
    vtkActor* a = s.AddQuad(true, 0.0, 0.6, 0.4, kWhite);
    a->GetProperty()->SetSpecular(0.6);
    a->GetProperty()->SetSpecularPower(10);
    im[k] = s.Render();
    const unsigned char* cp = im[k].at(100, 75);
    std::printf("  %s: centre (%d %d %d), marked %d, errors %d %s\n", k ? "scene light" : "camera light", cp[0], cp[1],
                cp[2], s.pass->GetLastMarkedProps(), s.errors->count, s.errors->last.c_str());
  }
  int maxDiff = 0, lit = 0;
  for (size_t i = 0; i < im[0].rgb.size(); ++i)
  {
    maxDiff = std::max(maxDiff, std::abs(int(im[0].rgb[i]) - int(im[1].rgb[i])));
    lit += im[0].rgb[i] > 10;
  }
  std::printf("camera light vs scene light: max difference %d/255, %d lit channels\n", maxDiff, lit);
  EXPECT_GT(lit, 1000);
  EXPECT_LE(maxDiff, 1);
}

}  // namespace
