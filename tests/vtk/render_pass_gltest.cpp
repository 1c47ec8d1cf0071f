// OpenGL tests of vtkWireFurRenderPass (offscreen windows under Xvfb, Mesa llvmpipe): a marked
// wire drawn by the pass against the core's own software render of the same scene; OpenGL
// planes in front of and behind it; a frame without marked props against the plain delegate.
//
// The scene: a 200 x 150 window, camera at (0, 0, 5) looking at the origin (view angle 30,
// clipping range 1 ... 20), one scene light from (1, 1, 2), black background; the wire is a
// 3-pixel polyline through the image centre at depths -0.2 ... 0.2 about z = 0.
#include "pass_window.h"
#include "vtkWireFurRenderPass.h"

#include "core/srgb.h"
#include "render/renderer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerKey.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr int W = 200, H = 150;

const std::vector<glm::dvec3> kWirePoints = {
  { -1.2, -0.5, 0.0 }, { -0.4, 0.4, 0.2 }, { 0.4, -0.3, -0.2 }, { 1.2, 0.5, 0.0 }
};
const double kWireColour[3] = { 0.8, 0.5, 0.2 };

using wf::linearToSrgb; // core/srgb.h: apps/image_io.cpp's PNG encoding
using wf::srgbToLinear;

struct Window
{
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkWireFurRenderPass> pass;
  vtkSmartPointer<vtkActor> wire;

  explicit Window(int multiSamples = 0)
  {
    setUpPassWindow(window, renderer, pass, W, H, multiSamples);
  }

  vtkActor* AddWire(bool marked)
  {
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> lines;
    lines->InsertNextCell(vtkIdType(kWirePoints.size()));
    for (const glm::dvec3& p : kWirePoints)
      lines->InsertCellPoint(pts->InsertNextPoint(p.x, p.y, p.z));
    vtkNew<vtkPolyData> pd;
    pd->SetPoints(pts);
    pd->SetLines(lines);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    mapper->ScalarVisibilityOff();
    wire = vtkSmartPointer<vtkActor>::New();
    wire->SetMapper(mapper);
    vtkProperty* p = wire->GetProperty();
    p->SetDiffuseColor(kWireColour[0], kWireColour[1], kWireColour[2]);
    p->SetDiffuse(1.0);
    p->SetSpecularColor(1, 1, 1);
    p->SetSpecular(0.5);
    p->SetSpecularPower(20);
    p->SetLineWidth(3);
    if (marked)
      vtkWireFurRenderPass::Mark(wire);
    renderer->AddActor(wire);
    return wire;
  }

  /// An unmarked green plane at depth z, flat-shaded (ambient 1): pixels (0, 255, 0).
  void AddPlane(double z, double halfX, double halfY)
  {
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(-halfX, -halfY, z);
    pts->InsertNextPoint(halfX, -halfY, z);
    pts->InsertNextPoint(halfX, halfY, z);
    pts->InsertNextPoint(-halfX, halfY, z);
    vtkNew<vtkCellArray> quad;
    const vtkIdType ids[4] = { 0, 1, 2, 3 };
    quad->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> plane;
    plane->SetPoints(pts);
    plane->SetPolys(quad);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(plane);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(0, 1, 0);
    actor->GetProperty()->SetAmbient(1.0);
    actor->GetProperty()->SetDiffuse(0.0);
    actor->GetProperty()->SetSpecular(0.0);
    renderer->AddActor(actor);
  }

  /// RGB bytes, row 0 at the bottom (OpenGL's order).
  std::vector<unsigned char> Render()
  {
    window->Render();
    vtkNew<vtkUnsignedCharArray> rgb;
    window->GetPixelData(0, 0, W - 1, H - 1, 1, rgb);
    return std::vector<unsigned char>(rgb->GetPointer(0), rgb->GetPointer(0) + size_t(W) * H * 3);
  }
};

