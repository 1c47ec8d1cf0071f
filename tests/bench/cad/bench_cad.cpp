// Reading, meshing and rendering a CAD model of some thousand faces (the CAD reader, WireFur::CAD).
//
// The model is made with OpenCASCADE at start-up (the first benchmark that needs it) in a
// temporary directory, written as STEP (AP214, STEPControl_Writer) and as BREP (text): a grid of
// NX x NY blocks, each a box with all twelve edges filleted (6 planes, 12 cylinders, 8 sphere
// corners) and a hole drilled through it (one more cylinder), every block of its own size,
// fillet radius and hole radius so that no two share geometry: 27 faces a block, 3,240 faces
// for the default 12 x 10 (WF_BENCH_CAD_GRID=NXxNY changes it, e.g. 4x3 for a quick run).
//
// Benchmarks (wall-clock time, UseRealTime: the reader meshes with oneTBB on all cores):
//   BM_ReadMesh/<STEP|BREP>/<default|fine>  vtkWireFurCADReader::Update(): read the file, mesh
//       every face with BRepMesh, evaluate the exact surface data at every vertex, sample the
//       edges. default: the reader's defaults, linear deflection 1e-3 of the model's diagonal
//       and angular deflection 0.35 rad; fine: both 4x finer (2.5e-4, 0.0875 rad). Both, because
//       on this model the angular deflection governs every curved face (a 0.6 fillet at 0.35 rad
//       deviates 0.009 from its chord, far under the linear 0.18), so a finer linear deflection
//       alone changes nothing. Counters: faces, triangles, edges, read_s and mesh_s (the
//       reader's own split), peak_rss_MiB.
//   BM_ToScene/<default|fine>  the reader's two outputs to wf::Scene: one SceneSurface
//       (positions, normals, derivU, derivV, uvs, linear colours) and the edges as one
//       SceneWire of 1.5-pixel shaded wire, as the wirefur command does for CAD input.
//   BM_Render/<default|fine>  wf::render of that scene at 1280x960 (A-buffer, maps shading
//       path, 8x4 masks), camera framed on the model. Counters: triangles, segments (as the
//       renderer counted them), render_peak_MiB (RenderStats::peakBytes), peak_rss_MiB.
//
// peak_rss_MiB is getrusage's ru_maxrss: the peak of the whole process so far, so it only
// grows from benchmark to benchmark; for one benchmark's own peak run it alone
// (--benchmark_filter=BM_ReadMesh/STEP/fine).
//
// Run: bench_cad --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "render/renderer.h"
#include "render/scene.h"
#include "core/srgb.h"

#include "vtkWireFurCADReader.h"
#include "wf_cad_mesh.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>

#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Deflection {
  const char* name;
  double linear;   // relative to the model's diagonal
  double angular;  // radians
  bool operator<(const Deflection& o) const { return linear < o.linear || (linear == o.linear && angular < o.angular); }
};
constexpr Deflection kDefault{"default", 1e-3, 0.35};  // the reader's defaults
constexpr Deflection kFine{"fine", 1e-3 / 4.0, 0.35 / 4.0};

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;  // KiB on Linux
}

// ---------------------------------------------------------------------------------------------
// The model.

struct Model {
  fs::path dir, step, brep;
  int faces = 0, blocks = 0;
  double seconds = 0.0;  // to make and write it
};

fs::path g_modelDir;  // removed at exit (set before the atexit call, so destroyed after it runs)

void removeModelDir() {
  std::error_code ec;
  if (!g_modelDir.empty()) fs::remove_all(g_modelDir, ec);
}

void gridSize(int& nx, int& ny) {
  nx = 12, ny = 10;
  if (const char* g = std::getenv("WF_BENCH_CAD_GRID")) {
    int a = 0, b = 0;
    if (std::sscanf(g, "%dx%d", &a, &b) == 2 && a > 0 && b > 0 && a * b <= 10000) nx = a, ny = b;
  }
}

