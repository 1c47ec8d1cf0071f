#include "vtkWireFurRenderPass.h"

#include "render/shading_cache.h"

#include "wf_render_pass_distributed.h"
#include "wf_render_pass_scene.h"

#include "core/timer.h"
#include "render/renderer.h"

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkCamera.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationIntegerKey.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkCommunicator.h"
#include "vtkPropCollection.h"
#include "vtkNew.h"
#include "vtkCommand.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkProp.h"
#include "vtkRenderState.h"
#include "vtkRenderStepsPass.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkWireFurRenderPass);
vtkInformationKeyMacro(vtkWireFurRenderPass, WIREFUR, Integer);
vtkInformationKeyMacro(vtkWireFurRenderPass, WIREFUR_WIRE_THICKNESS, Double);
vtkInformationKeyMacro(vtkWireFurRenderPass, WIREFUR_WIRE_STYLE, Integer);

namespace {

const char* kCopyVS = R"(//VTK::System::Dec
in vec4 ndCoordIn;
in vec2 texCoordIn;
out vec2 texCoord;
void main()
{
  gl_Position = ndCoordIn;
  texCoord = texCoordIn;
}
)";

// Texel for pixel: the quad spans the viewport, so the texel under a fragment is
// floor(texCoord x size) (texCoord is (i + 0.5) / size at pixel centres; no filtering).
const char* kCopyFS = R"(//VTK::System::Dec
in vec2 texCoord;
uniform sampler2D source;
//VTK::Output::Dec
void main(void)
{
  ivec2 size = textureSize(source, 0);
  ivec2 p = clamp(ivec2(floor(texCoord * vec2(size))), ivec2(0), size - ivec2(1));
  gl_FragData[0] = texelFetch(source, p, 0);
}
)";

// The same with the window depth written from a second texture (a distributed frame: every
// process writes the same colour and depth, for the depth compositor after this pass).
const char* kCopyDepthFS = R"(//VTK::System::Dec
in vec2 texCoord;
uniform sampler2D source;
uniform sampler2D depthSource;
//VTK::Output::Dec
void main(void)
{
  ivec2 size = textureSize(source, 0);
  ivec2 p = clamp(ivec2(floor(texCoord * vec2(size))), ivec2(0), size - ivec2(1));
  gl_FragData[0] = texelFetch(source, p, 0);
  gl_FragDepth = texelFetch(depthSource, p, 0).r;
}
)";

/// Window depth written where lines lie over no surface: below the far plane (1), which a depth
/// compositor takes for empty, and above every depth a surface can have in a 24-bit buffer but
/// the farthest few.
constexpr float kLinesOverBackground = 0.99999f;

using wf::secondsSince;  // core/timer.h

}  // namespace

class vtkWireFurRenderPass::vtkInternals
{
public:
  std::vector<wfvtk::ActorPiece> Pieces;  ///< conversion cache, in marked-prop order
  std::shared_ptr<const wf::Scene> Core;   ///< SetScene
  bool CoreChanged = false;
  wf::Scene Scene;                        ///< the pieces assembled (camera and lights per frame)
  bool SceneFailed = false;               ///< the last build failed: nothing of ours is drawn
  bool Gathered = false;                  ///< Scene holds every process's lines (distributed)
  bool SaidRanksDiffer = false;           ///< the ranks' marked actors differ: said once
  std::vector<vtkProp*> DelegateProps, OverlayProps;
  std::vector<vtkActor*> Marked;
  std::vector<float> WindowDepth, ViewDepth;
  std::vector<float> ReducedDepth;  ///< ViewDepth at the reduced size (ImageReductionFactor)
  wf::ImageRGBA Upscaled;           ///< a reduced render scaled up to the viewport
  std::vector<unsigned char> Colour;
  float SrgbToLinear[256];
  /// Linear [0, 1] in steps of 1 / 65535 to 8-bit sRGB: within 0.05 of a step of the exact
  /// encoding where it is steepest (12.92 x 255 / 65535 at 0), without a pow per channel.
  std::vector<unsigned char> LinearToSrgb8;
  vtkSmartPointer<vtkTextureObject> Texture;
  vtkSmartPointer<vtkTextureObject> DepthTexture;  ///< distributed frames: the depth written back
  std::unique_ptr<vtkOpenGLQuadHelper> DepthQuad;
  vtkSmartPointer<vtkOpenGLFramebufferObject> Resolve;  ///< multisampled framebuffers resolve here
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
  /// Shading tables kept between frames: rebuilt only when a material, the lights in eye space or
  /// the view change (a camera turning with a headlight rebuilds nothing).
  std::shared_ptr<wf::ShadingCache> Tables = std::make_shared<wf::ShadingCache>();

  vtkInternals()
  {
    for (int i = 0; i < 256; ++i)
      this->SrgbToLinear[i] = wfvtk::srgbToLinear(float(i) / 255.0f);
    this->LinearToSrgb8.resize(65536);
    for (int i = 0; i < 65536; ++i)
      this->LinearToSrgb8[size_t(i)] =
        static_cast<unsigned char>(std::lround(255.0f * wfvtk::linearToSrgb(float(i) / 65535.0f)));
  }

