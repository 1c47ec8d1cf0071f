// Reading meshes and polylines through VTK's readers (.vtp .vtk .stl .obj .ply), converted to
// the core's TriangleMesh and PolylineSet. Bad files are reported as one line (UsageError:
// exit status 2) naming the file and the problem; VTK's own multi-line messages are captured.
#pragma once

#include "render/scene.h"

#include <string>

namespace wfapp {

struct LoadedGeometry {
  wf::TriangleMesh mesh;    ///< polygons and strips, triangulated, with point normals
  wf::PolylineSet lines;    ///< line and polyline cells
};

/// True for the extensions readGeometry accepts.
bool isGeometryFile(const std::string& path);
/// Reads a mesh / polyline file. Throws UsageError("FILE: problem") on failure.
LoadedGeometry readGeometry(const std::string& path);
/// Writes polylines as a VTK XML PolyData file (used to make the example data).
void writePolylinesVtp(const wf::PolylineSet& lines, const std::string& path);

}  // namespace wfapp
