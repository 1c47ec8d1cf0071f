// vtkWireFurCADReader with ReadInWorker on (wirefur-cad-worker, wf_cad_worker.h): the outputs
// equal the in-process read bit for bit; OpenCASCADE's crashes and hangs on the fuzzing findings
// (tests/apps/cad_regressions) become one line naming the file while this process carries on; the
// exact faces are read on demand; the temporary folder is made under TMPDIR and removed.
#include "cad_fixtures.h"
#include "wf_cad_plugin.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>

#include <vtkAbstractArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>

#include "core/worker_process.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>

#include <signal.h>

#include <chrono>
#include <clocale>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

using namespace cadtest;

namespace {

std::string regression(const std::string& name) {
  return std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/cad_regressions/" + name;
}

void inWorker(vtkWireFurCADReader* r) { r->ReadInWorkerOn(); }

// Every value of two arrays, compared as doubles of the same type and shape.
void expectSameArray(vtkAbstractArray* a, vtkAbstractArray* b, const std::string& what) {
  ASSERT_TRUE(a && b) << what;
  EXPECT_EQ(a->GetDataType(), b->GetDataType()) << what;
  EXPECT_EQ(a->GetNumberOfComponents(), b->GetNumberOfComponents()) << what;
  ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues()) << what;
  vtkIdType differ = 0;
  if (a->IsNumeric() && a->GetDataType() == b->GetDataType()) {  // bits: NaN equals NaN
    const size_t bytes = size_t(a->GetDataTypeSize());
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
      differ += std::memcmp(a->GetVoidPointer(i), b->GetVoidPointer(i), bytes) != 0;
  } else {
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
      if (a->GetVariantValue(i) != b->GetVariantValue(i)) ++differ;
  }
  EXPECT_EQ(differ, 0) << what << ": values differ";
}

void expectSameData(vtkPolyData* a, vtkPolyData* b, const std::string& what) {
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints()) << what;
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells()) << what;
  if (a->GetNumberOfPoints()) expectSameArray(a->GetPoints()->GetData(), b->GetPoints()->GetData(), what + " points");
  for (vtkCellArray* ca : {a->GetPolys(), a->GetLines()}) {
    vtkCellArray* cb = ca == a->GetPolys() ? b->GetPolys() : b->GetLines();
    ASSERT_EQ(ca->GetNumberOfCells(), cb->GetNumberOfCells()) << what;
    vtkIdType na = 0, nb = 0;
    const vtkIdType *pa = nullptr, *pb = nullptr;
    vtkIdType differ = 0;
    ca->InitTraversal(), cb->InitTraversal();
    while (ca->GetNextCell(na, pa) && cb->GetNextCell(nb, pb)) {
      if (na != nb) ++differ;
      else
        for (vtkIdType k = 0; k < na; ++k) differ += pa[k] != pb[k];
    }
    EXPECT_EQ(differ, 0) << what << ": cells differ";
  }
  for (auto [da, db] : {std::pair<vtkFieldData*, vtkFieldData*>{a->GetPointData(), b->GetPointData()},
                        {a->GetCellData(), b->GetCellData()}, {a->GetFieldData(), b->GetFieldData()}}) {
    ASSERT_EQ(da->GetNumberOfArrays(), db->GetNumberOfArrays()) << what;
    for (int i = 0; i < da->GetNumberOfArrays(); ++i) {
      vtkAbstractArray* x = da->GetAbstractArray(i);
      expectSameArray(x, db->GetAbstractArray(x->GetName()), what + " array " + x->GetName());
    }
  }
  // The active attributes the downstream filters use.
  auto name = [](vtkDataArray* d) { return d && d->GetName() ? std::string(d->GetName()) : std::string("(none)"); };
  EXPECT_EQ(name(a->GetPointData()->GetNormals()), name(b->GetPointData()->GetNormals())) << what;
  EXPECT_EQ(name(a->GetPointData()->GetTCoords()), name(b->GetPointData()->GetTCoords())) << what;
  EXPECT_EQ(name(a->GetPointData()->GetTangents()), name(b->GetPointData()->GetTangents())) << what;
  EXPECT_EQ(name(a->GetPointData()->GetScalars()), name(b->GetPointData()->GetScalars())) << what;
}

