// Fixtures and checks for the CAD reader's tests (tests/cad/*_test.cpp).
//
// Every fixture is made here at run time with OpenCASCADE (shapes, STEP, IGES, BREP) or libzip
// (FreeCAD documents) in a per-process temporary directory, removed at exit. The checks compute
// their expectations independently of the reader: closed forms of the primitives'
// parameterisations (OpenCASCADE's ElSLib conventions), central finite differences, exact counts.
#pragma once

#include "vtkWireFurCADReader.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Pnt.hxx>
#include <gp_Trsf.hxx>
#include <gp_Vec.hxx>

#include <gtest/gtest.h>
#include <zip.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <string>
#include <chrono>
#include <csignal>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <fcntl.h>
#include <cstring>
#include <vector>

namespace cadtest {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 unit(const Vec3& a) { return scale(a, 1.0 / norm(a)); }
inline Vec3 fromGp(const gp_XYZ& p) { return {p.X(), p.Y(), p.Z()}; }
inline gp_Pnt toPnt(const Vec3& p) { return gp_Pnt(p[0], p[1], p[2]); }

// ---------------------------------------------------------------------------------------------
// The temporary directory: one per test process (ctest runs each test in its own process),
// removed when the process exits. A child started by runIsolated works in a folder of its
// parent's directory (WIREFUR_CAD_TEMP_DIR), which the parent removes: a child that crashes
// leaves nothing behind.

class TempDir {
 public:
  TempDir() {
    if (const char* given = std::getenv("WIREFUR_CAD_TEMP_DIR")) {
      path_ = given;
      owned_ = false;
      return;
    }
    std::string tmpl = (std::filesystem::temp_directory_path() / "wirefur_cad_tests_XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    if (owned_) std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  bool owned_ = true;
};

inline const TempDir& tempDir() {
  static TempDir dir;
  return dir;
}

inline std::string tempPath(const std::string& name) { return (tempDir().path() / name).string(); }

inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// Writers.

/// OpenCASCADE's writers print statistics banners on the console: removes its console printer
/// (the reader installs its own message capture anyway).
inline void quietOcct() {
  static std::once_flag once;
  std::call_once(once, [] { Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream)); });
}

inline std::string writeBrep(const TopoDS_Shape& shape, const std::string& name) {
  const std::string path = tempPath(name);
  if (!BRepTools::Write(shape, path.c_str())) ADD_FAILURE() << "BRepTools::Write failed: " << path;
  return path;
}

inline std::string brepText(const TopoDS_Shape& shape) {
  std::ostringstream s;
  BRepTools::Write(shape, s);
  return s.str();
}

inline std::string writeStep(const TopoDS_Shape& shape, const std::string& name) {
  quietOcct();
  const std::string path = tempPath(name);
  STEPControl_Writer w;
  if (w.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone || w.Write(path.c_str()) != IFSelect_RetDone)
    ADD_FAILURE() << "STEP writing failed: " << path;
  return path;
}

/// IGES in OpenCASCADE's default "Faces" mode (brepMode 0: each face a trimmed surface, type 144)
/// or in "BRep" mode (1: a manifold solid B-rep object, type 186, shared edges).
inline std::string writeIges(const TopoDS_Shape& shape, const std::string& name, int brepMode = 0) {
  static std::once_flag once;
  std::call_once(once, [] { IGESControl_Controller::Init(); });
  quietOcct();
  const std::string path = tempPath(name);
  IGESControl_Writer w("MM", brepMode);
  if (!w.AddShape(shape)) ADD_FAILURE() << "IGES AddShape failed";
  w.ComputeModel();
  if (!w.Write(path.c_str())) ADD_FAILURE() << "IGES writing failed: " << path;
  return path;
}

/// A zip archive with the given entries (name, bytes), deflated, written with libzip.
inline std::string writeZip(const std::string& name, const std::vector<std::pair<std::string, std::string>>& entries) {
  const std::string path = tempPath(name);
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  if (!z) {
    ADD_FAILURE() << "zip_open failed: " << err;
    return path;
  }
  for (const auto& [entry, bytes] : entries) {
    // libzip reads the buffer at zip_close: it must outlive this loop (entries does).
    zip_source_t* src = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
    if (!src || zip_file_add(z, entry.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
      ADD_FAILURE() << "zip_file_add failed: " << zip_strerror(z);
      if (src) zip_source_free(src);
    }
  }
  if (zip_close(z) != 0) {
    ADD_FAILURE() << "zip_close failed: " << zip_strerror(z);
    zip_discard(z);
  }
  return path;
}

// ---------------------------------------------------------------------------------------------
// Reading.

struct Read {
  vtkSmartPointer<vtkWireFurCADReader> reader;
  vtkPolyData* faces = nullptr;
  vtkPolyData* edges = nullptr;
  vtkIdType nPoints() const { return faces->GetNumberOfPoints(); }
  Vec3 point(vtkIdType i) const {
    Vec3 p;
    faces->GetPoint(i, p.data());
    return p;
  }
  Vec3 normal(vtkIdType i) const { return tuple3("Normals", i); }
  Vec3 su(vtkIdType i) const { return tuple3("Su", i); }
  Vec3 sv(vtkIdType i) const { return tuple3("Sv", i); }
  std::array<double, 2> uv(vtkIdType i) const {
    std::array<double, 2> t;
    faces->GetPointData()->GetArray("TCoords")->GetTuple(i, t.data());
    return t;
  }
  Vec3 tuple3(const char* name, vtkIdType i) const {
    Vec3 t;
    faces->GetPointData()->GetArray(name)->GetTuple(i, t.data());
    return t;
  }
  /// The face (cell "FaceId") of each point; points are not shared across faces.
  std::vector<int> pointFaces() const {
    std::vector<int> out(size_t(nPoints()), -1);
    vtkDataArray* ids = faces->GetCellData()->GetArray("FaceId");
    vtkIdType n = 0;
    const vtkIdType* pts = nullptr;
    vtkCellArray* polys = faces->GetPolys();
    vtkIdType c = 0;
    for (polys->InitTraversal(); polys->GetNextCell(n, pts); ++c)
      for (vtkIdType k = 0; k < n; ++k) out[size_t(pts[k])] = int(ids->GetTuple1(c));
    return out;
  }
  std::vector<std::array<vtkIdType, 3>> triangles() const {
    std::vector<std::array<vtkIdType, 3>> out;
    vtkIdType n = 0;
    const vtkIdType* pts = nullptr;
    vtkCellArray* polys = faces->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(n, pts);) {
      EXPECT_EQ(n, 3);
      out.push_back({pts[0], pts[1], pts[2]});
    }
    return out;
  }
};

inline Read readCad(const std::string& path, const std::function<void(vtkWireFurCADReader*)>& configure = {}) {
  Read r;
  r.reader = vtkSmartPointer<vtkWireFurCADReader>::New();
  r.reader->SetFileName(path.c_str());
  if (configure) configure(r.reader);
  r.reader->Update();
  r.faces = r.reader->GetOutput(0);
  r.edges = r.reader->GetOutput(1);
  return r;
}

/// Reads a file the update must fail on, with VTK's error output silenced (the message is
/// checked through GetErrorMessage()).
inline Read readBad(const std::string& path, const std::function<void(vtkWireFurCADReader*)>& configure = {}) {
  const vtkTypeBool was = vtkObject::GetGlobalWarningDisplay();
  vtkObject::GlobalWarningDisplayOff();
  Read r = readCad(path, configure);
  vtkObject::SetGlobalWarningDisplay(was);
  return r;
}

/// Reads and requires success (an empty error message and some triangles).
inline Read readOk(const std::string& path, const std::function<void(vtkWireFurCADReader*)>& configure = {}) {
  Read r = readCad(path, configure);
  EXPECT_EQ(r.reader->GetErrorMessage(), "") << path;
  EXPECT_GT(r.faces->GetNumberOfCells(), 0) << path;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Isolation: reading a bad file may crash or hang inside OpenCASCADE. A test that must survive
// that runs the read first in a fresh copy of this executable (only the current test, with
// WIREFUR_CAD_ISOLATED set in its environment), under a time limit, and reports a crash or a
// hang as a failure of its own instead of taking the whole run down with it.

/// True in the copy started by runIsolated: the test body must do the risky read and exit.
inline bool inIsolatedChild() { return std::getenv("WIREFUR_CAD_ISOLATED") != nullptr; }

struct IsolatedRun {
  bool timedOut = false;
  int signal = 0;      // the signal that ended the child, 0 if it exited
  int exitCode = -1;   // its exit code, when it exited
  std::string output;  // its stdout and stderr (the last 2000 characters)
  std::string describe() const {
    if (timedOut) return "did not finish in time (a hang?)";
    if (signal) return "was killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
    return "exited with code " + std::to_string(exitCode);
  }
};

/// Runs the current test again in a child process with WIREFUR_CAD_ISOLATED=1, waiting at most
/// `seconds`; a child past its time is killed (SIGKILL, by its pid).
inline IsolatedRun runIsolated(double seconds) {
  IsolatedRun result;
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string filter = std::string("--gtest_filter=") + info->test_suite_name() + "." + info->name();
  const std::string log = tempPath(std::string("isolated_") + info->name() + ".log");
  const std::string childDir = tempPath(std::string("isolated_") + info->name());
  std::filesystem::create_directories(childDir);
  std::string self(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  if (n <= 0) {
    ADD_FAILURE() << "cannot find this executable";
    return result;
  }
  self.resize(size_t(n));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) env.emplace_back(*e);
  env.emplace_back("WIREFUR_CAD_ISOLATED=1");
  env.emplace_back("WIREFUR_CAD_TEMP_DIR=" + childDir);
  std::vector<char*> envp, argv = {self.data(), const_cast<char*>(filter.c_str()), nullptr};
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    ADD_FAILURE() << "posix_spawn failed: " << rc;
    return result;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      result.timedOut = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!result.timedOut) {
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    else if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
  }
  result.output = readBytes(log);
  if (result.output.size() > 2000) result.output = result.output.substr(result.output.size() - 2000);
  return result;
}

// ---------------------------------------------------------------------------------------------
// Checks shared by several tests.

/// Sum of the triangles' areas.
inline double meshArea(const Read& r) {
  double a = 0;
  for (const auto& t : r.triangles())
    a += 0.5 * norm(cross(sub(r.point(t[1]), r.point(t[0])), sub(r.point(t[2]), r.point(t[0]))));
  return a;
}

struct WindingReport {
  int triangles = 0, degenerate = 0, wrong = 0;
};

/// Triangles that wind clockwise about a vertex normal (geometric normal . vertex normal <= 0).
/// Triangles whose area is below `degenerateArea` (collapsed at a pole) are counted apart.
inline WindingReport checkWinding(const Read& r, double degenerateArea) {
  WindingReport w;
  for (const auto& t : r.triangles()) {
    ++w.triangles;
    const Vec3 g = cross(sub(r.point(t[1]), r.point(t[0])), sub(r.point(t[2]), r.point(t[0])));
    if (0.5 * norm(g) <= degenerateArea) {
      ++w.degenerate;
      continue;
    }
    for (vtkIdType v : t)
      if (!(dot(g, r.normal(v)) > 0)) {
        ++w.wrong;
        break;
      }
  }
  return w;
}

/// Largest | |n| - 1 | over the point normals (float: ~1e-7 is rounding).
inline double maxNormalLengthError(const Read& r) {
  double e = 0;
  for (vtkIdType i = 0; i < r.nPoints(); ++i) {
    const Vec3 n = r.normal(i);
    e = std::max(e, std::isfinite(norm(n)) ? std::abs(norm(n) - 1.0) : 1e300);
  }
  return e;
}

inline std::vector<TopoDS_Face> facesOf(const TopoDS_Shape& s) {
  std::vector<TopoDS_Face> out;
  for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next()) out.push_back(TopoDS::Face(e.Current()));
  return out;
}

