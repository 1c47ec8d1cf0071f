// Stage "camera" (render/pipeline.h): which camera a render uses and its near and far planes.
#include "render/pipeline.h"

#include <algorithm>
#include <cmath>

namespace wf {

namespace {

// The scene's bounding sphere, found on first use only (two passes over every point: a camera
// with its planes set needs none of it) and then kept.
class SceneSphere {
 public:
  explicit SceneSphere(const Scene& s) : scene_(s) {}
  bool get(glm::dvec3& centre, double& radius) {
    if (!done_) has_ = scene_.boundingSphere(centre_, radius_), done_ = true;
    centre = centre_, radius = radius_;
    return has_;
  }

 private:
  const Scene& scene_;
  bool done_ = false, has_ = false;
  glm::dvec3 centre_{0.0};
  double radius_ = 0;
};

Camera withDepthRange(Camera c, SceneSphere& sphere) {
  if (c.nearPlane > 0 && c.farPlane > 0) return c;
  // Near and far from the bounding sphere, as tight as the scene allows.
  glm::dvec3 centre;
  double sphereRadius = 0;
  const bool hasBounds = sphere.get(centre, sphereRadius);
  const glm::dvec3 dir = glm::normalize(c.target - c.eye);
  double dmin = 1e-3, dmax = 1e3;
  if (hasBounds) {
    const double radius = std::max(sphereRadius, 1e-300);
    const double along = glm::dot(centre - c.eye, dir);
    dmax = along + radius * 1.01;
    dmin = std::max(along - radius * 1.01, dmax * 1e-6);
    if (!(dmax > 0)) dmax = 1.0, dmin = 1e-6;
  }
  // A far plane given alone may lie before the scene's nearest point: near then stays before it
  // (the scene lies wholly beyond far and nothing shows), so that near < far always holds.
  if (c.nearPlane <= 0) c.nearPlane = c.farPlane > 0 ? std::min(dmin, 0.5 * c.farPlane) : dmin;
  if (c.farPlane <= 0) c.farPlane = std::max(dmax, c.nearPlane * 2);
  return c;
}

}  // namespace

Camera withDepthRange(Camera c, const Scene& scene) {
  SceneSphere sphere(scene);
  return withDepthRange(c, sphere);
}

Camera chooseCamera(const Scene& scene, const RenderOptions& o, RenderStats& st) {
  SceneSphere sphere(scene);
  bool useScenes = scene.camera.has_value();
  if (useScenes) {
    const std::string problem = scene.camera->problem();
    if (!problem.empty()) {
      st.warnings.push_back("camera: " + problem + "; framed from the scene's bounds instead");
      useScenes = false;
    }
  }
  Camera c{};
  glm::dvec3 centre;
  double sphereRadius = 0;
  if (useScenes)
    c = *scene.camera;
  else if (sphere.get(centre, sphereRadius))
    c = frameSphere(centre, sphereRadius, double(o.width) / o.height);
  return withDepthRange(c, sphere);
}

}  // namespace wf