TopoDS_Shape block(int i, int j) {
  const double dx = 8.0 + 0.07 * i, dy = 6.0 + 0.05 * j, dz = 3.0 + 0.03 * (i + j);
  const gp_Pnt corner(12.0 * i, 10.0 * j, 0.0);
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(corner, dx, dy, dz).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  const double r = 0.6 + 0.01 * ((i * 7 + j * 3) % 10);
  for (int e = 1; e <= edges.Extent(); ++e) fillet.Add(r, TopoDS::Edge(edges(e)));
  const TopoDS_Shape rounded = fillet.Shape();
  const gp_Ax2 axis(gp_Pnt(corner.X() + dx / 2, corner.Y() + dy / 2, -1.0), gp::DZ());
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(axis, 1.2 + 0.02 * i + 0.01 * j, dz + 2.0).Shape();
  BRepAlgoAPI_Cut cut(rounded, drill);
  if (!cut.IsDone()) throw std::runtime_error("bench_cad: the boolean cut failed");
  return cut.Shape();
}

const Model& model() {
  static const Model m = [] {
    Model r;
    const auto t0 = std::chrono::steady_clock::now();
    Message::DefaultMessenger()->ChangePrinters().Clear();  // the STEP writer's chatter
    std::string tmpl = (fs::temp_directory_path() / "wf-bench-cad-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("bench_cad: mkdtemp failed");
    r.dir = g_modelDir = tmpl;
    std::atexit(removeModelDir);
    int nx = 0, ny = 0;
    gridSize(nx, ny);
    TopoDS_Compound c;
    BRep_Builder b;
    b.MakeCompound(c);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) b.Add(c, block(i, j));
    r.blocks = nx * ny;
    for (TopExp_Explorer e(c, TopAbs_FACE); e.More(); e.Next()) ++r.faces;
    r.brep = r.dir / "blocks.brep";
    r.step = r.dir / "blocks.step";
    if (!BRepTools::Write(c, r.brep.c_str())) throw std::runtime_error("bench_cad: writing the BREP failed");
    STEPControl_Writer w;
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    if (w.Transfer(c, STEPControl_AsIs) != IFSelect_RetDone || w.Write(r.step.c_str()) != IFSelect_RetDone)
      throw std::runtime_error("bench_cad: writing the STEP failed");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "bench_cad: model: %d blocks, %d faces; STEP %.1f MiB, BREP %.1f MiB; made in %.1f s (%s)\n", r.blocks,
                 r.faces, double(fs::file_size(r.step)) / 1048576.0, double(fs::file_size(r.brep)) / 1048576.0, r.seconds,
                 r.dir.c_str());
    return r;
  }();
  return m;
}

// ---------------------------------------------------------------------------------------------
// Reading, and the scene.

vtkSmartPointer<vtkWireFurCADReader> read(const fs::path& file, const Deflection& deflection) {
  auto reader = vtkSmartPointer<vtkWireFurCADReader>::New();
  reader->SetFileName(file.c_str());
  reader->SetLinearDeflection(deflection.linear);
  reader->SetAngularDeflection(deflection.angular);
  reader->Update();
  if (!reader->GetErrorMessage().empty()) throw std::runtime_error(reader->GetErrorMessage());
  return reader;
}

// The reader's outputs at a deflection, read once (from the BREP) for the scene benchmarks.
vtkWireFurCADReader* cachedReader(const Deflection& deflection) {
  static std::map<Deflection, vtkSmartPointer<vtkWireFurCADReader>> cache;
  auto it = cache.find(deflection);
  if (it == cache.end()) it = cache.emplace(deflection, read(model().brep, deflection)).first;
  return it->second;
}

