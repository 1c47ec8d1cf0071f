#include "vtkPVWireFurRenderView.h"

#include "vtkActor.h"
#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkBoundingBox.h"
#include "vtkCamera.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkInformation.h"
#include "vtkMapper.h"
#include "vtkMath.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPVRenderViewSettings.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkProcessModule.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkProp3D.h"
#include "vtkPropCollection.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWireFurRenderPass.h"

#include <cstdio>
#include <cmath>
#include <cstring>
#include <vector>

vtkStandardNewMacro(vtkPVWireFurRenderView);

namespace
{
// A prop that draws nothing and has the bounds it is given (ShareBounds).
class BoundsOnlyProp : public vtkProp3D
{
public:
  static BoundsOnlyProp* New();
  vtkTypeMacro(BoundsOnlyProp, vtkProp3D);
  double* GetBounds() override { return this->Box; }
  void SetBox(const double b[6]) { std::copy(b, b + 6, this->Box); }

private:
  double Box[6] = { 0, 0, 0, 0, 0, 0 };
};
vtkStandardNewMacro(BoundsOnlyProp);

// The local half of drawnAsWire: 0 not a candidate, 1 a candidate whose data has no polygons
// and no lines (an empty piece), 2 lines and no polygons, 3 polygons or strips somewhere.
// True when the actor should be drawn through the A-buffer: a polygonal mapper (not glyphs, not
// point Gaussians) whose data (a vtkPolyData, or every non-empty vtkPolyData leaf of a
// composite) has lines and no polygons or strips, drawn as lines or a surface (not as points),
// and the actor counts in the bounds (ParaView's centre axes and widgets do not). The data is the
// output of the mapper's input algorithm (ParaView's representations have delivered it before
// the render; the mapper itself has not run yet).
int wireClass(vtkActor* actor)
{
  vtkMapper* mapper = actor->GetMapper();
  if (!mapper || !mapper->IsA("vtkPolyDataMapper") || mapper->IsA("vtkPointGaussianMapper") ||
    !actor->GetUseBounds() || actor->GetProperty()->GetRepresentation() == VTK_POINTS)
  {
    return 0;
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
    return !linesOnly(pd, lines) ? 3 : lines ? 2 : 1;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    auto it = vtk::TakeSmartPointer(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* leaf = vtkPolyData::SafeDownCast(it->GetCurrentDataObject()); leaf && !linesOnly(leaf, lines))
      {
        return 3;
      }
    }
    return lines ? 2 : 1;
  }
  return data ? 3 : 1;  // another data type: not ours; none (yet): an empty piece
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
  // After the frame's image has gone from the server to the client (ParaView's synchronizers
  // observe the same event at priority 0) and before the annotation's renderer draws.
  this->RendererObserver->SetCallback(&vtkPVWireFurRenderView::OnRendererEnd);
  this->RendererObserver->SetClientData(this);
  this->GetRenderer()->AddObserver(vtkCommand::EndEvent, this->RendererObserver, -1.0f);
  this->SharedBounds = vtkSmartPointer<BoundsOnlyProp>::New();
  this->SharedBounds->VisibilityOff();
  this->SharedBounds->PickableOff();
  this->SharedBounds->DragableOff();
  this->GetRenderer()->AddActor(this->SharedBounds);

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
  this->GetRenderer()->RemoveObserver(this->RendererObserver);
  this->GetRenderer()->RemoveActor(this->SharedBounds);
}

