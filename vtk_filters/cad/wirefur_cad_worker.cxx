// wirefur-cad-worker: vtkWireFurCADReader's worker process (ReadInWorker; wf_cad_worker.h has
// the protocol). Not for people: it reads one CAD file in process, under a memory cap, and
// writes both outputs and the reader's figures for the parent, which reports crashes and hangs.
#include "vtkWireFurCADReader.h"
#include "wf_cad_worker.h"

#include "core/worker_process.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{

bool write(vtkPolyData* data, const std::string& path)
{
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetInputData(data);
  w->SetFileName(path.c_str());
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();
  w->SetCompressorTypeToNone();
  return w->Write() == 1;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 1 + wfcad::kWorkerArguments)
  {
    std::fprintf(stderr, "%s is vtkWireFurCADReader's worker process, not a command\n", wfcad::kWorkerName);
    return 1;
  }
  wf::capWorkerMemory();  // (OpenCASCADE can be talked into allocating without end)
  const std::string folder = argv[2];
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(argv[1]);
  reader->SetLinearDeflection(std::strtod(argv[3], nullptr));
  reader->SetRelativeDeflection(std::string(argv[4]) == "1");
  reader->SetAngularDeflection(std::strtod(argv[5], nullptr));
  reader->SetNumberOfUIsoLines(std::atoi(argv[6]));
  reader->SetNumberOfVIsoLines(std::atoi(argv[7]));
  reader->SetMaximumTriangles(vtkIdType(std::strtoll(argv[8], nullptr, 10)));
  reader->SetFeatureAngle(std::strtod(argv[9], nullptr));
  reader->SetNumberOfThreads(std::atoi(argv[10]));
  reader->Update();

  vtkNew<vtkPolyData> faces;
  faces->ShallowCopy(reader->GetOutput(0));
  vtkNew<vtkFieldData> field;
  field->ShallowCopy(faces->GetFieldData());
  vtkNew<vtkDoubleArray> figures;
  figures->SetName(wfcad::kWorkerFigures);
  figures->SetNumberOfValues(wfcad::kFigureCount);
  figures->SetValue(wfcad::kFaces, reader->GetNumberOfFaces());
  figures->SetValue(wfcad::kMeshedFaces, reader->GetNumberOfMeshedFaces());
  figures->SetValue(wfcad::kSkippedFaces, reader->GetNumberOfSkippedFaces());
  figures->SetValue(wfcad::kEdges, reader->GetNumberOfEdges());
  for (int c = 0; c < 7; ++c)
    figures->SetValue(wfcad::kEdgesOfClass0 + c, reader->GetNumberOfEdgesOfClass(c));
  figures->SetValue(wfcad::kAppliedDeflection, reader->GetAppliedLinearDeflection());
  figures->SetValue(wfcad::kModelSize, reader->GetModelSize());
  figures->SetValue(wfcad::kReadSeconds, reader->GetReadSeconds());
  figures->SetValue(wfcad::kMeshSeconds, reader->GetMeshSeconds());
  field->AddArray(figures);
  vtkNew<vtkStringArray> messages;
  messages->SetName(wfcad::kWorkerMessages);
  messages->InsertNextValue(reader->GetErrorMessage());
  messages->InsertNextValue(reader->GetWarningMessage());
  field->AddArray(messages);
  faces->SetFieldData(field);
  if (!write(faces, folder + "/faces.vtp") || !write(reader->GetOutput(1), folder + "/edges.vtp"))
    return 1;
  return reader->GetErrorMessage().empty() ? 0 : 2;
}
