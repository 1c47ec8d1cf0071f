// libFuzzer target for the scene loader (apps/scene_file.cpp, scene_materials.cpp,
// scene_growth.cpp): the input is the text of a scene file.
//
// Each input goes through wfapp::parseScene exactly as `wirefur render SCENE.json` reads it
// (loadSceneFile is readText + parseScene): JSON, camera, lights, materials (burnish, textures,
// bumps), objects (parametric sources tessellated, mesh / polyline files read, fur and scales
// grown, within the scene's budget of primitives). Relative file names resolve in this process's
// folder, which holds small mesh files and PNG images (fuzz_app_assets.h: mesh.vtp, mesh.obj,
// lines.vtp, tex.png, bump.png, ...; the dictionary names them). A scene naming a CAD file gets
// "this build has no CAD support" (cad_input.cpp is compiled without the CAD module, which
// tests/fuzz's CAD targets fuzz on their own).
//
// A scene that loads is then rendered as the command renders it (the scene's mask, budget and
// view grid, one thread), at 24 x 16 pixels so that the run stays fast: what the scene's numbers
// make the renderer allocate or compute, beyond the image size the command line picks, shows here.
// WF_FUZZ_RENDER=0 turns the render off.
//
// Expected: parseScene throws wfapp::UsageError with one line naming the file, or returns.
// Findings (the program aborts, so libFuzzer keeps the input):
//  - a crash, a sanitizer report, a hang past -timeout, memory past -rss_limit_mb (libFuzzer);
//  - any other exception out of parseScene or the render (in the command an exception that is
//    not a UsageError is exit status 1, "internal failure", not the contract's clear error);
//  - a UsageError of more than one line or that does not name the file;
//  - a loaded scene that breaks what the renderer relies on: triangle indices out of range,
//    per-vertex arrays of the wrong size, material indices out of range, polylines whose starts
//    do not match their points, a camera with a problem(), an image size out of range;
//  - a rendered pixel that is not finite (docs/design.md: "no NaN in any pixel").
#include "fuzz_app_assets.h"
#include "fuzz_app_checks.h"

#include "cli.h"
#include "render_command.h"
#include "scene_file.h"

#include "core/limits.h"
#include "render/renderer.h"

#include <vtkObject.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <typeinfo>

namespace {

bool g_render = true;
bool g_verbose = false;  // WF_FUZZ_VERBOSE=1: one line per input (what the loader made of it)
const std::string kName = "fuzz.json";
constexpr size_t kMaxRenderedPrimitives = 20000;

void checkScene(const wfapp::SceneFile& sf) {
  using wffuzz::finding;
  const wf::Scene& s = sf.scene;
  const int nMaterials = int(s.materials.size());
  if (nMaterials < 1) finding("a scene without the default material");
  if (sf.width < 1 || sf.width > wf::kMaxImageSide || sf.height < 1 || sf.height > wf::kMaxImageSide)
    finding("image size " + std::to_string(sf.width) + "x" + std::to_string(sf.height) + " out of range");
  if (!s.camera) finding("a loaded scene without a camera");
  if (const std::string p = s.camera->problem(); !p.empty()) finding("the loaded camera has a problem: " + p);
  for (size_t i = 0; i < s.surfaces.size(); ++i) {
    const std::string what = "surface " + std::to_string(i) + " (" + s.surfaces[i].name + ")";
    wffuzz::checkMesh(s.surfaces[i].mesh, what);
    if (s.surfaces[i].material < 0 || s.surfaces[i].material >= nMaterials) finding(what + ": material index out of range");
  }
  for (size_t i = 0; i < s.wires.size(); ++i) {
    const std::string what = "wire " + std::to_string(i) + " (" + s.wires[i].name + ")";
    wffuzz::checkLines(s.wires[i].lines, what);
    if (s.wires[i].material < 0 || s.wires[i].material >= nMaterials) finding(what + ": material index out of range");
  }
}

size_t primitives(const wf::Scene& s) {
  size_t n = 0;
  for (const wf::SceneSurface& x : s.surfaces) n += x.mesh.triangles.size();
  for (const wf::SceneWire& w : s.wires) n += w.lines.points.size();
  return n;
}

}  // namespace

