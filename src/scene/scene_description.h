// Stage "scene" of the data path (docs/design.md): one plain-data description of what to draw,
// and one builder that turns it into the renderer's wf::Scene. Every entry point fills a
// description and calls buildScene: the scene-file loader (apps/scene_file.cpp), bare mesh and
// polyline files and CAD files (with a style preset), `wirefur export`, the viewer. Reading files
// (JSON, meshes, CAD, images) is the I/O layer's job (apps/); nothing here reads a file or links
// VTK or OpenCASCADE.
//
//   SceneDescription --buildScene--> BuiltScene { wf::Scene, what was grown, seconds }
//
// An object has a parametric source, or a file's geometry (a mesh, polylines, CAD faces with their
// exact surfaces); a transform; what to draw of it (surface, wire, fur, scales) with materials by
// index. Styles ("wire", "burnished", "fur", ...) are presets (scene/style_presets.h) that fill
// these fields: data, not one builder per input kind.
#pragma once

#include "geometry/parametric_sources.h"
#include "growth/fur.h"
#include "growth/scales.h"
#include "render/scene.h"
#include "render/edge_classes.h"
#include "surface/grain_layout.h"
#include "surface/silhouette.h"
#include "surface/surface.h"
#include "texture/texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace wf {

/// A problem with a description, found while building: `where` names the part (a scene file's
/// JSON pointer, "--style", ...), what() the problem. The caller prefixes its file name.
struct SceneError : std::runtime_error {
  SceneError(std::string where, const std::string& what) : std::runtime_error(what), where(std::move(where)) {}
  std::string where;
};

/// One exact face of a CAD part: its surface with (u, v) and derivatives, and where the face is
/// (1) and is trimmed away (0) over that (u, v) domain.
struct FaceSurface {
  std::shared_ptr<const Surface> surface;
  std::shared_ptr<const ScalarTexture> inside;
  int id = 0;    ///< stable face number (hair and scale identities)
  int part = 0;  ///< index into GeometryData::partNames
};

/// A file's geometry as the I/O layer read it (apps/mesh_io.h, apps/cad_input.h).
struct GeometryData {
  TriangleMesh mesh;                   ///< polygons, triangulated (CAD: every face's tessellation)
  PolylineSet lines;                   ///< line cells (CAD: the B-rep edges)
  /// CAD: each edge's class and the angle between its faces (render/edge_classes.h), one per
  /// polyline of `lines`; empty for other files.
  std::vector<EdgeClass> lineClasses;
  std::vector<float> lineAngles;
  PolylineSet isoLines;                ///< CAD: iso-parameter lines asked for, drawn thin
  bool cad = false;                    ///< a CAD model: its edges are `lines`, not the tessellation's
  std::vector<std::string> partNames;  ///< CAD: one surface per part, named
  std::vector<int> trianglePart;       ///< CAD: part of each triangle of mesh (empty: one part)
  std::vector<int> triangleFace;       ///< CAD: face of each triangle of mesh (empty: one face)
  std::vector<FaceSurface> faces;      ///< CAD: the exact faces (fur and scales grow on them)
};

/// An object's wire-frame: which lines, drawn how (the SceneWire's style, material, thickness,
/// colour, opacity, ends; its name and lines are filled by the builder).
struct WireDescription {
  enum class From { Default, Isolines, Edges, Lines };
  From from = From::Default;  ///< Default: isolines of a source, a file's lines, else mesh edges
  int linesU = 16, linesV = 8;  ///< isolines
  SceneWire wire;
  std::string where;
  /// Adds the silhouettes of the object's exact surface (a parametric source, a CAD model's
  /// faces; surface/silhouette.h), drawn as this wire, traced for the camera (traceSilhouettes).
  bool silhouettes = false;
  SilhouetteOptions silhouetteOptions;
  /// Which edges (From::Edges of a mesh, a CAD model's B-rep edges): render/edge_classes.h. A
  /// mesh's edges are classified from its triangles only when the selection is not `all`.
  EdgeSelection edges;
};

/// Fur grown on the object's surface (a source, a CAD file's faces, or a mesh; growth/fur.h).
struct FurDescription {
  FurParams params;
  int material = 0;
  float opacity = 1.0f;
  bool roundEnds = false;
  std::string where;
};

/// Scales grown on the object's surface (growth/scales.h).
struct ScalesDescription {
  ScaleParams params;
  /// > 0: the cells are about this size in world units on every patch (params' cellsU, cellsV
  /// are then set per patch from its extent), so the scales of a model do not depend on how its
  /// faces are parametrised or how finely a mesh is cut.
  double cellSize = 0.0;
  int material = 0;
  std::string where;       ///< errors of the parameters
  std::string cellsWhere;  ///< errors of the count (the budget)
};