TopoDS_Shape model() {
  TopoDS_Compound c;
  BRep_Builder b;
  b.MakeCompound(c);
  b.Add(c, BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(10, 20, 30).Shape(),
                           BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(5, 10, -1), gp_Dir(0, 0, 1)), 3, 40).Shape()).Shape());
  b.Add(c, BRepPrimAPI_MakeSphere(gp_Pnt(30, 0, 0), 6).Shape());
  return c;
}

} // namespace

TEST(CadWorker, TheWorkerIsBesideTheLibrary) {
  const std::string exe = vtkWireFurCADReader::GetWorkerExecutable();
  ASSERT_FALSE(exe.empty());
  EXPECT_EQ(std::filesystem::path(exe).filename(), "wirefur-cad-worker");
}

TEST(CadWorker, OutputsEqualTheInProcessReadBitForBit) {
  for (const std::string& path : {writeStep(model(), "worker_model.step"), writeBrep(model(), "worker_model.brep")}) {
    SCOPED_TRACE(path);
    auto configure = [](vtkWireFurCADReader* r) {
      r->SetNumberOfUIsoLines(3);
      r->SetNumberOfVIsoLines(2);
      r->SetLinearDeflection(2e-3);
      r->SetFeatureAngle(15);
    };
    const Read local = readOk(path, configure);
    const Read worker = readOk(path, [&](vtkWireFurCADReader* r) { configure(r), r->ReadInWorkerOn(); });
    expectSameData(local.faces, worker.faces, "faces");
    expectSameData(local.edges, worker.edges, "edges");
    EXPECT_EQ(local.reader->GetNumberOfParts(), worker.reader->GetNumberOfParts());
    for (int p = 0; p < local.reader->GetNumberOfParts(); ++p) {
      EXPECT_EQ(local.reader->GetPartName(p), worker.reader->GetPartName(p));
    }
    EXPECT_EQ(local.reader->GetNumberOfFaces(), worker.reader->GetNumberOfFaces());
    EXPECT_EQ(local.reader->GetNumberOfMeshedFaces(), worker.reader->GetNumberOfMeshedFaces());
    EXPECT_EQ(local.reader->GetNumberOfEdges(), worker.reader->GetNumberOfEdges());
    for (int c = 0; c < 6; ++c) {
      EXPECT_EQ(local.reader->GetNumberOfEdgesOfClass(c), worker.reader->GetNumberOfEdgesOfClass(c));
    }
    EXPECT_EQ(local.reader->GetAppliedLinearDeflection(), worker.reader->GetAppliedLinearDeflection());
    EXPECT_EQ(local.reader->GetModelSize(), worker.reader->GetModelSize());
    EXPECT_EQ(local.reader->GetWarningMessage(), worker.reader->GetWarningMessage());
    EXPECT_GT(local.faces->GetNumberOfCells(), 100);
  }
}

TEST(CadWorker, ExactFacesAreReadOnDemand) {
  const std::string path = writeBrep(model(), "worker_faces.brep");
  const Read local = readOk(path);
  const Read worker = readOk(path, inWorker);
  std::vector<WireFurCadFace> a, b;
  const int n = wirefur_cad_face_surfaces(local.reader, &a);
  EXPECT_GT(n, 6);
  ASSERT_EQ(wirefur_cad_face_surfaces(worker.reader, &b), n);
  ASSERT_EQ(wirefur_cad_face_surfaces(worker.reader, &b), n);  // a second call reads nothing again
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].faceId, b[i].faceId);
    EXPECT_EQ(a[i].part, b[i].part);
    const wf::ParameterDomain d = a[i].surface->domain();
    const double u = 0.3 * d.u0 + 0.7 * d.u1, v = 0.6 * d.v0 + 0.4 * d.v1;
    EXPECT_EQ(a[i].surface->frame(u, v).P, b[i].surface->frame(u, v).P);
  }
}

