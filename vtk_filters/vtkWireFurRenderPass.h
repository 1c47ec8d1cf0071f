/**
 * @class   vtkWireFurRenderPass
 * @brief   renders the props marked for it through WireFur's A-buffer over what the delegate drew
 *
 * A vtkRenderPass for vtkOpenGLRenderer::SetPass. The delegate pass (default: a
 * vtkRenderStepsPass, VTK's ordinary steps: camera, lights, opaque, translucent, volumes,
 * overlay) draws every prop that is NOT marked, with OpenGL. The marked vtkActors are then
 * rendered by the core's A-buffer renderer (Miller 1988, section 3: exact coverage, resolved
 * in depth order, wires shaded as cylinders at every fragment's own view vector, or through the
 * paper's pseudo-reflectance map with SetShadingToMaps) and composited, antialiased,
 * over the delegate's colour, hidden where the delegate's depth buffer holds a nearer surface.
 *
 * Marking: `vtkWireFurRenderPass::Mark(prop)` sets the integer key WIREFUR() to 1 in the prop's
 * PropertyKeys. Marked props are hidden from the delegate by giving it a render state whose
 * prop array leaves them out (no prop is modified, so no MTime changes and no re-render of
 * anything else). With no marked prop in the frame the delegate gets the renderer's state
 * unchanged: nothing extra is done.
 *
 * Conversion of a marked vtkActor (its mapper's vtkPolyData input): lines and polylines become
 * a wire, shaded by default (WIREFUR_WIRE_STYLE(): 0 shaded, 1 plain, 2 depth-cued), of
 * diameter WIREFUR_WIRE_THICKNESS() in world units when that key is set, else the property's
 * LineWidth in pixels; polygons and strips become a triangle surface with the point normals
 * and texture coordinates when present. Material: diffuse colour x Diffuse, specular colour x
 * Specular, SpecularPower, Opacity (colours taken as linear). Mapped 8-bit point colours
 * (sRGB-encoded) multiply. The actor's matrix is applied. Lights: the renderer's switched-on
 * vtkLights as directional lights (headlight, camera light, scene light; positional lights
 * from their position towards their focal point). Camera: the active vtkCamera for the
 * renderer's viewport (view angle or parallel scale, clipping range).
 *
 * Depth: the delegate's depth buffer is read back, turned into view depth with the camera's
 * projection, and given to the core as an opaque depth (wf::RenderOptions::opaqueDepth): a
 * fragment counts only where it is nearer than the OpenGL surface at its pixel.
 * Colour: out = core + (1 - core alpha) x delegate colour, in linear light (the 8-bit colour
 * buffer is taken as sRGB-encoded, as WireFur writes its PNGs), drawn back over the viewport
 * with a full-viewport quad; the depth buffer is left as the delegate drew it. 2-D props
 * (vtkActor2D: text, scalar bars) are drawn after the composite so they stay on top.
 *
 * The conversion of the marked actors is cached and redone only for actors whose MTime (or
 * their property's, keys', mapper's or input's) changed. The core's shading tables are built
 * by each core render (only those the scene needs).
 *
 * Known limits: translucent OpenGL geometry does not hide marked props (only the opaque depth
 * is used); marked props other than vtkActor with a vtkPolyData input are drawn by nobody.
 *
 * Defaults: MaskWidth x MaskHeight = 8 x 4, Budget = 64, Threads = 0 (all cores),
 * Ambient = (0, 0, 0), Shading = closed, Delegate = a vtkRenderStepsPass.
 */
#ifndef vtkWireFurRenderPass_h
#define vtkWireFurRenderPass_h

#include "WireFurFiltersModule.h"
#include "vtkRenderPass.h"

#include <memory>

namespace wf
{
struct Scene;
}

class vtkInformationDoubleKey;
class vtkMultiProcessController;
class vtkInformationIntegerKey;
class vtkProp;
class vtkRenderWindow;
class vtkRenderer;

class WIREFURFILTERS_EXPORT vtkWireFurRenderPass : public vtkRenderPass
{
public:
  static vtkWireFurRenderPass* New();
  vtkTypeMacro(vtkWireFurRenderPass, vtkRenderPass);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Key in a prop's PropertyKeys: 1 = drawn by this pass, not by the delegate.
  static vtkInformationIntegerKey* WIREFUR();
  /// Optional key: wire diameter in world units (default: the property's LineWidth in pixels).
  static vtkInformationDoubleKey* WIREFUR_WIRE_THICKNESS();
  /// Optional key: wire style, 0 shaded (default), 1 plain (diffuse colour), 2 depth-cued.
  static vtkInformationIntegerKey* WIREFUR_WIRE_STYLE();

#ifndef __VTK_WRAP__
  /// A scene of the core drawn through the A-buffer with the marked props, in the renderer's
  /// camera: built by wf::buildScene (scene/scene_description.h) with its own materials (burnish
  /// grain and grooves, chrome, colour and bump maps, fur, scales), so that it looks as
  /// `wirefur render` draws it. While a scene is set, its lights (and lights-follow-camera, its
  /// ambient, its environment) light the whole A-buffer render instead of the renderer's
  /// vtkLights, and the A-buffer's near and far planes come from the geometry's bounds. Null
  /// (the default) removes it. The pass keeps a reference; set a new scene to change it.
  void SetScene(std::shared_ptr<const wf::Scene> scene);
  std::shared_ptr<const wf::Scene> GetScene() const;
#endif

