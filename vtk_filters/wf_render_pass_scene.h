// Private to the module (vtkWireFurRenderPass, and the view-dependent filters' camera): the conversion of marked vtkActors into a scene description
// (src/scene/scene_description.h) built by the core's buildScene, of the renderer's vtkLights and
// its vtkCamera into the core's, and of the OpenGL depth buffer into view depth. Kept apart from
// the OpenGL code so that each step reads on its own (docs/vtk.md).
#pragma once

#include "render/scene.h"
#include "scene/scene_description.h"

#include <vtkSmartPointer.h>
#include <vtkTimeStamp.h>
#include <vtkType.h>
#include <vtkWeakPointer.h>

#include <vector>

class vtkActor;
class vtkCamera;
class vtkMatrix4x4;
class vtkRenderer;

namespace wfvtk {

/// One marked actor as one object of a scene description: its data in object space (the file
/// geometry of the description), the actor's matrix as the object's transform, its surface in
/// `material` and its wire in `wireMaterial` (numbered when the pieces are described together).
struct ActorPiece {
  vtkWeakPointer<vtkActor> actor;
  vtkMTimeType signature = 0;  ///< max MTime of actor, property, keys, mapper and input at conversion
  wf::Material material;      ///< of the surface
  wf::Material wireMaterial;  ///< of the wire (a highlight where the property has none)
  /// The object (geometry, transform, surface and wire; material indices 0 and 1 until
  /// describeActors numbers them). Empty (no geometry) when the actor draws nothing.
  wf::ObjectDescription object;
};

/// The MTime an actor's piece depends on: the actor (with its property, transform and keys),
/// its mapper, the mapper's input. Updates the mapper's input first.
vtkMTimeType actorSignature(vtkActor* actor);

/// Converts one actor into an object: lines and polylines -> its wire (style and thickness from
/// the pass's information keys, else shaded at the property's LineWidth in pixels), polys and
/// strips -> its surface's mesh (point normals and texture coordinates when present; a
/// vtkWireFurBurnish output's tangents as the grain, its groove intensity into the vertex
/// colours), the actor's matrix as the transform, mapped point colours (8-bit, sRGB-encoded)
/// decoded to linear multipliers, material from the vtkProperty. Non-finite points pass
/// through: the core rejects them itself.
ActorPiece convertActor(vtkActor* actor);

/// The pieces as one scene description: two materials per piece (surface, wire) after
/// `firstMaterials`, an object per piece that draws something; no primitive bound (the render's
/// memory estimate applies), camera and lights left for the pass to set per frame.
wf::SceneDescription describeActors(const std::vector<ActorPiece>& pieces, std::vector<wf::Material> firstMaterials = {});

/// The pieces built by wf::buildScene, after the surfaces, wires, materials and environment of
/// `core` when given (vtkWireFurRenderPass::SetScene); camera and lights left for the pass.
/// Throws wf::SceneError as buildScene does.
wf::Scene assembleScene(const std::vector<ActorPiece>& pieces, const wf::Scene* core = nullptr);

/// The vtkCamera as the core's camera for a width x height viewport: position, focal point,
/// view up, vertical view angle (a horizontal one converted) or 2 x parallel scale, clipping range.
wf::Camera convertCamera(vtkCamera* camera, int width, int height);

/// The view a view-dependent filter (vtkWireFurSilhouette, vtkWireFurEdgeVisibility) works
/// for: its own camera, else the renderer's active camera, looked up at every use; the viewport
/// the renderer's size when it has one, else the filter's. mtime() is what the filter's GetMTime
/// adds: the camera's MTime, and the time the camera object or the viewport size last changed
/// (an active camera replaced by an older one, a window resized, re-execute the filter too).
class FilterView {
 public:
  vtkSmartPointer<vtkCamera> camera;
  vtkWeakPointer<vtkRenderer> renderer;  ///< weak: the renderer usually holds the pipeline
  vtkCamera* active() const;
  /// The viewport: the renderer's size, else `fallback`, at least 1 x 1.
  void size(const int fallback[2], int& width, int& height) const;
  vtkMTimeType mtime(const int fallback[2]);

 private:
  vtkCamera* last_ = nullptr;
  int lastWidth_ = -1, lastHeight_ = -1;
  vtkTimeStamp changed_;
};

/// The renderer's switched-on vtkLights as world-space directional lights: headlights along the
/// view direction, camera lights from the camera frame, scene lights from position to focal
/// point (positional lights too: they are taken as directional from the focal point). A
/// renderer without lights gets one headlight. `ambient` is the rig's ambient radiance.
wf::LightRig convertLights(vtkRenderer* renderer, vtkCamera* camera, const double ambient[3]);

/// View depth d = -z_eye per pixel (row 0 at the top, +inf where the buffer is cleared to 1)
/// from an OpenGL depth buffer (row 0 at the bottom, window depth in [0, 1]) drawn with the
/// projection `projection` (VTK's, z_ndc in [-1, 1]).
void viewDepthFromWindowDepth(const std::vector<float>& windowDepth, int width, int height,
                              vtkMatrix4x4* projection, std::vector<float>& viewDepth);

/// sRGB transfer function (IEC 61966-2-1), the same as the `wirefur render` PNG writer's.
float srgbToLinear(float v);
float linearToSrgb(float v);

}  // namespace wfvtk