  /// Converts the marked actors that changed; true when any did (or the core scene changed).
  bool ConvertMarked()
  {
    bool changed = this->Pieces.size() != this->Marked.size() || this->CoreChanged;
    this->CoreChanged = false;
    this->Pieces.resize(this->Marked.size());
    for (size_t i = 0; i < this->Marked.size(); ++i)
    {
      vtkActor* actor = this->Marked[i];
      wfvtk::ActorPiece& p = this->Pieces[i];
      if (p.actor.GetPointer() == actor && p.signature == wfvtk::actorSignature(actor))
        continue;
      p = wfvtk::convertActor(actor);
      changed = true;
    }
    return changed;
  }

  /// Converts what changed; true when the assembled scene was rebuilt.
  bool UpdateScene()
  {
    const bool changed = this->ConvertMarked();
    if (changed || this->Gathered)  // a gathered scene is not this process's own
    {
      this->Assemble(this->Pieces);
      this->Gathered = false;
    }
    return changed;
  }

  /// A distributed frame's scene (collective): the local conversion, then, when any process's
  /// marked actors changed, every process's lines gathered and assembled.
  void UpdateSceneDistributed(vtkMultiProcessController* controller)
  {
    // (Gathered is this process's own state: reduced with the rest, so that every process takes
    // the same decision to gather.)
    const int changed = this->ConvertMarked() || !this->Gathered ? 1 : 0;
    int any = 1;
    if (!controller->AllReduce(&changed, &any, 1, vtkCommunicator::MAX_OP))
      any = 1;
    if (!any && this->Gathered)
      return;
    try
    {
      int dropped = 0;
      const std::vector<wfvtk::ActorPiece> all = wfvtk::gatherWires(controller, this->Pieces, dropped);
      if (dropped > 0)
        vtkGenericWarningMacro(<< "vtkWireFurRenderPass: " << dropped
                               << " marked actor(s) with polygons: in a distributed frame only lines are drawn");
      this->Assemble(all);
      this->Gathered = true;
    }
    catch (const std::exception& e)
    {
      vtkGenericWarningMacro(<< "vtkWireFurRenderPass: the marked lines cannot be gathered: " << e.what());
      this->Scene = wf::Scene{};
      this->SceneFailed = true;
      this->Gathered = false;
    }
  }

  void Assemble(const std::vector<wfvtk::ActorPiece>& pieces)
  {
    {
      try
      {
        this->Scene = wfvtk::assembleScene(pieces, this->Core.get());
        this->SceneFailed = false;
      }
      catch (const std::exception& e)  // out of memory: nothing of ours is drawn until a prop changes
      {
        vtkGenericWarningMacro(<< "vtkWireFurRenderPass: the marked actors cannot be built: " << e.what());
        this->Scene = wf::Scene{};
        this->SceneFailed = true;
      }
    }
  }

  /// The frame's camera and lights in Scene (the core scene's own lights, near and far from its
  /// geometry's bounds, when one is set) and the options every core render of the pass shares.
  void PrepareFrame(const vtkWireFurRenderPass& pass, vtkRenderer* ren, vtkCamera* camera, int w, int h,
                    wf::RenderOptions& options)
  {
    this->Scene.camera = wfvtk::convertCamera(camera, w, h);
    if (this->Core)
    {
      this->Scene.lights = this->Core->lights;
      this->Scene.lightsFollowCamera = this->Core->lightsFollowCamera;
      this->Scene.camera->nearPlane = this->Scene.camera->farPlane = 0.0;
    }
    else
    {
      this->Scene.lights = wfvtk::convertLights(ren, camera, pass.Ambient);
      this->Scene.lightsFollowCamera = false;
    }
    options.mask = wf::MaskLayout{ pass.MaskWidth, pass.MaskHeight };
    options.budget = pass.Budget;
    options.threads = pass.Threads;
    options.shadingCache = this->Tables;
    options.shading = pass.Shading == 1 ? wf::ShadingPath::Maps
      : pass.Shading == 2               ? wf::ShadingPath::Exact
                                        : wf::ShadingPath::Closed;
  }

  /// The shading error bound of a core render (the pass's LastErrorEstimate).
  static double ShadingBound(const wf::RenderResult& r)
  {
    return std::max({ r.stats.mapError, r.stats.sphereError, r.stats.orthographicError, r.stats.lobeError });
  }