  /// Marks (or unmarks) a prop for this pass (creates its PropertyKeys when it has none).
  static void Mark(vtkProp* prop, bool marked = true);
  /// True when the prop carries WIREFUR() = 1.
  static bool IsMarked(vtkProp* prop);

  /// Draws the props that are not marked with the delegate, then the marked ones through the
  /// A-buffer, composited over it.
  void Render(const vtkRenderState* s) override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  ///@{
  /// The pass that draws everything not marked. Default: a vtkRenderStepsPass.
  virtual void SetDelegatePass(vtkRenderPass* pass);
  vtkGetObjectMacro(DelegatePass, vtkRenderPass);
  ///@}

  ///@{
  /// Coverage mask of the A-buffer: 4 x 4, 8 x 4 (default) or 8 x 8 subpixels. Other sizes are
  /// refused with an error.
  void SetMaskSize(int width, int height);
  vtkGetMacro(MaskWidth, int);
  vtkGetMacro(MaskHeight, int);
  ///@}

  ///@{
  /// Fragments kept exactly per pixel (1 ... 65535); the rest blend into a tail. Default 64.
  vtkSetClampMacro(Budget, int, 1, 65535);
  vtkGetMacro(Budget, int);
  ///@}

  ///@{
  /// Threads of the core render (0: all cores). Default 0.
  vtkSetClampMacro(Threads, int, 0, 1024);
  vtkGetMacro(Threads, int);
  ///@}

  ///@{
  /// How the core shades wires, hairs, grain and surfaces (wf::ShadingPath): 0, closed (the
  /// default): at every fragment's own view vector, exact in perspective but for a table of one
  /// variable per exponent (error ~1e-9); 1, maps: the paper's pseudo-reflectance maps and
  /// reflectance spheres (orthographic view assumption); 2, exact: the reference.
  vtkSetClampMacro(Shading, int, 0, 2);
  vtkGetMacro(Shading, int);
  void SetShadingToClosed() { this->SetShading(0); }
  void SetShadingToMaps() { this->SetShading(1); }
  void SetShadingToExact() { this->SetShading(2); }
  ///@}

  ///@{
  /// Renders the A-buffer at 1/F of the viewport's width and height (rounded up), with widths
  /// given in pixels scaled to match, and scales the result up bilinearly before the composite;
  /// the delegate's depth is scaled down to the nearest depth over each reduced pixel's bilinear
  /// support, so a marked prop is never drawn over the delegate's geometry (near an occluder's
  /// edge it is hidden up to about 1.5 F pixels early). Every frame (as ParaView's image
  /// reduction factor); for frames while the camera moves only, see
  /// InteractiveImageReductionFactor. 1 ... 8; default 1: every pixel rendered.
  vtkSetClampMacro(ImageReductionFactor, int, 1, 8);
  vtkGetMacro(ImageReductionFactor, int);
  ///@}

  ///@{
  /// The image reduction while the render window is in an interaction, as VTK's LOD actors
  /// decide it: VTK's interactor styles raise the window's desired update rate to the
  /// interactor's (15 frames per second by default) while the camera moves and lower it to the
  /// still rate (0.0001) when it stops, then render the still frame. Above 1 frame per second
  /// the pass renders at this reduction (or ImageReductionFactor when larger), so any VTK
  /// application gets fast frames while moving and the exact frame when still. 1 ... 8;
  /// default 1: off (`wirefur view` sets 2).
  vtkSetClampMacro(InteractiveImageReductionFactor, int, 1, 8);
  vtkGetMacro(InteractiveImageReductionFactor, int);
  ///@}

  /// The reduction the next Render will use in `window`: InteractiveImageReductionFactor (or
  /// ImageReductionFactor when larger) while its desired update rate is above 1 frame per
  /// second, else ImageReductionFactor.
  int GetImageReductionFactorFor(vtkRenderWindow* window) const;