/// The same wire through the core directly: wf::render with the camera and light written out
/// here (not converted by the pass), premultiplied linear RGBA over transparent.
wf::RenderResult coreRender(const Window& win)
{
  wf::Scene s;
  double range[2];
  win.renderer->GetActiveCamera()->GetClippingRange(range);
  wf::Camera c;
  c.projection = wf::Camera::Projection::Perspective;
  c.eye = { 0, 0, 5 };
  c.target = { 0, 0, 0 };
  c.up = { 0, 1, 0 };
  c.fovYDegrees = 30;
  c.nearPlane = range[0];
  c.farPlane = range[1];
  s.camera = c;
  s.lights.lights.push_back({ glm::normalize(glm::dvec3(1, 1, 2)), glm::dvec3(1.0) });
  s.materials[0].phong.diffuse = { kWireColour[0], kWireColour[1], kWireColour[2] };
  s.materials[0].phong.specular = glm::dvec3(0.5);
  s.materials[0].phong.exponent = 20;
  wf::SceneWire w;
  w.lines.add(kWirePoints);
  w.thickness = 3;
  w.thicknessInPixels = true;
  w.style = wf::WireStyle::Shaded;
  s.wires.push_back(w);
  s.background = glm::vec4(0.0f);
  wf::RenderOptions o;
  o.width = W;
  o.height = H;
  return wf::render(s, o);
}

/// The core pixel at window pixel (x, y) (y from the bottom).
glm::vec4 coreAt(const wf::ImageRGBA& im, int x, int y)
{
  return im.at(x, H - 1 - y);
}

/// The core pixel over an 8-bit background colour, composited as the pass does: encoded.
glm::dvec3 expectedOver(const glm::vec4& c, const unsigned char bg[3])
{
  glm::dvec3 e;
  for (int k = 0; k < 3; ++k)
    e[k] = 255.0 * linearToSrgb(c[k] + (1.0f - c.w) * srgbToLinear(bg[k] / 255.0f));
  return e;
}

TEST(RenderPass, MarkingSetsTheKey)
{
  vtkNew<vtkActor> a;
  EXPECT_FALSE(vtkWireFurRenderPass::IsMarked(a));
  vtkWireFurRenderPass::Mark(a);
  EXPECT_TRUE(vtkWireFurRenderPass::IsMarked(a));
  EXPECT_EQ(a->GetPropertyKeys()->Get(vtkWireFurRenderPass::WIREFUR()), 1);
  vtkWireFurRenderPass::Mark(a, false);
  EXPECT_FALSE(vtkWireFurRenderPass::IsMarked(a));
}

// (a) The marked wire alone over black: the window holds the core's own render, sRGB-encoded.
// Expected: identical bytes (the pass composites over black with the same encoding); stated
// tolerance RMS < 2/255 and max < 8/255 per channel for the 8-bit path.
TEST(RenderPass, MarkedWireMatchesTheCoreRender)
{
  Window win;
  win.AddWire(true);
  const std::vector<unsigned char> px = win.Render();
  EXPECT_EQ(win.pass->GetLastMarkedProps(), 1);
  const wf::RenderResult core = coreRender(win);
  double sum2 = 0, maxErr = 0;
  int covered = 0;
  const unsigned char black[3] = { 0, 0, 0 };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
    {
      const glm::vec4 c = coreAt(core.image, x, y);
      if (c.w > 0.5f)
        ++covered;
      const glm::dvec3 e = expectedOver(c, black);
      for (int k = 0; k < 3; ++k)
      {
        const double d = std::abs(double(px[(size_t(y) * W + x) * 3 + k]) - e[k]);
        sum2 += d * d;
        maxErr = std::max(maxErr, d);
      }
    }
  if (const char* dump = std::getenv("WIREFUR_DUMP"))  // PPMs of both, for a person to look at
  {
    std::FILE* f = std::fopen((std::string(dump) + "_pass.ppm").c_str(), "wb");
    std::FILE* g = std::fopen((std::string(dump) + "_core.ppm").c_str(), "wb");
    std::fprintf(f, "P6 %d %d 255\n", W, H);
    std::fprintf(g, "P6 %d %d 255\n", W, H);
    for (int y = H - 1; y >= 0; --y)
      for (int x = 0; x < W; ++x)
      {
        std::fwrite(&px[(size_t(y) * W + x) * 3], 1, 3, f);
        const glm::dvec3 e = expectedOver(coreAt(core.image, x, y), black);
        for (int k = 0; k < 3; ++k)
          std::fputc(int(std::lround(e[k])), g);
      }
    std::fclose(f);
    std::fclose(g);
  }
  const double rms = std::sqrt(sum2 / (double(W) * H * 3));
  RecordProperty("rms_over_255", std::to_string(rms));
  RecordProperty("max_over_255", std::to_string(maxErr));
  std::printf("(a) wire vs core: RMS %.4f/255, max %.4f/255, %d covered pixels\n", rms, maxErr, covered);
  EXPECT_GT(covered, 300);  // the wire is really there: ~2.5 units of 3-pixel wire at ~70 px/unit
  EXPECT_LT(rms, 2.0);
  EXPECT_LT(maxErr, 8.0);
  EXPECT_GT(win.pass->GetLastCoreSeconds(), 0.0);
  EXPECT_GE(win.pass->GetLastRenderSeconds(), win.pass->GetLastCoreSeconds());
  EXPECT_GT(win.pass->GetLastErrorEstimate(), 0.0);
}

