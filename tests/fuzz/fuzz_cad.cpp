// libFuzzer target for the CAD reader (vtkWireFurCADReader), one format per program: compiled
// with exactly one of WF_FUZZ_FORMAT_STEP, _IGES, _BREP, _FCSTD (tests/fuzz/standalone).
//
// Each input is written to a file with the format's extension and read by the reader itself,
// exactly as the wirefur command reads it: wfcad::readStepOrIges / readBrep / readFreeCad, then
// BRepMesh_IncrementalMesh at the default relative deflection, the per-face walk with the exact
// surface data (FaceSurface, Surface::frame), the edges from the face tessellation and iso lines
// (2 x 2 per face, to reach StdPrs_Isolines too). One thread, for reproducible runs.
//
// Expected: the update fails with one line in GetErrorMessage() (the reader turns
// wfcad::CadError, Standard_Failure and std::bad_alloc from reading into that), or succeeds.
// Findings (the program aborts, so libFuzzer saves the input):
//  - a crash, a sanitizer report, a hang past -timeout, memory past -rss_limit_mb (libFuzzer);
//  - any exception escaping vtkWireFurCADReader::Update() -- Standard_Failure and CadError
//    included: the reader promises to catch them, and in the wirefur command an escaping one
//    terminates the program;
//  - an output that breaks the reader's documented contract: point ids out of range, array sizes
//    that do not match, non-finite points or normals, non-unit normals, a multi-line error
//    message. Set WF_FUZZ_CONTRACT=0 to check only for crashes and escaping exceptions.
#include "vtkWireFurCADReader.h"

#include "wf_cad_model.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <Standard_Failure.hxx>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <typeinfo>
#include <vector>

#if defined(WF_FUZZ_FORMAT_STEP)
#define WF_FUZZ_EXTENSION ".step"
#elif defined(WF_FUZZ_FORMAT_IGES)
#define WF_FUZZ_EXTENSION ".iges"
#elif defined(WF_FUZZ_FORMAT_BREP)
#define WF_FUZZ_EXTENSION ".brep"
#elif defined(WF_FUZZ_FORMAT_FCSTD)
#define WF_FUZZ_EXTENSION ".FCStd"  // mixed case on purpose: the reader lower-cases extensions
#include <zip.h>
#else
#error "compile with one of WF_FUZZ_FORMAT_STEP, _IGES, _BREP, _FCSTD"
#endif