void vtkPVWireFurRenderView::ShareBounds(vtkMultiProcessController* controller)
{
  this->SharedBounds->VisibilityOff();
  if (!controller)
  {
    return;
  }
  vtkRenderer* renderer = this->GetRenderer();
  double local[6];
  renderer->ComputeVisiblePropBounds(local);
  // Every rank's bounds (as -min, max) and the widest line: the half width in world units
  // (WIREFUR_WIRE_THICKNESS) and in pixels (LineWidth), of every actor that may be drawn as lines.
  double mine[8], all[8];
  const bool valid = vtkMath::AreBoundsInitialized(local) && local[0] <= local[1];
  for (int k = 0; k < 3; ++k)
  {
    mine[k] = valid ? -local[2 * k] : -VTK_DOUBLE_MAX;
    mine[3 + k] = valid ? local[2 * k + 1] : -VTK_DOUBLE_MAX;
  }
  mine[6] = mine[7] = 0.0;
  vtkCollectionSimpleIterator it;
  vtkPropCollection* props = renderer->GetViewProps();
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    auto* actor = vtkActor::SafeDownCast(prop);
    if (!actor || !actor->GetVisibility())
    {
      continue;
    }
    vtkInformation* keys = actor->GetPropertyKeys();
    if (keys && keys->Has(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS()))
    {
      mine[6] = std::max(mine[6], 0.5 * keys->Get(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS()));
    }
    mine[7] = std::max(mine[7], 0.5 * actor->GetProperty()->GetLineWidth());
  }
  if (!controller->AllReduce(mine, all, 8, vtkCommunicator::MAX_OP) || !(all[0] > -VTK_DOUBLE_MAX))
  {
    return;
  }
  double box[6];
  for (int k = 0; k < 3; ++k)
  {
    box[2 * k] = -all[k];
    box[2 * k + 1] = all[3 + k];
  }
  // The width of a pixel at the box's farthest corner (the widest a pixel is over the box),
  // times the half width in pixels and one pixel of antialiasing.
  vtkCamera* camera = renderer->GetActiveCamera();
  const int height = std::max(1, renderer->GetSize()[1]);
  double pixel = 0.0;
  if (camera->GetParallelProjection())
  {
    pixel = 2.0 * camera->GetParallelScale() / height;
  }
  else
  {
    double eye[3], far = 0.0;
    camera->GetPosition(eye);
    for (int c = 0; c < 8; ++c)
    {
      const double p[3] = { box[(c & 1) ? 1 : 0], box[(c & 2) ? 3 : 2], box[(c & 4) ? 5 : 4] };
      far = std::max(far, std::sqrt(vtkMath::Distance2BetweenPoints(p, eye)));
    }
    pixel = 2.0 * far * std::tan(vtkMath::RadiansFromDegrees(0.5 * camera->GetViewAngle())) / height;
  }
  const double margin = all[6] + (all[7] + 1.0) * pixel;
  if (!std::isfinite(margin))
  {
    return;
  }
  for (int k = 0; k < 3; ++k)
  {
    box[2 * k] -= margin;
    box[2 * k + 1] += margin;
  }
  static_cast<BoundsOnlyProp*>(this->SharedBounds.Get())->SetBox(box);
  this->SharedBounds->VisibilityOn();
}

void vtkPVWireFurRenderView::MarkActors()
{
  vtkRenderer* renderer = this->GetRenderer();
  vtkPropCollection* props = renderer->GetViewProps();
  std::vector<vtkActor*> actors;
  std::vector<int> classes;
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    if (auto* actor = vtkActor::SafeDownCast(prop))
    {
      actors.push_back(actor);
      classes.push_back(wireClass(actor));
    }
  }
  // Distributed: the same decision on every rank, from every rank's piece (a rank whose piece
  // is empty draws the others' lines). The ranks hold the same actors in the same order (the
  // representations are created on all of them); when they do not, each decides alone and the
  // pass falls back to drawing each rank's own lines.
  if (vtkMultiProcessController* c = this->Pass->GetControllerActive() ? this->Pass->GetController() : nullptr)
  {
    const int n = int(classes.size());
    int range[2] = { n, -n }, all[2] = { 0, 0 };
    if (c->AllReduce(range, all, 2, vtkCommunicator::MAX_OP) && all[0] == -all[1] && n > 0)
    {
      std::vector<int> joined(classes.size());
      if (c->AllReduce(classes.data(), joined.data(), n, vtkCommunicator::MAX_OP))
      {
        classes = joined;
      }
    }
  }
  for (size_t i = 0; i < actors.size(); ++i)
  {
    const bool lines = classes[i] == 2;
    if (lines != vtkWireFurRenderPass::IsMarked(actors[i]))
    {
      vtkWireFurRenderPass::Mark(actors[i], lines);
    }
  }
}

