// The VTK peer of the hair benchmark (issue 3): the same segments drawn by VTK's own line-as-tube
// impostors (vtkProperty::RenderLinesAsTubes), off-screen, unlit white on black, so that the red
// channel of a pixel is VTK's coverage of that pixel: 0 or 1 aliased, fractional with
// multisampling or supersampling.
//
// VTK components this file needs (find_package(VTK COMPONENTS ...) without a version; the target
// also needs vtk_module_autoinit(TARGETS <t> MODULES <same list>) so that the OpenGL2 object
// factory overrides of RenderingCore get registered):
//   CommonCore CommonDataModel RenderingCore RenderingOpenGL2
// InteractionStyle is NOT needed: no interactor is ever created.
// At run time it needs an X display (under CI: xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ...).
#pragma once

#include "hair_torus.h"

#include <string>
#include <vector>

namespace wfbench {

struct VtkTubesResult {
  std::vector<double> frameSeconds;  // each timed frame: Render() + WaitForCompletion() (glFinish), and
                                     // supersampled also the read-back and averaging
  double medianSeconds = 0;
  double setupSeconds = 0;           // vtkPolyData + pipeline + the untimed warm-up frame
  long peakRssBytes = 0;             // getrusage ru_maxrss of the whole process after rendering
  std::vector<float> coverage;       // width * height, row 0 = top of the image, values in [0, 1]
  std::string renderer;              // the "OpenGL renderer string" line, e.g. "llvmpipe (LLVM ...)"
  int multiSamplesAsked = 0;         // the MSAA samples asked for (vtkRenderWindow::SetMultiSamples)
  int multiSamples = -1;             // the samples VTK's render framebuffer has (-1: unknown)
  int supersample = 1;               // k: drawn at k times the size each way and averaged down
  double downsampleSeconds = 0;      // the median of each frame's read-back (GetPixelData) and averaging
};

// Renders `segments` with `timedFrames` >= 1 timed frames after one warm-up frame. `multiSamples`:
// the MSAA samples to ask the window for (0: aliased, the benchmark's usual choice; VTK's own
// default on Linux is 8). VTK lowers what it is asked to what the OpenGL implementation offers
// (llvmpipe: 4): VtkTubesResult::multiSamples is what its framebuffer got. `supersample` k > 1:
// drawn at k width x k height with k times the line width, read back and averaged over k x k
// blocks (supersampling, the way past MSAA's few samples); each timed frame then includes the
// read-back and the averaging, as producing the antialiased image needs them.
VtkTubesResult renderVtkTubes(const std::vector<HairSegment>& segments, const HairCamera& camera,
                              int width, int height, double lineWidthPixels, int timedFrames, int multiSamples = 0,
                              int supersample = 1);

}  // namespace wfbench