  /// Reads the colour and depth of the viewport (x, y, w, h) of the framebuffer being drawn,
  /// resolving a multisampled one first. False when it cannot.
  bool ReadBack(vtkOpenGLRenderWindow* renWin, int x, int y, int w, int h, bool depth)
  {
    vtkOpenGLState* ostate = renWin->GetState();
    GLint drawFb = 0, samples = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFb);
    glGetIntegerv(GL_SAMPLES, &samples);
    ostate->PushFramebufferBindings();
    ostate->vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(drawFb));
    int rx = x, ry = y;
    if (samples > 0)
    {
      if (!this->Resolve)
        this->Resolve = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
      this->Resolve->SetContext(renWin);
      int size[2] = { 0, 0 };
      this->Resolve->GetLastSize(size);
      if (size[0] != w || size[1] != h || this->Resolve->GetFBOIndex() == 0)
      {
        ostate->PushFramebufferBindings();
        this->Resolve->PopulateFramebuffer(w, h, true, 1, VTK_UNSIGNED_CHAR, true, 32, 0);
        ostate->PopFramebufferBindings();
      }
      ostate->vtkglBindFramebuffer(GL_DRAW_FRAMEBUFFER, this->Resolve->GetFBOIndex());
      {
        // The blit is clipped by the scissor box, which the delegate may leave anywhere.
        vtkOpenGLState::ScopedglEnableDisable scissorTest(ostate, GL_SCISSOR_TEST);
        ostate->vtkglDisable(GL_SCISSOR_TEST);
        glBlitFramebuffer(x, y, x + w, y + h, 0, 0, w, h, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
      }
      ostate->vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, this->Resolve->GetFBOIndex());
      rx = ry = 0;
      drawFb = GLint(this->Resolve->GetFBOIndex());
    }
    ostate->vtkglReadBuffer(drawFb != 0 ? GL_COLOR_ATTACHMENT0 : GL_BACK);
    this->Colour.resize(size_t(w) * size_t(h) * 4);
    this->WindowDepth.resize(depth ? size_t(w) * size_t(h) : 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(rx, ry, w, h, GL_RGBA, GL_UNSIGNED_BYTE, this->Colour.data());
    if (depth)
      glReadPixels(rx, ry, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, this->WindowDepth.data());
    const bool ok = glGetError() == GL_NO_ERROR;
    ostate->PopFramebufferBindings();
    return ok;
  }

  /// The reduced image's pixel coordinates (centres at integers) of the viewport's pixel centre
  /// (x + 1/2, y + 1/2). Both images span the same view: the same vertical extent, and the
  /// horizontal extent of each one's own aspect, so x scales by (w ch) / (h cw) about the centre.
  static void ReducedCoordinates(int x, int y, int w, int h, int cw, int ch, double& u, double& v)
  {
    const double k = (double(w) * ch) / (double(h) * cw);
    u = (((2.0 * (x + 0.5) / w - 1.0) * k + 1.0) * 0.5) * cw - 0.5;
    v = (y + 0.5) / h * ch - 0.5;
  }

  /// ViewDepth (w x h) scaled down to cw x ch: each reduced pixel the nearest depth of every
  /// viewport pixel whose bilinear upscale (Upscale) reads it, so that no viewport pixel behind
  /// an opaque surface gets colour from a reduced pixel in front of it: a marked prop is never
  /// drawn over the delegate's geometry (it is hidden a little more near an occluder's edge).
  void ReduceDepth(int w, int h, int cw, int ch)
  {
    this->ReducedDepth.assign(size_t(cw) * size_t(ch), std::numeric_limits<float>::infinity());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
      {
        const float d = this->ViewDepth[size_t(y) * size_t(w) + size_t(x)];
        if (!(d < std::numeric_limits<float>::infinity()))
          continue;  // nothing opaque here (NaN too)
        int i0, j0, i1, j1;
        float fu, fv;
        BilinearSupport(x, y, w, h, cw, ch, i0, j0, i1, j1, fu, fv);
        for (int j : { j0, j1 })
          for (int i : { i0, i1 })
          {
            float& r = this->ReducedDepth[size_t(j) * size_t(cw) + size_t(i)];
            r = std::min(r, d);
          }
      }
  }

  /// The reduced pixels (i0 | i1, j0 | j1) the upscale reads for viewport pixel (x, y), and the
  /// weights of i1 and j1.
  static void BilinearSupport(int x, int y, int w, int h, int cw, int ch, int& i0, int& j0, int& i1, int& j1,
                              float& fu, float& fv)
  {
    double u, v;
    ReducedCoordinates(x, y, w, h, cw, ch, u, v);
    u = std::clamp(u, 0.0, double(cw - 1));
    v = std::clamp(v, 0.0, double(ch - 1));
    i0 = int(u), j0 = int(v);
    i1 = std::min(i0 + 1, cw - 1), j1 = std::min(j0 + 1, ch - 1);
    fu = float(u - i0), fv = float(v - j0);
  }

  /// The reduced render scaled up to w x h (bilinear in premultiplied RGBA, clamped at the
  /// edges), on `threads` threads (0: all); the buffer is kept between frames.
  const wf::ImageRGBA& Upscale(const wf::ImageRGBA& small, int w, int h, int threads)
  {
    if (this->Upscaled.width != w || this->Upscaled.height != h)
      this->Upscaled = wf::ImageRGBA(w, h);
    const int cw = small.width, ch = small.height;
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] { tbb::parallel_for(0, h, [&](int y)
    {
      for (int x = 0; x < w; ++x)
      {
        int i0, j0, i1, j1;
        float fu, fv;
        BilinearSupport(x, y, w, h, cw, ch, i0, j0, i1, j1, fu, fv);
        const glm::vec4 top = small.at(i0, j0) * (1.0f - fu) + small.at(i1, j0) * fu;
        const glm::vec4 bottom = small.at(i0, j1) * (1.0f - fu) + small.at(i1, j1) * fu;
        this->Upscaled.at(x, y) = top * (1.0f - fv) + bottom * fv;
      }
    }); });
    return this->Upscaled;
  }

  /// out = core + (1 - core alpha) x delegate, in linear light; untouched where the core drew
  /// nothing (so those pixels stay bit for bit the delegate's). Rows in parallel (each row's
  /// pixels depend on that row alone), on `threads` threads (0: all).
  void Composite(const wf::ImageRGBA& core, int w, int h, int threads)
  {
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] { tbb::parallel_for(0, h, [&](int y)
    {
      unsigned char* row = this->Colour.data() + size_t(y) * size_t(w) * 4;  // bottom-up
      for (int x = 0; x < w; ++x)
      {
        const glm::vec4 c = core.at(x, h - 1 - y);  // core row 0 is the top
        if (!(c.w > 0.0f) && !(c.x > 0.0f) && !(c.y > 0.0f) && !(c.z > 0.0f))
          continue;
        unsigned char* o = row + size_t(x) * 4;
        const float t = 1.0f - std::clamp(c.w, 0.0f, 1.0f);
        for (int k = 0; k < 3; ++k)
        {
          float lin = c[k] + t * this->SrgbToLinear[o[k]];
          lin = lin >= 0.0f ? std::min(lin, 1.0f) : 0.0f;  // NaN too
          o[k] = this->LinearToSrgb8[size_t(lin * 65535.0f + 0.5f)];
        }
        const float a = c.w + t * (float(o[3]) / 255.0f);
        o[3] = static_cast<unsigned char>(std::lround(255.0f * std::clamp(a, 0.0f, 1.0f)));
      }
    }); });
  }

  /// Draws Colour over the viewport (x, y, w, h): no blending, no depth test or write; with
  /// `withDepth`, WindowDepth is written as the depth too (a distributed frame).
  void WriteBack(vtkOpenGLRenderWindow* renWin, int x, int y, int w, int h, bool withDepth = false)
  {
    vtkOpenGLState* ostate = renWin->GetState();
    if (!this->Texture)
      this->Texture = vtkSmartPointer<vtkTextureObject>::New();
    this->Texture->SetContext(renWin);
    this->Texture->Create2DFromRaw(unsigned(w), unsigned(h), 4, VTK_UNSIGNED_CHAR, this->Colour.data());
    this->Texture->SetMinificationFilter(vtkTextureObject::Nearest);
    this->Texture->SetMagnificationFilter(vtkTextureObject::Nearest);
    std::unique_ptr<vtkOpenGLQuadHelper>& quad = withDepth ? this->DepthQuad : this->Quad;
    if (!quad)
      quad = std::make_unique<vtkOpenGLQuadHelper>(renWin, kCopyVS, withDepth ? kCopyDepthFS : kCopyFS, "");
    else
      renWin->GetShaderCache()->ReadyShaderProgram(quad->Program);
    if (!quad->Program)
      return;
    if (withDepth)
    {
      if (!this->DepthTexture)
        this->DepthTexture = vtkSmartPointer<vtkTextureObject>::New();
      this->DepthTexture->SetContext(renWin);
      this->DepthTexture->Create2DFromRaw(unsigned(w), unsigned(h), 1, VTK_FLOAT, this->WindowDepth.data());
      this->DepthTexture->SetMinificationFilter(vtkTextureObject::Nearest);
      this->DepthTexture->SetMagnificationFilter(vtkTextureObject::Nearest);
    }
    vtkOpenGLState::ScopedglEnableDisable depthTest(ostate, GL_DEPTH_TEST);
    vtkOpenGLState::ScopedglEnableDisable blend(ostate, GL_BLEND);
    vtkOpenGLState::ScopedglDepthMask depthMask(ostate);
    vtkOpenGLState::ScopedglDepthFunc depthFunc(ostate);
    vtkOpenGLState::ScopedglViewport viewport(ostate);
    vtkOpenGLState::ScopedglScissor scissor(ostate);
    vtkOpenGLState::ScopedglColorMask colorMask(ostate);
    if (withDepth)
    {
      ostate->vtkglEnable(GL_DEPTH_TEST);  // depth writes need the test on
      ostate->vtkglDepthFunc(GL_ALWAYS);
      ostate->vtkglDepthMask(GL_TRUE);
    }
    else
    {
      ostate->vtkglDisable(GL_DEPTH_TEST);
      ostate->vtkglDepthMask(GL_FALSE);
    }
    ostate->vtkglDisable(GL_BLEND);
    ostate->vtkglViewport(x, y, w, h);
    ostate->vtkglScissor(x, y, w, h);
    ostate->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    this->Texture->Activate();
    quad->Program->SetUniformi("source", this->Texture->GetTextureUnit());
    if (withDepth)
    {
      this->DepthTexture->Activate();
      quad->Program->SetUniformi("depthSource", this->DepthTexture->GetTextureUnit());
    }
    quad->Render();
    if (withDepth)
      this->DepthTexture->Deactivate();
    this->Texture->Deactivate();
  }
};