// (b) An unmarked OpenGL plane at z = 1, in front of the wire, hides it: inside the plane's
// image (x 65 ... 135, y 33 ... 117 at 70 px per unit; 3 pixels in from its edges) every pixel
// is the plane's green, although the wire crosses that region.
void expectPlaneHidesWire(int multiSamples)
{
  Window win(multiSamples);
  win.AddWire(true);
  win.AddPlane(1.0, 0.5, 0.6);
  const std::vector<unsigned char> px = win.Render();
  const wf::RenderResult core = coreRender(win);
  int wirePixelsBehind = 0, notGreen = 0;
  for (int y = 36; y <= 114; ++y)
    for (int x = 68; x <= 132; ++x)
    {
      if (coreAt(core.image, x, y).w > 0.1f)
        ++wirePixelsBehind;
      const unsigned char* p = &px[(size_t(y) * W + x) * 3];
      if (p[0] > 1 || p[1] < 254 || p[2] > 1)
        ++notGreen;
    }
  std::printf("(b) plane in front (%d samples): %d wire pixels behind it, %d not green\n", multiSamples,
              wirePixelsBehind, notGreen);
  EXPECT_GT(wirePixelsBehind, 50);
  EXPECT_EQ(notGreen, 0);
}

TEST(RenderPass, OpaquePlaneInFrontHidesTheWire)
{
  expectPlaneHidesWire(0);
}

TEST(RenderPass, OpaquePlaneInFrontHidesTheWireMultisampled)
{
  expectPlaneHidesWire(4);
}

// (c) The same plane at z = -1, behind the wire, does not hide it: inside the plane's image
// (x 77 ... 123, y 47 ... 103 at 46.6 px per unit) every pixel is the core's wire composited
// over the plane's green, within 2/255 (the plane's pixels are exactly green).
TEST(RenderPass, OpaquePlaneBehindKeepsTheWire)
{
  Window win;
  win.AddWire(true);
  win.AddPlane(-1.0, 0.5, 0.6);
  const std::vector<unsigned char> px = win.Render();
  const wf::RenderResult core = coreRender(win);
  const unsigned char green[3] = { 0, 255, 0 };
  int wirePixels = 0;
  double maxErr = 0;
  for (int y = 50; y <= 100; ++y)
    for (int x = 80; x <= 120; ++x)
    {
      const glm::vec4 c = coreAt(core.image, x, y);
      if (c.w > 0.9f)
        ++wirePixels;
      const glm::dvec3 e = expectedOver(c, green);
      for (int k = 0; k < 3; ++k)
        maxErr = std::max(maxErr, std::abs(double(px[(size_t(y) * W + x) * 3 + k]) - e[k]));
    }
  std::printf("(c) plane behind: %d wire pixels over it, max error %.3f/255\n", wirePixels, maxErr);
  EXPECT_GT(wirePixels, 30);
  EXPECT_LE(maxErr, 2.0);
}

