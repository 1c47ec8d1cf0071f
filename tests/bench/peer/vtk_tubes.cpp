#include "vtk_tubes.h"

#include "bench_support.h"
#include "core/timer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <string>

namespace wfbench {
namespace {

using wf::secondsSince;  // core/timer.h

// ReportCapabilities() is the only portable way to get GL_RENDERER without pulling in GL headers.
std::string rendererLine(vtkRenderWindow* window) {
  std::istringstream caps(window->ReportCapabilities());
  const std::string key = "OpenGL renderer string:";
  for (std::string line; std::getline(caps, line);)
    if (line.rfind(key, 0) == 0) return line.substr(line.find_first_not_of(' ', key.size()));
  return "unknown";
}

}  // namespace

VtkTubesResult renderVtkTubes(const std::vector<HairSegment>& segments, const HairCamera& camera,
                              int width, int height, double lineWidthPixels, int timedFrames, int multiSamples,
                              int supersample) {
  if (timedFrames < 1 || width < 1 || height < 1 || multiSamples < 0 || supersample < 1 || supersample > 16)
    throw std::invalid_argument("renderVtkTubes");
  VtkTubesResult result;
  result.multiSamplesAsked = multiSamples;
  result.supersample = supersample;
  const int k = supersample;
  const int bigW = width * k, bigH = height * k;
  const auto setupStart = std::chrono::steady_clock::now();

  // Double points keep the segments bit-identical to ours; VTK shifts/scales them to float VBOs.
  const vtkIdType n = vtkIdType(segments.size());
  vtkNew<vtkDoubleArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(2 * n);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(2 * n);
  double* p = xyz->GetPointer(0);
  for (vtkIdType i = 0; i < n; ++i) {
    const HairSegment& s = segments[size_t(i)];
    for (int k = 0; k < 3; ++k) p[6 * i + k] = s.p0[k], p[6 * i + 3 + k] = s.p1[k];
    offsets->SetValue(i, 2 * i);
    connectivity->SetValue(2 * i, 2 * i);
    connectivity->SetValue(2 * i + 1, 2 * i + 1);
  }
  offsets->SetValue(n, 2 * n);
  vtkNew<vtkPoints> points;
  points->SetData(xyz);
  vtkNew<vtkCellArray> lines;
  lines->SetData(offsets, connectivity);  // one 2-point line cell per segment, no copies
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(lines);

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  // Unlit white: ambient 1 and nothing else, so that a covered pixel reads exactly 1.0 whatever
  // normal the tube impostor invents. LightingOff() selects VTK's unlit shader outright; the
  // ambient/diffuse/specular settings alone give the same result through the lit shader.
  vtkProperty* prop = actor->GetProperty();
  prop->SetRenderLinesAsTubes(true);  // only honoured for line width > 1 (DrawingTubes in 9.1)
  prop->SetLineWidth(float(lineWidthPixels * k));  // the same width in the final image's pixels
  prop->SetColor(1, 1, 1);
  prop->SetAmbientColor(1, 1, 1);
  prop->SetAmbient(1);
  prop->SetDiffuse(0);
  prop->SetSpecular(0);
  prop->LightingOff();

  // Our own camera: a renderer-created one would be reset to the bounds on the first Render().
  vtkNew<vtkCamera> cam;
  cam->SetPosition(camera.eye.x, camera.eye.y, camera.eye.z);
  cam->SetFocalPoint(camera.target.x, camera.target.y, camera.target.z);
  cam->SetViewUp(camera.up.x, camera.up.y, camera.up.z);
  cam->SetViewAngle(camera.fovYDegrees);  // vertical: UseHorizontalViewAngle is off by default
  cam->SetClippingRange(camera.nearPlane, camera.farPlane);

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0, 0, 0);
  renderer->AddActor(actor);
  renderer->SetActiveCamera(cam);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(multiSamples);  // 0: aliased (VTK's own default would be 8)
  window->SetSize(bigW, bigH);
  window->AddRenderer(renderer);

  window->Render();  // warm-up: context, shader compilation, VBO upload
  window->WaitForCompletion();
  result.setupSeconds = secondsSince(setupStart);
  result.renderer = rendererLine(window);
  if (auto* gl = vtkOpenGLRenderWindow::SafeDownCast(window); gl && gl->GetRenderFramebuffer()) {
    // A framebuffer VTK could not make at this size (past the implementation's limit) is logged
    // and skipped, leaving a black image: refused here instead.
    int fw = 0, fh = 0;
    gl->GetRenderFramebuffer()->GetLastSize(fw, fh);
    if (fw < bigW || fh < bigH)
      throw std::runtime_error("VTK's framebuffer is " + std::to_string(fw) + " x " + std::to_string(fh) + ", not " +
                               std::to_string(bigW) + " x " + std::to_string(bigH));
    // What it got: VTK lowers the window's samples to the implementation's maximum.
    result.multiSamples = gl->GetRenderFramebuffer()->GetMultiSamples();
  }

  // The k x k image read back as bytes (coverage is 0 or 1 where aliased, a multiple of 1/255
  // with MSAA) and averaged into the final pixel; GL rows run bottom-up, ours top-down.
  vtkNew<vtkUnsignedCharArray> bytes;
  result.coverage.assign(size_t(width) * size_t(height), 0.0f);
  auto readBack = [&] {
    window->GetPixelData(0, 0, bigW - 1, bigH - 1, /*front=*/1, bytes);
    const unsigned char* px = bytes->GetPointer(0);
    const float full = 255.0f * float(k * k);  // (a division below: a covered pixel reads exactly 1)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        unsigned sum = 0;
        for (int j = 0; j < k; ++j) {
          const unsigned char* row = px + 3 * (size_t(y * k + j) * size_t(bigW) + size_t(x * k));
          for (int i = 0; i < k; ++i) sum += row[3 * i];
        }
        result.coverage[size_t(height - 1 - y) * size_t(width) + size_t(x)] = std::min(1.0f, float(sum) / full);
      }
  };
  std::vector<double> downsample;
  for (int f = 0; f < timedFrames; ++f) {
    cam->Modified();  // forces a full redraw without invalidating the mapper's VBOs
    const auto t0 = std::chrono::steady_clock::now();
    window->Render();
    window->WaitForCompletion();  // glFinish in vtkOpenGLRenderWindow
    if (k > 1) {
      const auto t1 = std::chrono::steady_clock::now();
      readBack();
      downsample.push_back(secondsSince(t1));
    }
    result.frameSeconds.push_back(secondsSince(t0));
  }
  result.medianSeconds = median(result.frameSeconds);
  if (k > 1) result.downsampleSeconds = median(downsample);
  else readBack();  // (aliased and multisampled: the image was ready in the framebuffer, read once untimed)

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  result.peakRssBytes = long(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
  return result;
}

}  // namespace wfbench