// run_fuzz.sh runs with -detect_leaks=0 for every target (see there); -detect_leaks=1 by hand.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vtkObject::GlobalWarningDisplayOff();  // the readers' own messages: caught by mesh_io, and noisy
  const char* r = std::getenv("WF_FUZZ_RENDER");
  g_render = !(r && std::strcmp(r, "0") == 0);
  const char* v = std::getenv("WF_FUZZ_VERBOSE");
  g_verbose = v && std::strcmp(v, "1") == 0;
  wffuzz::makeDir("scene");
  wffuzz::writeMeshFiles(wffuzz::g_dir);
  wffuzz::writeImages(wffuzz::g_dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using wffuzz::finding;
  const std::string text(reinterpret_cast<const char*>(data), size);
  wfapp::SceneOverrides overrides;
  overrides.cad.isolate = false;  // no worker process: the CAD module is not in this program
  overrides.cad.threads = 1;
  wfapp::SceneFile sf;
  try {
    sf = wfapp::parseScene(kName, text, wffuzz::g_dir, overrides);
  } catch (const wfapp::UsageError& e) {
    if (g_verbose) std::fprintf(stderr, "WF_FUZZ: %zu bytes: error: %s\n", size, e.what());
    wffuzz::checkMessage(e.what(), kName);
    return 0;
  } catch (const std::runtime_error& e) {
    // The one runtime_error a scene may cause here: it names a CAD file (readCad of a build
    // without the CAD module). The command reports it the same way (exit status 1: the build,
    // not the input, lacks something).
    if (std::strstr(e.what(), "this build has no CAD support")) return 0;
    finding(std::string("exception escaped parseScene: ") + typeid(e).name() + ": " + e.what());
  } catch (const std::exception& e) {
    finding(std::string("exception escaped parseScene: ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("unknown exception escaped parseScene");
  }
  checkScene(sf);
  const size_t n = primitives(sf.scene);
  if (g_verbose)
    std::fprintf(stderr, "WF_FUZZ: %zu bytes: %zu surfaces, %zu wires, %zu primitives, %zu hairs, %zu scales, %dx%d\n", size,
                 sf.scene.surfaces.size(), sf.scene.wires.size(), n, sf.hairsGrown, sf.scalesGrown, sf.width, sf.height);
  // Rendering a large scene at 24 x 16 takes seconds under the sanitizers and shows nothing the
  // loader's bounds do not already (the renderer is fuzzed through small scenes).
  if (!g_render || n > kMaxRenderedPrimitives) return 0;
  wf::RenderOptions ro = wfapp::renderOptionsFor(sf);
  ro.width = 24;
  ro.height = 16;
  ro.threads = 1;
  // Small shading tables: the same code, a fraction of the time (the defaults cost about 0.5 s
  // per material under the sanitizers).
  ro.map.resolution = 16;
  ro.map.samples = 4;
  ro.sphereResolution = 16;
  wfapp::reframe(sf, ro.width, ro.height);
  if (const std::string p = ro.problem(); !p.empty()) finding("render options from a loaded scene have a problem: " + p);
  wf::RenderResult result;
  try {
    result = wf::render(sf.scene, ro);
  } catch (const std::exception& e) {
    finding(std::string("exception escaped wf::render: ") + typeid(e).name() + ": " + e.what());
  }
  if (result.image.width != ro.width || result.image.height != ro.height ||
      result.image.pixels.size() != size_t(ro.width) * size_t(ro.height))
    finding("the render is not " + std::to_string(ro.width) + "x" + std::to_string(ro.height));
  for (size_t i = 0; i < result.image.pixels.size(); ++i)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(result.image.pixels[i][c]))
        finding("pixel " + std::to_string(i) + " channel " + std::to_string(c) + " is not finite");
  return 0;
}
