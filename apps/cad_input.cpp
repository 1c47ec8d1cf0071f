#include "cad_input.h"

#include "cli.h"
#include "reader_worker.h"
#include "safe_files.h"

#include "core/srgb.h"
#include "core/worker_process.h"
#include "growth/fur.h"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#ifdef WIREFUR_CAD_LIBRARY
#include "vtkWireFurCADReader.h"
#include "wf_cad_mesh.h"
#include "wf_cad_plugin.h"
#include <dlfcn.h>
#endif

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <mutex>

namespace wfapp {

bool isCadFile(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e == ".step" || e == ".stp" || e == ".iges" || e == ".igs" || e == ".brep" || e == ".fcstd";
}

#ifdef WIREFUR_CAD_LIBRARY

namespace {

using Factory = vtkWireFurCADReader* (*)();

WireFurCadFacesFunction facesFunction = nullptr;

// Opens the CAD module once: the one installed beside this program (../lib), else the library
// it was built with, else by name (a copy on the library path).
Factory cadFactory() {
  static std::once_flag once;
  static Factory factory = nullptr;
  static std::string problem;
  std::call_once(once, [] {
    // An installed wirefur (bin/) opens the module installed with it (lib/), not the build's.
    const std::string name = std::filesystem::path(WIREFUR_CAD_LIBRARY).filename().string();
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::filesystem::path installed = exe.parent_path().parent_path() / WIREFUR_INSTALL_LIBDIR / name;
    void* h = nullptr;
    // The first failure is the one that explains (the installed module missing a library);
    // the fallbacks' would hide it.
    std::string first;
    auto open = [&](const char* path) {
      if (!h) h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
      if (const char* e = h ? nullptr : dlerror(); e && first.empty()) first = e;
    };
    if (!ec && std::filesystem::is_regular_file(installed, ec)) open(installed.c_str());
    open(WIREFUR_CAD_LIBRARY);
    open(name.c_str());
    if (!h) {
      problem = first.empty() ? "dlopen failed" : first;
      return;
    }
    factory = reinterpret_cast<Factory>(dlsym(h, "wirefur_cad_new_reader"));
    facesFunction = reinterpret_cast<WireFurCadFacesFunction>(dlsym(h, "wirefur_cad_face_surfaces"));
    if (!factory) problem = "the CAD module has no entry point wirefur_cad_new_reader";
  });
  if (!factory) throw std::runtime_error("CAD support could not be loaded: " + problem);
  return factory;
}

}  // namespace

namespace {

nlohmann::ordered_json edgesByClass(vtkWireFurCADReader* reader) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (int c = 0; c <= int(wf::EdgeClass::NonManifold); ++c)
    j[wf::edgeClassName(wf::EdgeClass(c))] = reader->GetNumberOfEdgesOfClass(c);
  return j;
}

// facesOnly: the exact faces alone (CadGeometry::faces), nothing meshed (vtkWireFurCADReader's
// FacesOnly), for a tessellation that came from the worker.
CadGeometry readCadInProcess(const std::string& path, const CadOptions& o, bool withSurfaces, bool facesOnly = false) {
  vtkSmartPointer<vtkWireFurCADReader> reader;
  reader.TakeReference(cadFactory()());
  reader->SetFileName(path.c_str());
  if (o.deflection > 0) {
    reader->SetRelativeDeflection(!o.absoluteDeflection);
    reader->SetLinearDeflection(o.deflection);
  }
  if (o.angularDegrees > 0) reader->SetAngularDeflection(o.angularDegrees * M_PI / 180.0);
  reader->SetNumberOfUIsoLines(o.isos);
  reader->SetNumberOfVIsoLines(o.isos);
  reader->SetNumberOfThreads(o.threads);
  reader->SetMaximumTriangles(8388608);  // the scene budget of generated primitives (SceneBudget)
  reader->GlobalWarningDisplayOff();
  // Progress on a terminal: a line at every tenth (OpenCASCADE reports from its worker threads).
  vtkNew<vtkCallbackCommand> progress;
  struct ProgressState {
    std::string path;
    std::atomic<int> shown{-1};
  } state{path};
  if (o.showProgress) {
    progress->SetClientData(&state);
    progress->SetCallback([](vtkObject* caller, unsigned long, void* client, void*) {
      auto* st = static_cast<ProgressState*>(client);
      const int tenth = int(std::floor(static_cast<vtkAlgorithm*>(caller)->GetProgress() * 10.0 + 1e-9));
      int was = st->shown.load();
      while (tenth > was)
        if (st->shown.compare_exchange_weak(was, tenth)) {
          std::cerr << "wirefur: reading and meshing " + oneLine(st->path) + ": " + std::to_string(10 * tenth) + "%\n";
          break;
        }
    });
    reader->AddObserver(vtkCommand::ProgressEvent, progress);
  }
  reader->SetFacesOnly(facesOnly);
  reader->Update();
  const std::string error = reader->GetErrorMessage();
  if (!error.empty()) throw UsageError(error);

  CadGeometry out;
  if (withSurfaces || facesOnly) {
    if (!facesFunction) throw std::runtime_error("the CAD module has no entry point wirefur_cad_face_surfaces");
    facesFunction(reader, &out.faces);
  }
  if (facesOnly) {
    out.info = {{"seconds_read", reader->GetReadSeconds()}};
    return out;
  }
  for (int p = 0; p < reader->GetNumberOfParts(); ++p) out.partNames.push_back(reader->GetPartName(p));
  out.warning = reader->GetWarningMessage();

  try {
    out.geometry.mesh = wfcad::facesToMesh(reader->GetOutput(0), &out.trianglePart, &out.triangleFace);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }

  out.geometry.lines = wfcad::edgesToPolylines(reader->GetOutput(1), false, &out.edgeClasses, &out.edgeAngles);
  out.isoLines = wfcad::edgesToPolylines(reader->GetOutput(1), true);
  out.info = {{"file", path},
              {"parts", reader->GetNumberOfParts()},
              {"faces", reader->GetNumberOfFaces()},
              {"faces_meshed", reader->GetNumberOfMeshedFaces()},
              {"faces_skipped", reader->GetNumberOfSkippedFaces()},
              {"edges", reader->GetNumberOfEdges()},
              {"iso_lines", out.isoLines.polylineCount()},
              {"edges_by_class", edgesByClass(reader)},
              {"model_size", reader->GetModelSize()},
              {"linear_deflection", reader->GetAppliedLinearDeflection()},
              {"linear_deflection_relative", reader->GetAppliedLinearDeflection() / reader->GetModelSize()},
              {"angular_deflection_degrees", reader->GetAngularDeflection() * 180.0 / M_PI},
              {"seconds_read", reader->GetReadSeconds()},
              {"seconds_mesh", reader->GetMeshSeconds()}};
  return out;
}

}  // namespace

