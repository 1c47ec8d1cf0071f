// A VTK pipeline of vtkWireFurBurnish -> mapper -> actor marked for vtkWireFurRenderPass gives
// brushed metal: it differs from the same actor without the filter (which the pass drew as
// plastic before), and it matches the core's render of the same geometry in the `burnished` style
// (scene/style_presets.h: what `wirefur render FILE --style burnished` draws), with the window's
// camera and light. And lines shaded by vtkWireFurTangentShading are not shaded a second time.
#include "pass_window.h"
#include "vtkWireFurBurnish.h"
#include "vtkWireFurRenderPass.h"
#include "vtkWireFurTangentShading.h"

#include "core/srgb.h"
#include "render/renderer.h"
#include "scene/style_presets.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace {

constexpr int W = 200, H = 150;

/// The window of the render pass tests: camera at (0, 0, 5) looking at the origin, view angle
/// 30, one white scene light from (1, 1, 2), black background.
struct Window {
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkWireFurRenderPass> pass;
  Window() { setUpPassWindow(window, renderer, pass, W, H); }
  /// Linear RGB, row 0 at the top.
  std::vector<glm::dvec3> Render() {
    window->Render();
    vtkNew<vtkUnsignedCharArray> rgb;
    window->GetPixelData(0, 0, W - 1, H - 1, 1, rgb);
    std::vector<glm::dvec3> out(size_t(W) * H);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        for (int k = 0; k < 3; ++k)
          out[size_t(H - 1 - y) * W + x][k] = wf::srgbToLinear(rgb->GetValue((vtkIdType(y) * W + x) * 3 + k) / 255.0f);
    return out;
  }
};

/// A plane facing the camera, u along x (so that grain U runs along x, as the burnished style
/// lays grain on a mesh whose normal is the up axis: along x), cut into triangles.
vtkSmartPointer<vtkPolyData> plane() {
  vtkNew<vtkPlaneSource> p;
  p->SetOrigin(-1.2, -0.8, 0.0);
  p->SetPoint1(1.2, -0.8, 0.0);
  p->SetPoint2(-1.2, 0.8, 0.0);
  p->SetResolution(24, 16);
  vtkNew<vtkTriangleFilter> t;
  t->SetInputConnection(p->GetOutputPort());
  t->Update();
  vtkSmartPointer<vtkPolyData> out = t->GetOutput();
  return out;
}

double rms(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 d = a[i] - b[i];
    s += glm::dot(d, d);
  }
  return std::sqrt(s / (3.0 * double(a.size())));
}

/// The presets' brushed steel on a vtkProperty (colour x coefficient; specular 5 as a colour).
void steel(vtkProperty* p) {
  p->SetDiffuseColor(0.18, 0.18, 0.18);
  p->SetDiffuse(1.0);
  p->SetSpecularColor(5.0, 5.0, 5.0);
  p->SetSpecular(1.0);
  p->SetSpecularPower(30.0);
  p->SetAmbient(0.0);
}

/// `input` as a steel actor marked for the pass, in the window: linear RGB, row 0 at the top.
std::vector<glm::dvec3> drawSteel(vtkPolyData* input) {
  Window win;
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(input);
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  steel(actor->GetProperty());
  vtkWireFurRenderPass::Mark(actor);
  win.renderer->AddActor(actor);
  return win.Render();
}

/// The core's render of `scene` in the window's camera and light, linear RGB, row 0 at the top.
std::vector<glm::dvec3> coreImage(wf::Scene scene) {
  wf::Camera c;
  c.eye = {0, 0, 5};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fovYDegrees = 30;
  scene.camera = c;
  scene.lights = wf::LightRig{};
  scene.lights.lights.push_back({glm::normalize(glm::dvec3(1, 1, 2)), glm::dvec3(1.0)});
  scene.lightsFollowCamera = false;
  scene.background = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  wf::RenderOptions o;
  o.width = W;
  o.height = H;
  const wf::RenderResult r = wf::render(scene, o);
  std::vector<glm::dvec3> out(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) out[size_t(y) * W + x] = glm::dvec3(glm::vec3(r.image.at(x, y)));
  return out;
}

TEST(BurnishPass, BurnishedActorIsBrushedSteelAsTheCommandDrawsIt) {
  vtkSmartPointer<vtkPolyData> mesh = plane();
  vtkNew<vtkWireFurBurnish> burnish;
  burnish->SetInputData(mesh);
  burnish->SetGrain(vtkWireFurBurnish::GrainU);
  burnish->Update();
  ASSERT_GT(burnish->GetOutput()->GetNumberOfPoints(), 0);

  const std::vector<glm::dvec3> brushed = drawSteel(burnish->GetOutput()), plain = drawSteel(mesh);

  // The command's burnished style on the same triangles, with the window's camera and light.
  auto g = std::make_shared<wf::GeometryData>();
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    g->mesh.positions.emplace_back(p[0], p[1], p[2]);
    g->mesh.normals.emplace_back(0.0, 0.0, 1.0);
  }
  vtkNew<vtkIdList> ids;
  for (mesh->GetPolys()->InitTraversal(); mesh->GetPolys()->GetNextCell(ids);)
    g->mesh.triangles.emplace_back(std::uint32_t(ids->GetId(0)), std::uint32_t(ids->GetId(1)), std::uint32_t(ids->GetId(2)));
  const std::vector<glm::dvec3> command = coreImage(wf::buildScene(wf::describeStyled(g, wf::Style::Burnished)).scene);

  const double toCommand = rms(brushed, command), toPlain = rms(brushed, plain), plainToCommand = rms(plain, command);
  std::printf("burnished pass vs command %.4g, vs unburnished %.4g; unburnished vs command %.4g\n", toCommand, toPlain,
              plainToCommand);
  EXPECT_LE(toCommand, 1e-2);
  EXPECT_GT(toPlain, 5.0 * toCommand);
  EXPECT_GT(plainToCommand, 1e-2);
}

