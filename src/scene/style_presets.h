// Styles as data (docs/scenes.md, "Styles"): what `--style` asks of a bare mesh, polyline or CAD
// file, written into a scene description (scene/scene_description.h) that buildScene makes. The
// same style gives the same materials, widths and growth on a mesh and on a CAD file of the same
// shape; only what the input has (CAD faces with exact surfaces, a mesh's texture coordinates)
// changes where hairs and scales root.
#pragma once

#include "scene/scene_description.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>
#include <string>

namespace wf {

enum class Style { Wire, WireOverSurface, Burnished, Fur, Scales };

/// "wire", "wire-over-surface", "burnished", "fur", "scales"; false for anything else.
bool parseStyle(const std::string& name, Style& style);
const char* styleName(Style style);
/// The names, for messages: "wire, wire-over-surface, burnished, fur or scales".
const char* styleNames();

/// The size of a model (its bounding box diagonal), that the presets' lengths are relative to.
double modelSize(const GeometryData& geometry);

/// A scene of one file's geometry in a style, framed from its bounds under the studio rig:
///   wire               the edges (a CAD model's B-rep edges and the silhouettes of its curved
///                      faces, a mesh's triangle edges) or the file's lines, copper, 1.5 px
///   wire-over-surface  the same at 2 px over the shaded part (a CAD model's colours kept)
///   burnished          brushed steel, grain along u (a CAD face's, a mesh's texture u, else the
///                      up axis projected onto the surface)
///   fur                hairs grown on the surface: about 60,000, area-correct, length 3% of the
///                      model's size, a little droop
///   scales             two scales per cell of about 2.5% of the model's size, over the surface
/// A file of polylines only (hair, streamlines) draws them as hair-like shaded strands in every
/// style that draws lines. Throws SceneError("--style", ...) where the style means nothing for
/// the input (burnished, fur or scales without polygons).
SceneDescription describeStyled(std::shared_ptr<const GeometryData> geometry, Style style);

/// Hidden lines (`--hidden`, HiddenLines) for every object's wire-frame that is not hair-like
/// (aggregate): its wire draws where surfaces hide it as `hidden` says. An object whose surface
/// is not drawn (the wire style) gets it as a hold-out, unless `hidden` is off: its faces then
/// decide which edges show (hidden-line removal) and draw nothing. Iso lines are hidden, not
/// dashed.
void applyHiddenLines(SceneDescription& description, const HiddenLines& hidden);
/// Silhouettes on or off for every object's wire-frame that is not hair-like (`--silhouettes`).
void applySilhouettes(SceneDescription& description, bool on);
/// Which edges wire-frames draw, as the command line overrides it (`--edges`, `--seams`,
/// `--feature-angle`): each given part replaces that part of every not hair-like wire's
/// EdgeSelection (render/edge_classes.h).
struct EdgeOverrides {
  std::optional<EdgeSelection::Mode> mode;
  std::optional<bool> seams;
  std::optional<double> featureAngle;
};
void applyEdgeSelection(SceneDescription& description, const EdgeOverrides& edges);

/// Brushed steel's visible grooves by default (the burnished style): grooves per world unit
/// across the grain (per millimetre for CAD files), and their depth (GrooveTexture).
inline constexpr double kDefaultGroovesPerUnit = 10.0;
inline constexpr double kDefaultGrooveDepth = 0.3;

/// Brushed steel as the command line overrides it (`--grain`, `--grain-axis`,
/// `--grooves-per-mm`), for every object whose surface's material is burnished: the grain laid
/// along each face's u, v or longer extent (surface/grain_layout.h), or circular or radial about
/// an axis (default: through the object's bounding-box centre, along z; the command line refuses an
/// axis without one of those two); grooves per world unit
/// across the grain (0: none visible; u and v are then made world lengths where they are not).
struct BurnishOverrides {
  enum class Grain : std::uint8_t { U, V, Longer, Circular, Radial };
  std::optional<Grain> grain;
  std::optional<glm::dvec3> axisPoint, axisDirection;  ///< both or neither
  std::optional<double> groovesPerUnit;
};
/// Returns a warning for each object left without grooves because its mesh has no (u, v) (it gets
/// a copy of its material without them).
std::vector<std::string> applyBurnish(SceneDescription& description, const BurnishOverrides& burnish);
/// "off", "dashed", "ghost", "hide"; false for anything else.
bool parseHiddenMode(const std::string& name, HiddenLines::Mode& mode);

}  // namespace wf
