// The protocol between vtkWireFurCADReader (ReadInWorker on) and its worker process,
// wirefur-cad-worker (wirefur_cad_worker.cxx), which lives beside the module's library:
//   wirefur-cad-worker FILE FOLDER PARENT TIMEOUT LINEAR RELATIVE ANGULAR UISOS VISOS MAXTRIANGLES
//                      FEATURE THREADS
// (numbers as wf::workerNumber writes them: the same in every locale; PARENT the parent's pid,
// TIMEOUT its time limit, for wf::becomeWorker) reads FILE with the reader in process and writes
// FOLDER/faces.vtp and FOLDER/edges.vtp (VTK XML, raw binary: every value exact), the faces'
// field data carrying the reader's figures and messages in the two arrays below, which the
// parent takes off again. Meanwhile it rewrites its progress (one double, 0 to 1) in
// FOLDER/progress. Last it writes FOLDER/done holding its exit status: 0, read; 2, the reader
// failed with the message in the arrays. Without that marker there is no whole result: a crash
// (or a status of wf::kWorkerExit*: out of memory, a failed write, wrong arguments).
#pragma once

namespace wfcad {

constexpr const char* kWorkerName = "wirefur-cad-worker";
constexpr const char* kWorkerFigures = "WireFurCADWorkerFigures";   // vtkDoubleArray, kFigureCount values
constexpr const char* kWorkerMessages = "WireFurCADWorkerMessages"; // vtkStringArray: error, warning
constexpr const char* kWorkerProgressFile = "progress";
constexpr const char* kWorkerDoneFile = "done";
constexpr int kWorkerArguments = 12;

// The order of the figures.
enum WorkerFigure {
  kFaces, kMeshedFaces, kSkippedFaces, kEdges, kEdgesOfClass0,  // then 6 more classes
  kAppliedDeflection = kEdgesOfClass0 + 7, kModelSize, kReadSeconds, kMeshSeconds, kFigureCount
};

} // namespace wfcad