wf::Scene toScene(vtkWireFurCADReader* reader) {
  wf::Scene s;
  s.lights = wf::LightRig::studioRig(3);
  s.lightsFollowCamera = true;
  wf::Material part;
  part.name = "part";
  part.phong = {glm::dvec3(0.8), glm::dvec3(0.25), 30.0};
  wf::Material wire;
  wire.name = "wire";
  wire.phong = {glm::dvec3(0.6, 0.3, 0.1), glm::dvec3(0.9), 40.0};
  s.materials = {wf::Material{}, part, wire};

  wf::SceneSurface surface;
  surface.name = "blocks";
  surface.material = 1;
  surface.mesh = wfcad::facesToMesh(reader->GetOutput(0));
  s.surfaces.push_back(std::move(surface));

  vtkPolyData* edges = reader->GetOutput(1);
  wf::SceneWire w;
  w.name = "edges";
  w.material = 2;
  w.thickness = 1.5;
  w.thicknessInPixels = true;
  w.lines = wfcad::edgesToPolylines(edges, false);
  s.wires.push_back(std::move(w));

  glm::dvec3 centre(0.0);
  double radius = 1.0;
  if (!s.boundingSphere(centre, radius)) centre = glm::dvec3(0.0), radius = 1.0;
  s.camera = wf::frameSphere(centre, radius, 1280.0 / 960.0);
  return s;
}

const wf::Scene& cachedScene(const Deflection& deflection) {
  static std::map<Deflection, std::unique_ptr<wf::Scene>> cache;
  auto it = cache.find(deflection);
  if (it == cache.end()) it = cache.emplace(deflection, std::make_unique<wf::Scene>(toScene(cachedReader(deflection)))).first;
  return *it->second;
}

// ---------------------------------------------------------------------------------------------
// Benchmarks.

void readMesh(benchmark::State& state, bool step, const Deflection& deflection) {
  try {
    const Model& m = model();
    const fs::path& file = step ? m.step : m.brep;
    vtkSmartPointer<vtkWireFurCADReader> last;
    double readS = 0, meshS = 0;
    for (auto _ : state) {
      last = read(file, deflection);
      readS += last->GetReadSeconds();
      meshS += last->GetMeshSeconds();
    }
    const double n = double(state.iterations());
    state.counters["faces"] = last->GetNumberOfFaces();
    state.counters["triangles"] = double(last->GetOutput(0)->GetNumberOfPolys());
    state.counters["edges"] = last->GetNumberOfEdges();
    state.counters["skipped"] = last->GetNumberOfSkippedFaces();
    state.counters["read_s"] = readS / n;
    state.counters["mesh_s"] = meshS / n;
    state.counters["peak_rss_MiB"] = peakRssMiB();
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

void sceneConversion(benchmark::State& state, const Deflection& deflection) {
  try {
    vtkWireFurCADReader* reader = cachedReader(deflection);
    size_t triangles = 0, points = 0;
    for (auto _ : state) {
      wf::Scene s = toScene(reader);
      triangles = s.surfaces[0].mesh.triangles.size();
      points = s.wires[0].lines.points.size();
      benchmark::DoNotOptimize(s);
    }
    state.counters["triangles"] = double(triangles);
    state.counters["wire_points"] = double(points);
    state.counters["peak_rss_MiB"] = peakRssMiB();
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

void render(benchmark::State& state, const Deflection& deflection) {
  try {
    const wf::Scene& scene = cachedScene(deflection);
    wf::RenderOptions options;
    options.width = 1280;
    options.height = 960;
    if (const std::string problem = options.problem(); !problem.empty()) throw std::runtime_error(problem);
    wf::RenderStats stats;
    for (auto _ : state) {
      wf::RenderResult r = wf::render(scene, options);
      stats = r.stats;
      benchmark::DoNotOptimize(r.image);
    }
    state.counters["triangles"] = double(stats.triangles);
    state.counters["segments"] = double(stats.segments);
    state.counters["render_peak_MiB"] = double(stats.peakBytes) / 1048576.0;
    state.counters["peak_rss_MiB"] = peakRssMiB();
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const char* format : {"STEP", "BREP"})
    for (const Deflection& d : {kDefault, kFine}) {
      const bool step = std::string(format) == "STEP";
      benchmark::RegisterBenchmark((std::string("BM_ReadMesh/") + format + "/" + d.name).c_str(),
                                   [step, d](benchmark::State& s) { readMesh(s, step, d); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  for (const Deflection& d : {kDefault, kFine}) {
    benchmark::RegisterBenchmark((std::string("BM_ToScene/") + d.name).c_str(), [d](benchmark::State& s) { sceneConversion(s, d); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark((std::string("BM_Render/") + d.name).c_str(), [d](benchmark::State& s) { render(s, d); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
