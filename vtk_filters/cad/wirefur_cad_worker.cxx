// wirefur-cad-worker: vtkWireFurCADReader's worker process (ReadInWorker; wf_cad_worker.h has
// the protocol). Not for people: it reads one CAD file in process, under a memory cap, and
// writes both outputs and the reader's figures for the parent, which reports crashes and hangs.
#include "vtkWireFurCADReader.h"
#include "wf_cad_worker.h"

#include "core/worker_process.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkXMLPolyDataWriter.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
  w->SetHeaderTypeToUInt64();  // (an array past 4 GiB)
  return w->Write() == 1;
}

// Written whole, then renamed: the parent never reads half a file.
bool writeSmall(const std::string& path, const std::string& text)
{
  const std::string part = path + ".part";
  FILE* f = std::fopen(part.c_str(), "w");
  if (!f)
    return false;
  const bool ok = std::fputs(text.c_str(), f) >= 0;
  return (std::fclose(f) == 0) && ok && std::rename(part.c_str(), path.c_str()) == 0;
}

int progressFile = -1;

void onProgress(vtkObject*, unsigned long, void*, void* data)
{
  const double p = *static_cast<double*>(data);
  if (progressFile >= 0)
    [[maybe_unused]] const ssize_t n = pwrite(progressFile, &p, sizeof p, 0);
}

bool integer(const char* text, long long& value)
{
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(text, &end, 10);
  return errno == 0 && end != text && *end == '\0';
}

} // namespace

int main(int argc, char** argv)
{
  double linear = 0, angular = 0, feature = 0;
  long long uIsos = 0, vIsos = 0, maxTriangles = 0, threads = 0;
  if (argc != 1 + wfcad::kWorkerArguments || !wf::parseWorkerNumber(argv[5], linear) ||
    !wf::parseWorkerNumber(argv[7], angular) || !integer(argv[8], uIsos) || !integer(argv[9], vIsos) ||
    !integer(argv[10], maxTriangles) || !wf::parseWorkerNumber(argv[11], feature) || !integer(argv[12], threads))
  {
    std::fprintf(stderr, "%s is vtkWireFurCADReader's worker process, not a command (or another version's)\n",
      wfcad::kWorkerName);
    return wf::kWorkerExitUsage;
  }
  wf::becomeWorker(argv[3], argv[4]);
  const std::string folder = argv[2];
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(argv[1]);
  reader->SetLinearDeflection(linear);
  reader->SetRelativeDeflection(std::string(argv[6]) == "1");
  reader->SetAngularDeflection(angular);
  reader->SetNumberOfUIsoLines(int(uIsos));
  reader->SetNumberOfVIsoLines(int(vIsos));
  reader->SetMaximumTriangles(vtkIdType(maxTriangles));
  reader->SetFeatureAngle(feature);
  reader->SetNumberOfThreads(int(threads));
  progressFile = open((folder + "/" + wfcad::kWorkerProgressFile).c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  vtkNew<vtkCallbackCommand> progress;
  progress->SetCallback(onProgress);
  reader->AddObserver(vtkCommand::ProgressEvent, progress);
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
  const int status = reader->GetErrorMessage().empty() ? 0 : 2;
  if (!write(faces, folder + "/faces.vtp") || !write(reader->GetOutput(1), folder + "/edges.vtp") ||
    !writeSmall(folder + "/" + wfcad::kWorkerDoneFile, std::to_string(status)))
  {
    std::fprintf(stderr, "cannot write the result under %s: %s\n", folder.c_str(), std::strerror(errno));
    wf::endWorker(wf::kWorkerExitWriteFailed);
  }
  wf::endWorker(status);
}