  ///@{
  /// Distributed rendering (sort-first bands of rows; docs/paraview.md). With a controller of
  /// more than one process every process must Render together (each call is collective: in
  /// ParaView, the view turns on IceT's RenderEmptyImages), with the same marked actors in the
  /// same order and the same viewport. Each process draws its own props that are not marked;
  /// the marked actors' lines of every process are gathered to every process; each process
  /// depth-composites every process's colour and depth for its band of rows, renders that band
  /// of the A-buffer over it, and the bands are gathered, so that every process writes the same
  /// colour and depth: a depth compositor (IceT) then picks identical pixels, and the picture is
  /// the one-process picture. Marked polygons are not gathered (not drawn; a warning). The
  /// pixels no process's surface covers are taken as the background colour(s) below, since a
  /// compositor clears them to transparent. Null (the default): every process on its own.
  virtual void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  /// Off: the frames rendered now are not collective (a redraw of one process's window), and
  /// each process draws its own lines although a controller is set. A host that knows which of
  /// its renders are collective (the WireFur ParaView view) turns it on around them only, so
  /// that a stray render on one rank cannot wait for the others for ever. Default on.
  vtkSetMacro(ControllerActive, bool);
  vtkGetMacro(ControllerActive, bool);
  /// The background under the lines in a distributed frame: Background at the bottom,
  /// Background2 at the top when GradientBackground is on (vtkViewport's vertical gradient).
  vtkSetVector3Macro(Background, double);
  vtkGetVector3Macro(Background, double);
  vtkSetVector3Macro(Background2, double);
  vtkGetVector3Macro(Background2, double);
  vtkSetMacro(GradientBackground, bool);
  vtkGetMacro(GradientBackground, bool);
  /// Off: the background of a distributed frame is not a uniform colour or a vertical gradient
  /// (a texture, a skybox): the lines over no surface are left over transparent black, with
  /// their coverage as alpha, for the compositor's background blend (exact only where a line
  /// covers its pixel wholly). Default on.
  vtkSetMacro(BackgroundKnown, bool);
  vtkGetMacro(BackgroundKnown, bool);
  /// Seconds the last distributed frame spent exchanging: gathering the lines (0 when no
  /// marked actor changed), compositing the surfaces' bands and gathering the finished bands.
  vtkGetMacro(LastGatherSeconds, double);
  vtkGetMacro(LastCompositeSeconds, double);
  ///@}

  ///@{
  /// Ambient radiance of the core's light rig (linear RGB). Default (0, 0, 0).
  vtkSetVector3Macro(Ambient, double);
  vtkGetVector3Macro(Ambient, double);
  ///@}

  /// (At the start of every Render the pass invokes vtkCommand::StartEvent, before it reads
  /// the marks: an observer may mark props then; at the end, before the 2-D props are drawn,
  /// vtkCommand::EndEvent: the figures below are then that frame's.)
  /// Seconds the last Render took in all (delegate, conversion, A-buffer, composite).
  vtkGetMacro(LastRenderSeconds, double);
  /// The image reduction factor the last core render was drawn with (1 when none ran). The
  /// figures below (times, error estimates, fragments) are those of that render: at a factor
  /// above 1 they describe the render at the reduced size, not its scaled-up picture, which
  /// differs from the full-size frame by the upscale's blur (docs/vtk.md).
  vtkGetMacro(LastImageReductionFactor, int);
  /// Seconds of the last core A-buffer render alone (0 when no prop was marked).
  vtkGetMacro(LastCoreSeconds, double);
  /// The shading error bound of the last core render (radiance, linear): on the closed path
  /// the lobe tables' bound; on the map path the maps, reflectance spheres and the
  /// orthographic-view approximation, whichever is worst; 0 on the exact path.
  vtkGetMacro(LastErrorEstimate, double);
  /// Coverage quantisation of the last core render: 1 / subpixels of the mask.
  vtkGetMacro(LastCoverageError, double);
  /// Fragments of the last core render.
  vtkGetMacro(LastFragments, vtkTypeInt64);
  /// Marked actors drawn by the last Render.
  vtkGetMacro(LastMarkedProps, int);
  /// Shading tables (lobe tables; maps, spheres) the last Render built, and those it took from the
  /// frame before (lobe tables are kept while used; maps and spheres are rebuilt only when a
  /// material, the lights in eye space or the view change).
  vtkGetMacro(LastTablesBuilt, int);
  vtkGetMacro(LastTablesReused, int);

protected:
  vtkWireFurRenderPass();
  ~vtkWireFurRenderPass() override;

  vtkRenderPass* DelegatePass = nullptr;
  vtkMultiProcessController* Controller = nullptr;
  double Background[3] = { 0.0, 0.0, 0.0 };
  double Background2[3] = { 0.0, 0.0, 0.0 };
  bool GradientBackground = false;
  bool BackgroundKnown = true;
  bool ControllerActive = true;
  double LastGatherSeconds = 0.0;
  double LastCompositeSeconds = 0.0;
  int MaskWidth = 8;
  int MaskHeight = 4;
  int Budget = 64;
  int Threads = 0;
  int Shading = 0;
  int ImageReductionFactor = 1;
  int InteractiveImageReductionFactor = 1;
  int LastImageReductionFactor = 1;
  double Ambient[3] = { 0.0, 0.0, 0.0 };
  double LastRenderSeconds = 0.0;
  double LastCoreSeconds = 0.0;
  double LastErrorEstimate = 0.0;
  double LastCoverageError = 0.0;
  vtkTypeInt64 LastFragments = 0;
  int LastMarkedProps = 0;
  int LastTablesBuilt = 0;
  int LastTablesReused = 0;

private:
  vtkWireFurRenderPass(const vtkWireFurRenderPass&) = delete;
  void operator=(const vtkWireFurRenderPass&) = delete;

  /// The distributed frame after the delegate drew (SetController; collective).
  void RenderDistributed(vtkRenderer* renderer, vtkMultiProcessController* controller);

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
