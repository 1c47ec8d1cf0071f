// Scene files (JSON, docs/scenes.md): camera, lights, materials and objects (parametric sources
// or mesh / polyline files) with their surfaces and wire-frames, plus the image settings.
// Read with nlohmann-json; every problem is one line naming the file and the JSON pointer
// (UsageError, exit status 2), found before anything is rendered or written.
#pragma once

#include "abuffer/coverage_mask.h"
#include "render/scene.h"
#include "scene/scene_description.h"
#include "scene/style_presets.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace wfapp {

struct SceneFile {
  wf::Scene scene;
  std::string title, caption, paperImage;  ///< for the gallery
  int width = 640, height = 480;
  wf::MaskLayout mask{8, 4};
  int budget = 64;
  int viewGrid = 1;  ///< view-direction tables per side (image.view_grid)
  /// Seconds spent growing fur and scales, and counts of what was grown (part of reading).
  double generateSeconds = 0.0;
  std::size_t hairsGrown = 0, scalesGrown = 0;
  std::size_t grainFaces = 0, grainAlongU = 0, grainAlongV = 0;  ///< BuiltScene's
  /// The camera was framed from the bounds (no eye given): reframe() fits it to another size.
  bool framed = false;
  wf::CameraDescription camera;  ///< as described (framing direction, projection, field of view)
  /// What reading the input found, for --stats ("input"): for CAD files the counts, the
  /// deflection and the seconds spent reading and meshing; empty otherwise.
  nlohmann::ordered_json inputStats;
  /// Silhouette wires (BuiltScene::silhouettes): traced again when the camera changes (reframe,
  /// the viewer); what tracing them counted and cost so far.
  std::vector<wf::SilhouetteSource> silhouettes;
  wf::SilhouetteStats silhouetteStats;
  double silhouetteSeconds = 0.0;
};

/// Tessellation settings for CAD input (--deflection, --linear-deflection, --angular-deflection,
/// --isos; docs/cad.md).
struct CadOptions {
  double deflection = 0.0;         ///< 0: the reader's default (1e-3 of the model's diagonal)
  bool absoluteDeflection = false; ///< deflection in world units instead of relative
  double angularDegrees = 0.0;     ///< 0: the reader's default (about 20 degrees)
  int isos = 0;                    ///< u and v iso lines per face
  int threads = 0;
  bool showProgress = false;       ///< progress lines on stderr while reading and meshing
  bool isolate = true;             ///< read in a worker process (crashes and hangs become errors)
  double timeoutSeconds = 600.0;   ///< the worker's time limit (--cad-timeout)
};

/// What the command line may override in a scene while it is read.
struct SceneOverrides {
  /// How CAD files (given directly or named by scene objects) are tessellated.
  CadOptions cad;
  /// Time of every fur's wind (`--time`): render an animation frame by frame.
  std::optional<double> time;
  /// `--hidden`: hidden lines of every wire-frame (scene/style_presets.h, applyHiddenLines).
  std::optional<wf::HiddenLines> hidden;
  /// `--silhouettes on|off`: the silhouettes of curved faces with every wire-frame (default: on
  /// for the wire styles of CAD files, as a scene file's wires say otherwise).
  std::optional<bool> silhouettes;
  /// `--edges`, `--seams`, `--feature-angle`: which edges every wire-frame draws.
  wf::EdgeOverrides edges;
  /// `--grain`, `--grain-axis`, `--grooves-per-mm`: brushed steel of every burnished surface.
  wf::BurnishOverrides burnish;
};

/// Refits an automatically framed camera to a width x height image (after --size).
void reframe(SceneFile& sf, int width, int height);

/// Parses a scene file; relative file names in it are relative to the file's folder.
SceneFile loadSceneFile(const std::string& path, const SceneOverrides& overrides = {});
/// Parses scene text; `name` is used in messages, `folder` resolves relative file names.
SceneFile parseScene(const std::string& name, const std::string& text, const std::string& folder,
                     const SceneOverrides& overrides = {});

/// The built-in scene `wirefur render` draws with no input: data/scenes/cage_shaded.json, the
/// paper's image 9b (a wire-frame cage as shaded wire over a shaded torus), compiled in.
SceneFile defaultScene(const SceneOverrides& overrides = {});

/// A scene around one mesh / polyline file, drawn in one of the contract's styles:
/// "wire" (its edges or lines as shaded wire), "wire-over-surface" (shaded wire over the
/// shaded surface). Throws UsageError for styles this version cannot draw.
SceneFile sceneForGeometryFile(const std::string& path, const std::string& style, const SceneOverrides& overrides = {});

/// Builds one file's geometry in a style preset (scene/style_presets.h) into sf: title, caption,
/// scene, framed camera. Bad combinations: UsageError naming the file and the style.
void buildStyled(SceneFile& sf, const std::string& path, std::shared_ptr<const wf::GeometryData> geometry, wf::Style style,
                 const SceneOverrides& overrides = {});

}  // namespace wfapp
