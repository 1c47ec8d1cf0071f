// `wirefur view [INPUT]`: an interactive VTK window over any input `render` accepts, the built
// scene drawn whole through the A-buffer by vtkWireFurRenderPass::SetScene (docs/vtk.md), so a
// frame is the picture `render` makes. `--frames N` renders N frames turning the camera
// and prints the median frame time (a benchmark that runs without a person; `--offscreen`
// without a display too).
#pragma once

#include "scene_file.h"

#include <string>

namespace wfapp {

/// The command's options (declared in apps/main.cpp).
struct ViewOptions {
  std::string input, style;
  int width = 800, height = 600;
  int frames = 0;         ///< > 0: benchmark N frames turning the camera, then exit
  /// While the camera moves the A-buffer renders at 1/F of the size, scaled up
  /// (vtkWireFurRenderPass::SetInteractiveImageReductionFactor); the still frame is full size. 1: off.
  int interactiveReduction = 2;
  bool offscreen = false;
  std::string png;        ///< --png FILE: the last benchmark frame as a PNG (for a person to look at)
  std::string mask;       ///< empty: the scene's
  int threads = 0;
  bool quiet = false;     ///< accepted as by every command (view prints no progress)
  CadOptions cad;         ///< --deflection, --angular-deflection, --isos (CAD input)
  std::optional<wf::HiddenLines> hidden;  ///< --hidden
  std::optional<bool> silhouettes;        ///< --silhouettes
  wf::EdgeOverrides edges;                ///< --edges, --seams, --feature-angle
  wf::BurnishOverrides burnish;           ///< --grain, --grain-axis, --grooves-per-mm
};

/// Runs the command. Returns the exit status.
int runView(const ViewOptions& options);

}  // namespace wfapp
