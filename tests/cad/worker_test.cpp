// vtkWireFurCADReader with ReadInWorker on (wirefur-cad-worker, wf_cad_worker.h): the outputs
// equal the in-process read bit for bit; OpenCASCADE's crashes and hangs on the fuzzing findings
// (tests/apps/cad_regressions) become one line naming the file while this process carries on; the
// exact faces are read on demand; the temporary folder is made under TMPDIR and removed.
#include "cad_fixtures.h"
#include "core/sanitizers.h"
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

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <clocale>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
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
  // (localedef into a folder named by LOCPATH, about a second). Both are put back at the end.
  const std::string oldNumeric = std::setlocale(LC_NUMERIC, nullptr);
  const char* oldLocpath = std::getenv("LOCPATH");
  const std::string keptLocpath = oldLocpath ? oldLocpath : "";
  struct Restore {
    std::string numeric, locpath;
    bool had;
    ~Restore() {
      if (had) setenv("LOCPATH", locpath.c_str(), 1);
      else unsetenv("LOCPATH");
      std::setlocale(LC_NUMERIC, numeric.c_str());
    }
  } restore{oldNumeric, keptLocpath, oldLocpath != nullptr};
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
  run.timeoutSeconds = 10.0;
  // The shell is killed only once its worker is seen running (else the test would prove nothing).
  int seenRunning = 0;
  auto lastLook = std::chrono::steady_clock::now();
  run.poll = [&] {
    if (std::chrono::steady_clock::now() - lastLook < std::chrono::milliseconds(50)) return true;
    lastLook = std::chrono::steady_clock::now();
    if (running() > 0) ++seenRunning;
    return seenRunning < 3;  // (seen three times, 100 ms apart: past its start-up)
  };
  const wf::WorkerExit e = wf::runWorker(
    "/bin/sh", {"sh", "-c", "\"$0\" \"$1\" \"$2\" $$ 60 1e-7 1 0.5 0 0 9223372036854775807 30 1 & wait", exe, path, folder},
    run);
  EXPECT_TRUE(e.aborted);
  EXPECT_GE(seenRunning, 3);
  int left = 1;
  for (int i = 0; i < 100 && left > 0; ++i) {
    left = running();
    if (left > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(left, 0) << "the worker outlived its parent by 2 s";
  // And a worker that finds its parent gone already ends at once, writing nothing.
  const wf::WorkerExit stale = wf::runWorker(exe, {exe, path, folder, "0", "60", "1e-3", "1", "0.5", "0", "0",
                                                   "1000000", "30", "1"}, wf::WorkerOptions());
  EXPECT_EQ(stale.status, wf::kWorkerExitOrphaned);
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

// What a worker inherits: no file descriptor past stderr (fd 100 is opened here without
// O_CLOEXEC first), stdin on /dev/null, no blocked signal (SIGUSR1 is blocked here) and no
// ignored one (SIGPIPE is ignored here). `ls` and `grep`, started as workers, write what they
// have to their stderr files (ls opens one fd of its own, the folder it lists).
TEST(CadWorker, AWorkerInheritsNoFdAndNoSignalState) {
  const std::string folder = tempPath("worker_inherits");
  std::filesystem::create_directories(folder);
  const int fd = ::open("/dev/null", O_RDONLY);  // (no O_CLOEXEC)
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::dup2(fd, 100), 100);
  sigset_t usr1, old;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &usr1, &old);
  struct sigaction ignore {}, oldPipe {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &oldPipe);
  wf::WorkerOptions run;
  run.timeoutSeconds = 20;
  run.stderrPath = folder + "/fds";
  const wf::WorkerExit a = wf::runWorker("/bin/sh", {"sh", "-c", "exec ls /proc/self/fd 1>&2"}, run);
  const std::string fds = run.stderrPath;
  run.stderrPath = folder + "/signals";
  const wf::WorkerExit b =
    wf::runWorker("/bin/sh", {"sh", "-c", "exec grep -E '^Sig(Blk|Ign)|^State' /proc/self/status 1>&2"}, run);
  run.stderrPath = folder + "/stdin";
  const wf::WorkerExit c = wf::runWorker("/bin/sh", {"sh", "-c", "exec readlink /proc/self/fd/0 1>&2"}, run);
  sigaction(SIGPIPE, &oldPipe, nullptr);
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  ::close(100);
  ::close(fd);
  EXPECT_EQ(a.status + b.status + c.status, 0);
  std::vector<std::string> listed;
  {
    std::ifstream in(fds);
    for (std::string line; std::getline(in, line);) listed.push_back(line);
  }
  EXPECT_LE(listed.size(), 4u);  // 0, 1, 2 and ls's own
  for (const std::string& f : listed) {
    EXPECT_NE(f, "100") << "fd 100 inherited";
  }
  std::map<std::string, unsigned long long> mask;
  {
    std::ifstream in(folder + "/signals");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("Sig", 0) == 0) mask[line.substr(0, 6)] = std::stoull(line.substr(line.find('\t') + 1), nullptr, 16);
  }
  ASSERT_EQ(mask.size(), 2u);
  // Signals 1 to 31 (glibc keeps 32 and 33 for itself).
  EXPECT_EQ(mask["SigBlk"] & 0x7fffffffull, 0ull);
  EXPECT_EQ(mask["SigIgn"] & 0x7fffffffull, 0ull);
  EXPECT_EQ(wf::lastLineOf(folder + "/stdin"), "/dev/null");
}

