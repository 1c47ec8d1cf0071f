// `wirefur render`: a scene file, a mesh / polyline file or the built-in scene, rendered by the
// A-buffer (or the brute-force reference) to PNG, with --stats JSON (docs/cli.md).
#pragma once

#include "scene_file.h"

#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace wfapp {

struct RenderCommandOptions {
  std::string input;           ///< empty: the built-in scene
  std::string output;          ///< PNG path (required)
  std::string statsPath;
  std::string style;           ///< for bare mesh files
  int width = 0, height = 0;   ///< 0: from the scene
  std::string mask;            ///< empty: from the scene
  int budget = 0;              ///< 0: from the scene
  bool deepShares = true;      ///< --no-deep-shares turns it off (RenderOptions::deepShares)
  int threads = 0;
  std::string shading = "closed";  ///< --shading closed|maps|exact (wf::ShadingPath)
  bool reference = false;      ///< brute-force reference instead of the A-buffer
  bool measureError = false;   ///< also render the reference and report the measured error
  int samples = 16;            ///< reference samples per side
  int viewGrid = 0;            ///< view-direction tables per side (0: from the scene)
  std::optional<double> simplify;  ///< --simplify WIDTH: stochastic simplification of fur to WIDTH pixels
  std::string wireDepth;       ///< --wire-depth round|flat (empty: round)
  bool quiet = false;
  std::optional<double> time;  ///< --time: every fur's wind time (an animation frame)
  std::optional<std::size_t> memoryBudget;  ///< --memory-budget: bytes (0: unlimited); unset: the core's default
  CadOptions cad;              ///< --deflection, --angular-deflection, --isos (CAD input)
  std::optional<wf::HiddenLines> hidden;  ///< --hidden
  std::optional<bool> silhouettes;        ///< --silhouettes
  wf::EdgeOverrides edges;                ///< --edges, --seams, --feature-angle
  wf::BurnishOverrides burnish;           ///< --grain, --grain-axis, --grooves-per-mm
};

int runRender(const RenderCommandOptions& options);

/// Loads INPUT as the contract says (scene, mesh file, or built-in when empty).
SceneFile loadInput(const std::string& input, const std::string& style, const SceneOverrides& overrides = {});

/// The shading path of --shading's name (closed, maps, exact), and the name of a path.
wf::ShadingPath shadingPathNamed(const std::string& name);
const char* shadingPathName(wf::ShadingPath path);

/// Render options from a scene file's settings.
wf::RenderOptions renderOptionsFor(const SceneFile& sf);

/// The --stats document: the keys of docs/design.md plus what was left out and the error estimate.
nlohmann::ordered_json statsJson(const wf::RenderStats& stats, const wf::RenderOptions& options,
                                 bool reference);

/// Per-pixel RGBA difference of two renders: RMS and max over all pixels and channels, and the
/// RMS of the alpha (coverage) channel.
struct ImageError {
  double rms = 0, max = 0, coverageRms = 0, coverageMax = 0;
};
ImageError imageError(const wf::ImageRGBA& a, const wf::ImageRGBA& reference);

/// Peak resident memory of this process so far, bytes.
long peakRssBytes();
/// Resident memory now (/proc/self/statm), bytes.
long currentRssBytes();

}  // namespace wfapp