// (c2) A reduced frame (SetImageReductionFactor 2, for frames while the camera moves) is the
// same view at half the size scaled up: the wire's centroid (weighted by its difference from the
// background) within 0.5 px of the full frame's, the image within an RMS of 10/255 of it (the
// wire is 3 px wide: at 1/2 size its antialiasing blurs over a pixel either side), and the plane
// in front still hides it (the delegate's depth scaled down to the nearest over each reduced
// pixel's bilinear support): every pixel the plane covers in the full frame is exactly green at
// factors 2, 3 and 4, up to the plane's edge. Factor 1 again gives the full frame bit for bit.
TEST(RenderPass, ReducedFrameIsTheSameViewScaledUp)
{
  Window win;
  win.AddWire(true);
  win.AddPlane(1.0, 0.25, 0.3);  // x 83 ... 117, y 54 ... 96 at 70 px per unit
  const std::vector<unsigned char> full = win.Render();
  win.pass->SetImageReductionFactor(2);
  const std::vector<unsigned char> reduced = win.Render();
  win.pass->SetImageReductionFactor(1);
  EXPECT_EQ(win.Render(), full);

  auto centroid = [](const std::vector<unsigned char>& px, double& cx, double& cy) {
    double sw = 0, sx = 0, sy = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
      {
        const unsigned char* p = &px[(size_t(y) * W + x) * 3];
        if (p[1] == 255 && p[0] == 0 && p[2] == 0)
          continue;  // the plane
        const double w = p[0] + p[1] + p[2];
        sw += w, sx += w * x, sy += w * y;
      }
    cx = sx / sw, cy = sy / sw;
  };
  double fx, fy, rx, ry;
  centroid(full, fx, fy);
  centroid(reduced, rx, ry);
  double sq = 0;
  for (size_t i = 0; i < full.size(); ++i)
    sq += (double(full[i]) - reduced[i]) * (double(full[i]) - reduced[i]);
  const double rms = std::sqrt(sq / double(full.size()));
  auto isGreen = [](const unsigned char* p) { return p[0] == 0 && p[1] == 255 && p[2] == 0; };
  int plane = 0, notGreen = 0;
  for (int f : { 2, 3, 4 })
  {
    win.pass->SetImageReductionFactor(f);
    const std::vector<unsigned char> px = f == 2 ? reduced : win.Render();
    for (size_t i = 0; i < full.size(); i += 3)
      if (isGreen(&full[i]))
      {
        ++plane;
        notGreen += !isGreen(&px[i]);
      }
  }
  win.pass->SetImageReductionFactor(1);

  std::printf("(c2) reduced 1/2: centroid moved (%.3f, %.3f) px, RMS %.2f/255; factors 2, 3, 4: %d of %d plane pixels "
              "not green\n", rx - fx, ry - fy, rms, notGreen, plane);
  EXPECT_GT(plane, 3 * 1000);
  EXPECT_LE(std::hypot(rx - fx, ry - fy), 0.5);
  EXPECT_GT(rms, 0.0);
  EXPECT_LE(rms, 10.0);
  EXPECT_EQ(notGreen, 0);
}

// (c3) InteractiveImageReductionFactor follows VTK's interaction protocol: between a trackball
// style's StartRotate and EndRotate (which raise and lower the window's desired update rate) the
// pass renders at 1/2 size, the image differs from the still frame, and after EndRotate the
// frame is full size again, bit for bit the frame before the interaction. On the map path the
// reduced frames and the still frame share the tables (one view node does not depend on the
// image size): none is rebuilt while the camera does not turn.
TEST(RenderPass, InteractionRendersReducedAndTheStillFrameFull)
{
  Window win;
  win.AddWire(true);
  win.pass->SetShadingToMaps();
  win.pass->SetInteractiveImageReductionFactor(2);
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(win.window);
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor->SetInteractorStyle(style);
  const std::vector<unsigned char> still = win.Render();
  EXPECT_EQ(win.pass->GetImageReductionFactorFor(win.window), 1);
  style->StartRotate();
  EXPECT_EQ(win.pass->GetImageReductionFactorFor(win.window), 2);
  const std::vector<unsigned char> moving = win.Render();
  EXPECT_EQ(win.pass->GetLastImageReductionFactor(), 2);
  EXPECT_EQ(win.pass->GetLastTablesBuilt(), 0);
  EXPECT_GT(win.pass->GetLastTablesReused(), 0);
  EXPECT_NE(moving, still);
  style->EndRotate();
  EXPECT_EQ(win.Render(), still);
  EXPECT_EQ(win.pass->GetLastImageReductionFactor(), 1);
  EXPECT_EQ(win.pass->GetLastTablesBuilt(), 0);
}

// (d) Without marked props the pass is its delegate: bit-identical to a vtkRenderStepsPass.
TEST(RenderPass, NoMarkedPropsIsTheDelegateBitForBit)
{
  Window win;
  win.AddWire(false);
  win.AddPlane(-1.0, 0.5, 0.6);
  const std::vector<unsigned char> withPass = win.Render();
  EXPECT_EQ(win.pass->GetLastMarkedProps(), 0);
  EXPECT_EQ(win.pass->GetLastCoreSeconds(), 0.0);
  vtkNew<vtkRenderStepsPass> steps;
  win.renderer->SetPass(steps);
  const std::vector<unsigned char> plain = win.Render();
  size_t differ = 0, lit = 0;
  for (size_t i = 0; i < plain.size(); ++i)
  {
    differ += withPass[i] != plain[i];
    lit += plain[i] != 0;
  }
  EXPECT_GT(lit, 1000u);
  EXPECT_EQ(differ, 0u);
}