// A worker of another version (arguments it cannot read) and one that cannot write its result
// are named as such, with the line the worker printed, not taken for a corrupt file.
TEST(CadWorker, AWorkerThatCannotRunOrWriteSaysSo) {
  const std::string exe = vtkWireFurCADReader::GetWorkerExecutable();
  ASSERT_FALSE(exe.empty());
  const std::string folder = tempPath("worker_cannot");
  std::filesystem::create_directories(folder);
  const std::string path = writeBrep(model(), "worker_cannot.brep");
  wf::WorkerOptions run;
  run.stderrPath = folder + "/stderr";
  const wf::WorkerExit usage = wf::runWorker(exe, {exe, path, folder, std::to_string(getpid()), "60", "0,001", "1", "0.5",
                                                   "0", "0", "1000000", "30", "1"}, run);
  EXPECT_EQ(usage.status, wf::kWorkerExitUsage);
  EXPECT_NE(wf::lastLineOf(run.stderrPath).find("not a command"), std::string::npos) << wf::lastLineOf(run.stderrPath);
  const std::string gone = folder + "/no/such/folder";
  const wf::WorkerExit write = wf::runWorker(exe, {exe, path, gone, std::to_string(getpid()), "60", "1e-3", "1", "0.5",
                                                   "0", "0", "1000000", "30", "1"}, run);
  EXPECT_EQ(write.status, wf::kWorkerExitWriteFailed);
  EXPECT_NE(wf::lastLineOf(run.stderrPath).find("cannot write the result under " + gone), std::string::npos)
    << wf::lastLineOf(run.stderrPath);
}

// Past the worker's memory cap (set low here with WIREFUR_WORKER_MEMORY_CAP), meshing fails with
// "out of memory in the CAD worker", not with faces skipped: OpenCASCADE's failed allocations end
// the worker (worker_malloc.cpp) instead of failing faces one by one.
TEST(CadWorker, PastTheMemoryCapTheReadFailsAsOutOfMemory) {
#if defined(WF_UNDER_ASAN)
  // (There the cap is ASan's resident-size limit, with room for its own shadow and quarantine
  // added to it: a cap of 0.4 GiB is no test of it.)
  GTEST_SKIP() << "no RLIMIT_DATA cap under AddressSanitizer (its shadow memory needs the room)";
#endif
  const std::string path = writeBrep(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 10).Shape(), "worker_oom.brep");
  setenv("WIREFUR_WORKER_MEMORY_CAP", "400000000", 1);
  const auto t0 = std::chrono::steady_clock::now();
  const Read r = readBad(path, [](vtkWireFurCADReader* reader) {
    reader->ReadInWorkerOn();
    reader->SetWorkerTimeout(60);
    reader->SetLinearDeflection(1e-7);
    reader->SetMaximumTriangles(VTK_ID_MAX);
  });
  unsetenv("WIREFUR_WORKER_MEMORY_CAP");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string m = r.reader->GetErrorMessage();
  EXPECT_EQ(m.rfind(path + ": out of memory in the CAD worker (its cap is 0.4 GiB", 0), 0u) << m;
  EXPECT_EQ(r.faces->GetNumberOfCells(), 0);
  EXPECT_LT(seconds, 60.0);
}
