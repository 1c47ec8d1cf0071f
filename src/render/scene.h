// What the core renders: triangle meshes (surfaces) and polylines (wires, hairs) with their
// materials, lights and camera, all in world space. The apps layer fills this from scene files
// and VTK readers; later issues add generators (surfaces, fur, scales) that fill it too.
#pragma once

#include "render/camera.h"
#include "render/edge_classes.h"
#include "shading/environment_map.h"
#include "shading/light.h"
#include "shading/phong.h"
#include "texture/texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace wf {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;   ///< per vertex, or empty (face normals)
  std::vector<glm::dvec3> tangents;  ///< per vertex, or empty (the shading tangent: burnish grain)
  std::vector<glm::dvec3> derivU;    ///< per vertex dS/du (surfaces from a parametric patch), or empty
  std::vector<glm::dvec3> derivV;    ///< per vertex dS/dv, or empty
  std::vector<glm::dvec2> uvs;       ///< per vertex, or empty
  std::vector<glm::vec3> colours;    ///< per vertex (multiplies the shading), or empty
  std::vector<glm::uvec3> triangles;
};

struct PolylineSet {
  std::vector<glm::dvec3> points;
  std::vector<glm::vec3> colours;     ///< per point (multiplies the shading), or empty
  std::vector<std::uint32_t> starts;  ///< polyline i is points[starts[i], starts[i+1]); last = size
  size_t polylineCount() const { return starts.empty() ? 0 : starts.size() - 1; }
  void add(const std::vector<glm::dvec3>& line) {
    if (starts.empty()) starts.push_back(0);
    points.insert(points.end(), line.begin(), line.end());
    starts.push_back(std::uint32_t(points.size()));
  }
};

class GrooveTexture;

/// How the scene builder lays a burnish's grain out over each face of a surface
/// (surface/grain_layout.h): along its u, its v, or the longer of the two by the face's extent in
/// world units; each then with (u, v) scaled to world lengths, so grooves per unit are per
/// millimetre of a CAD part. Raw: the surface's own (u, v), as given.
enum class GrainLayout : std::uint8_t { Raw, U, V, Longer };

/// Burnished metal (paper §2.2, images 5-8, 19): the surface is taken to be fine parallel
/// cylinders (grooves) along a grain direction, shaded through the pseudo-reflectance map of the
/// material's Phong model by the eye-space grain tangent, exactly as a wire is. Grooves made
/// visible by a groove texture modulate the diffuse and the specular part together (the paper's
/// stand-in for self-shadowing by uneven groove depth).
struct Burnish {
  enum class Grain {
    None,      ///< not burnished: isotropic shading by the normal
    U,         ///< along dS/du (grooves indexed by v)
    V,         ///< along dS/dv (grooves indexed by u)
    Radial,    ///< away from an axis (grooves indexed by the angle about it)
    Circular,  ///< around an axis: a record on a turntable (grooves indexed by the distance from it)
  };
  Grain grain = Grain::None;
  glm::dvec3 axisPoint{0.0};                   ///< radial / circular: a point of the axis (world)
  glm::dvec3 axisDirection{0.0, 0.0, 1.0};     ///< radial / circular: the axis direction (world)
  /// Visible grooves (optional). Their coordinate: v for grain U, u for grain V, the turn
  /// (angle / 2 pi) for radial grain, the distance from the axis (world units) for circular.
  std::shared_ptr<const GrooveTexture> grooves;
  /// Grain U or V only: how the scene builder lays it out per face (the renderer reads the
  /// result, not this).
  GrainLayout layout = GrainLayout::Raw;
  bool active() const { return grain != Grain::None; }
};

struct Material {
  enum class Kind { Phong, Chrome };
  std::string name = "default";
  Kind kind = Kind::Phong;
  PhongMaterial phong{};
  glm::dvec3 chromeReflectance{0.9};  ///< chrome: mirror reflectance of the environment
  float opacity = 1.0f;
  Burnish burnish;                    ///< Phong materials only
  /// Colour map over the surface's (u, v) (paper §4.1, images 12, 13): multiplies the diffuse
  /// part (highlights keep the light's colour), box-filtered over the pixel's footprint.
  std::shared_ptr<const ColourTexture> colourMap;
  /// Bump map (Blinn 1978, paper image 14): a height over (u, v), in world units times
  /// `bumpScale`, perturbing the normal; the outline stays smooth.
  std::shared_ptr<const ScalarTexture> bumpMap;
  double bumpScale = 1.0;
};