// The fuzzing findings that crash OpenCASCADE 7.6 in process: in the worker they fail the update
// with one line, and this process goes on (the test would die with them otherwise).
TEST(CadWorker, CrashesBecomeOneLine) {
  for (const char* name : {"step_segv_cartesianpoint.step", "iges_segv_face_nbloops.iges", "brep_segv_in_mesher.brep",
                           "fcstd_segv_trimmed_curve.FCStd"}) {
    const std::string path = regression(name);
    SCOPED_TRACE(path);
    const Read r = readBad(path, inWorker);
    const std::string m = r.reader->GetErrorMessage();
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find("crashed"), std::string::npos) << m;
    EXPECT_EQ(r.faces->GetNumberOfCells(), 0);
    EXPECT_EQ(r.edges->GetNumberOfCells(), 0);
  }
}

// A worker that runs past WorkerTimeout is killed: a stand-in for OpenCASCADE's endless loops
// (fixed in the reader, so none is at hand): a file read with a deflection so fine that meshing
// takes far longer than the limit.
TEST(CadWorker, AHangIsKilledAtTheTimeLimit) {
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 10).Shape(), "worker_slow.brep");
  const auto t0 = std::chrono::steady_clock::now();
  const Read r = readBad(path, [](vtkWireFurCADReader* reader) {
    reader->ReadInWorkerOn();
    reader->SetWorkerTimeout(0.3);
    reader->SetLinearDeflection(1e-7);
    reader->SetMaximumTriangles(VTK_ID_MAX);
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string m = r.reader->GetErrorMessage();
  EXPECT_EQ(m, path + ": reading and meshing did not finish within 0.3 s (OpenCASCADE may loop on a corrupt file; "
               "WorkerTimeout sets the limit)");
  EXPECT_LT(seconds, 5.0);
  EXPECT_EQ(r.faces->GetNumberOfCells(), 0);
}

// Bad input the reader itself reports gives the same line in the worker as in process.
TEST(CadWorker, TheReadersOwnErrorsAreTheSame) {
  const std::string path = tempPath("worker_truncated.step");
  const std::string whole = readBytes(writeStep(model(), "worker_whole.step"));
  writeBytes(path, whole.substr(0, whole.size() / 3));
  const Read local = readBad(path);
  const Read worker = readBad(path, inWorker);
  EXPECT_FALSE(local.reader->GetErrorMessage().empty());
  EXPECT_EQ(local.reader->GetErrorMessage(), worker.reader->GetErrorMessage());
}

// The folder is made under TMPDIR; where it cannot be (TMPDIR a file), under /tmp.
TEST(CadWorker, TheTemporaryFolderIsUnderTmpdir) {
  const std::filesystem::path tmp = std::filesystem::path(tempPath("worker_tmpdir_direct"));
  std::filesystem::create_directories(tmp);
  const char* was = std::getenv("TMPDIR");
  const std::string old = was ? was : "";
  setenv("TMPDIR", tmp.c_str(), 1);
  std::string made, fallback;
  {
    const wf::TemporaryFolder f("wirefur-test-");
    made = f.path();
    EXPECT_TRUE(std::filesystem::is_directory(made));
  }
  const std::string file = tempPath("worker_tmpdir_is_a_file");
  writeBytes(file, "x");
  setenv("TMPDIR", file.c_str(), 1);
  {
    const wf::TemporaryFolder f("wirefur-test-");
    fallback = f.path();
  }
  if (was) setenv("TMPDIR", old.c_str(), 1);
  else unsetenv("TMPDIR");
  EXPECT_EQ(made.rfind(tmp.string() + "/wirefur-test-", 0), 0u) << made;
  EXPECT_FALSE(std::filesystem::exists(made)) << "removed when it goes";
  EXPECT_EQ(fallback.rfind("/tmp/wirefur-test-", 0), 0u) << fallback;
}

TEST(CadWorker, TemporaryFilesGoUnderTmpdirAndAreRemoved) {
  const std::string path = writeBrep(model(), "worker_tmpdir.brep");
  const std::filesystem::path tmp = std::filesystem::path(tempPath("worker_tmpdir"));
  std::filesystem::create_directories(tmp);
  const char* was = std::getenv("TMPDIR");
  const std::string old = was ? was : "";
  setenv("TMPDIR", tmp.c_str(), 1);
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(path.c_str());
  reader->ReadInWorkerOn();
  // Looked at while the worker runs (its progress events): its folder is under TMPDIR.
  int seen = 0;
  vtkNew<vtkCallbackCommand> look;
  look->SetClientData(&seen);
  look->SetCallback([](vtkObject*, unsigned long, void* data, void*) {
    std::error_code ec;
    if (!std::filesystem::is_empty(std::getenv("TMPDIR"), ec)) ++*static_cast<int*>(data);
  });
  reader->AddObserver(vtkCommand::ProgressEvent, look);
  reader->Update();
  EXPECT_GT(seen, 0) << "no folder under TMPDIR while the worker ran";
  if (was) setenv("TMPDIR", old.c_str(), 1);
  else unsetenv("TMPDIR");
  EXPECT_EQ(reader->GetErrorMessage(), "");
  EXPECT_TRUE(std::filesystem::is_empty(tmp)) << "left behind in " << tmp;
}

// Numbers cross to the worker in a form no locale changes: every double comes back exactly, and
// under a decimal-comma locale (when one is installed) the worker reads what in-process reads.
TEST(CadWorker, NumbersCrossInEveryLocale) {
  for (double v : {0.1, 1e-7, 1.0 / 3.0, 1e308, 5e-324, -0.0, 600.0, 2e-3, 0.5}) {
    double back = 1.0;
    ASSERT_TRUE(wf::parseWorkerNumber(wf::workerNumber(v), back)) << wf::workerNumber(v);
    EXPECT_EQ(std::memcmp(&v, &back, sizeof v), 0) << wf::workerNumber(v);
  }
  double x = 0;
  EXPECT_FALSE(wf::parseWorkerNumber("0,001", x));
  EXPECT_FALSE(wf::parseWorkerNumber("", x));
  // An installed German locale, else one compiled here from the locales package's definitions
  // (localedef into a folder named by LOCPATH, about a second).
  const char* comma = nullptr;
  for (const char* name : {"de_DE.UTF-8", "de_DE.utf8"})
    if (std::setlocale(LC_NUMERIC, name)) comma = name;
  const std::string compiled = tempPath("worker_locales");
  if (!comma && std::filesystem::exists("/usr/share/i18n/locales/de_DE")) {
    std::filesystem::create_directories(compiled);
    const std::string command = "localedef -i de_DE -f UTF-8 " + compiled + "/de_DE.UTF-8 >/dev/null 2>&1";
    if (std::system(command.c_str()) == 0) {
      setenv("LOCPATH", compiled.c_str(), 1);
      if (std::setlocale(LC_NUMERIC, "de_DE.UTF-8")) comma = "de_DE.UTF-8";
    }
  }
  if (!comma) GTEST_SKIP() << "no decimal-comma locale (neither installed nor made by localedef): the round trip alone was checked";
  char text[32];
  std::snprintf(text, sizeof text, "%g", 0.5);
  EXPECT_STREQ(text, "0,5") << "the locale does not use a decimal comma";
  EXPECT_EQ(wf::workerNumber(0.5), "0.5");
  const std::string path = writeBrep(model(), "worker_locale.brep");
  auto configure = [](vtkWireFurCADReader* r) { r->SetLinearDeflection(2e-3), r->SetFeatureAngle(15); };
  const Read worker = readOk(path, [&](vtkWireFurCADReader* r) { configure(r), r->ReadInWorkerOn(); });
  std::setlocale(LC_NUMERIC, "C");
  unsetenv("LOCPATH");
  const Read local = readOk(path, configure);
  expectSameData(local.faces, worker.faces, "faces");
  expectSameData(local.edges, worker.edges, "edges");
}

// A host that reaps its children itself (SIGCHLD ignored: the kernel reaps them) leaves the exit
// status unknown: the worker's completion marker decides, and the read succeeds.
TEST(CadWorker, AHostThatReapsItsChildren) {
  const std::string path = writeBrep(model(), "worker_reaped.brep");
  const Read local = readOk(path);
  struct sigaction ignore {}, old {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGCHLD, &ignore, &old);
  const Read worker = readOk(path, inWorker);
  const Read bad = readBad(regression("brep_segv_in_mesher.brep"), inWorker);
  sigaction(SIGCHLD, &old, nullptr);
  expectSameData(local.faces, worker.faces, "faces");
  expectSameData(local.edges, worker.edges, "edges");
  const std::string m = bad.reader->GetErrorMessage();
  EXPECT_NE(m.find("crashed"), std::string::npos) << m;
  EXPECT_NE(m.find("an unknown status"), std::string::npos) << m;
}

// Progress comes from the worker while it meshes, and AbortExecute stops it at once.
TEST(CadWorker, ProgressComesFromTheWorkerAndAbortStopsIt) {
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 10).Shape(), "worker_abort.brep");
  struct Seen {
    double most = 0;
    int events = 0;
  } seen;
  vtkNew<vtkCallbackCommand> watch;
  watch->SetClientData(&seen);
  watch->SetCallback([](vtkObject* caller, unsigned long, void* data, void* call) {
    Seen& s = *static_cast<Seen*>(data);
    const double p = *static_cast<double*>(call);
    s.most = std::max(s.most, p);
    ++s.events;
    if (p >= 0.3) static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);  // read, now meshing
  });
  const auto t0 = std::chrono::steady_clock::now();
  const Read r = readBad(path, [&](vtkWireFurCADReader* reader) {
    reader->ReadInWorkerOn();
    reader->SetLinearDeflection(1e-7);
    reader->SetMaximumTriangles(VTK_ID_MAX);
    reader->AddObserver(vtkCommand::ProgressEvent, watch);
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.reader->GetErrorMessage(), path + ": the read was aborted");
  EXPECT_GE(seen.most, 0.3);
  EXPECT_LT(seen.most, 1.0);
  EXPECT_LT(seconds, 10.0);
}