void vtkPVWireFurRenderView::Render(bool interactive, bool skip_rendering)
{
  // Distributed rendering through IceT: every rank must enter the pass every frame (it
  // exchanges), so IceT must not skip ranks with nothing visible; the background is read
  // here, before IceT clears to transparent black for the compositing.
  vtkMultiProcessController* global = vtkMultiProcessController::GetGlobalController();
  // Not with ordered compositing (translucent surfaces, volumes: IceT blends in rank order, and
  // the bands keep one rank's pixel), tile displays or CAVE (IceT's own projections per tile):
  // there each rank draws its own lines, as before (docs/paraview.md).
  const bool distributed = global && global->GetNumberOfProcesses() > 1 &&
    (interactive && this->GetUseLODForInteractiveRender() ? this->GetUseDistributedRenderingForLODRender()
                                                          : this->GetUseDistributedRenderingForRender()) &&
    !this->GetUseOrderedCompositing() && !this->InTileDisplayMode() && !this->InCaveDisplayMode();
  // The controller stays set between frames (changing it rebuilds the pass's scene); it is
  // active only inside this collective render (a redraw of one rank's window is not one).
  this->Pass->SetController(distributed ? global : nullptr);
  this->Pass->SetControllerActive(distributed);
  this->ShareBounds(distributed ? global : nullptr);
  // FXAA (on by default in ParaView, applied to the composited image under MPI) would blur the
  // A-buffer's exact coverage: off in this view.
  this->UseFXAA = false;
  if (distributed)
  {
    this->RenderEmptyImages = true;
    // This frame's background, as vtkPVRenderView::UpdateBackground will set it (the renderer's
    // still holds the last frame's: a transparent screenshot renders over white, then black).
    int mode = this->ColorMode;
    double b1[3], b2[3];
    this->GetBackground(b1);
    this->GetBackground2(b2);
    if (this->GetUseRenderViewSettingsForBackground())
    {
      vtkPVRenderViewSettings* settings = vtkPVRenderViewSettings::GetInstance();
      mode = settings->GetBackgroundColorMode();
      settings->GetBackgroundColor(b1);
      settings->GetBackground2Color(b2);
    }
    this->Pass->SetBackground(b1);
    this->Pass->SetBackground2(b2);
    this->Pass->SetGradientBackground(mode == GRADIENT);
    this->Pass->SetBackgroundKnown(mode == DEFAULT || mode == GRADIENT);
  }
  // IceT's image reduction renders the global view into a corner of the window through its own
  // projection, which the A-buffer's camera does not follow: full size while distributed.
  const int still = this->StillRenderImageReductionFactor;
  const int moving = this->InteractiveRenderImageReductionFactor;
  if (distributed)
  {
    this->StillRenderImageReductionFactor = this->InteractiveRenderImageReductionFactor = 1;
  }
  // The client of a pvserver that renders remotely draws no lines itself (the lines are in the
  // server's image): its annotation and figures must be the server's. Every process that
  // renders this frame (the client and every server rank, or every pvbatch rank) exchanges
  // them once the image is across, on the same condition ParaView uses to render remotely.
  const bool remote = (interactive && this->GetUseLODForInteractiveRender()
      ? this->GetUseDistributedRenderingForLODRender()
      : this->GetUseDistributedRenderingForRender());
  this->ExchangeFigures = remote && !skip_rendering && !this->GetMakingSelection() &&
    !this->InTileDisplayMode() && !this->InCaveDisplayMode();
  this->Superclass::Render(interactive, skip_rendering);
  this->Pass->SetControllerActive(false);
  this->ExchangeFigures = false;
  this->StillRenderImageReductionFactor = still;
  this->InteractiveRenderImageReductionFactor = moving;
}