vtkWireFurRenderPass::vtkWireFurRenderPass()
  : Internals(new vtkInternals)
{
  vtkNew<vtkRenderStepsPass> steps;
  this->SetDelegatePass(steps);
}

vtkWireFurRenderPass::~vtkWireFurRenderPass()
{
  this->SetDelegatePass(nullptr);
  this->SetController(nullptr);
  delete this->Internals;
}

void vtkWireFurRenderPass::SetDelegatePass(vtkRenderPass* pass)
{
  vtkSetObjectBodyMacro(DelegatePass, vtkRenderPass, pass);
}

void vtkWireFurRenderPass::SetController(vtkMultiProcessController* controller)
{
  if (controller == this->Controller)
    return;
  vtkSetObjectBodyMacro(Controller, vtkMultiProcessController, controller);
  this->Internals->CoreChanged = true;  // the scene is rebuilt: gathered or local
  this->Internals->Gathered = false;
}

void vtkWireFurRenderPass::SetMaskSize(int width, int height)
{
  const wf::MaskLayout layout{ width, height };
  if (!layout.valid())
  {
    vtkErrorMacro(<< "mask must be 4x4, 8x4 or 8x8, not " << width << "x" << height);
    return;
  }
  if (this->MaskWidth != width || this->MaskHeight != height)
  {
    this->MaskWidth = width;
    this->MaskHeight = height;
    this->Modified();
  }
}