namespace {

std::string g_dir;   // this process's temporary directory (libFuzzer -fork/-jobs run several)
std::string g_path;  // the input file, rewritten for every input
bool g_contract = true;
bool g_verbose = false;  // WF_FUZZ_VERBOSE=1: one line per input (what the reader made of it)

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "\n==WIREFUR-CAD-FUZZ== FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

void removeDir() {
  std::error_code ec;
  if (!g_dir.empty()) std::filesystem::remove_all(g_dir, ec);
}

bool finite3(const double* p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// The reader's documented output (vtkWireFurCADReader.h), checked after a good update.
void checkOutput(vtkWireFurCADReader* r) {
  vtkPolyData* faces = r->GetOutput(0);
  vtkPolyData* edges = r->GetOutput(1);
  const vtkIdType np = faces->GetNumberOfPoints();
  const vtkIdType nPolys = faces->GetNumberOfPolys();
  const int parts = r->GetNumberOfParts();
  if (r->GetNumberOfMeshedFaces() + r->GetNumberOfSkippedFaces() != r->GetNumberOfFaces())
    finding("meshed + skipped faces != faces (" + std::to_string(r->GetNumberOfMeshedFaces()) + " + " +
            std::to_string(r->GetNumberOfSkippedFaces()) + " != " + std::to_string(r->GetNumberOfFaces()) + ")");
  if (faces->GetNumberOfVerts() || faces->GetNumberOfLines() || faces->GetNumberOfStrips())
    finding("faces output holds cells other than triangles");
  for (const char* name : {"Normals", "TCoords", "Su", "Sv", "Colors"}) {
    vtkDataArray* a = faces->GetPointData()->GetArray(name);
    if (!a) finding(std::string("faces output: no point array ") + name);
    if (a->GetNumberOfTuples() != np)
      finding(std::string("faces output: ") + name + " has " + std::to_string(a->GetNumberOfTuples()) + " tuples for " +
              std::to_string(np) + " points");
  }
  for (const char* name : {"FaceId", "PartId"}) {
    vtkDataArray* a = faces->GetCellData()->GetArray(name);
    if (!a || a->GetNumberOfTuples() != nPolys) finding(std::string("faces output: cell array ") + name + " missing or of the wrong size");
  }
  vtkDataArray* normals = faces->GetPointData()->GetArray("Normals");
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    faces->GetPoint(i, p);
    if (!finite3(p)) finding("faces output: point " + std::to_string(i) + " is not finite");
    normals->GetTuple(i, p);
    if (!finite3(p)) finding("faces output: normal " + std::to_string(i) + " is not finite");
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (std::abs(len - 1.0) > 1e-3) finding("faces output: normal " + std::to_string(i) + " has length " + std::to_string(len));
  }
  {
    auto it = vtk::TakeSmartPointer(faces->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      it->GetCurrentCell(n, ids);
      if (n != 3) finding("faces output: a polygon of " + std::to_string(n) + " points");
      for (vtkIdType k = 0; k < n; ++k)
        if (ids[k] < 0 || ids[k] >= np) finding("faces output: point id " + std::to_string(ids[k]) + " out of range");
    }
  }
  vtkDataArray* partIds = faces->GetCellData()->GetArray("PartId");
  for (vtkIdType c = 0; c < nPolys; ++c) {
    const double v = partIds->GetTuple1(c);
    if (v < 0 || v >= parts) finding("faces output: PartId " + std::to_string(v) + " out of range");
  }
  const vtkIdType ne = edges->GetNumberOfPoints();
  const vtkIdType nLines = edges->GetNumberOfLines();
  for (const char* name : {"Kind", "EdgeId", "PartId"}) {
    vtkDataArray* a = edges->GetCellData()->GetArray(name);
    if (!a || a->GetNumberOfTuples() != nLines) finding(std::string("edges output: cell array ") + name + " missing or of the wrong size");
  }
  for (vtkIdType i = 0; i < ne; ++i) {
    double p[3];
    edges->GetPoint(i, p);
    if (!finite3(p)) finding("edges output: point " + std::to_string(i) + " is not finite");
  }
  auto it = vtk::TakeSmartPointer(edges->GetLines()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    it->GetCurrentCell(n, ids);
    if (n < 2) finding("edges output: a polyline of " + std::to_string(n) + " points");
    for (vtkIdType k = 0; k < n; ++k)
      if (ids[k] < 0 || ids[k] >= ne) finding("edges output: point id " + std::to_string(ids[k]) + " out of range");
  }
}

#if defined(WF_FUZZ_FORMAT_FCSTD)
// ---------------------------------------------------------------------------------------------
// A FreeCAD document is a zip: bytes mutated in place break its CRCs, and the reader stops at
// libzip. Half the time the mutator unpacks the archive, mutates one entry (or its name) with
// libFuzzer's own mutator and packs it again (stored, valid CRCs), so that Document.xml,
// GuiDocument.xml, the BREP files and the colour lists inside are reached; the other half it
// mutates the raw bytes, for libzip and the archive checks.

struct Entry {
  std::string name, data;
};

bool unpack(const uint8_t* data, size_t size, std::vector<Entry>& out) {
  zip_error_t err;
  zip_error_init(&err);
  zip_source_t* src = zip_source_buffer_create(data, size, 0, &err);
  if (!src) return false;
  zip_t* za = zip_open_from_source(src, ZIP_RDONLY, &err);
  zip_error_fini(&err);
  if (!za) {
    zip_source_free(src);
    return false;
  }
  bool ok = true;
  const zip_int64_t n = zip_get_num_entries(za, 0);
  for (zip_int64_t i = 0; ok && i < n && i < 64; ++i) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(za, zip_uint64_t(i), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME) || !(st.valid & ZIP_STAT_SIZE) ||
        st.size > (zip_uint64_t(1) << 24)) {
      ok = false;
      break;
    }
    Entry e;
    e.name = st.name;
    e.data.resize(size_t(st.size));
    zip_file_t* f = zip_fopen_index(za, zip_uint64_t(i), 0);
    if (!f) {
      ok = false;
      break;
    }
    zip_uint64_t got = 0;
    while (got < st.size) {
      const zip_int64_t k = zip_fread(f, e.data.data() + got, st.size - got);
      if (k <= 0) break;
      got += zip_uint64_t(k);
    }
    zip_fclose(f);
    if (got != st.size) ok = false;
    out.push_back(std::move(e));
  }
  zip_discard(za);  // frees src
  return ok && !out.empty();
}

bool pack(const std::vector<Entry>& entries, std::string& out) {
  zip_error_t err;
  zip_error_init(&err);
  zip_source_t* buf = zip_source_buffer_create(nullptr, 0, 0, &err);
  if (!buf) return false;
  zip_source_keep(buf);
  zip_t* zw = zip_open_from_source(buf, ZIP_TRUNCATE, &err);
  zip_error_fini(&err);
  if (!zw) {
    zip_source_free(buf);
    zip_source_free(buf);
    return false;
  }
  for (const Entry& e : entries) {
    zip_source_t* s = zip_source_buffer(zw, e.data.data(), e.data.size(), 0);
    if (!s) continue;
    const zip_int64_t idx = zip_file_add(zw, e.name.c_str(), s, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8);
    if (idx < 0) {
      zip_source_free(s);
      continue;
    }
    zip_set_file_compression(zw, zip_uint64_t(idx), ZIP_CM_STORE, 0);
  }
  if (zip_close(zw) != 0) {
    zip_discard(zw);
    zip_source_free(buf);
    return false;
  }
  bool ok = zip_source_open(buf) == 0;
  if (ok) {
    zip_source_seek(buf, 0, SEEK_END);
    const zip_int64_t size = zip_source_tell(buf);
    zip_source_seek(buf, 0, SEEK_SET);
    ok = size >= 0;
    if (ok) {
      out.resize(size_t(size));
      ok = zip_source_read(buf, out.data(), zip_uint64_t(size)) == size;
    }
    zip_source_close(buf);
  }
  zip_source_free(buf);
  return ok;
}
#endif

}  // namespace

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t maxSize);

