// The protocol between vtkWireFurCADReader (ReadInWorker on) and its worker process,
// wirefur-cad-worker (wirefur_cad_worker.cxx), which lives beside the module's library:
//   wirefur-cad-worker FILE FOLDER LINEAR RELATIVE ANGULAR UISOS VISOS MAXTRIANGLES FEATURE THREADS
// reads FILE with the reader in process and writes FOLDER/faces.vtp and FOLDER/edges.vtp (VTK
// XML, raw binary: every value exact), the faces' field data carrying the reader's figures and
// messages in the two arrays below, which the parent takes off again. Exit status 0: read; 2:
// the reader failed with the message in the arrays; anything else, or a signal: a crash.
#pragma once

namespace wfcad {

constexpr const char* kWorkerName = "wirefur-cad-worker";
constexpr const char* kWorkerFigures = "WireFurCADWorkerFigures";   // vtkDoubleArray, kFigureCount values
constexpr const char* kWorkerMessages = "WireFurCADWorkerMessages"; // vtkStringArray: error, warning
constexpr int kWorkerArguments = 10;

// The order of the figures.
enum WorkerFigure {
  kFaces, kMeshedFaces, kSkippedFaces, kEdges, kEdgesOfClass0,  // then 6 more classes
  kAppliedDeflection = kEdgesOfClass0 + 7, kModelSize, kReadSeconds, kMeshSeconds, kFigureCount
};

} // namespace wfcad