#else

namespace {
CadGeometry readCadInProcess(const std::string& path, const CadOptions&, bool, bool = false) {
  throw std::runtime_error(path + ": this build has no CAD support (configure with WIREFUR_WITH_CAD=ON and OpenCASCADE)");
}
}  // namespace

#endif

// ---------------------------------------------------------------------------------------------
// The worker process. OpenCASCADE 7.6 can crash (a null entity in a corrupt STEP file) or loop
// for ever (a BREP whose counts it reads from a failed stream) on bad input: fuzzing found both.
// The command therefore reads and meshes CAD files in a child process of its own ("wirefur
// cad-worker", not part of the contract), waits for it with a time limit, and takes the result
// back through a temporary file. A crash or a hang becomes one line and exit status 2.

namespace {

const std::string kCadMagic("WFCAD1\n\0", 8);

void writeGeometry(BlobWriter& w, const CadGeometry& g) {
  const wf::TriangleMesh& m = g.geometry.mesh;
  w.vec(m.positions), w.vec(m.normals), w.vec(m.derivU), w.vec(m.derivV), w.vec(m.uvs), w.vec(m.colours), w.vec(m.triangles);
  w.vec(g.trianglePart), w.vec(g.triangleFace);
  w.vec(g.geometry.lines.points), w.vec(g.geometry.lines.starts), w.vec(g.edgeClasses), w.vec(g.edgeAngles);
  w.vec(g.isoLines.points), w.vec(g.isoLines.starts);
  w.pod(std::uint64_t(g.partNames.size()));
  for (const std::string& n : g.partNames) w.str(n);
  w.str(g.info.dump());
  w.str(g.warning);
}

CadGeometry readGeometry(BlobReader& r) {
  CadGeometry g;
  wf::TriangleMesh& m = g.geometry.mesh;
  m.positions = r.vec<glm::dvec3>();
  m.normals = r.vec<glm::dvec3>();
  m.derivU = r.vec<glm::dvec3>();
  m.derivV = r.vec<glm::dvec3>();
  m.uvs = r.vec<glm::dvec2>();
  m.colours = r.vec<glm::vec3>();
  m.triangles = r.vec<glm::uvec3>();
  g.trianglePart = r.vec<int>();
  g.triangleFace = r.vec<int>();
  g.geometry.lines.points = r.vec<glm::dvec3>();
  g.geometry.lines.starts = r.vec<std::uint32_t>();
  g.edgeClasses = r.vec<wf::EdgeClass>();
  g.edgeAngles = r.vec<float>();
  g.isoLines.points = r.vec<glm::dvec3>();
  g.isoLines.starts = r.vec<std::uint32_t>();
  const std::uint64_t parts = r.pod<std::uint64_t>();
  if (parts > (std::uint64_t(1) << 24)) throw std::runtime_error("CAD worker result is corrupt");
  for (std::uint64_t i = 0; i < parts; ++i) g.partNames.push_back(r.str());
  g.info = nlohmann::ordered_json::parse(r.str());
  g.warning = r.str();
  // The arrays must fit together before anyone indexes them.
  const size_t nv = m.positions.size();
  for (size_t n : {m.normals.size(), m.derivU.size(), m.derivV.size(), m.uvs.size(), m.colours.size()})
    if (n != nv) throw std::runtime_error("CAD worker result is inconsistent");
  for (const glm::uvec3& t : m.triangles)
    if (t.x >= nv || t.y >= nv || t.z >= nv) throw std::runtime_error("CAD worker result is inconsistent");
  if (g.trianglePart.size() != m.triangles.size() || g.triangleFace.size() != m.triangles.size())
    throw std::runtime_error("CAD worker result is inconsistent");
  if (!polylineStartsFit(g.geometry.lines.starts, g.geometry.lines.points.size()) ||
      !polylineStartsFit(g.isoLines.starts, g.isoLines.points.size()))
    throw std::runtime_error("CAD worker result is inconsistent");
  const size_t edges = g.geometry.lines.polylineCount();
  if (g.edgeClasses.size() != edges || g.edgeAngles.size() != edges) throw std::runtime_error("CAD worker result is inconsistent");
  for (wf::EdgeClass c : g.edgeClasses)
    if (int(c) > int(wf::EdgeClass::NonManifold)) throw std::runtime_error("CAD worker result is inconsistent");
  return g;
}

CadGeometry readCadInWorker(const std::string& path, const CadOptions& o) {
  ReaderWorkerCall call;
  call.mode = "cad-worker";
  call.magic = kCadMagic;
  call.workerName = "CAD worker";
  call.what = "reading and meshing";
  call.library = "OpenCASCADE";
  call.cannotRead = "it is corrupt, or uses something OpenCASCADE 7.6 cannot read";
  call.timeoutHint = "--read-timeout S sets the limit";
  call.timeoutSeconds = o.timeoutSeconds;
  call.inheritStderr = o.showProgress;
  call.extra = {wf::workerNumber(o.deflection), o.absoluteDeflection ? "1" : "0", wf::workerNumber(o.angularDegrees),
                std::to_string(o.isos), std::to_string(o.threads), o.showProgress ? "1" : "0"};
  const std::string body = runReaderWorker(path, call);
  BlobReader r(body);
  return readGeometry(r);
}

}  // namespace

