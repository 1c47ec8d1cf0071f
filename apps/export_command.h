// `wirefur export INPUT -o OUT.vtp|.vtk|.obj|.ply`: the geometry a scene draws (tessellated
// surfaces, scales, wires, fur) as one vtkPolyData, written by VTK's writers for use in other
// tools (docs/cli.md).
#pragma once

#include "scene_file.h"

#include "render/scene.h"

#include <vtkSmartPointer.h>

#include <cstdint>
#include <string>
#include <vector>

class vtkPolyData;

namespace wfapp {

/// The scene's surfaces (triangles) and wires (polylines) in world space, one vtkPolyData:
/// point arrays "Normals" (surfaces; zero on wires), "Tangents" (surfaces: dS/du or the mesh's
/// tangents; wires: the polyline direction), "Su" and "Sv" (raw dS/du, dS/dv where surfaces have
/// them: parametric sources, CAD faces; only when some surface has them), "TCoords" ((u, v); zero where there are none),
/// "Colors" (RGB, the vertex colours that multiply the shading); cell arrays "ObjectId" (index
/// of the surface, then of the wire, in the scene), "Thickness" (a wire's diameter in world
/// units, 0 for surfaces and pixel-wide wires), "EdgeClass" (a model's edges and silhouettes:
/// render/edge_classes.h; -1 elsewhere), and with `visible` (one list per wire, one value per
/// polyline, or an empty list) "Visible" (1 seen, 0 hidden; -1 for surfaces and wires without);
/// field data "ObjectNames". Hold-out surfaces draw nothing and are left out.
vtkSmartPointer<vtkPolyData> sceneToPolyData(const wf::Scene& scene,
                                             const std::vector<std::vector<std::uint8_t>>* visible = nullptr);

/// The command's options (declared in apps/main.cpp).
struct ExportOptions {
  std::string input;           ///< scene .json, CAD or mesh / polyline file (required)
  std::string output;          ///< .vtp, .vtk, .obj or .ply (required)
  std::string style;           ///< for CAD and mesh input
  bool quiet = false;          ///< accepted as by every command (export prints no progress)
  SceneOverrides overrides;    ///< --time, --edges ..., the CAD options
  /// --visibility: each wire-frame (not fur) split where the opaque surfaces start and stop
  /// hiding it from the scene's camera (scene/edge_visibility.h), marked by "Visible".
  bool visibility = false;
  int width = 0, height = 0;   ///< --size: the image the camera is framed for (0: the scene's)
};

/// Runs the command; returns the exit status.
int runExport(const ExportOptions& options);

}  // namespace wfapp
