#include "view_command.h"

#include "x_display.h"

#include "cli.h"
#include "safe_files.h"
#include "render_command.h"
#include "scene_file.h"

#include "core/srgb.h"
#include "vtkWireFurRenderPass.h"

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationDoubleKey.h>
#include <vtkInformationIntegerKey.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkPNGWriter.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace wfapp {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The trackball camera with WireFur's keys instead of the style's own (w, s, f, m would switch
// representation, fly to a point ...): our keys go to `onKey`, the rest to the trackball.
class ViewerStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static ViewerStyle* New();
  vtkTypeMacro(ViewerStyle, vtkInteractorStyleTrackballCamera);
  std::function<bool(char)> onKey;  ///< true: handled
  void OnChar() override {
    const char key = this->Interactor->GetKeyCode();
    if (onKey && onKey(key)) return;
    if (key == 'q' || key == 'Q' || key == 'e' || key == 'E') {
      this->Interactor->ExitCallback();
      return;
    }
    vtkInteractorStyleTrackballCamera::OnChar();
  }
};
vtkStandardNewMacro(ViewerStyle);

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int runView(const ViewOptions& o) {
  if (!o.png.empty() && o.frames == 0) throw UsageError("view: --png needs --frames N");
  // --png: checked, and its folder shown writable, before the window opens (apps/safe_files.h).
  if (!o.png.empty()) requireOutputPath(o.png), OutputFile::probe(o.png);
  if (o.offscreen && o.frames == 0) throw UsageError("view: --offscreen needs --frames N (there is no window to interact with)");
  SceneOverrides overrides;
  overrides.cad = o.cad;
  overrides.hidden = o.hidden;
  overrides.silhouettes = o.silhouettes;
  overrides.edges = o.edges;
  overrides.burnish = o.burnish;
  SceneFile sf = loadInput(o.input, o.style, overrides);  // bad input first: exit 2, whatever the display
  // Debian's VTK 9.1 draws through X (GLX) even off-screen, and aborts the process when it
  // cannot open the display: check first, and say so in one line.
  {
    const char* name = std::getenv("DISPLAY");
    if (!canOpenXDisplay())
      throw std::runtime_error(std::string("view: cannot open the X display") +
                               (name ? std::string(" '") + name + "'" : std::string(" (DISPLAY is not set)")) +
                               "; VTK renders through X even with --offscreen: run under xvfb-run");
  }
  reframe(sf, o.width, o.height);
  // The scene shown; its silhouette wires (if any) are traced again whenever the camera moves.
  wf::Scene& scene = sf.scene;

  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  window->SetSize(o.width, o.height);
  window->SetMultiSamples(0);  // the A-buffer antialiases the marked props; OpenGL surfaces stay as drawn
  window->SetWindowName(("wirefur view " + (sf.title.empty() ? o.input : sf.title)).c_str());
  if (o.offscreen) window->SetOffScreenRendering(1);
  window->AddRenderer(renderer);
  const glm::vec4 bg = scene.background;
  renderer->SetBackground(wf::srgb8(bg.x) / 255.0, wf::srgb8(bg.y) / 255.0, wf::srgb8(bg.z) / 255.0);

  vtkNew<vtkWireFurRenderPass> pass;
  pass->SetMaskSize(o.mask.empty() ? sf.mask.w : o.mask[0] - '0', o.mask.empty() ? sf.mask.h : o.mask[2] - '0');
  pass->SetBudget(sf.budget);
  pass->SetThreads(o.threads);
  pass->SetAmbient(scene.lights.ambient.x, scene.lights.ambient.y, scene.lights.ambient.z);
  // While the camera moves (a drag, a wheel step: VTK's styles raise the window's desired update
  // rate), frames at 1/F of the size; the frame after it full size.
  pass->SetInteractiveImageReductionFactor(o.interactiveReduction);
  renderer->SetPass(pass);

  // The scene as `wirefur render` draws it: every surface, wire, hair and scale through the
  // A-buffer with the scene's own materials and lights (the pass's SetScene); OpenGL only shows
  // the result. The keys below hand the pass a changed copy.
  bool plainWires = false, showFur = true, showScales = true;
  auto update = [&] {
    auto shown = std::make_shared<wf::Scene>(scene);
    shown->surfaces.clear();
    shown->wires.clear();
    for (const wf::SceneSurface& s : scene.surfaces)
      if (showScales || !endsWith(s.name, " scales")) shown->surfaces.push_back(s);
    for (const wf::SceneWire& w : scene.wires) {
      if (!showFur && w.aggregate) continue;
      shown->wires.push_back(w);
      if (plainWires && shown->wires.back().style == wf::WireStyle::Shaded) {
        wf::SceneWire& p = shown->wires.back();
        p.style = wf::WireStyle::Plain;
        p.colour = glm::vec3(scene.materials[size_t(std::clamp(p.material, 0, int(scene.materials.size()) - 1))].phong.diffuse);
      }
    }
    pass->SetScene(shown);
  };
  update();

  vtkCamera* camera = renderer->GetActiveCamera();
  if (scene.camera) {
    const wf::Camera& c = *scene.camera;
    camera->SetPosition(c.eye.x, c.eye.y, c.eye.z);
    camera->SetFocalPoint(c.target.x, c.target.y, c.target.z);
    camera->SetViewUp(c.up.x, c.up.y, c.up.z);
    camera->SetViewAngle(c.fovYDegrees);
    camera->SetParallelProjection(c.projection == wf::Camera::Projection::Orthographic);
    camera->SetParallelScale(c.orthoHeight / 2);
    camera->OrthogonalizeViewUp();
  } else {
    renderer->ResetCamera();
  }
  renderer->ResetCameraClippingRange();

  // Frame time and error estimate in the lower-left corner (of the frame before: the text is
  // set before each render from what the pass measured last).
  vtkNew<vtkTextActor> text;
  text->GetTextProperty()->SetFontSize(14);
  text->GetTextProperty()->SetColor(1.0, 1.0, 0.6);
  text->SetDisplayPosition(8, 8);
  renderer->AddViewProp(text);
  auto caption = [&] {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(1);
    // The frame about to be drawn: reduced while the camera moves (its figures are not shown:
    // they would be the render at the reduced size, not the picture); still, the last frame's
    // time and error bounds.
    const int coming = pass->GetImageReductionFactorFor(window);
    if (coming > 1) {
      s << "moving: 1/" << coming << " size, scaled up (the still frame is full size)";
    } else {
      s << "last frame " << 1000.0 * pass->GetLastRenderSeconds() << " ms (A-buffer " << 1000.0 * pass->GetLastCoreSeconds()
        << " ms";
      if (pass->GetLastImageReductionFactor() > 1) s << ", at 1/" << pass->GetLastImageReductionFactor() << " size";
      s << ")   ";
      s.unsetf(std::ios::fixed);
      s.precision(2);  // the shading bound is ~1e-9 on the default path: significant digits, not decimals
      s << "error <= " << pass->GetLastErrorEstimate() << " (shading), " << pass->GetLastCoverageError() << " (coverage)";
    }
    s << "   mask " << pass->GetMaskWidth() << "x" << pass->GetMaskHeight() << (plainWires ? "   plain wire" : "   shaded wire")
      << "\nkeys: w plain/shaded wire  f fur  s scales  m mask  q quit";
    text->SetInput(s.str().c_str());
  };
  vtkNew<vtkCallbackCommand> before;
  before->SetCallback([](vtkObject*, unsigned long, void* cd, void*) { (*static_cast<std::function<void()>*>(cd))(); });
  // Silhouettes follow the view: traced again for VTK's camera before a frame whose camera
  // changed (surface/silhouette.h; product.step's 35 faces take a few milliseconds).
  vtkMTimeType cameraSeen = camera->GetMTime();
  auto retrace = [&] {
    if (sf.silhouettes.empty() || camera->GetMTime() == cameraSeen) return;
    cameraSeen = camera->GetMTime();
    wf::Camera c;
    double p[3], f[3], u[3], range[2];
    camera->GetPosition(p);
    camera->GetFocalPoint(f);
    camera->GetViewUp(u);
    camera->GetClippingRange(range);
    c.eye = {p[0], p[1], p[2]};
    c.target = {f[0], f[1], f[2]};
    c.up = {u[0], u[1], u[2]};
    c.fovYDegrees = camera->GetViewAngle();
    c.projection = camera->GetParallelProjection() ? wf::Camera::Projection::Orthographic : wf::Camera::Projection::Perspective;
    c.orthoHeight = 2.0 * camera->GetParallelScale();
    c.nearPlane = range[0];
    c.farPlane = range[1];
    const int* size = window->GetSize();
    wf::SilhouetteStats st;
    wf::traceSilhouettes(scene, sf.silhouettes, c, size[0], size[1], st);
    update();
  };
  std::function<void()> captionFn = [&] {
    retrace();
    caption();
  };
  before->SetClientData(&captionFn);
  renderer->AddObserver(vtkCommand::StartEvent, before);

  if (o.frames > 0) {
    // Benchmark: N frames, the camera turning 360 / N degrees a frame about the view up, as an
    // interaction draws them (at the interactive reduction), then N still frames (full size).
    struct Run {
      std::vector<double> frame, core;
      double error = 0;
    };
    const double step = 360.0 / o.frames;
    auto turn = [&](bool moving) {
      Run r;
      // As an interaction does: the interactor's desired update rate, then the still rate.
      window->SetDesiredUpdateRate(moving ? 15.0 : 0.0001);
      for (int i = 0; i < o.frames; ++i) {
        if (i > 0) {
          camera->Azimuth(step);
          renderer->ResetCameraClippingRange();
        }
        const auto t0 = std::chrono::steady_clock::now();
        window->Render();
        r.frame.push_back(secondsSince(t0));
        r.core.push_back(pass->GetLastCoreSeconds());
        r.error = std::max(r.error, pass->GetLastErrorEstimate());
      }
      return r;
    };
    Run moving;
    if (o.interactiveReduction > 1) {
      moving = turn(true);
      camera->Azimuth(step);  // back where it started: the still frames turn the same way
      renderer->ResetCameraClippingRange();
    }
    const Run still = turn(false);
    const std::string what = o.input.empty() ? "built-in scene" : o.input;
    std::printf("view: %s at %dx%d, %d frames: median frame %.1f ms (%.1f frames/s), median A-buffer %.1f ms, "
                "shading error estimate %.4g, coverage %.4g\n",
                what.c_str(), o.width, o.height, o.frames, 1000.0 * median(still.frame),
                1.0 / std::max(1e-9, median(still.frame)), 1000.0 * median(still.core), still.error,
                pass->GetLastCoverageError());
    if (o.interactiveReduction > 1)
      std::printf("view: %s moving (1/%d size, scaled up): median frame %.1f ms (%.1f frames/s), median A-buffer %.1f ms\n",
                  what.c_str(), o.interactiveReduction, 1000.0 * median(moving.frame),
                  1.0 / std::max(1e-9, median(moving.frame)), 1000.0 * median(moving.core));
    if (!o.png.empty()) {
      vtkNew<vtkWindowToImageFilter> grab;
      grab->SetInput(window);
      grab->ReadFrontBufferOff();
      grab->ShouldRerenderOn();
      std::optional<OutputFile> pngFile(o.png);
      vtkNew<vtkPNGWriter> writer;
      writer->SetInputConnection(grab->GetOutputPort());
      writer->SetFileName(pngFile->temporaryPath().c_str());
      writer->Write();
      if (writer->GetErrorCode() != 0) throw OutputError(o.png + ": cannot write PNG");
      pngFile->commit();
    }
    return 0;
  }

  vtkNew<vtkRenderWindowInteractor> interactor;
  vtkNew<ViewerStyle> style;
  int maskIndex = pass->GetMaskWidth() == 4 ? 0 : pass->GetMaskHeight() == 4 ? 1 : 2;
  style->onKey = [&](char key) {
    switch (key) {
      case 'w':
        plainWires = !plainWires;
        update();
        break;
      case 'f':
        showFur = !showFur;
        update();
        break;
      case 's':
        showScales = !showScales;
        update();
        break;
      case 'm': {
        static const int masks[3][2] = {{4, 4}, {8, 4}, {8, 8}};
        maskIndex = (maskIndex + 1) % 3;
        pass->SetMaskSize(masks[maskIndex][0], masks[maskIndex][1]);
        break;
      }
      default:
        return false;
    }
    window->Render();
    return true;
  };
  interactor->SetInteractorStyle(style);
  interactor->SetRenderWindow(window);
  interactor->Initialize();
  window->Render();
  interactor->Start();
  renderer->RemoveObserver(before);
  return 0;
}

}  // namespace wfapp
