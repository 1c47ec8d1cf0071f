/**
 * @class   vtkPVWireFurRenderView
 * @brief   ParaView's render view with lines drawn through WireFur's A-buffer
 *
 * A vtkPVRenderView whose geometry pass (vtkPVSynchronizedRenderer::SetRenderPass, inside
 * ParaView's camera pass) is a vtkWireFurRenderPass with VTK's render steps as its delegate. As every render starts (the pass's StartEvent, whatever path renders: a still
 * render, an interactive one, a screenshot) the view marks for the A-buffer every actor whose data has
 * lines (a vtkPolyData, or the vtkPolyData leaves of the composite data ParaView's
 * representations hand their mappers): wire-frames, edges, fur and shaded polylines are drawn
 * as antialiased cylinders in depth order, composited over the surfaces ParaView draws with
 * OpenGL (hidden where a surface is nearer). Actors without lines are left to ParaView.
 *
 * The error estimate is shown: a line of text in the corner (ShowErrorEstimate, default on)
 * with the A-buffer's time, its shading error bound and its coverage quantisation, the
 * figures of the frame it is drawn on; the same figures are information properties.
 *
 * Distributed (pvbatch or pvserver under mpirun, IceT compositing): the pass renders sort-first
 * bands of rows over every rank's surfaces with every rank's lines (vtkWireFurRenderPass::
 * SetController), the picture of one process; the view turns on IceT's RenderEmptyImages so
 * that every rank renders every frame, decides the marks over all ranks (an actor is drawn as
 * lines when some rank's piece has lines and none has polygons) and hands the pass the
 * background (docs/paraview.md).
 */
#ifndef vtkPVWireFurRenderView_h
#define vtkPVWireFurRenderView_h

#include "WireFurParaViewViewModule.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkPVRenderView.h"

class vtkCallbackCommand;
class vtkMultiProcessController;
class vtkProp3D;
class vtkTextActor;
class vtkWireFurRenderPass;

class WIREFURPARAVIEWVIEW_EXPORT vtkPVWireFurRenderView : public vtkPVRenderView
{
public:
  static vtkPVWireFurRenderView* New();
  vtkTypeMacro(vtkPVWireFurRenderView, vtkPVRenderView);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The pass's settings (vtkWireFurRenderPass): shading path 0 closed (default), 1 maps,
  /// 2 exact; fragments kept exactly per pixel; coverage mask 4x4, 8x4 (default) or 8x8.
  void SetShading(int shading);
  int GetShading();
  void SetBudget(int budget);
  int GetBudget();
  void SetMaskSize(int width, int height);
  ///@}

  ///@{
  /// Shows the last A-buffer render's time and error bounds in the lower left corner. Default on.
  void SetShowErrorEstimate(bool show);
  vtkGetMacro(ShowErrorEstimate, bool);
  ///@}

  ///@{
  /// The last render's figures (vtkWireFurRenderPass): the shading error bound (radiance), the
  /// coverage quantisation (1 / subpixels), seconds of the A-buffer alone and of the whole pass,
  /// fragments, and the number of actors drawn through the A-buffer. With pvserver and remote
  /// rendering, the client shows the server's figures (exchanged after each frame, below).
  double GetErrorEstimate();
  double GetCoverageError();
  double GetCoreSeconds();
  double GetPassSeconds();
  double GetFragments();
  int GetMarkedActors();
  ///@}

  vtkWireFurRenderPass* GetWireFurPass();

  /// Seconds the last frame exchanged between ranks (vtkWireFurRenderPass: gathering lines,
  /// compositing bands); 0 in one process.
  double GetGatherSeconds();
  double GetCompositeSeconds();

  /// Recorded (vtkPVRenderView keeps it private) for the distributed frames' background.
  void SetBackgroundColorMode(int mode) override;

protected:
  vtkPVWireFurRenderView();
  ~vtkPVWireFurRenderView() override;
  void Render(bool interactive, bool skip_rendering) override;

private:
  vtkPVWireFurRenderView(const vtkPVWireFurRenderView&) = delete;
  void operator=(const vtkPVWireFurRenderView&) = delete;
  static void OnPassEvent(vtkObject*, unsigned long event, void* self, void*);
  static void OnRendererEnd(vtkObject*, unsigned long event, void* self, void*);
  void MarkActors();
  void UpdateAnnotation();

  vtkNew<vtkWireFurRenderPass> Pass;
  vtkNew<vtkTextActor> Annotation;
  vtkNew<vtkCallbackCommand> PassObserver;
  vtkNew<vtkCallbackCommand> RendererObserver;
  // An invisible prop whose bounds are every rank's, widened by the lines' half width, shown
  // in distributed frames only: IceT reads back only the window area each rank's bounds
  // project to, and every rank's picture holds every rank's lines.
  vtkSmartPointer<vtkProp3D> SharedBounds;
  void ShareBounds(vtkMultiProcessController* controller);
  bool ShowErrorEstimate = true;
  // The figures shown and reported: this process's pass's, or, on a client whose frame the
  // server rendered, the server's. The order of kFigureNames in the .cxx.
  enum Figure
  {
    MarkedProps,
    CoreSeconds,
    Fragments,
    ErrorEstimate,
    CoverageError,
    PassSeconds,
    GatherSeconds,
    CompositeSeconds,
    FigureCount
  };
  double Figures[FigureCount] = {};
  int ColorMode = DEFAULT;       // BackgroundColorMode
  bool ExchangeFigures = false;  // in this frame (decided in Render, the same on every process)
};

#endif