// Unmarking a prop gives it back to OpenGL: the conversion cache follows the keys' MTime.
TEST(RenderPass, UnmarkingReturnsThePropToTheDelegate)
{
  Window win;
  vtkActor* wire = win.AddWire(true);
  win.Render();
  EXPECT_EQ(win.pass->GetLastMarkedProps(), 1);
  vtkWireFurRenderPass::Mark(wire, false);
  win.Render();
  EXPECT_EQ(win.pass->GetLastMarkedProps(), 0);
  vtkWireFurRenderPass::Mark(wire, true);
  const std::vector<unsigned char> again = win.Render();
  EXPECT_EQ(win.pass->GetLastMarkedProps(), 1);
  size_t lit = 0;
  for (unsigned char v : again)
    lit += v != 0;
  EXPECT_GT(lit, 300u);
}

}  // namespace

// The map path's tables are rebuilt only when the camera moves relative to the lights (the
// paper's rule, §2.2): a second frame of an unchanged view builds none; a turned camera with a
// scene light (fixed in the world) builds the wire's map again; with a headlight (fixed to the
// camera) turning rebuilds nothing. The closed path's lobe table depends on neither: built once.
TEST(RenderPass, TablesAreRebuiltOnlyWhenTheCameraMovesRelativeToTheLights)
{
  {
    Window closed;
    closed.AddWire(true);
    closed.Render();
    EXPECT_EQ(closed.pass->GetLastTablesBuilt(), 1);
    closed.renderer->GetActiveCamera()->Azimuth(25);
    closed.Render();
    EXPECT_EQ(closed.pass->GetLastTablesBuilt(), 0);
    EXPECT_EQ(closed.pass->GetLastTablesReused(), 1);
  }
  Window win;
  win.pass->SetShadingToMaps();
  win.AddWire(true);
  win.Render();
  EXPECT_GT(win.pass->GetLastTablesBuilt(), 0);
  win.Render();
  EXPECT_EQ(win.pass->GetLastTablesBuilt(), 0);
  EXPECT_GT(win.pass->GetLastTablesReused(), 0);
  win.renderer->GetActiveCamera()->Azimuth(25);
  win.Render();
  EXPECT_GT(win.pass->GetLastTablesBuilt(), 0);  // a scene light: the eye-space lights moved

  Window head;
  head.renderer->RemoveAllLights();
  vtkNew<vtkLight> headlight;
  headlight->SetLightTypeToHeadlight();
  head.renderer->AddLight(headlight);
  head.pass->SetShadingToMaps();
  head.AddWire(true);
  head.Render();
  head.renderer->GetActiveCamera()->Azimuth(25);
  head.Render();
  EXPECT_EQ(head.pass->GetLastTablesBuilt(), 0);
  EXPECT_GT(head.pass->GetLastTablesReused(), 0);
}

// The same picture in an on-screen window (an X window of the Xvfb server) as off-screen: the
// pass reads back and writes the window's own framebuffer either way.
TEST(RenderPass, OnScreenWindowGivesTheOffScreenPicture)
{
  Window off;
  off.AddWire(true);
  off.AddPlane(-1.0, 0.5, 0.6);
  const std::vector<unsigned char> a = off.Render();
  Window on;
  on.window->SetOffScreenRendering(0);
  on.AddWire(true);
  on.AddPlane(-1.0, 0.5, 0.6);
  const std::vector<unsigned char> b = on.Render();
  ASSERT_EQ(a.size(), b.size());
  size_t differ = 0, lit = 0;
  for (size_t i = 0; i < a.size(); ++i)
  {
    differ += a[i] != b[i];
    lit += a[i] != 0;
  }
  EXPECT_GT(lit, 1000u);
  EXPECT_EQ(on.pass->GetLastMarkedProps(), 1);
  EXPECT_LE(differ, a.size() / 1000);  // the same bytes (a few may differ at GL edge rasterisation)
}