// Every grain of the filter reaches the pass: V and Circular (the style path has only U) against
// the core's render of the same triangles with the filter's tangents as the grain.
TEST(BurnishPass, EveryGrainIsTheFiltersTangents) {
  vtkSmartPointer<vtkPolyData> mesh = plane();
  for (int grain : {int(vtkWireFurBurnish::GrainV), int(vtkWireFurBurnish::Circular)}) {
    SCOPED_TRACE(grain);
    vtkNew<vtkWireFurBurnish> burnish;
    burnish->SetInputData(mesh);
    burnish->SetGrain(grain);
    burnish->SetAxisPoint(0.3, -0.2, 0.0);
    burnish->Update();
    vtkPolyData* out = burnish->GetOutput();
    ASSERT_GT(out->GetNumberOfPoints(), 0);
    const std::vector<glm::dvec3> pass = drawSteel(out);

    wf::Scene s;
    wf::SceneSurface surf;
    vtkDataArray* T = out->GetPointData()->GetTangents();
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
      double p[3], t[3];
      out->GetPoint(i, p);
      T->GetTuple(i, t);
      surf.mesh.positions.emplace_back(p[0], p[1], p[2]);
      surf.mesh.normals.emplace_back(0.0, 0.0, 1.0);
      surf.mesh.derivU.emplace_back(t[0], t[1], t[2]);
      surf.mesh.derivV.push_back(glm::normalize(glm::cross(glm::dvec3(0, 0, 1), glm::dvec3(t[0], t[1], t[2]))));
    }
    vtkNew<vtkIdList> ids;
    for (out->GetPolys()->InitTraversal(); out->GetPolys()->GetNextCell(ids);)
      surf.mesh.triangles.emplace_back(std::uint32_t(ids->GetId(0)), std::uint32_t(ids->GetId(1)), std::uint32_t(ids->GetId(2)));
    s.surfaces.push_back(surf);
    s.materials[0].phong = {glm::dvec3(0.18), glm::dvec3(5.0), 30.0};
    s.materials[0].burnish.grain = wf::Burnish::Grain::U;
    const std::vector<glm::dvec3> core = coreImage(s);
    const double e = rms(pass, core);
    std::printf("grain %d: pass vs core with the filter's tangents %.4g\n", grain, e);
    EXPECT_LE(e, 1e-2);
  }
}

TEST(BurnishPass, TangentShadedLinesAreNotShadedTwice) {
  // A few lines, shaded by the filter with the window's light; the pass must show the filter's
  // radiance as it is (drawn plain), not shade it again.
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  for (int k = 0; k < 5; ++k) {
    const vtkIdType a = pts->InsertNextPoint(-1.0, -0.6 + 0.3 * k, 0.0), b = pts->InsertNextPoint(1.0, -0.4 + 0.3 * k, 0.3);
    const vtkIdType ids[2] = {a, b};
    lines->InsertNextCell(2, ids);
  }
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(pts);
  pd->SetLines(lines);
  Window win;
  vtkNew<vtkWireFurTangentShading> shading;
  shading->SetInputData(pd);
  shading->SetRenderer(win.renderer);
  shading->Update();
  vtkDataArray* radiance = shading->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  ASSERT_NE(radiance, nullptr);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(shading->GetOutput());
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetLineWidth(5);
  vtkWireFurRenderPass::Mark(actor);
  win.renderer->AddActor(actor);
  const std::vector<glm::dvec3> px = win.Render();
  // The brightest pixel along the lines is the filter's brightest radiance (a pixel wholly
  // covered shows it as it is), not that radiance shaded again (its square, roughly).
  double brightest = 0.0, filter = 0.0;
  for (const glm::dvec3& p : px) brightest = std::max(brightest, std::max({p.x, p.y, p.z}));
  for (vtkIdType i = 0; i < radiance->GetNumberOfTuples(); ++i)
    for (int k = 0; k < 3; ++k) filter = std::max(filter, std::min(1.0, radiance->GetComponent(i, k)));
  std::printf("brightest pixel %.4f, filter's brightest radiance %.4f\n", brightest, filter);
  EXPECT_NEAR(brightest, filter, 0.03);
}

}  // namespace