inline std::vector<GeomAbs_SurfaceType> surfaceTypes(const TopoDS_Shape& s) {
  std::vector<GeomAbs_SurfaceType> out;
  for (const TopoDS_Face& f : facesOf(s)) out.push_back(BRepAdaptor_Surface(f).GetType());
  return out;
}

/// Polylines of the edges output, each with its cell data.
struct Line {
  std::vector<vtkIdType> ids;
  int kind = 0, id = 0, part = 0;
  int edgeClass = -1;  ///< "EdgeClass"
  double angle = 0;    ///< "EdgeAngle" (degrees, NaN where not between two faces)
};
inline std::vector<Line> lines(const Read& r) {
  std::vector<Line> out;
  vtkIdType n = 0;
  const vtkIdType* pts = nullptr;
  vtkCellArray* ls = r.edges->GetLines();
  vtkDataArray* kind = r.edges->GetCellData()->GetArray("Kind");
  vtkDataArray* eid = r.edges->GetCellData()->GetArray("EdgeId");
  vtkDataArray* pid = r.edges->GetCellData()->GetArray("PartId");
  vtkIdType c = 0;
  for (ls->InitTraversal(); ls->GetNextCell(n, pts); ++c) {
    Line l;
    l.ids.assign(pts, pts + n);
    l.kind = int(kind->GetTuple1(c));
    l.id = int(eid->GetTuple1(c));
    l.part = int(pid->GetTuple1(c));
    if (vtkDataArray* cls = r.edges->GetCellData()->GetArray("EdgeClass")) l.edgeClass = int(cls->GetTuple1(c));
    if (vtkDataArray* a = r.edges->GetCellData()->GetArray("EdgeAngle")) l.angle = a->GetTuple1(c);
    out.push_back(l);
  }
  return out;
}
inline Vec3 edgePoint(const Read& r, vtkIdType i) {
  Vec3 p;
  r.edges->GetPoint(i, p.data());
  return p;
}

}  // namespace cadtest