void vtkWireFurRenderPass::SetScene(std::shared_ptr<const wf::Scene> scene)
{
  if (this->Internals->Core == scene)
    return;
  this->Internals->Core = std::move(scene);
  this->Internals->CoreChanged = true;
  this->Modified();
}

std::shared_ptr<const wf::Scene> vtkWireFurRenderPass::GetScene() const
{
  return this->Internals->Core;
}

void vtkWireFurRenderPass::Mark(vtkProp* prop, bool marked)
{
  if (!prop)
    return;
  vtkInformation* keys = prop->GetPropertyKeys();
  if (!keys)
  {
    if (!marked)
      return;
    vtkNew<vtkInformation> fresh;
    prop->SetPropertyKeys(fresh);
    keys = fresh;
  }
  if (marked)
    keys->Set(WIREFUR(), 1);
  else
    keys->Remove(WIREFUR());
  prop->Modified();
}

bool vtkWireFurRenderPass::IsMarked(vtkProp* prop)
{
  vtkInformation* keys = prop ? prop->GetPropertyKeys() : nullptr;
  return keys && keys->Has(WIREFUR()) && keys->Get(WIREFUR()) == 1;
}

void vtkWireFurRenderPass::Render(const vtkRenderState* s)
{
  const auto t0 = std::chrono::steady_clock::now();
  this->InvokeEvent(vtkCommand::StartEvent);  // observers may mark or unmark props now
  this->NumberOfRenderedProps = 0;
  vtkInternals& in = *this->Internals;
  vtkRenderer* ren = s->GetRenderer();

  // A hardware selection (picking, ParaView's selections) renders ids, not pictures: every prop
  // as the renderer's own pipeline draws it, the marked ones included, and no A-buffer over it.
  if (ren->GetSelector())
  {
    this->UpdateGeometry(ren, s->GetFrameBuffer());
    this->NumberOfRenderedProps = ren->GetNumberOfPropsRendered();
    return;
  }

  // Split the props: marked (ours), 2-D overlay (after the composite), the rest (delegate).
  in.Marked.clear();
  in.DelegateProps.clear();
  in.OverlayProps.clear();
  bool anyMarked = false;
  for (int i = 0; i < s->GetPropArrayCount(); ++i)
  {
    vtkProp* p = s->GetPropArray()[i];
    if (IsMarked(p))
    {
      anyMarked = true;
      if (vtkActor* a = vtkActor::SafeDownCast(p); a && a->GetMapper())
        in.Marked.push_back(a);
    }
    else if (vtkActor2D::SafeDownCast(p))
      in.OverlayProps.push_back(p);
    else
      in.DelegateProps.push_back(p);
  }
  // A distributed frame: the marked actors are every visible marked actor of the renderer
  // (not culled per process), and every process must agree on them and on the viewport, else
  // each renders on its own (every process sees the same comparison, so all fall back together).
  vtkMultiProcessController* controller =
    this->Controller && this->ControllerActive && this->Controller->GetNumberOfProcesses() > 1 ? this->Controller : nullptr;
  if (controller)
  {
    std::vector<vtkActor*> local = in.Marked;
    in.Marked.clear();
    vtkCollectionSimpleIterator pit;
    ren->GetViewProps()->InitTraversal(pit);
    while (vtkProp* p = ren->GetViewProps()->GetNextProp(pit))
      if (vtkActor* a = vtkActor::SafeDownCast(p); a && a->GetVisibility() && a->GetMapper() && IsMarked(a))
        in.Marked.push_back(a);
    int vw = 0, vh = 0, vx = 0, vy = 0;
    ren->GetTiledSizeAndOrigin(&vw, &vh, &vx, &vy);
    if (!wfvtk::sameOnEveryRank(controller, { double(in.Marked.size()), double(vw), double(vh), in.Core ? 1.0 : 0.0 }))
    {
      // Said once until the ranks agree again (not every frame).
      if (!in.SaidRanksDiffer)
        vtkErrorMacro(<< "the processes differ in their marked actors or viewport: each draws its own lines");
      in.SaidRanksDiffer = true;
      controller = nullptr;
      in.Marked = local;
    }
    else
    {
      in.SaidRanksDiffer = false;
      anyMarked = !in.Marked.empty();
    }
  }
  this->LastMarkedProps = int(in.Marked.size());
  this->LastCoreSeconds = 0.0;
  this->LastGatherSeconds = this->LastCompositeSeconds = 0.0;
  this->LastImageReductionFactor = 1;
  if (in.Core)
    anyMarked = true;

  if (!anyMarked)  // nothing of ours: the delegate alone, with the renderer's own state
  {
    if (this->DelegatePass)
    {
      this->DelegatePass->Render(s);
      this->NumberOfRenderedProps = this->DelegatePass->GetNumberOfRenderedProps();
    }
    // Nothing drawn through the A-buffer: the figures say so (not the last frame's).
    this->LastErrorEstimate = 0.0;
    this->LastCoverageError = 0.0;
    this->LastFragments = 0;
    this->LastRenderSeconds = secondsSince(t0);
    this->InvokeEvent(vtkCommand::EndEvent);
    return;
  }

  if (this->DelegatePass)
  {
    vtkRenderState ds(ren);
    ds.SetPropArrayAndCount(in.DelegateProps.empty() ? nullptr : in.DelegateProps.data(),
                            int(in.DelegateProps.size()));
    ds.SetFrameBuffer(s->GetFrameBuffer());
    ds.SetRequiredKeys(s->GetRequiredKeys());
    this->DelegatePass->Render(&ds);
    this->NumberOfRenderedProps = this->DelegatePass->GetNumberOfRenderedProps();
  }

  vtkOpenGLRenderWindow* renWin = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  vtkCamera* camera = ren->GetActiveCamera();
  int w = 0, h = 0, x = 0, y = 0;
  ren->GetTiledSizeAndOrigin(&w, &h, &x, &y);
  if (controller)
  {
    this->RenderDistributed(ren, controller);
    this->NumberOfRenderedProps += int(in.Marked.size());
  }
  else if (renWin && camera && w > 0 && h > 0 && (!in.Marked.empty() || in.Core))
  {
    in.UpdateScene();
  }
  if (!controller && renWin && camera && w > 0 && h > 0 && (!in.Marked.empty() || in.Core) && !in.SceneFailed)
  {
    // The delegate's depth matters only where it drew something: with no prop of its own (a
    // core scene alone, as in `wirefur view`) it only cleared, and nothing hides the A-buffer.
    const bool depth = !in.DelegateProps.empty() || ren->GetPreserveDepthBuffer();
    if (in.ReadBack(renWin, x, y, w, h, depth))
    {
      if (depth)
        wfvtk::viewDepthFromWindowDepth(in.WindowDepth, w, h,
          camera->GetProjectionTransformMatrix(double(w) / double(h), -1, 1), in.ViewDepth);
      wf::RenderOptions options;
      in.PrepareFrame(*this, ren, camera, w, h, options);
      // A reduced frame (ImageReductionFactor, or InteractiveImageReductionFactor while the
      // window is in an interaction): the same view at 1/F of the size.
      const int f = this->GetImageReductionFactorFor(renWin);
      const int cw = f > 1 ? std::max(1, (w + f - 1) / f) : w;
      const int ch = f > 1 ? std::max(1, (h + f - 1) / f) : h;
      if (depth && f > 1)
        in.ReduceDepth(w, h, cw, ch);
      options.width = cw;
      options.height = ch;
      options.pixelScale = double(ch) / double(h);  // pixel widths stay widths in the scaled-up picture
      options.opaqueDepth = depth ? (f > 1 ? &in.ReducedDepth : &in.ViewDepth) : nullptr;
      try
      {
        const wf::RenderResult r = wf::render(in.Scene, options);
        this->LastCoreSeconds = r.stats.total;
        this->LastImageReductionFactor = f;
        this->LastErrorEstimate = vtkInternals::ShadingBound(r);
        this->LastCoverageError = r.stats.coverageQuantisation;
        this->LastFragments = vtkTypeInt64(r.stats.abuffer.fragments);
        this->LastTablesBuilt =
          r.stats.pseudoReflectanceMaps + r.stats.reflectanceSpheres + r.stats.lobeTables;
        this->LastTablesReused = int(r.stats.tablesReused);
        in.Composite(f > 1 ? in.Upscale(r.image, w, h, this->Threads) : r.image, w, h, this->Threads);
        in.WriteBack(renWin, x, y, w, h);

        this->NumberOfRenderedProps += int(in.Marked.size());
      }
      catch (const std::exception& e)
      {
        vtkErrorMacro(<< "the A-buffer render failed: " << e.what());
      }
    }
    else
    {
      vtkErrorMacro(<< "cannot read back the delegate's colour and depth");
    }
  }

  // The figures above are this frame's: observers (the ParaView view's annotation) read them now.
  this->InvokeEvent(vtkCommand::EndEvent);
  // 2-D props as vtkRenderStepsPass would draw them (a text actor lays out its text in the
  // opaque step), after the composite so that they stay on top.
  for (vtkProp* p : in.OverlayProps)
    p->RenderOpaqueGeometry(ren);
  for (vtkProp* p : in.OverlayProps)
    this->NumberOfRenderedProps += p->RenderOverlay(ren);
  this->LastRenderSeconds = secondsSince(t0);
}