/// How a wire is drawn: the paper's shaded wire (a thin cylinder through the pseudo-reflectance
/// map), plain constant-colour lines, or depth-cued lines dimmed with distance (the baseline
/// the paper argues against, §3).
enum class WireStyle { Shaded, Plain, DepthCued };

struct SceneSurface {
  std::string name;
  TriangleMesh mesh;
  int material = 0;
  /// Hides what lies behind it and draws nothing of its own (hidden-line removal of a
  /// wire-frame: the part's faces decide which edges show, the background shows where they are).
  bool holdout = false;
};

/// How a wire is drawn where an opaque surface hides it (CAD hidden lines). Off and Hide draw
/// nothing there (Hide differs only in the styles, which then add the faces as hold-outs);
/// Dashed draws dashes of `dash` pixels with gaps of `gap` along the polyline's screen arc length
/// (from its first point, so the phase runs on across joints), box-filtered over a pixel along
/// the wire; Ghost draws it at `ghost` opacity. Visibility is the A-buffer's, per subpixel, at
/// the surface's exact depth: no depth offset.
struct HiddenLines {
  enum class Mode { Off, Dashed, Ghost, Hide };
  Mode mode = Mode::Off;
  double dash = 6.0, gap = 4.0;  ///< pixels
  float ghost = 0.3f;
  /// Draws hidden parts at all (dashed or ghosted).
  bool drawn() const { return mode == Mode::Dashed || mode == Mode::Ghost; }
};

struct SceneWire {
  std::string name;
  PolylineSet lines;
  int material = 0;
  WireStyle style = WireStyle::Shaded;
  double thickness = 0.01;         ///< diameter, world units (or pixels, see below)
  bool thicknessInPixels = false;
  glm::vec3 colour{1.0f};          ///< plain and depth-cued styles
  float opacity = 1.0f;
  /// Free ends of a polyline (not its joints) drawn as half discs: the outline of a round
  /// cylinder with spherical caps, as ray casters draw round curves (Embree's round linear
  /// curves). False: the paper's square-ended polygon.
  bool roundEnds = false;
  /// Where the wire's cylinder lies relative to its polyline. True (edges, the default): the
  /// polyline is where the wire rests on what it is drawn over, and the cylinder lies one radius
  /// nearer the viewer, so a wire lying on a surface (a CAD edge on its face, a mesh's own edge)
  /// shows whole in front of it. False (hairs): the polyline is the cylinder's axis, as a ray
  /// caster draws a round curve, and a hair enters the skin it grows from.
  bool restsOnSurface = true;
  /// Many similar strands (fur): RenderOptions::simplify may draw a fraction of them where they
  /// are much denser than the pixels resolve. False: every polyline is drawn as it is.
  bool aggregate = false;
  HiddenLines hidden;  ///< where surfaces hide it
  /// Per polyline of `lines`, its class (render/edge_classes.h) where they are a model's edges or
  /// silhouettes; else empty. The renderer does not read it; `wirefur export` writes it.
  std::vector<EdgeClass> edgeClasses;
};

struct Scene {
  std::optional<Camera> camera;    ///< framed from the bounds when absent
  LightRig lights;                 ///< world space (eye space when lightsFollowCamera)
  bool lightsFollowCamera = false; ///< lights fixed to the viewer (studio set-ups, paper images)
  std::vector<Material> materials{Material{}};
  std::vector<SceneSurface> surfaces;
  std::vector<SceneWire> wires;
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};  ///< linear RGBA
  std::shared_ptr<const EnvironmentMap> environment;  ///< chrome materials reflect this
  /// Bounds of all finite geometry; false when there is none.
  bool bounds(glm::dvec3& lo, glm::dvec3& hi) const;
  /// A sphere holding all finite geometry (centre of the bounds, radius to the farthest point);
  /// false when there is none.
  bool boundingSphere(glm::dvec3& centre, double& radius) const;
};

/// `camera` with its near and far planes, where it leaves them open (0), from the scene's bounding
/// sphere as tight as it allows: the planes a render uses (render/view_setup.cpp).
Camera withDepthRange(Camera camera, const Scene& scene);

}  // namespace wf
