// What the core renders: triangle meshes (surfaces) and polylines (wires, hairs) with their
// materials, lights and camera, all in world space. The apps layer fills this from scene files
// and VTK readers; later issues add generators (surfaces, fur, scales) that fill it too.
#pragma once

#include "render/camera.h"
#include "shading/environment_map.h"
#include "shading/light.h"
#include "shading/phong.h"

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

struct Material {
  enum class Kind { Phong, Chrome };
  std::string name = "default";
  Kind kind = Kind::Phong;
  PhongMaterial phong{};
  glm::dvec3 chromeReflectance{0.9};  ///< chrome: mirror reflectance of the environment
  float opacity = 1.0f;
};

/// How a wire is drawn: the paper's shaded wire (a thin cylinder through the pseudo-reflectance
/// map), plain constant-colour lines, or depth-cued lines dimmed with distance (the baseline
/// the paper argues against, §3).
enum class WireStyle { Shaded, Plain, DepthCued };

struct SceneSurface {
  std::string name;
  TriangleMesh mesh;
  int material = 0;
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

 private:
  /// Calls f on every vertex a triangle or polyline uses.
  template <class F>
  void forEachPoint(F&& f) const;
};

}  // namespace wf