CadGeometry readCad(const std::string& path, const CadOptions& o, bool withSurfaces) {
  requireInputFile(path);
  if (!o.isolate || !readerWorkersEnabled()) return readCadInProcess(path, o, withSurfaces);
  CadGeometry g = readCadInWorker(path, o);
  // The exact surfaces live in this process only: once the worker has shown the file reads
  // cleanly, it is read again here for them, without meshing it again; the faces the worker
  // meshed are kept (a face that failed to mesh there is left out here too).
  if (withSurfaces) {
    CadGeometry s = readCadInProcess(path, o, true, true);
    std::vector<int> meshed = g.triangleFace;
    std::sort(meshed.begin(), meshed.end());
    meshed.erase(std::unique(meshed.begin(), meshed.end()), meshed.end());
    for (WireFurCadFace& f : s.faces)
      if (std::binary_search(meshed.begin(), meshed.end(), f.faceId)) g.faces.push_back(std::move(f));
    g.info["seconds_read_faces"] = s.info["seconds_read"];
  }
  return g;
}

int runCadWorker(const std::vector<std::string>& a) {
  CadOptions o;
  if (a.size() != 10 || !wf::parseWorkerNumber(a[4], o.deflection) || !wf::parseWorkerNumber(a[6], o.angularDegrees)) {
    std::fprintf(stderr, "wirefur: cad-worker is internal "
                         "(FILE OUT PARENT TIMEOUT DEFLECTION ABSOLUTE ANGULAR ISOS THREADS PROGRESS)\n");
    return wf::kWorkerExitUsage;
  }
  wf::becomeWorker(a[2], a[3]);
  o.absoluteDeflection = a[5] == "1";
  o.isos = std::atoi(a[7].c_str());
  o.threads = std::atoi(a[8].c_str());
  o.showProgress = a[9] == "1";
  finishReaderWorker(a[0], a[1], kCadMagic, [&](BlobWriter& w) { writeGeometry(w, readCadInProcess(a[0], o, false)); });
}