void vtkWireFurRenderPass::RenderDistributed(vtkRenderer* ren, vtkMultiProcessController* controller)
{
  // Every step that exchanges runs on every process whatever failed locally (a process that
  // skipped one would leave the others waiting).
  vtkInternals& in = *this->Internals;
  vtkOpenGLRenderWindow* renWin = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  vtkCamera* camera = ren->GetActiveCamera();
  int w = 0, h = 0, x = 0, y = 0;
  ren->GetTiledSizeAndOrigin(&w, &h, &x, &y);
  const int ranks = controller->GetNumberOfProcesses(), me = controller->GetLocalProcessId();
  if (w <= 0 || h <= 0)
    return;  // the same on every process (checked)

  auto t = std::chrono::steady_clock::now();
  in.UpdateSceneDistributed(controller);
  this->LastGatherSeconds = secondsSince(t);

  t = std::chrono::steady_clock::now();
  // Local work that may throw (out of memory) never skips an exchange: a failure is carried to
  // the last reduction, and the frame then draws no lines on any process.
  bool localOk = true;
  const bool read = renWin && in.ReadBack(renWin, x, y, w, h, true);
  if (!read)
  {
    vtkErrorMacro(<< "cannot read back the delegate's colour and depth");
    in.Colour.assign(size_t(w) * size_t(h) * 4, 0);
    in.WindowDepth.assign(size_t(w) * size_t(h), 1.0f);
  }
  // The background's 8-bit colours as this OpenGL stores them (a one-pixel clear read back: the
  // driver's rounding, so that the pixels match a one-process frame's cleared background).
  unsigned char probe[2][4] = { { 0, 0, 0, 255 }, { 0, 0, 0, 255 } };
  for (int k = 0; k < 2; ++k)
  {
    const double* c = k == 0 ? this->Background : this->Background2;
    for (int j = 0; j < 3; ++j)
      probe[k][j] = static_cast<unsigned char>(std::lround(255.0 * std::clamp(c[j], 0.0, 1.0)));
    if (renWin && read)
    {
      vtkOpenGLState* ostate = renWin->GetState();
      vtkOpenGLState::ScopedglScissor scissor(ostate);
      vtkOpenGLState::ScopedglClearColor clearColor(ostate);
      vtkOpenGLState::ScopedglColorMask colorMask(ostate);
      vtkOpenGLState::ScopedglEnableDisable scissorTest(ostate, GL_SCISSOR_TEST);
      ostate->vtkglEnable(GL_SCISSOR_TEST);
      ostate->vtkglScissor(x, y, 1, 1);
      ostate->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      ostate->vtkglClearColor(GLclampf(c[0]), GLclampf(c[1]), GLclampf(c[2]), 1.0f);
      ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(x, y, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, probe[k]);
      probe[k][3] = 255;
    }
  }
  bool exchanged = wfvtk::compositeSurfaceBands(controller, w, h, in.Colour, in.WindowDepth);
  int b0 = 0, b1 = 0;
  wfvtk::bandOf(me, ranks, h, b0, b1);
  // Where no process drew (the compositor cleared to transparent black): the background
  // (vtkViewport's vertical gradient: Background at the bottom, Background2 at the top), when
  // it is one (BackgroundKnown).
  for (int gy = h - b1; this->BackgroundKnown && gy < h - b0; ++gy)
  {
    const double s = this->GradientBackground ? (gy + 0.5) / h : 0.0;
    unsigned char bg[4];
    for (int k = 0; k < 3; ++k)
      bg[k] = static_cast<unsigned char>(std::lround(probe[0][k] * (1.0 - s) + probe[1][k] * s));
    bg[3] = 255;
    for (int gx = 0; gx < w; ++gx)
    {
      const size_t i = size_t(gy) * size_t(w) + size_t(gx);
      if (!(in.WindowDepth[i] < 1.0f) && in.Colour[4 * i + 3] == 0)
        std::memcpy(in.Colour.data() + 4 * i, bg, 4);
    }
  }
  this->LastCompositeSeconds = secondsSince(t);

  double figures[4] = { 0.0, 0.0, 0.0, 0.0 };  // core seconds, error, coverage, fragments
  if (renWin && camera && b1 > b0 && !in.SceneFailed)
  try
  {
    wfvtk::viewDepthFromWindowDepth(in.WindowDepth, w, h,
      camera->GetProjectionTransformMatrix(double(w) / double(h), -1, 1), in.ViewDepth);
    wf::RenderOptions options;
    in.PrepareFrame(*this, ren, camera, w, h, options);
    options.width = w;
    options.height = h;
    options.rowBegin = b0;
    options.rowEnd = b1;
    options.tileSize = wfvtk::kBandRows;  // (the default: bands are whole rows of tiles, bandOf)
    options.opaqueDepth = &in.ViewDepth;
    try
    {
      const wf::RenderResult r = wf::render(in.Scene, options);
      figures[0] = r.stats.total;
      figures[1] = vtkInternals::ShadingBound(r);
      figures[2] = r.stats.coverageQuantisation;
      figures[3] = double(r.stats.abuffer.fragments);
      this->LastTablesBuilt = r.stats.pseudoReflectanceMaps + r.stats.reflectanceSpheres + r.stats.lobeTables;
      this->LastTablesReused = int(r.stats.tablesReused);
      in.Composite(r.image, w, h, this->Threads);
      // Lines over no surface get a depth below the far plane, so the compositor keeps them.
      for (int gy = h - b1; gy < h - b0; ++gy)
        for (int gx = 0; gx < w; ++gx)
        {
          const glm::vec4 c = r.image.at(gx, h - 1 - gy);
          float& d = in.WindowDepth[size_t(gy) * size_t(w) + size_t(gx)];
          if (!(d < 1.0f) && (c.w > 0.0f || c.x > 0.0f || c.y > 0.0f || c.z > 0.0f))
            d = kLinesOverBackground;
        }
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< "the A-buffer render failed: " << e.what());
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "the band cannot be prepared: " << e.what());
    localOk = false;
  }

  t = std::chrono::steady_clock::now();
  exchanged = wfvtk::gatherBands(controller, w, h, in.Colour, in.WindowDepth) && exchanged;
  // The frame's figures over all processes: the slowest band, the worst bound, all fragments.
  double worst[3] = { 0.0, 0.0, 0.0 }, sum = 0.0;
  // (figures[4]: 1 where this process failed; max over all: any failed.)
  double local[5] = { figures[0], figures[1], figures[2], figures[3], (exchanged && localOk) ? 0.0 : 1.0 };
  double reduced[5] = { 0.0, 0.0, 0.0, 0.0, 1.0 };
  const bool ok1 = controller->AllReduce(local, reduced, 3, vtkCommunicator::MAX_OP);
  const bool ok2 = controller->AllReduce(local + 3, &sum, 1, vtkCommunicator::SUM_OP);
  const bool ok3 = controller->AllReduce(local + 4, reduced + 4, 1, vtkCommunicator::MAX_OP);
  std::copy(reduced, reduced + 3, worst);
  exchanged = ok1 && ok2 && ok3 && reduced[4] == 0.0;
  this->LastCompositeSeconds += secondsSince(t);
  if (!exchanged)
  {
    vtkErrorMacro(<< "the exchange between processes failed: the lines are not drawn");
    return;
  }
  this->LastCoreSeconds = worst[0];
  this->LastErrorEstimate = worst[1];
  this->LastCoverageError = worst[2];
  this->LastFragments = vtkTypeInt64(sum);
  if (renWin)
    in.WriteBack(renWin, x, y, w, h, true);
}