struct ObjectDescription {
  std::string name;
  std::string where;  ///< names this object in errors (e.g. "/objects/2")
  /// Exactly one of the two.
  std::optional<ParametricSource> source;
  std::shared_ptr<const GeometryData> geometry;
  std::string sourceWhere, fileWhere;  ///< errors of the source's tessellation / the file's geometry
  glm::dmat4 transform{1.0};
  /// The surface: drawn when the object has polygons, unless drawSurface is false.
  bool drawSurface = true;
  bool surfaceExplicit = false;  ///< asked for (a scene file's `"surface": true`): no polygons is an error
  int surfaceMaterial = 0;
  /// The surface hides the wires behind it and draws nothing (SceneSurface::holdout).
  bool surfaceHoldout = false;
  std::string surfaceWhere;
  /// A CAD model's parts as surfaces of their own, named after them (else one surface).
  bool splitParts = false;
  /// False: the file's vertex colours are dropped (brushed steel is not painted).
  bool keepColours = true;
  std::optional<WireDescription> wire;
  /// A CAD model's iso lines drawn apart, as this wire (name, lines filled), instead of with its
  /// edges in `wire`.
  std::optional<SceneWire> isoLineWire;
  std::optional<FurDescription> fur;
  std::optional<ScalesDescription> scales;
};

/// The camera: given whole, or framed from the scene's bounds looking along `frameDirection`
/// (from the target to the eye) with the rest of `camera` (projection, field of view, near and
/// far), refitted to the image size by frameCamera.
struct CameraDescription {
  Camera camera;
  bool framed = true;
  glm::dvec3 frameDirection{0.55, -0.75, 0.45};
  std::string where;  ///< errors of the camera (Camera::problem)
};

struct SceneDescription {
  std::vector<Material> materials{Material{}};  ///< objects name them by index
  LightRig lights = LightRig::studioRig(3);
  bool lightsFollowCamera = true;
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
  std::shared_ptr<const EnvironmentMap> environment;
  std::vector<ObjectDescription> objects;
  CameraDescription camera;
  int width = 640, height = 480;  ///< the image the camera is framed for
  /// Overrides every fur's wind time (an animation frame).
  std::optional<double> time;
  /// The most primitives (triangles, wire and hair segments, scale triangles) the scene may make,
  /// checked before each is made: about 4 GB of renderer memory by default.
  double maxPrimitives = kMaxScenePrimitives;
  static constexpr double kMaxScenePrimitives = 8388608.0;
};

/// An object's exact surfaces whose silhouettes a wire of the scene draws: the faces (world
/// space), each with where it is over its (u, v) (null: everywhere).
struct SilhouetteSource {
  std::size_t wire = 0;  ///< index into Scene::wires of the silhouette wire
  std::vector<std::pair<std::shared_ptr<const Surface>, std::shared_ptr<const ScalarTexture>>> faces;
  SilhouetteOptions options;
};

/// What buildScene made.
struct BuiltScene {
  Scene scene;
  double generateSeconds = 0.0;  ///< growing fur and scales
  std::size_t hairsGrown = 0, scalesGrown = 0;
  double primitives = 0.0;       ///< counted against maxPrimitives
  bool framed = false;           ///< the camera was framed from the bounds (reframe on resize)
  /// Silhouette wires, traced for the camera by buildScene and frameCamera (traceSilhouettes
  /// again whenever the camera changes).
  std::vector<SilhouetteSource> silhouettes;
  SilhouetteStats silhouetteStats;
  double silhouetteSeconds = 0.0;
  /// Faces whose brushed grain was laid out (Burnish::layout), and along which.
  std::size_t grainFaces = 0, grainAlongU = 0, grainAlongV = 0;
};

/// Builds the scene: tessellates sources, makes edges and isolines, places everything by its
/// transform, grows fur and scales on the placed surfaces, and frames the camera. Throws
/// SceneError for what the description asks and cannot be (no polygons to draw, fur on an object
/// without a surface, the primitive budget), naming the part.
BuiltScene buildScene(const SceneDescription& description);

/// Refits a framed camera to a width x height image (the scene's bounds seen along the
/// description's frame direction). No-op for a given camera.
void frameCamera(BuiltScene& built, const CameraDescription& camera, int width, int height);

/// Traces every silhouette wire of `scene` (its lines replaced) for `camera` at width x height
/// (the screen tolerance is in its pixels); faces in parallel, the same lines for any thread
/// count. Returns the seconds taken; adds to `stats`.
double traceSilhouettes(Scene& scene, const std::vector<SilhouetteSource>& sources, const Camera& camera, int width,
                        int height, SilhouetteStats& stats);

}  // namespace wf
