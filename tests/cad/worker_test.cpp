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

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>

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
  // Looked at while the worker runs: its folder is under TMPDIR.
  reader->Update();
  if (was) setenv("TMPDIR", old.c_str(), 1);
  else unsetenv("TMPDIR");
  EXPECT_EQ(reader->GetErrorMessage(), "");
  EXPECT_TRUE(std::filesystem::is_empty(tmp)) << "left behind in " << tmp;
}