// A worker whose parent is killed dies too (a killed pvserver must not leave OpenCASCADE looping
// for ever): a shell starts the worker on a slow mesh and is killed after 0.5 s.
TEST(CadWorker, TheWorkerDiesWithItsParent) {
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 10).Shape(), "worker_orphan.brep");
  const std::string folder = tempPath("worker_orphan_folder");
  std::filesystem::create_directories(folder);
  const std::string exe = vtkWireFurCADReader::GetWorkerExecutable();
  ASSERT_FALSE(exe.empty());
  auto running = [&] {  // a process whose command line names the folder
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator("/proc")) {
      std::ifstream in(e.path() / "cmdline", std::ios::binary);
      std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (cmd.rfind(exe, 0) == 0 && cmd.find(folder) != std::string::npos) ++n;
    }
    return n;
  };
  wf::WorkerOptions run;
  run.timeoutSeconds = 0.5;
  const wf::WorkerExit e = wf::runWorker(
    "/bin/sh", {"sh", "-c", "\"$0\" \"$1\" \"$2\" $$ 60 1e-7 1 0.5 0 0 9223372036854775807 30 1 & wait", exe, path, folder},
    run);
  EXPECT_TRUE(e.timedOut);
  int left = 1;
  for (int i = 0; i < 100 && left > 0; ++i) {
    left = running();
    if (left > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(left, 0) << "the worker outlived its parent by 2 s";
  // And a worker that finds its parent gone already ends at once (status 3), writing nothing.
  const wf::WorkerExit stale = wf::runWorker(exe, {exe, path, folder, "1", "60", "1e-3", "1", "0.5", "0", "0",
                                                   "1000000", "30", "1"}, wf::WorkerOptions());
  EXPECT_EQ(stale.status, wf::kWorkerExitUsage);
  EXPECT_FALSE(std::filesystem::exists(folder + "/done"));
}

// The exact faces read later come from the file the worker read: once it has changed, none (with
// a warning), and the silhouette filter falls back to the mesh.
TEST(CadWorker, LazyFacesRefuseAChangedFile) {
  const std::string path = writeBrep(model(), "worker_changed.brep");
  const Read worker = readOk(path, inWorker);
  std::ofstream(path, std::ios::app) << "\n";  // changed after the read
  std::vector<WireFurCadFace> faces;
  EXPECT_EQ(wirefur_cad_face_surfaces(worker.reader, &faces), 0);
  EXPECT_TRUE(faces.empty());
}
