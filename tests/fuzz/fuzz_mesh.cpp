// libFuzzer target for the mesh / polyline readers of the wirefur command (apps/mesh_io.cpp):
// VTK's readers for .vtp .vtk .stl .obj .ply and WireFur's checks and conversion around them.
//
// The first byte of the input picks the format (byte % 5: vtp, vtk, stl, obj, ply; the seeds of
// make_app_seeds carry it); the rest is written to a file of that extension and read by
// wfapp::readGeometryInProcess: what the wirefur command's mesh worker runs for `wirefur render
// FILE` and for scene objects with "file" (in the command a crash there ends the worker only).
// What it returns is then checked and turned into wires as sceneForGeometryFile does (the mesh's
// edges when the file has no lines).
//
// Expected: readGeometryInProcess throws wfapp::UsageError with one line naming the file, or returns.
// Findings (the program aborts, so libFuzzer keeps the input):
//  - a crash, a sanitizer report, a hang past -timeout, memory past -rss_limit_mb (libFuzzer);
//    inside VTK's readers these are VTK's (run_fuzz.sh lists them as [library]), in mesh_io.cpp
//    or the core they are WireFur's;
//  - any other exception out of readGeometry (in the command: exit status 1, not the contract's
//    clear error);
//  - a UsageError of more than one line or that does not name the file;
//  - geometry that breaks what the renderer relies on: triangle indices out of range, per-vertex
//    arrays of the wrong size, polylines whose starts do not match their points, nothing to draw.
#include "fuzz_app_assets.h"
#include "fuzz_app_checks.h"

#include "cli.h"
#include "mesh_io.h"

#include "geometry/parametric_sources.h"

#include <vtkObject.h>

#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <typeinfo>

namespace {
bool g_verbose = false;  // WF_FUZZ_VERBOSE=1: one line per input (what the reader made of it)
}

// run_fuzz.sh runs with -detect_leaks=0 for every target (see there); -detect_leaks=1 by hand.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vtkObject::GlobalWarningDisplayOff();  // VTK's messages are caught by mesh_io, and noisy
  const char* v = std::getenv("WF_FUZZ_VERBOSE");
  g_verbose = v && std::strcmp(v, "1") == 0;
  wffuzz::makeDir("mesh");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using wffuzz::finding;
  if (size < 1) return -1;  // not kept in the corpus
  const auto& exts = wffuzz::meshExtensions();
  const std::string path = wffuzz::g_dir + "/input" + exts[data[0] % exts.size()];
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  }
  wfapp::LoadedGeometry g;
  try {
    g = wfapp::readGeometryInProcess(path);
  } catch (const wfapp::UsageError& e) {
    if (g_verbose) std::fprintf(stderr, "WF_FUZZ: %zu bytes: error: %s\n", size, e.what());
    wffuzz::checkMessage(e.what(), path);
    return 0;
  } catch (const std::exception& e) {
    finding(std::string("exception escaped readGeometry: ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("unknown exception escaped readGeometry");
  }
  if (g_verbose)
    std::fprintf(stderr, "WF_FUZZ: %zu bytes: %s: %zu points, %zu triangles, %zu polylines (%zu points)\n", size,
                 exts[data[0] % exts.size()].c_str(), g.mesh.positions.size(), g.mesh.triangles.size(), g.lines.polylineCount(),
                 g.lines.points.size());
  if (g.mesh.triangles.empty() && g.lines.points.empty()) finding("readGeometry returned nothing to draw");
  wffuzz::checkMesh(g.mesh, "mesh");
  wffuzz::checkLines(g.lines, "lines");
  // What sceneForGeometryFile draws as wire: the lines, or the mesh's edges.
  if (g.lines.points.empty()) wffuzz::checkLines(wf::meshEdges(g.mesh), "mesh edges");
  return 0;
}