void vtkPVWireFurRenderView::SetBackgroundColorMode(int mode)
{
  this->ColorMode = mode;
  this->Superclass::SetBackgroundColorMode(mode);
}

void vtkPVWireFurRenderView::OnRendererEnd(vtkObject*, unsigned long, void* self, void*)
{
  auto* view = static_cast<vtkPVWireFurRenderView*>(self);
  if (!view->ExchangeFigures)
  {
    return;
  }
  view->ExchangeFigures = false;  // (once a frame)
  // A maximum of the figures' bits over every process (vtkPVView::AllReduce: the ranks, then
  // the server's root with the client): the client contributes zeros, the server's ranks their
  // figures, which the distributed pass has already made the same on every rank; non-negative
  // doubles order as their bits do.
  const bool client = vtkProcessModule::GetProcessType() == vtkProcessModule::PROCESS_CLIENT;
  for (double& figure : view->Figures)
  {
    vtkTypeUInt64 bits = 0, result = 0;
    if (!client && figure > 0.0)
    {
      std::memcpy(&bits, &figure, sizeof bits);
    }
    view->AllReduce(bits, result, vtkCommunicator::MAX_OP);
    std::memcpy(&figure, &result, sizeof figure);
  }
  view->UpdateAnnotation();
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
    vtkWireFurRenderPass* p = view->Pass;
    double* f = view->Figures;
    f[MarkedProps] = p->GetLastMarkedProps();
    f[CoreSeconds] = p->GetLastCoreSeconds();
    f[Fragments] = static_cast<double>(p->GetLastFragments());
    f[ErrorEstimate] = p->GetLastErrorEstimate();
    f[CoverageError] = p->GetLastCoverageError();
    f[PassSeconds] = p->GetLastRenderSeconds();
    f[GatherSeconds] = p->GetLastGatherSeconds();
    f[CompositeSeconds] = p->GetLastCompositeSeconds();
    view->UpdateAnnotation();
  }
}

void vtkPVWireFurRenderView::UpdateAnnotation()
{
  if (!this->ShowErrorEstimate)
  {
    return;
  }
  const double* f = this->Figures;
  char line[256];
  if (f[MarkedProps] == 0)
  {
    std::snprintf(line, sizeof line, "WireFur: no lines to draw");
  }
  else
  {
    std::snprintf(line, sizeof line,
      "WireFur %.1f ms, %lld fragments, shading error <= %.1e, coverage 1/%d", 1e3 * f[CoreSeconds],
      static_cast<long long>(f[Fragments]), f[ErrorEstimate],
      f[CoverageError] > 0 ? static_cast<int>(1.0 / f[CoverageError] + 0.5) : 0);
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
  return this->Figures[ErrorEstimate];
}
double vtkPVWireFurRenderView::GetCoverageError()
{
  return this->Figures[CoverageError];
}
double vtkPVWireFurRenderView::GetCoreSeconds()
{
  return this->Figures[CoreSeconds];
}
double vtkPVWireFurRenderView::GetPassSeconds()
{
  return this->Figures[PassSeconds];
}
double vtkPVWireFurRenderView::GetFragments()
{
  return this->Figures[Fragments];
}
double vtkPVWireFurRenderView::GetGatherSeconds()
{
  return this->Figures[GatherSeconds];
}
double vtkPVWireFurRenderView::GetCompositeSeconds()
{
  return this->Figures[CompositeSeconds];
}
int vtkPVWireFurRenderView::GetMarkedActors()
{
  return static_cast<int>(this->Figures[MarkedProps]);
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