void vtkWireFurRenderPass::ReleaseGraphicsResources(vtkWindow* w)
{
  if (this->DelegatePass)
    this->DelegatePass->ReleaseGraphicsResources(w);
  vtkInternals& in = *this->Internals;
  if (in.Quad)
  {
    in.Quad->ReleaseGraphicsResources(w);
    in.Quad.reset();
  }
  if (in.DepthQuad)
  {
    in.DepthQuad->ReleaseGraphicsResources(w);
    in.DepthQuad.reset();
  }
  if (in.Texture)
    in.Texture->ReleaseGraphicsResources(w);
  if (in.DepthTexture)
    in.DepthTexture->ReleaseGraphicsResources(w);
  if (in.Resolve)
    in.Resolve->ReleaseGraphicsResources(w);
}

int vtkWireFurRenderPass::GetImageReductionFactorFor(vtkRenderWindow* window) const
{
  return window && window->GetDesiredUpdateRate() > 1.0
    ? std::max(this->ImageReductionFactor, this->InteractiveImageReductionFactor)
    : this->ImageReductionFactor;
}

void vtkWireFurRenderPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DelegatePass: " << (this->DelegatePass ? this->DelegatePass->GetClassName() : "(none)") << "\n";
  os << indent << "Mask: " << this->MaskWidth << "x" << this->MaskHeight << "\n";
  os << indent << "Budget: " << this->Budget << "\n";
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "Shading: " << (this->Shading == 1 ? "maps" : this->Shading == 2 ? "exact" : "closed") << "\n";
  os << indent << "Ambient: (" << this->Ambient[0] << ", " << this->Ambient[1] << ", " << this->Ambient[2] << ")\n";
  os << indent << "ImageReductionFactor: " << this->ImageReductionFactor << "\n";
  os << indent << "InteractiveImageReductionFactor: " << this->InteractiveImageReductionFactor << "\n";
  os << indent << "LastImageReductionFactor: " << this->LastImageReductionFactor << "\n";
  os << indent << "LastRenderSeconds: " << this->LastRenderSeconds << "\n";
  os << indent << "LastCoreSeconds: " << this->LastCoreSeconds << "\n";
  os << indent << "LastErrorEstimate: " << this->LastErrorEstimate << "\n";
  os << indent << "LastCoverageError: " << this->LastCoverageError << "\n";
  os << indent << "LastMarkedProps: " << this->LastMarkedProps << "\n";
}
