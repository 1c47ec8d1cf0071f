// Reading meshes and polylines through VTK's readers (.vtp .vtk .stl .obj .ply), converted to
// the core's TriangleMesh and PolylineSet. Bad files are reported as one line (UsageError:
// exit status 2) naming the file and the problem; VTK's own multi-line messages are captured.
#pragma once

#include "render/scene.h"

#include <string>
#include <vector>

namespace wfapp {

struct LoadedGeometry {
  wf::TriangleMesh mesh;    ///< polygons and strips, triangulated, with point normals
  wf::PolylineSet lines;    ///< line and polyline cells
};

/// True for the extensions readGeometry accepts.
bool isGeometryFile(const std::string& path);
/// Reads a mesh / polyline file. Throws UsageError("FILE: problem") on failure. With `isolate`
/// (the wirefur command) VTK's reader runs in a worker process ("wirefur mesh-worker",
/// apps/reader_worker.h) stopped after `timeoutSeconds` and capped in memory: a reader that
/// crashes, hangs or asks for unbounded memory on a corrupt file becomes that one line too.
/// Without, in this process (readGeometryInProcess).
LoadedGeometry readGeometry(const std::string& path, bool isolate = true, double timeoutSeconds = 600.0);
/// The reading itself, in this process: what the worker runs, and the fuzz target.
LoadedGeometry readGeometryInProcess(const std::string& path);
/// The worker's main: FILE OUT PARENT TIMEOUT (apps/main.cpp's "mesh-worker").
int runMeshWorker(const std::vector<std::string>& args);
/// Writes polylines as a VTK XML PolyData file (used to make the example data).
void writePolylinesVtp(const wf::PolylineSet& lines, const std::string& path);

}  // namespace wfapp