std::shared_ptr<wf::GeometryData> cadGeometryData(CadGeometry&& cad) {
  auto g = std::make_shared<wf::GeometryData>();
  g->cad = true;
  g->mesh = std::move(cad.geometry.mesh);
  g->lines = std::move(cad.geometry.lines);
  g->lineClasses = std::move(cad.edgeClasses);
  g->lineAngles = std::move(cad.edgeAngles);
  g->isoLines = std::move(cad.isoLines);
  g->partNames = std::move(cad.partNames);
  g->trianglePart = std::move(cad.trianglePart);
  g->triangleFace = std::move(cad.triangleFace);
  for (const WireFurCadFace& f : cad.faces) g->faces.push_back({f.surface, f.inside, f.faceId, f.part});
  return g;
}

SceneFile sceneForCadFile(const std::string& path, const std::string& style, const SceneOverrides& overrides) {
  wf::Style s;
  if (!wf::parseStyle(style, s)) throw UsageError("--style " + style + ": expected " + wf::styleNames());
  // The exact faces, read in this process too (readCad), for growth and for silhouettes.
  const bool lines = s == wf::Style::Wire || s == wf::Style::WireOverSurface;
  const bool silhouettes = lines && overrides.silhouettes.value_or(true);
  CadGeometry cad = readCad(path, overrides.cad, s == wf::Style::Fur || s == wf::Style::Scales || silhouettes);
  if (!cad.warning.empty()) warn(cad.warning);
  SceneFile sf;
  sf.inputStats = cad.info;
  buildStyled(sf, path, cadGeometryData(std::move(cad)), s, overrides);
  return sf;
}

}  // namespace wfapp
