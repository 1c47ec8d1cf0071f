#include "vtkPVWireFurRenderView.h"

#include "vtkActor.h"
#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkMapper.h"
#include "vtkObjectFactory.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkPropCollection.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWireFurRenderPass.h"

#include <cstdio>

vtkStandardNewMacro(vtkPVWireFurRenderView);

namespace
{
// True when the actor should be drawn through the A-buffer: a polygonal mapper (not glyphs, not
// point Gaussians) whose data (a vtkPolyData, or every non-empty vtkPolyData leaf of a
// composite) has lines and no polygons or strips, drawn as lines or a surface (not as points),
// and the actor counts in the bounds (ParaView's centre axes and widgets do not). The data is the
// output of the mapper's input algorithm (ParaView's representations have delivered it before
// the render; the mapper itself has not run yet).
bool drawnAsWire(vtkActor* actor)
{
  vtkMapper* mapper = actor->GetMapper();
  if (!mapper || !mapper->IsA("vtkPolyDataMapper") || mapper->IsA("vtkPointGaussianMapper") ||
    !actor->GetUseBounds() || actor->GetProperty()->GetRepresentation() == VTK_POINTS)
  {
    return false;
  }
  vtkDataObject* data = nullptr;
  if (mapper->GetNumberOfInputConnections(0) > 0)
  {
    vtkAlgorithmOutput* port = mapper->GetInputConnection(0, 0);
    data = port->GetProducer()->GetOutputDataObject(port->GetIndex());
  }
  else
  {
    data = mapper->GetInputDataObject(0, 0);
  }
  auto linesOnly = [](vtkPolyData* pd, bool& lines) {
    if (pd->GetNumberOfPolys() > 0 || pd->GetNumberOfStrips() > 0)
    {
      return false;
    }
    lines = lines || pd->GetNumberOfLines() > 0;
    return true;
  };
  bool lines = false;
  if (auto* pd = vtkPolyData::SafeDownCast(data))
  {
    return linesOnly(pd, lines) && lines;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    auto it = vtk::TakeSmartPointer(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* leaf = vtkPolyData::SafeDownCast(it->GetCurrentDataObject()); leaf && !linesOnly(leaf, lines))
      {
        return false;
      }
    }
  }
  return lines;
}
}

vtkPVWireFurRenderView::vtkPVWireFurRenderView()
{
  // The pass's own delegate stays (a vtkRenderStepsPass: it honours the render state's prop
  // list, which is how the pass keeps its marked actors from OpenGL; ParaView's vtkPVDefaultPass
  // renders every prop of the renderer and would draw the lines a second time).
  this->SynchronizedRenderers->SetRenderPass(this->Pass);

  this->PassObserver->SetCallback(&vtkPVWireFurRenderView::OnPassEvent);
  this->PassObserver->SetClientData(this);
  this->Pass->AddObserver(vtkCommand::StartEvent, this->PassObserver);
  this->Pass->AddObserver(vtkCommand::EndEvent, this->PassObserver);

  vtkTextProperty* text = this->Annotation->GetTextProperty();
  text->SetFontSize(11);
  text->SetColor(1.0, 1.0, 1.0);
  text->SetShadow(1);
  text->SetBackgroundColor(0.0, 0.0, 0.0);
  text->SetBackgroundOpacity(0.45);
  this->Annotation->SetPosition(8, 8);
  this->Annotation->SetInput("");
  this->GetNonCompositedRenderer()->AddActor2D(this->Annotation);
}

vtkPVWireFurRenderView::~vtkPVWireFurRenderView()
{
  this->Pass->RemoveObserver(this->PassObserver);
}

void vtkPVWireFurRenderView::MarkActors()
{
  vtkRenderer* renderer = this->GetRenderer();
  vtkPropCollection* props = renderer->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    if (auto* actor = vtkActor::SafeDownCast(prop))
    {
      const bool lines = drawnAsWire(actor);
      if (lines != vtkWireFurRenderPass::IsMarked(actor))
      {
        vtkWireFurRenderPass::Mark(actor, lines);
      }
    }
  }
}

void vtkPVWireFurRenderView::OnPassEvent(vtkObject*, unsigned long event, void* self, void*)
{
  auto* view = static_cast<vtkPVWireFurRenderView*>(self);
  if (event == vtkCommand::StartEvent)
  {
    view->MarkActors();
  }
  else
  {
    view->UpdateAnnotation();
  }
}

void vtkPVWireFurRenderView::UpdateAnnotation()
{
  if (!this->ShowErrorEstimate)
  {
    return;
  }
  vtkWireFurRenderPass* p = this->Pass;
  char line[256];
  if (p->GetLastMarkedProps() == 0)
  {
    std::snprintf(line, sizeof line, "WireFur: no lines to draw");
  }
  else
  {
    std::snprintf(line, sizeof line,
      "WireFur %.1f ms, %lld fragments, shading error <= %.1e, coverage 1/%d",
      1e3 * p->GetLastCoreSeconds(), static_cast<long long>(p->GetLastFragments()),
      p->GetLastErrorEstimate(),
      p->GetLastCoverageError() > 0 ? static_cast<int>(1.0 / p->GetLastCoverageError() + 0.5) : 0);
  }
  this->Annotation->SetInput(line);
}

void vtkPVWireFurRenderView::SetShading(int shading)
{
  this->Pass->SetShading(shading);
  this->Modified();
}
int vtkPVWireFurRenderView::GetShading()
{
  return this->Pass->GetShading();
}
void vtkPVWireFurRenderView::SetBudget(int budget)
{
  this->Pass->SetBudget(budget);
  this->Modified();
}
int vtkPVWireFurRenderView::GetBudget()
{
  return this->Pass->GetBudget();
}
void vtkPVWireFurRenderView::SetMaskSize(int width, int height)
{
  this->Pass->SetMaskSize(width, height);
  this->Modified();
}
void vtkPVWireFurRenderView::SetShowErrorEstimate(bool show)
{
  if (show != this->ShowErrorEstimate)
  {
    this->ShowErrorEstimate = show;
    this->Annotation->SetVisibility(show);
    this->Modified();
  }
}
double vtkPVWireFurRenderView::GetErrorEstimate()
{
  return this->Pass->GetLastErrorEstimate();
}
double vtkPVWireFurRenderView::GetCoverageError()
{
  return this->Pass->GetLastCoverageError();
}
double vtkPVWireFurRenderView::GetCoreSeconds()
{
  return this->Pass->GetLastCoreSeconds();
}
double vtkPVWireFurRenderView::GetPassSeconds()
{
  return this->Pass->GetLastRenderSeconds();
}
double vtkPVWireFurRenderView::GetFragments()
{
  return static_cast<double>(this->Pass->GetLastFragments());
}
int vtkPVWireFurRenderView::GetMarkedActors()
{
  return this->Pass->GetLastMarkedProps();
}
vtkWireFurRenderPass* vtkPVWireFurRenderView::GetWireFurPass()
{
  return this->Pass;
}

void vtkPVWireFurRenderView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ShowErrorEstimate: " << this->ShowErrorEstimate << "\n";
}
