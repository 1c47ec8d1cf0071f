// `wirefur view [INPUT]`: an interactive VTK window over any input `render` accepts, drawn by
// vtkWireFurRenderPass (docs/vtk_render_pass.md): wires and fur through the A-buffer,
// composited over the surfaces OpenGL draws. `--frames N` renders N frames turning the camera
// and prints the median frame time (a benchmark that runs without a person; `--offscreen`
// without a display too).
#pragma once

#include <string>
#include <vector>

namespace wfapp {

/// Runs the command on its arguments (those after `view`). Returns the exit status.
int runView(const std::vector<std::string>& args);

}  // namespace wfapp