// Leak checking off by default (ASAN_OPTIONS=detect_leaks=1 turns it back on): OpenCASCADE fills
// global registries lazily (Interface_Static, IFSelect_Editor, TPrsStd_DriverTable) and
// LeakSanitizer reports them as direct leaks at exit, with stacks that end inside the
// uninstrumented OpenCASCADE, so a real leak per input could not be told from them. No leak per
// input was seen: the peak RSS of 200 and of 2000 runs of one seed is the same (quarantine off).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vtkObject::GlobalWarningDisplayOff();  // the reader's vtkErrorMacro: expected, and noisy
  const char* c = std::getenv("WF_FUZZ_CONTRACT");
  g_contract = !(c && std::strcmp(c, "0") == 0);
  const char* v = std::getenv("WF_FUZZ_VERBOSE");
  g_verbose = v && std::strcmp(v, "1") == 0;
  std::string tmpl = (std::filesystem::temp_directory_path() / "wf-cadfuzz-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) {
    std::perror("mkdtemp");
    std::exit(1);
  }
  g_dir = tmpl;
  g_path = g_dir + "/input" WF_FUZZ_EXTENSION;
  std::atexit(removeDir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  {
    std::ofstream f(g_path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(g_path.c_str());
  reader->SetNumberOfThreads(1);
  reader->SetMaximumTriangles(2000000);
  reader->SetNumberOfUIsoLines(2);
  reader->SetNumberOfVIsoLines(2);
  try {
    reader->Update();
  } catch (const Standard_Failure& f) {
    const char* m = f.GetMessageString();
    finding(std::string("OpenCASCADE exception escaped vtkWireFurCADReader::Update(): ") + f.DynamicType()->Name() + ": " +
            (m ? m : ""));
  } catch (const wfcad::CadError& e) {
    finding(std::string("wfcad::CadError escaped vtkWireFurCADReader::Update(): ") + e.what());
  } catch (const std::exception& e) {
    finding(std::string("exception escaped vtkWireFurCADReader::Update(): ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("unknown exception escaped vtkWireFurCADReader::Update()");
  }
  const std::string error = reader->GetErrorMessage();
  if (g_verbose) {
    if (error.empty())
      std::fprintf(stderr, "WF_FUZZ: %zu bytes: %d parts, %d faces (%d skipped), %lld triangles, %d edges%s%s\n", size,
                   reader->GetNumberOfParts(), reader->GetNumberOfFaces(), reader->GetNumberOfSkippedFaces(),
                   static_cast<long long>(reader->GetOutput(0)->GetNumberOfPolys()), reader->GetNumberOfEdges(),
                   reader->GetWarningMessage().empty() ? "" : "; ", reader->GetWarningMessage().c_str());
    else
      std::fprintf(stderr, "WF_FUZZ: %zu bytes: error: %s\n", size, error.c_str());
  }
  if (!g_contract) return 0;
  if (error.find_first_of("\r\n") != std::string::npos) finding("error message of more than one line: " + error);
  if (error.empty()) checkOutput(reader);
  return 0;
}

#if defined(WF_FUZZ_FORMAT_FCSTD)
extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t maxSize, unsigned int seed) {
  std::vector<Entry> entries;
  if ((seed & 1) == 0 || !unpack(data, size, entries)) return LLVMFuzzerMutate(data, size, maxSize);
  // Mostly the XML; the name of an entry now and then.
  size_t pick = (seed >> 1) % entries.size();
  for (size_t i = 0; i < entries.size(); ++i)
    if (((seed >> 8) & 3) != 0 && entries[i].name.size() > 4 && entries[i].name.compare(entries[i].name.size() - 4, 4, ".xml") == 0 &&
        ((seed >> 10) % entries.size()) <= i) {
      pick = i;
      break;
    }
  std::string& target = ((seed >> 16) % 16 == 0) ? entries[pick].name : entries[pick].data;
  const size_t room = maxSize > size ? maxSize - size : 0;
  const size_t cap = target.size() + std::min<size_t>(room, 4096);
  std::string mutated = target;
  mutated.resize(std::max<size_t>(cap, 1));
  const size_t n = LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(mutated.data()), target.size(), mutated.size());
  mutated.resize(n);
  target = mutated;
  std::string packed;
  if (!pack(entries, packed) || packed.size() > maxSize) return LLVMFuzzerMutate(data, size, maxSize);
  std::memcpy(data, packed.data(), packed.size());
  return packed.size();
}
#endif
